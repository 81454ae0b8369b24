"""CW11 (THEORY §8.3, §8.4): conjugate cams, fixture inverse analysis and acceptance.

THEORY does not list the chapter's published extremes; the checks here are the
hand-checkable invariants of §8.3 (maximum radial dimensions), closed-form values on the
base-circle dwell computed by hand from triangle O2-O3-roller, the round trip of the
inverse analysis, and the command line's contract. The extremes camtol obtains are
reported to the lead for comparison with the paper.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.analysis.kinematics import analysis_grid
from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.mechanisms.conjugate import ConjugatePair
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.kinematics import conjugate_kinematics
from camtol.pair.variation import conjugate_factors, conjugate_variation


@pytest.fixture(scope="module")
def design():  # type: ignore[no-untyped-def]
    return load_example("cw11-conjugate")


def test_max_radial_dimensions(design) -> None:  # type: ignore[no-untyped-def]
    # THEORY §8.3 prints 93.793 mm (A) and 93.859 mm (B): agree within one unit of the
    # last printed digit (0.001 mm).
    theta, left = analysis_grid(0.01, design.program.boundaries_rad)
    k = conjugate_kinematics(design, theta, left_limit=left)
    assert k.a.radius_mm.max() == pytest.approx(93.793, abs=1e-3)
    assert k.b.radius_mm.max() == pytest.approx(93.859, abs=1e-3)
    assert k.a.radius_mm.min() == pytest.approx(60.0, abs=1e-9)  # r_b of cam A


def test_base_circle_dwell_by_hand(design) -> None:  # type: ignore[no-untyped-def]
    # On the dwell 280-360° V = 0, so Q = O2, λ = 0 and the triangles O2-O3-C and O2-O3-D
    # give every angle by the law of cosines: φ = (angle at the roller) − 90°,
    # α = angle at O2.
    pair = design.mechanism
    assert isinstance(pair, ConjugatePair)
    f, la, lb, rp = 120.0, 66.0, 66.0, 76.0
    xi0 = math.acos((la**2 + f**2 - rp**2) / (2 * la * f))
    gam_b = math.radians(100.0) - xi0
    rd = math.sqrt(lb**2 + f**2 - 2 * lb * f * math.cos(gam_b))  # |O2D|
    ang_c = math.acos((la**2 + rp**2 - f**2) / (2 * la * rp))
    ang_d = math.acos((lb**2 + rd**2 - f**2) / (2 * lb * rd))
    phi_a, phi_b = ang_c - math.pi / 2, ang_d - math.pi / 2
    alpha_a = math.pi - xi0 - ang_c
    alpha_b = math.pi - gam_b - ang_d
    fac = conjugate_factors(design, np.radians([300.0, 340.0]))
    assert fac.pressure_a_rad == pytest.approx(phi_a, abs=1e-12)
    assert fac.pressure_b_rad == pytest.approx(phi_b, abs=1e-12)
    assert fac.centre_line_a_rad == pytest.approx(alpha_a, abs=1e-12)
    assert fac.centre_line_b_rad == pytest.approx(alpha_b, abs=1e-12)
    assert fac.shift_a_rad == pytest.approx(0.0, abs=1e-12)
    # cam A on its base circle puts arm D at its widest, so |O2D| − r_D is cam B's largest
    # radial dimension: THEORY §8.3's 93.859 mm, by hand.
    assert rd - 16.0 == pytest.approx(93.859, abs=1e-3)
    d = la * math.cos(phi_a) * math.cos(alpha_b) + lb * math.cos(phi_b) * math.cos(alpha_a)
    spec = design.inspection
    v = conjugate_variation(fac, 0.0, 0.0, spec.errors)
    want_rf = (11 * lb * math.cos(phi_b) + 11 * la * math.cos(phi_a)) / d
    want_l = (
        19 * lb * math.cos(phi_b) * math.sin(phi_a) + 19 * la * math.cos(phi_a) * math.sin(phi_b)
    ) / d
    want_eta = -math.radians(0.022) * 1e3 * la * lb * math.cos(phi_a) * math.cos(phi_b) / d
    assert v.df_rf_um == pytest.approx(want_rf, rel=1e-12)
    assert v.df_l_um == pytest.approx(want_l, rel=1e-12)
    assert v.df_eta_um == pytest.approx(want_eta, rel=1e-12)


def test_simulated_example_inverse_and_verdicts(design) -> None:  # type: ignore[no-untyped-def]
    spec = design.inspection
    res = inspect_conjugate(design, spec, step_deg=0.1)
    est = res.estimate
    assert est is not None
    # eq. 19: Δf_r = Δf_mea − (Δf_rf + Δf_l + Δf_η), so Δf_est reproduces Δf_mea = 22 µm
    np.testing.assert_allclose(res.variation.df_est_um, 22.0, atol=1e-12)
    # put back: forward with Δr_A,est and master B returns the measurement
    back = conjugate_variation(res.factors, est.dr_a_est_um, spec.master_b, spec.errors)
    np.testing.assert_allclose(back.df_est_um, 22.0, atol=1e-9)
    # both inspected cams exceed +22 µm somewhere on the return (the master cams' errors
    # are near +20 µm and the measured Δf is high), so both fail there and pass elsewhere
    for cam, dr in (("A", est.dr_a_est_um), ("B", est.dr_b_est_um)):
        v = res.verdicts[cam]
        assert not v.passed and len(v.failing_intervals_deg) >= 1
        fails = dr > 22.0
        th = np.degrees(res.theta_rad)
        for a, b in v.failing_intervals_deg:
            inside = (th > a + 0.01) & (th < b - 0.01)
            assert np.all(fails[inside])
        assert res.passed is False


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_conjugate_json_and_curves(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    curves = tmp_path / "c.csv"
    code, out, err = _run(
        ["conjugate", "--example", "cw11-conjugate", "--json", "--curves", str(curves)], capsys
    )
    assert code == 1, err  # an inspected cam fails
    data = json.loads(out)
    for cam in ("A", "B"):
        v = data["verdicts"][cam]
        assert v["passed"] is False and v["failing_intervals_deg"]
    for key in (
        "dr_A_est_um",
        "dr_B_est_um",
        "df_A_upper_um",
        "df_A_lower_um",
        "df_B_upper_um",
        "df_B_lower_um",
        "df_rf_um",
        "df_l_um",
        "df_eta_um",
    ):
        assert {"min", "min_at_deg", "max", "max_at_deg"} <= set(data["extremes"][key])
    with curves.open() as fh:
        header = next(csv.reader(fh))
    for col in (
        "theta_deg",
        "df_r_um",
        "df_rf_um",
        "df_l_um",
        "df_eta_um",
        "dr_A_est_um",
        "dr_B_est_um",
        "df_A_upper_um",
        "df_A_lower_um",
        "df_B_upper_um",
        "df_B_lower_um",
    ):
        assert col in header


def test_cli_conjugate_overrides_and_pass(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(["conjugate", "--example", "cw11-conjugate", "--df-mea", "15 um"], capsys)
    assert code == 0, err
    assert "cam A: PASS" in out and "cam B: PASS" in out
    code, out, err = _run(
        ["conjugate", "--example", "cw11-conjugate", "--df-mea", "0.1 furlong"], capsys
    )
    assert code == 2 and "--df-mea" in err and len(err.strip().splitlines()) == 1


def test_cli_experiment_without_record(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(["conjugate", "--example", "cw11-experiment"], capsys)
    assert code == 0, err
    assert "no verdict" in out


def test_cli_conjugate_needs_conjugate_design(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(["conjugate", "--example", "cw06-translating"], capsys)
    assert code == 2 and "conjugate" in err


def test_cli_analyze_conjugate_writes_both_profiles(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    curves = tmp_path / "a.csv"
    code, out, err = _run(
        ["analyze", "--example", "cw11-conjugate", "--json", "--curves", str(curves)], capsys
    )
    assert code == 0, err
    data = json.loads(out)
    assert [c["cam"] for c in data["cams"]] == ["A", "B"]
    assert data["cams"][1]["max_radius_mm"] == pytest.approx(93.859, abs=1e-3)
    with curves.open() as fh:
        header = next(csv.reader(fh))
    for col in (
        "xA_mm",
        "yA_mm",
        "xB_mm",
        "yB_mm",
        "pressure_angle_A_deg",
        "pressure_angle_B_deg",
        "shift_angle_A_deg",
        "shift_angle_B_deg",
    ):
        assert col in header


def test_cli_experiment_with_a_csv_record(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A record made by the forward model of the built fixture (§8.4 constants) with cam A
    # off by 100 sin θ µm and a perfect master B: the estimate recovers cam A's error, and
    # both cams pass their ±220 µm bands.
    d = load_example("cw11-experiment")
    spec = d.inspection
    th = np.radians(np.arange(0.0, 360.0, 0.1))
    fac = conjugate_factors(d, th)
    dra = 100 * np.sin(th)
    rec_um = conjugate_variation(fac, dra, 0.0, spec.errors).df_est_um
    assert np.mean(rec_um) < -150  # the follower's errors shift Δf (mostly Δη = 0.275°)
    rec = tmp_path / "df.csv"
    rec.write_text(
        "theta_deg,um\n"
        + "".join(f"{t:.1f},{v:.9f}\n" for t, v in zip(np.degrees(th), rec_um, strict=True))
    )
    curves = tmp_path / "c.csv"
    code, out, err = _run(
        [
            "conjugate",
            "--example",
            "cw11-experiment",
            "--df-mea",
            str(rec),
            "--json",
            "--curves",
            str(curves),
        ],
        capsys,
    )
    assert code == 0, err
    data = json.loads(out)
    assert data["passed"] is True
    assert data["inputs"]["deta_deg"] == pytest.approx(0.275)
    rows = np.genfromtxt(curves, delimiter=",", names=True)
    np.testing.assert_allclose(
        rows["dr_A_est_um"], 100 * np.sin(np.radians(rows["theta_deg"])), atol=1e-6
    )


def test_cli_conjugate_plot(tmp_path: Path) -> None:
    from camtol.cli.app import main

    out = tmp_path / "fixture.png"
    assert main(["conjugate", "-e", "cw11-conjugate", "--plot", str(out), "-q"]) == 1
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = tmp_path / "fixture.gif"
    assert main(["conjugate", "-e", "cw11-conjugate", "--plot", str(bad), "-q"]) == 2
    assert not bad.exists()


def test_analyze_terminal_shows_both_cams(capsys: pytest.CaptureFixture[str]) -> None:
    from camtol.cli.app import main

    assert main(["analyze", "-e", "cw11-conjugate", "--step", "0.5"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    # THEORY §8.3: maximum radial dimensions 93.793 mm (A) and 93.859 mm (B)
    assert "cam A max radial dimension 93.79" in out
    assert "cam B max radial dimension 93.859" in out
    assert "cam B pressure angle" in out
