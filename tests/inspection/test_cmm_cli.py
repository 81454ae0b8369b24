"""`camtol inspect`, `camtol simulate cmm|record`, `camtol conjugate --cmm-a/--cmm-b` (issue 12)."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.pair.acceptance import acceptance_bands
from camtol.pair.variation import conjugate_factors


def _run(capsys, *args: str) -> tuple[int, str, str]:  # type: ignore[no-untyped-def]
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def scan_b(tmp_path_factory) -> Path:  # type: ignore[no-untyped-def]
    p = tmp_path_factory.mktemp("scan") / "b.csv"
    code = main(
        [
            "simulate",
            "cmm",
            "--example",
            "cw11-experiment",
            "-o",
            str(p),
            "--cam",
            "B",
            "--noise-um",
            "1",
            "--seed",
            "3",
            "--stylus-radius-mm",
            "1",
            "--eccentricity-um",
            "40",
            "--rotation-deg",
            "10",
            "--outliers",
            "4",
            "--error-rms-um",
            "50",
        ]
    )
    assert code == 0
    return p


def test_simulate_writes_scan_and_truth(scan_b: Path) -> None:
    truth = json.loads(scan_b.with_name("b.truth.json").read_text())
    assert truth["placement"] == {"rotation_deg": 10.0, "dx_mm": 0.04, "dy_mm": 0.0}
    assert len(truth["outlier_indices"]) == 4 and truth["stylus_radius_mm"] == 1.0
    assert truth["profile_error"]["kind"] == "radial"
    lines = [ln for ln in scan_b.read_text().splitlines() if not ln.startswith("#")]
    assert lines[0] == "x_mm,y_mm" and len(lines) == 3601


def test_inspect_json_curves_motion(capsys, scan_b: Path, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    curves, motion = tmp_path / "c.csv", tmp_path / "m.csv"
    code, out, err = _run(
        capsys,
        "inspect",
        "--example",
        "cw11-experiment",
        "--points",
        str(scan_b),
        "--cam",
        "B",
        "--stylus-radius-mm",
        "1",
        "--json",
        "--curves",
        str(curves),
        "--motion",
        str(motion),
    )
    assert code == 0, err
    data = json.loads(out)
    truth = json.loads(scan_b.with_name("b.truth.json").read_text())
    assert data["verdict"] == "pass"
    for key in ("rotation_deg", "dx_mm", "dy_mm", "u_rotation_deg", "u_dx_mm", "u_dy_mm"):
        assert key in data["registration"]
    assert data["outliers"] == {"count": 4, "indices": truth["outlier_indices"]}
    for key in ("form_um", "max_dn_um", "min_dn_um", "failing_intervals_deg", "motion"):
        assert key in data
    assert data["motion"]["unit"] == "deg"
    # issue 31: every motion key carries its unit (degrees for this swing)
    assert data["motion"]["max_abs_ds_deg"] == pytest.approx(
        data["motion"]["max_abs_ds_linear_deg"], rel=0.01
    )
    assert "hides eccentricity" in err  # the best-fit warning
    with curves.open() as fh:
        rows = list(csv.reader(ln for ln in fh if not ln.startswith("#")))
    assert rows[0] == ["x_mm", "y_mm", "theta_deg", "dn_um", "dr_um"] and len(rows) == 3601
    with motion.open() as fh:
        head = next(csv.reader(ln for ln in fh if not ln.startswith("#")))
    assert head == ["theta_deg", "dS_measured_deg", "dS_linear_deg"]


def test_inspect_fails_with_exit_1_and_angles(capsys, scan_b: Path, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    plot, report = tmp_path / "p.png", tmp_path / "r.html"
    code, out, _ = _run(
        capsys,
        "inspect",
        "-e",
        "cw11-experiment",
        "--points",
        str(scan_b),
        "--cam",
        "B",
        "--stylus-radius-mm",
        "1",
        "--tolerance-um",
        "-20,20",
        "--plot",
        str(plot),
        "--report",
        str(report),
    )
    assert code == 1
    flat = " ".join(out.split())  # lines wrap at 80 columns
    assert "verdict: FAIL" in out and "outside at polar angles" in flat
    assert max(len(line) for line in out.splitlines()) <= 80
    assert plot.stat().st_size > 10_000 and "<svg" in report.read_text()


def test_inspect_bore_datum(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    # A scan with bore points (flagged bore=1) placed off-centre by 0.3 mm: the bore datum
    # finds the centre from the bore circle; no best-fit warning.
    from camtol.inspection.twin import simulate_scan

    d = load_example("roller-translating")
    sim = simulate_scan(
        d, points=720, noise_um=0.5, seed=1, eccentricity_um=300.0, eccentricity_deg=45.0
    )
    ang = np.linspace(0, 2 * math.pi, 60, endpoint=False)
    bx, by = sim.truth.dx_mm + 10 * np.cos(ang), sim.truth.dy_mm + 10 * np.sin(ang)
    p = tmp_path / "bore.csv"
    rows = [f"{x:.9f},{y:.9f},0" for x, y in zip(sim.x_mm, sim.y_mm, strict=True)]
    rows += [f"{x:.9f},{y:.9f},1" for x, y in zip(bx, by, strict=True)]
    p.write_text("X,Y,bore\n" + "\n".join(rows) + "\n")
    code, out, err = _run(
        capsys,
        "inspect",
        "-e",
        "roller-translating",
        "--points",
        str(p),
        "--columns",
        "X=x_mm,Y=y_mm",
        "--datum",
        "bore",
        "--json",
    )
    assert code == 0, err
    reg = json.loads(out)["registration"]
    assert reg["dx_mm"] == pytest.approx(sim.truth.dx_mm, abs=1e-9)
    assert reg["dy_mm"] == pytest.approx(sim.truth.dy_mm, abs=1e-9)
    assert "hides eccentricity" not in err


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def _circle_rows(n: int, r: float = 60.0) -> list[str]:
    a = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return [f"{r * math.cos(t):.6f},{r * math.sin(t):.6f}" for t in a]


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        ("x_mm,y_mm\n" + "\n".join(_circle_rows(10)) + "\n", "at least 36 points"),
        ("x_mm,y_mm\n" + "\n".join(_circle_rows(720)[:300]) + "\n", "do not go round the cam"),
        ("x_mm,y_um\n" + "\n".join(_circle_rows(100)) + "\n", "mixed units"),
        ("x_mm,y_mm\n" + "\n".join(_circle_rows(100)) + "\nnan,1.0\n", "line 102"),
        ("x_mm,y_mm\n1,2\n" + "\n".join(_circle_rows(100)) + "\n1,2\n", "duplicate point"),
        ("x,y\n" + "\n".join(_circle_rows(100)) + "\n", "has no unit"),
    ],
)
def test_bad_scan_exit_2_one_line_nothing_written(
    capsys, tmp_path: Path, content: str, needle: str
) -> None:  # type: ignore[no-untyped-def]
    p = _write(tmp_path / "scan.csv", content)
    curves = tmp_path / "c.csv"
    code, out, err = _run(
        capsys, "inspect", "-e", "cw11-experiment", "--points", str(p), "--curves", str(curves)
    )
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and str(p) in lines[0]
    assert not curves.exists() and out == ""


def test_scan_of_the_wrong_cam_is_refused(capsys, scan_b: Path, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    # Cam B's scan inspected as a roller-translating design's cam: far beyond any tolerance.
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "roller-translating",
        "--points",
        str(scan_b),
        "--stylus-radius-mm",
        "1",
    )
    assert code == 2
    assert "is this a scan of that cam?" in err and len(err.strip().splitlines()) == 1


def test_table2_band_widths_from_the_constants() -> None:
    # THEORY §8.4: from the Table 2 constants alone, A(u) − A(l) = 338.85 µm at 216.4° and
    # B(u) − B(l) = 335.17 µm at 219.3° (±220 µm tolerance, zero masters). The chapter
    # prints two decimals (truncated: 335.1786 reads 335.17), hence abs=0.01 µm.
    d = load_example("cw11-experiment")
    spec = d.inspection
    assert spec is not None
    fac = conjugate_factors(d, np.radians([216.4, 219.3]))
    b = acceptance_bands(
        fac, spec.tolerance_a_um, spec.tolerance_b_um, spec.master_a, spec.master_b, spec.errors
    )
    assert b.df_a_upper_um[0] - b.df_a_lower_um[0] == pytest.approx(338.85, abs=0.01)
    assert b.df_b_upper_um[1] - b.df_b_lower_um[1] == pytest.approx(335.17, abs=0.01)


def test_item5_fixture_estimates_agree_with_cmm_on_simulated_parts(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    # The paper's loop (issue 12 item 5) on simulated parts: scans of both cams with known
    # errors (rms 120 and 90 µm), a fixture record of the same parts (Table 2 follower,
    # 10 revolutions, 2 µm indicator noise); each cam estimated from the record with the
    # other's CMM error as master agrees with its CMM error to within twice the
    # per-sample record noise: the mean of 10 revolutions leaves 0.63 µm of it, the rest
    # is the linearisation of eqs. 14-21 at these error sizes (Δf_est differs from the
    # exact twin by about 1.6 µm rms; the paper reports 2.75 µm for Δf_est − Δf_mea).
    a, b, rec = tmp_path / "a.csv", tmp_path / "b.csv", tmp_path / "rec.csv"
    for cam, path, rms, seed in (("A", a, "120", "1"), ("B", b, "90", "2")):
        assert (
            main(
                [
                    "simulate",
                    "cmm",
                    "-e",
                    "cw11-experiment",
                    "-o",
                    str(path),
                    "--cam",
                    cam,
                    "--error-rms-um",
                    rms,
                    "--seed",
                    seed,
                    "--noise-um",
                    "1",
                ]
            )
            == 0
        )
    assert (
        main(
            [
                "simulate",
                "record",
                "-e",
                "cw11-experiment",
                "-o",
                str(rec),
                "--truth-a",
                str(tmp_path / "a.truth.json"),
                "--truth-b",
                str(tmp_path / "b.truth.json"),
                "--noise-um",
                "2",
            ]
        )
        == 0
    )
    capsys.readouterr()
    code, out, err = _run(
        capsys,
        "conjugate",
        "-e",
        "cw11-experiment",
        "--record",
        str(rec),
        "--cmm-a",
        str(a),
        "--cmm-b",
        str(b),
        "--cmm-datum",
        "centre:0,0,0",
        "--json",
        "--cmm-plot",
        str(tmp_path / "cmm.png"),
    )
    assert code in (0, 1), err
    assert (tmp_path / "cmm.png").stat().st_size > 10_000
    s = json.loads(out)["cmm_comparison"]
    assert s["rms_dr_A_cmm_um"] == pytest.approx(120.0, rel=0.01)
    assert s["rms_dr_B_cmm_um"] == pytest.approx(90.0, rel=0.01)
    assert s["rms_dr_A_est_minus_cmm_um"] < 2.0 * 2
    assert s["rms_dr_B_est_minus_cmm_um"] < 2.0 * 2
    # the exact twin of the fixture from the two CMM profiles reproduces the record
    assert s["rms_df_twin_minus_mea_um"] < 1.0
    assert s["relative_deviation_df_est"] < 0.01


def test_scan_of_the_other_cam_of_a_pair_is_named(capsys, scan_b: Path) -> None:  # type: ignore[no-untyped-def]
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "cw11-experiment",
        "--points",
        str(scan_b),
        "--cam",
        "A",
        "--stylus-radius-mm",
        "1",
    )
    assert code == 2
    assert "it matches cam B: use --cam B" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("stylus", ["0", "1e9"])
def test_scan_of_neither_cam_of_a_pair_is_refused_once(  # type: ignore[no-untyped-def]
    capsys, tmp_path: Path, stylus: str
) -> None:
    # The hint tries the other cam; that try must not try back: a scan of neither cam
    # (another part, or centres compensated by an absurd ball) recursed between A and B
    # until Python's limit ("numerical failure ... nested too deeply").
    scan = tmp_path / "other.csv"
    code, _, _ = _run(capsys, "simulate", "cmm", "-e", "cw06-translating", "-o", str(scan))
    assert code == 0
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "cw11-experiment",
        "--points",
        str(scan),
        "--stylus-radius-mm",
        stylus,
    )
    assert code == 2
    assert "do not match the nominal profile of cam A" in err and "it matches" not in err
    assert "nested too deeply" not in err and len(err.strip().splitlines()) == 1


def test_cmm_options_bad_input(capsys, scan_b: Path, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    code, _, err = _run(capsys, "conjugate", "-e", "cw11-experiment", "--cmm-a", str(scan_b))
    assert code == 2 and "--cmm-a and --cmm-b go together" in err
    code, _, err = _run(
        capsys, "inspect", "-e", "cw11-experiment", "--points", str(scan_b), "--datum", "centre:1,x"
    )
    assert code == 2 and "--datum" in err and len(err.strip().splitlines()) == 1
    code, _, err = _run(
        capsys, "inspect", "-e", "roller-translating", "--points", str(scan_b), "--cam", "B"
    )
    assert code == 2 and "cam B exists only for a conjugate pair" in err
    out = tmp_path / "r.csv"
    code, _, err = _run(
        capsys,
        "simulate",
        "record",
        "-e",
        "roller-translating",
        "-o",
        str(out),
        "--truth-a",
        str(scan_b.with_name("b.truth.json")),
        "--truth-b",
        str(scan_b.with_name("b.truth.json")),
    )
    assert code == 2 and "conjugate" in err and not out.exists()


def test_motion_spec_pass_and_fail(capsys, scan_b: Path, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    base = ["inspect", "-e", "cw11-experiment", "--points", str(scan_b), "--cam", "B"]
    base += ["--stylus-radius-mm", "1", "--json"]
    code, out, err = _run(capsys, *base)
    assert code == 0, err
    m = json.loads(out)["motion"]
    assert m["spec_deg"] is None and m["verdict"] is None
    worst = m["max_abs_ds_deg"]  # deg: cw11 has an oscillating follower
    code, out, err = _run(capsys, *base, "--spec-deg", f"{1.01 * worst!r}")
    data = json.loads(out)
    assert code == 0, err
    assert data["motion"]["verdict"] == "pass" and data["verdict"] == "pass"
    # JSON floats carry 10 significant digits (issue 13 item 6)
    assert data["motion"]["spec_deg"] == pytest.approx(1.01 * worst, rel=1e-9)
    motion = tmp_path / "m.csv"
    code, out, err = _run(capsys, *base, "--spec-deg", f"{0.99 * worst!r}", "--motion", str(motion))
    data = json.loads(out)
    assert code == 1  # the profile passes, the follower error fails its spec
    assert data["profile_verdict"] == "pass" and data["motion"]["verdict"] == "fail"
    assert data["verdict"] == "fail" and motion.exists()
    code, out, _ = _run(capsys, *base[:-1], "--spec-deg", f"{0.99 * worst!r}")
    assert code == 1 and "FAIL against the motion spec" in " ".join(out.split())
    assert "verdict: FAIL (profile and follower error)" in out


@pytest.mark.parametrize(
    ("flags", "needle"),
    [
        (["--spec-um", "5"], "--spec-um=5 is not allowed: the output of this cam is an angle"),
        (["--spec-deg", "0"], "--spec-deg=0.0 is not allowed; give a number of degrees > 0"),
        (["--spec-deg", "nan"], "--spec-deg=nan is not allowed"),
        (["--spec-deg", "1", "--spec-um", "1"], "give --spec-um or --spec-deg, not both"),
    ],
)
def test_motion_spec_bad_input(
    capsys, scan_b: Path, tmp_path: Path, flags: list[str], needle: str
) -> None:  # type: ignore[no-untyped-def]
    curves = tmp_path / "c.csv"
    code, out, err = _run(
        capsys,
        "inspect",
        "-e",
        "cw11-experiment",
        "--points",
        str(scan_b),
        "--cam",
        "B",
        "--curves",
        str(curves),
        *flags,
    )
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1
    assert not curves.exists() and out == ""


def test_cmm_fixture_figure_shows_the_table4_differences() -> None:
    # The figure of conjugate --cmm-plot: Δf_mea, the twin and Δf_est, and below their
    # differences from Δf_mea with the rms of [CW11] Table 4 in the legend.
    from camtol.pair.cmm_fixture import CmmFixtureComparison
    from camtol.report.inspection_plots import cmm_fixture_figure

    t = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    mea = 20.0 * np.sin(t)
    comp = CmmFixtureComparison(
        theta_rad=t,
        dr_a_cmm_um=np.zeros_like(t),
        dr_b_cmm_um=np.zeros_like(t),
        df_mea_um=mea,
        df_twin_um=mea + 3.0,  # rms difference 3
        df_est_um=mea + 4.0 * np.sqrt(2.0) * np.cos(t),  # rms difference 4
        dr_a_est_um=None,
        dr_b_est_um=None,
    )
    top, bottom = cmm_fixture_figure(comp).axes
    assert len(top.lines) == 3
    labels = [t.get_text() for t in bottom.get_legend().get_texts()]
    assert labels == ["twin − Δf_mea (rms 3 µm)", "Δf_est − Δf_mea (rms 4 µm)"]
    comp = dataclasses.replace(comp, df_mea_um=None)
    top, bottom = cmm_fixture_figure(comp).axes
    assert len(top.lines) == 2
    # Δf_est − twin = 4√2 cos θ − 3: rms √(16 + 9) = 5
    assert [t.get_text() for t in bottom.get_legend().get_texts()] == ["Δf_est − twin (rms 5 µm)"]


def test_cmm_plot_needs_the_scans(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "c.png"
    code, _, err = _run(capsys, "conjugate", "-e", "cw11-experiment", "--cmm-plot", str(out))
    assert code == 2 and "--cmm-plot needs the CMM scans" in err and not out.exists()


def test_inspect_quiet_prints_nothing(capsys, scan_b: Path) -> None:  # type: ignore[no-untyped-def]
    """-q is 'exit status only': not even the best-fit warning (it stays in --json)."""
    args = ["inspect", "--example", "cw11-experiment", "--points", str(scan_b), "--cam", "B"]
    code, out, err = _run(capsys, *args, "--stylus-radius-mm", "1", "-q")
    assert code == 0 and out == "" and err == ""


@pytest.mark.parametrize(
    "command",
    [
        ["conjugate", "-e", "cw11-experiment"],
        ["report", "-e", "cw11-conjugate", "-o", "r.html"],  # a pair with [inspection]
        ["report", "-e", "roller-oscillating", "-o", "r.html"],  # not a pair: never read
    ],
)
@pytest.mark.parametrize(
    ("option", "value"),
    [("--cmm-stylus-radius-mm", "0.5"), ("--cmm-stylus-radius-mm", "2"), ("--cmm-datum", "bore")],
)
def test_cmm_scan_options_without_scans_are_refused(  # type: ignore[no-untyped-def]
    capsys,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    command: list[str],
    option: str,
    value: str,
) -> None:
    # They used to be ignored in silence (a NaN radius too, now refused as it is read).
    monkeypatch.chdir(tmp_path)
    code, _, err = _run(capsys, *command, option, value)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert f"{option}=" in err and "applies to CMM scans: give --cmm-a and --cmm-b" in err
    assert not (tmp_path / "r.html").exists()


def test_simulate_cmm_magnitudes_are_the_twins_bounds(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    """Beyond the twin's bounds (the command line states them as the library does), or a
    profile error that folds the cam: exit 2, one line, nothing written."""
    from camtol.inspection import twin

    out = tmp_path / "s.csv"
    for flag, most in (
        ("--noise-um", twin.MAX_NOISE_UM),
        ("--stylus-radius-mm", twin.MAX_STYLUS_RADIUS_MM),
        ("--eccentricity-um", twin.MAX_ECCENTRICITY_UM),
    ):
        code, _, err = _run(
            capsys, "simulate", "cmm", "-e", "cw06-translating", "-o", str(out), flag, "1e30"
        )
        assert code == 2 and f"{flag}=1e+30 is not allowed" in err and f"to {most:g}" in err
        assert len(err.strip().splitlines()) == 1 and not out.exists()
    code, _, err = _run(
        capsys,
        "simulate",
        "cmm",
        "-e",
        "cw06-translating",
        "-o",
        str(out),
        "--error-mean-um=-1e30",
    )
    assert code == 2 and "folds the profile over itself" in err
    assert not out.exists() and not out.with_name("s.truth.json").exists()
