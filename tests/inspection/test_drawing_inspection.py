"""CMM inspection as a drawing reads (issue 31): ISO 1101 zones, units, traceability,
feature datums, DMIS input, registration uncertainty and the decision rule."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.contact import FourierError
from camtol.exceptions import DesignError, InputFileError
from camtol.inspection.cmm import read_scan
from camtol.inspection.deviations import cam_profile, design_zone, inspect_scan
from camtol.inspection.registration import Datum, register
from camtol.inspection.twin import scan_csv_text, simulate_scan
from camtol.inspection.zone import ZoneSpec, zone_from_width

#: Every built-in example (the files shipped in camtol/data/examples).
EXAMPLES = sorted(
    p.stem
    for p in (Path(__file__).resolve().parents[2] / "src/camtol/data/examples").glob("*.toml")
)


def _run(capsys, *args: str) -> tuple[int, str, str]:  # type: ignore[no-untyped-def]
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


# --- 1. the profile zone as on a drawing -------------------------------------------------

ROT_DEG, ECC_UM, ECC_DEG = 10.0, 200.0, 35.0


def _judged(design_name: str, error: FourierError, zone_offset: float, t_um: float, located: bool):  # type: ignore[no-untyped-def]
    d = load_example(design_name)
    sim = simulate_scan(
        d,
        points=1440,
        noise_um=0.0,
        rotation_deg=ROT_DEG,
        eccentricity_um=ECC_UM,
        eccentricity_deg=ECC_DEG,
        profile_error=error,
        error_kind="normal",
    )
    from camtol.inspection.cmm import Scan

    scan = Scan("sim", sim.x_mm, sim.y_mm, np.zeros(sim.x_mm.size, bool), np.arange(sim.x_mm.size))
    datum = (
        Datum("centre", centre_mm=(sim.truth.dx_mm, sim.truth.dy_mm), angle_deg=ROT_DEG)
        if located
        else Datum()
    )
    zone = zone_from_width(t_um, zone_offset)
    return inspect_scan(d, scan, datum=datum, zone=zone)


@pytest.mark.parametrize("located", [False, True])
@pytest.mark.parametrize(
    ("t_um", "uz_um", "how"),
    [(30.0, 0.0, "um"), (30.0, 0.0, "grade"), (40.0, 8.0, "UZ")],
)
def test_zone_within_half_t_passes_and_0_6_t_on_one_side_fails(
    t_um: float, uz_um: float, how: str, located: bool
) -> None:
    # ISO 1101: t is the zone's width, ±t/2 about the nominal (shifted by UZ). A part
    # whose true Δn stays within UZ ± 0.45 t passes; one whose Δn reaches UZ + 0.6 t on
    # one side (a uniform excess: no rigid placement removes it) fails, floating or located.
    if how == "grade":  # cw06-translating states profile_tolerance = "IT7": 30 µm there
        zone = design_zone(load_example("cw06-translating"))
        assert zone is not None and zone.width_um == pytest.approx(t_um)
        assert zone.limits_um == pytest.approx((-15.0, 15.0))
    c = 1e-3
    inside = FourierError(uz_um * c, (0.0, 0.0, 0.45 * t_um * c), ())  # UZ + 0.45 t cos 3θ
    outside = FourierError((uz_um + 0.6 * t_um) * c, (), ())
    below = FourierError((uz_um - 0.6 * t_um) * c, (), ())
    ok = _judged("cw06-translating", inside, uz_um, t_um, located)
    assert ok.passed and ok.floating is (not located)
    assert ok.zone.limits_um == pytest.approx((uz_um - t_um / 2, uz_um + t_um / 2))
    for err in (outside, below):
        bad = _judged("cw06-translating", err, uz_um, t_um, located)
        assert not bad.passed
        assert bad.excess_um == pytest.approx(0.1 * t_um, abs=0.05)


def test_a_located_bump_fails_that_a_floating_zone_may_place() -> None:
    # One bump of 0.6 t: outside the located zone; the floating zone (no datum) may move
    # the profile by 0.1 t towards it (ISO 1101 without a datum: form only).
    t = 30.0
    k = np.arange(1, 13)
    bump = 0.6 * t * 1e-3 * np.exp(-0.5 * (k / 4.0) ** 2)
    bump *= 0.6 * t * 1e-3 / (bump.sum())  # peak 0.6 t at θ = 0
    err = FourierError(0.0, tuple(bump.tolist()), ())
    located = _judged("cw06-translating", err, 0.0, t, True)
    assert not located.passed and located.excess_um > 0.05 * t
    floating = _judged("cw06-translating", err, 0.0, t, False)
    assert floating.excess_um < located.excess_um


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_built_in_example_states_its_zone(name: str) -> None:
    d = load_example(name)
    for cam in d.cams():
        zone = design_zone(d, cam.letter)  # type: ignore[arg-type]
        assert zone is not None, f"{name} cam {cam.letter}: no [inspection] profile zone"
        assert zone.on == "normal" and zone.width_um > 0
        assert zone.lower_um == pytest.approx(zone.offset_um - zone.width_um / 2)


def test_the_fixture_bands_are_not_the_cmm_zone() -> None:
    d = load_example("cw11-experiment")
    spec = d.inspection
    assert spec is not None and spec.band_um("A") == (-220.0, 220.0)  # CW11's radial band
    zone = design_zone(d, "A")
    assert zone is not None and zone.width_um == 220.0 and zone.limits_um == (-110.0, 110.0)


def _design_with(tmp_path: Path, table: str) -> Path:
    from camtol.config.design_file import example_text

    p = tmp_path / "d.toml"
    text = example_text("roller-translating")
    text = text[: text.index("[inspection]")] + table
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    ("table", "needle"),
    [
        (
            "[inspection]\nprofile_tolerance_um = 30\nlimits_um = [-10, 20]\n",
            "inspection.limits_um and inspection.profile_tolerance_um both state the zone",
        ),
        ("[inspection]\nlimits_um = [20, -10]\n", "inspection.limits_um=[20, -10] is not allowed"),
        ("[inspection]\nlimits_um = [5, 5]\n", "inspection.limits_um=[5, 5] is not allowed"),
        ("[inspection]\nprofile_offset_um = 5\n", "needs the zone width"),
        ("[inspection]\nprofile_tolerance_um = 30\nprofile_offset_um = 15\n", "|UZ| < t/2"),
        ('[inspection]\nprofile_tolerance = "IT77"\n', "inspection.profile_tolerance='IT77'"),
        ("[inspection]\nprofile_tolerance_um = -3\n", "inspection.profile_tolerance_um=-3.0"),
    ],
)
def test_bad_zone_one_line_exit_2(capsys, tmp_path: Path, table: str, needle: str) -> None:  # type: ignore[no-untyped-def]
    design = _design_with(tmp_path, table)
    code, out, err = _run(capsys, "analyze", str(design))
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err


def test_offset_and_explicit_limits(tmp_path: Path) -> None:
    from camtol.config.design_file import load_design

    d = load_design(
        _design_with(tmp_path, "[inspection]\nprofile_tolerance_um = 30\nprofile_offset_um = 5\n")
    )
    zone = design_zone(d)
    assert zone is not None and zone.limits_um == (-10.0, 20.0) and zone.offset_um == 5.0
    d = load_design(_design_with(tmp_path, "[inspection]\nlimits_um = [-4, 26]\n"))
    zone = design_zone(d)
    assert zone is not None and zone.width_um == 30.0 and zone.offset_um == 11.0
    assert ZoneSpec("k", width_um=30.0).resolve(50.0).limits_um == (-15.0, 15.0)


@pytest.fixture(scope="module")
def scan_tr(tmp_path_factory) -> Path:  # type: ignore[no-untyped-def]
    p = tmp_path_factory.mktemp("tr") / "s.csv"
    args = ["simulate", "cmm", "-e", "roller-translating", "-o", str(p), "--n-points", "1440"]
    assert main([*args, "--error-rms-um", "3", "--seed", "5", "--stylus-radius-mm", "1.5"]) == 0
    return p


def test_inspect_without_a_zone_says_so(capsys, tmp_path: Path, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    from camtol.config.design_file import example_text

    p = tmp_path / "nozone.toml"
    text = example_text("roller-translating")
    p.write_text(text[: text.index("[inspection]")])
    code, _, err = _run(capsys, "inspect", str(p), "--points", str(scan_tr))
    assert code == 2 and "states no profile zone" in err and "--tolerance-um T" in err
    code, out, _ = _run(capsys, "inspect", str(p), "--points", str(scan_tr), "--tolerance-um", "40")
    assert code == 0 and "[-20, +20] µm (t = 40 µm)" in out


@pytest.mark.parametrize(
    ("flags", "needle"),
    [
        (["--tolerance-um", "20,-20"], "--tolerance-um='20,-20' is not allowed; give LO,HI"),
        (["--tolerance-um", "0"], "give a zone width T > 0"),
        (["--decision", "guard-band"], "--decision guard-band needs the measurement uncertainty"),
        (["--part-number", "P\x07-1", "--report", "{tmp}/r.html"], "control character U+0007"),
        (["--serial", "S\n2", "--report", "{tmp}/r.html"], "control character U+000A"),
    ],
)
def test_bad_inspect_input_one_line_exit_2_nothing_written(  # type: ignore[no-untyped-def]
    capsys, tmp_path: Path, scan_tr: Path, flags: list[str], needle: str
) -> None:
    flags = [f.replace("{tmp}", str(tmp_path)) for f in flags]
    code, out, err = _run(
        capsys, "inspect", "-e", "roller-translating", "--points", str(scan_tr), *flags
    )
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
    assert out == "" and not (tmp_path / "r.html").exists()


# --- 4. readable verdicts ---------------------------------------------------------------


def test_failing_angles_are_merged_into_stretches(capsys, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    args = ["inspect", "-e", "roller-translating", "--points", str(scan_tr)]
    code, out, _ = _run(
        capsys, *args, "--tolerance-um", "-2,2", "--datum", "centre:0,0,0", "--json"
    )
    data = json.loads(out)
    assert code == 1 and data["profile_verdict"] == "fail"
    exact, merged = data["failing_intervals_deg"], data["failing_stretches_deg"]
    assert 0 < len(merged) < len(exact)
    gaps = [b[0] - a[1] for a, b in zip(merged, merged[1:], strict=False)]
    assert all(g >= 1.0 for g in gaps)  # stretches closer than 1° are one (as conjugate)
    code, out, _ = _run(capsys, *args, "--tolerance-um", "-2,2", "--datum", "centre:0,0,0")
    assert max(len(line) for line in out.splitlines()) <= 80


def test_the_scan_header_gives_the_stylus_radius(capsys, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    args = ["inspect", "-e", "roller-translating", "--points", str(scan_tr), "--json"]
    code, out, err = _run(capsys, *args)
    data = json.loads(out)
    assert code == 0 and data["stylus_radius_mm"] == 1.5
    assert data["stylus_radius_source"] == "header"
    code, _, err = _run(capsys, *args, "--stylus-radius-mm", "0")
    assert code == 2 and "the header says stylus 1.5 mm: give --stylus-radius-mm 1.5" in err


def test_storing_a_720_point_scan_does_not_depend_on_step(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    scan = tmp_path / "s.csv"
    sim = ["simulate", "cmm", "-e", "roller-translating", "-o", str(scan), "--n-points", "720"]
    assert _run(capsys, *sim)[0] == 0
    store = tmp_path / "r.db"
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "roller-translating",
        "--points",
        str(scan),
        "--store",
        str(store),
        "-q",
    )
    assert code == 0, err
    from camtol.records.store import open_store

    with open_store(str(store), create=False, readonly=True) as s:
        rec = s.get(1)
    assert rec.n_points == 1800  # the finest grid whose 5 steps (1°) cover the 0.5° spacing


# --- 2. one unit per quantity ---------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "unit", "other"),
    [("roller-translating", "um", "deg"), ("roller-oscillating", "deg", "um")],
)
def test_units_inspect_store_show_report(
    capsys, tmp_path: Path, name: str, unit: str, other: str
) -> None:  # type: ignore[no-untyped-def]
    scan, store, report, motion = (tmp_path / n for n in ("s.csv", "r.db", "r.html", "m.csv"))
    sim = ["simulate", "cmm", "-e", name, "-o", str(scan), "--error-rms-um", "4"]
    assert _run(capsys, *sim, "--n-points", "1440")[0] == 0
    base = ["inspect", "-e", name, "--points", str(scan), "--serial", "S-1", "--part-number", "P-9"]
    code, out, err = _run(
        capsys,
        *base,
        "--store",
        str(store),
        "--report",
        str(report),
        "--motion",
        str(motion),
        "--json",
    )
    assert code == 0, err
    m = json.loads(out)["motion"]
    value = m[f"max_abs_ds_{unit}"]
    assert m["unit"] == unit and f"max_abs_ds_{other}" not in m
    # terminal
    code, text, _ = _run(capsys, *base)
    sym = "°" if unit == "deg" else " µm"
    assert f"max |ΔS| {value:.4g}{sym} exact" in " ".join(text.split())
    # CSV
    head = [ln for ln in motion.read_text().splitlines() if not ln.startswith("#")][0]
    assert head == f"theta_deg,dS_measured_{unit},dS_linear_{unit}"
    # store and records show
    code, out, _ = _run(capsys, "records", "show", "1", "--store", str(store), "--json")
    shown = json.loads(out)
    assert shown[f"max_abs_ds_{unit}"] == pytest.approx(value, rel=1e-9)
    assert shown[f"max_abs_ds_{other}"] is None and shown["motion_unit"] == unit
    code, out, _ = _run(capsys, "records", "show", "1", "--store", str(store))
    assert f"max_abs_ds_{unit}" in out
    # HTML report: the figure's axis and the summary carry the same unit
    html = report.read_text()
    assert f"{value:.4g}{sym}" in html
    axis = "follower error ΔS [deg]" if unit == "deg" else "follower error ΔS [µm]"
    assert axis in html and "arcsec" not in html
    for text in ("P-9", "S-1", "camtol version", "design hash", "scan SHA-256"):
        assert text in html


# --- 3. traceability --------------------------------------------------------------------


def test_part_report_is_traceable_without_a_store(capsys, tmp_path: Path, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    import hashlib

    report = tmp_path / "r.html"
    flags = ["--part-number", "CAM-7", "--drawing-number", "D-100", "--revision", "C"]
    flags += ["--serial", "0042", "--inspector", "QA", "--instrument", "CMM-3"]
    flags += ["--date", "2026-11-27T10:00:00+00:00"]
    code, out, err = _run(
        capsys,
        "inspect",
        "-e",
        "roller-translating",
        "--points",
        str(scan_tr),
        *flags,
        "--report",
        str(report),
        "--json",
    )
    assert code == 0, err
    trace = json.loads(out)["traceability"]
    digest = "sha256:" + hashlib.sha256(scan_tr.read_bytes()).hexdigest()
    assert trace["scan_sha256"] == digest and trace["part_number"] == "CAM-7"
    assert trace["design_hash"] == "sha256:" + load_example("roller-translating").content_hash
    html = report.read_text()
    for text in (
        "CAM-7",
        "D-100",
        "0042",
        "2026-11-27T10:00:00+00:00",
        digest,
        trace["camtol_version"],
    ):
        assert text in html


def test_old_flag_names_warn(capsys, tmp_path: Path, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    store = tmp_path / "r.db"
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "roller-translating",
        "--points",
        str(scan_tr),
        "--store",
        str(store),
        "--part",
        "P-1",
        "--inspected-at",
        "2026-11-27T10:00:00+00:00",
        "-q",
    )
    assert code == 0 and "--part is renamed --part-number" in err
    assert "--inspected-at is renamed --date" in err
    from camtol.records.store import open_store

    with open_store(str(store), create=False, readonly=True) as s:
        rec = s.get(1)
    assert rec.part_number == "P-1" and rec.inspected_at.hour == 10
    out = tmp_path / "s.csv"
    code, _, err = _run(
        capsys, "simulate", "cmm", "-e", "roller-translating", "-o", str(out), "--points", "720"
    )
    assert code == 0 and "--points is renamed --n-points" in err and "(720 points)" in _


# --- 6. registration uncertainty and the feature datum ---------------------------------


def test_registration_u95_covers_the_true_placement() -> None:
    # 200 seeded scans of cw06-translating (720 points) with a random profile error
    # (harmonics 2-20, amplitudes ∝ 1/k, 2-10 µm rms), probe noise 1 µm and a random
    # placement. The reported 95 % expanded uncertainty of the rotation and of each
    # translation must cover the true placement error in ≥ 92 % of the cases (a correct
    # 95 % interval: 190 ± 3 expected). The scans are built at once (vectorised), only
    # the registrations run one by one.
    d = load_example("cw06-translating")
    prof = cam_profile(d)
    n_case, n_pt = 200, 720
    rng = np.random.default_rng(20261127)
    t = np.linspace(0.0, 2 * math.pi, n_pt, endpoint=False)
    x, y, dx, dy, *_ = prof.table.evaluate(t)
    speed = np.hypot(dx, dy)
    nx, ny = dy / speed, -dx / speed
    k = np.arange(2, 21)
    a = rng.normal(size=(n_case, k.size)) / k
    b = rng.normal(size=(n_case, k.size)) / k
    amp = rng.uniform(2.0, 10.0, n_case) * 1e-3 / np.sqrt(0.5 * np.sum(a * a + b * b, axis=1))
    err = amp[:, None] * (a @ np.cos(np.outer(k, t)) + b @ np.sin(np.outer(k, t)))
    dn = err + rng.normal(0.0, 1e-3, (n_case, n_pt))
    px, py = x + dn * nx, y + dn * ny
    rot = rng.uniform(-math.pi, math.pi, n_case)
    ecc, ecc_dir = rng.uniform(0.0, 0.5, n_case), rng.uniform(0.0, 2 * math.pi, n_case)
    tx, ty = ecc * np.cos(ecc_dir), ecc * np.sin(ecc_dir)
    c, s = np.cos(rot)[:, None], np.sin(rot)[:, None]
    mx, my = c * px - s * py + tx[:, None], s * px + c * py + ty[:, None]
    covered = np.zeros((n_case, 3), dtype=bool)
    random_only = np.zeros(n_case, dtype=bool)
    for i in range(n_case):
        reg = register(prof.table, mx[i], my[i], Datum())
        e = np.abs(
            [
                math.remainder(reg.rotation_deg - math.degrees(rot[i]), 360.0),
                reg.dx_mm - tx[i],
                reg.dy_mm - ty[i],
            ]
        )
        covered[i] = e <= np.asarray(reg.expanded_95)
        random_only[i] = e[0] <= 2.0 * reg.u_rotation_deg
    assert np.all(covered.mean(axis=0) >= 0.92), covered.mean(axis=0)
    assert random_only.mean() < 0.8  # the random part alone does not cover (why u_form)


def test_feature_datum_bore_and_keyway_end_to_end(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    scan = tmp_path / "kw.csv"
    args = ["simulate", "cmm", "-e", "cw06-translating", "-o", str(scan), "--bore-points", "90"]
    args += ["--keyway", "30", "--rotation-deg", "25", "--eccentricity-um", "300"]
    args += ["--stylus-radius-mm", "1", "--error-rms-um", "5", "--seed", "2"]
    assert _run(capsys, *args)[0] == 0
    truth = json.loads(scan.with_name("kw.truth.json").read_text())
    assert truth["bore_points"] == 90 and truth["keyway_deg"] == 30
    code, out, err = _run(
        capsys,
        "inspect",
        "-e",
        "cw06-translating",
        "--points",
        str(scan),
        "--datum",
        "bore",
        "--keyway-deg",
        "30",
        "--json",
    )
    assert code in (0, 1), err
    data = json.loads(out)
    reg, place = data["registration"], truth["placement"]
    assert data["zone"]["placement"] == "located" and reg["fitted"] == []
    # keyway point 1 µm noise at ~ 20 mm: the angle within 0.01°; bore centre (90 points)
    assert reg["rotation_deg"] == pytest.approx(place["rotation_deg"], abs=0.01)
    assert reg["dx_mm"] == pytest.approx(place["dx_mm"], abs=1e-3)
    assert reg["dy_mm"] == pytest.approx(place["dy_mm"], abs=1e-3)
    code, _, err = _run(
        capsys,
        "inspect",
        "-e",
        "cw06-translating",
        "--points",
        str(scan),
        "--datum",
        "fit",
        "--keyway-deg",
        "30",
    )
    assert code == 2 and "goes with --datum bore or centre" in err


# --- 7. decision rule -------------------------------------------------------------------


def test_guard_band_shrinks_the_zone_by_u(capsys, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    base = ["inspect", "-e", "roller-translating", "--points", str(scan_tr), "--json"]
    code, out, _ = _run(capsys, *base)
    simple = json.loads(out)
    assert code == 0 and simple["decision"]["rule"] == "simple"
    excess = simple["zone"]["excess_um"]  # < 0: the margin to the zone
    assert excess < 0
    u = 1.5 * -excess  # a CMM uncertainty larger than the margin: the guard band fails it
    code, out, _ = _run(capsys, *base, "--decision", "guard-band", "--u-cmm-um", f"{u!r}")
    guarded = json.loads(out)
    lo, hi = guarded["decision"]["acceptance_um"]
    assert (lo, hi) == pytest.approx((-15.0 + u, 15.0 - u))
    assert code == 1 and guarded["profile_verdict"] == "fail"
    code, out, _ = _run(
        capsys, *base, "--decision", "guard-band", "--u-cmm-um", f"{0.5 * -excess!r}"
    )
    assert code == 0 and json.loads(out)["profile_verdict"] == "pass"


# --- 8. DMIS input ----------------------------------------------------------------------


def _dmis_text(x_mm: np.ndarray, y_mm: np.ndarray, *, unit: str = "MM", scale: float = 1.0) -> str:
    """DMIS output from the grammar (ANSI/DMIS 105.2 part 1, §6 output format)."""
    lines = [
        "$$ DMIS output written for the test from the standard's grammar",
        "DMISMN/'camtol test',05.2",
        f"UNITS/{unit},ANGDEC",
        "FILNAM/'cam scan',05.2",
    ]
    for i, (x, y) in enumerate(zip(x_mm.tolist(), y_mm.tolist(), strict=True)):
        lines.append(f"F(P{i})=FEAT/POINT,CART,{x / scale:.9f},{y / scale:.9f},0,0,0,1")
        if i % 7 == 3:  # a statement continued over two lines
            lines.append(f"FA(P{i})=FEAT/POINT,CART,{x / scale:.9f},$")
            lines.append(f"{y / scale:.9f},0.0,0,0,1")
        else:
            lines.append(f"FA(P{i})=FEAT/POINT,CART,{x / scale:.9f},{y / scale:.9f},0.0,0,0,1")
    lines.append("ENDFIL")
    return "\n".join(lines) + "\n"


def test_dmis_and_csv_give_identical_results(capsys, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    d = load_example("roller-oscillating")
    from camtol.inspection.twin import random_profile_error

    sim = simulate_scan(
        d,
        points=1440,
        noise_um=1.0,
        seed=4,
        rotation_deg=12.0,
        profile_error=random_profile_error(3.0, seed=4),
    )
    csv_path, mm, inch = tmp_path / "s.csv", tmp_path / "s.dmi", tmp_path / "s_in.dmo"
    csv_path.write_text(scan_csv_text(sim))
    x = np.array([float(f"{v:.9f}") for v in sim.x_mm])
    y = np.array([float(f"{v:.9f}") for v in sim.y_mm])
    mm.write_text(_dmis_text(x, y))
    inch.write_text(_dmis_text(x, y, unit="INCH", scale=25.4))
    a, b = read_scan(csv_path), read_scan(mm)
    assert np.array_equal(a.x_mm, b.x_mm) and np.array_equal(a.y_mm, b.y_mm)
    outs = []
    for path in (csv_path, mm):
        code, out, err = _run(
            capsys, "inspect", "-e", "roller-oscillating", "--points", str(path), "--json"
        )
        assert code == 0, err
        data = json.loads(out)
        data.pop("scan"), data.pop("traceability"), data.pop("camtol_version")
        outs.append(data)
    assert outs[0] == outs[1]
    c = read_scan(inch)  # inches: the same points to the 9 digits written
    assert np.max(np.abs(c.x_mm - a.x_mm)) < 25.4e-9


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("UNITS/MM,ANGDEC\nF(P1)=FEAT/POINT,CART,1,2,3,0,0,1\n", "no measured point"),
        (
            "UNITS/FURLONG,ANGDEC\nFA(P1)=FEAT/POINT,CART,1,2,3,0,0,1\n",
            "UNITS/FURLONG is not a known",
        ),
        ("FA(P1)=FEAT/POINT,CART,1,2,3,0,0,1\n", "a point before any UNITS statement"),
        ("UNITS/MM,ANGDEC\nFA(P1)=FEAT/POINT,POL,1,2,3,0,0,1\n", "is not a measured point"),
    ],
)
def test_bad_dmis_one_line_exit_2_nothing_written(
    capsys, tmp_path: Path, text: str, needle: str
) -> None:  # type: ignore[no-untyped-def]
    p = tmp_path / "bad.dmi"
    p.write_text(text)
    with pytest.raises(InputFileError, match="bad.dmi"):
        read_scan(p)
    report = tmp_path / "r.html"
    code, out, err = _run(
        capsys, "inspect", "-e", "roller-translating", "--points", str(p), "--report", str(report)
    )
    assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
    assert not report.exists()


def test_zone_bad_values_in_python() -> None:
    with pytest.raises(DesignError, match="lower < upper"):
        from camtol.inspection.zone import zone_from_limits

        zone_from_limits(3.0, 3.0)
    with pytest.raises(DesignError, match="guard band"):
        zone_from_width(10.0).with_guard_band(6.0)


def test_report_takes_a_single_cams_scan(capsys, tmp_path: Path, scan_tr: Path) -> None:  # type: ignore[no-untyped-def]
    out_html = tmp_path / "r.html"
    code, out, err = _run(
        capsys,
        "report",
        "-e",
        "roller-translating",
        "-o",
        str(out_html),
        "--cmm",
        str(scan_tr),
        "--part-number",
        "CAM-7",
        "--date",
        "2026-11-27",
    )
    assert code == 0, err
    html = out_html.read_text()
    assert "CMM inspection of cam A" in html and "CAM-7" in html and "scan SHA-256" in html
    assert "PASS" in out and "zone [-15, +15] µm (t = 30" in " ".join(out.split())
    code, _, err = _run(
        capsys,
        "report",
        "-e",
        "roller-translating",
        "-o",
        str(out_html),
        "--cmm",
        str(scan_tr),
        "--decision",
        "guard-band",
        "--u-cmm-um",
        "14",  # 2U = 28 of 30 µm: the scan fails
    )
    assert code == 1, err
    bad = tmp_path / "bad.html"
    for args, needle in (
        (
            ["-e", "roller-translating", "--cmm-a", str(scan_tr)],
            "--cmm-a is a scan of a conjugate pair's cam",
        ),
        (["-e", "cw11-conjugate", "--cmm", str(scan_tr)], "--cmm is a single cam's scan"),
        (
            ["-e", "roller-translating", "--cmm", str(scan_tr), "--serial", "a\tb"],
            "control character",
        ),
    ):
        code, _, err = _run(capsys, "report", *args, "-o", str(bad))
        assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
        assert not bad.exists()
