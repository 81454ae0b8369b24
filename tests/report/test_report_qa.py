"""Reports for QA (issue 13 items 12-15).

`camtol report` takes the inspection inputs of `camtol conjugate`, puts the verdict first
(terminal line and banner), exits 1 on a failing inspected part (``--no-fail``: 0), states
and applies the ISO 14253-1 decision rule (``--decision simple|guard-band``), carries
traceability fields, prints to a clean PDF and appends the radius table on request.
"""

from __future__ import annotations

import json
import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from camtol.analysis.profile import profile_points
from camtol.analysis.radius_table import radius_table
from camtol.cli.app import main
from camtol.config.design_file import load_design, load_example
from camtol.pair.decision import decide, decision_rule_text
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.indicator import write_indicator_csv
from camtol.pair.twin import simulate_record
from camtol.report.qa import PRINT_CSS

EXAMPLES_DIR = Path(__file__).parents[2] / "src/camtol/data/examples"


@cache
def _record_csv() -> Path:
    """A 10-revolution record of Δf = 10 µm with 1 µm reading noise (u_f ≈ 2.5 µm).

    At Δf = 10 µm cam B's smallest simple margin is about 1.75 µm (the band of the
    cw11-conjugate example), so the simple rule passes and the guard band (margin − u_f)
    fails: the case ISO 14253-1's rules decide differently.
    """
    import tempfile

    path = Path(tempfile.mkdtemp()) / "record.csv"
    rec = simulate_record(lambda t: np.full_like(t, 10.0), noise_um=1.0, rng=1, revolutions=10)
    write_indicator_csv(rec, path)
    return path


def _report(tmp_path: Path, *args: str) -> tuple[int, str]:
    out = tmp_path / "r.html"
    code = main(["report", *args, "-o", str(out), "--step", "0.5"])
    return code, out.read_text(encoding="utf-8") if out.exists() else ""


# ---------------------------------------------------------------------------------------
# Item 12: inspection inputs
# ---------------------------------------------------------------------------------------
def test_report_takes_inspection_inputs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, page = _report(tmp_path, "-e", "cw11-conjugate", "--df-mea", "12 um")
    assert code == 0, capsys.readouterr().err
    assert "<td>measured Δf</td><td>12 µm</td>" in page.replace("\n", "")
    assert "PASS" in page[: page.index("<h2")]
    code, page = _report(
        tmp_path, "-e", "cw11-conjugate", "--df-mea", "12 um", "--master-b", "30 um"
    )
    assert "<td>master cam B error</td><td>30 µm</td>" in page.replace("\n", "")
    code, page = _report(tmp_path, "-e", "cw11-conjugate", "--record", str(_record_csv()))
    assert code == 0 and "Indicator record: 10 revolutions" in page
    capsys.readouterr()
    # inspection inputs on a single-contact design: one line, exit 2, no file
    code, page = _report(tmp_path / "", "-e", "roller-translating", "--df-mea", "3 um")
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "conjugate" in err


# ---------------------------------------------------------------------------------------
# Item 13: verdict first, exit status
# ---------------------------------------------------------------------------------------
def test_verdict_first_and_exit_status(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # THEORY §8.3: the example's Δf_mea = 22 µm fails both cams.
    code, page = _report(tmp_path, "-e", "cw11-conjugate")
    line = capsys.readouterr().out.strip()
    assert code == 1
    assert line.startswith("FAIL: cw11-conjugate: cam A FAILS") and line.endswith("r.html")
    head = page[: page.index("<h2")]
    assert '<div class="banner fail" id="verdict"' in head and "<strong>FAIL</strong>" in head
    code, page = _report(tmp_path, "-e", "cw11-conjugate", "--no-fail")
    assert code == 0 and "<strong>FAIL</strong>" in page
    assert capsys.readouterr().out.startswith("FAIL: cw11-conjugate")
    # a design without a measurement: the design checks, never exit 1
    code, page = _report(tmp_path, "-e", "roller-translating")
    assert code == 0
    assert capsys.readouterr().out.startswith("design check PASS: roller-translating")
    assert '<div class="banner pass"' in page[: page.index("<h2")]
    assert main(["report", "-e", "cw11-conjugate", "-o", str(tmp_path / "j.html"), "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["verdict"]["status"] == "FAIL" and doc["verdict"]["inspected"] is True


# ---------------------------------------------------------------------------------------
# Item 14: decision rule (ISO 14253-1)
# ---------------------------------------------------------------------------------------
def test_guard_band_shrinks_the_acceptance_zone() -> None:
    d = load_example("cw11-conjugate")
    spec = d.inspection
    assert spec is not None
    from dataclasses import replace

    from camtol.inspection.error_functions import parse_error_function

    spec = replace(spec, df_mea=parse_error_function("10 um", field="df"))
    res = inspect_conjugate(d, spec, step_deg=0.5)
    simple = decide(res, "simple")
    assert simple == res.verdicts and all(v.passed for v in simple.values())
    u_f = np.full(res.theta_rad.shape, 2.0)
    gb = decide(res, "guard-band", u_f)
    for cam in "AB":  # the margin drops by exactly u_f
        assert gb[cam].min_margin_um == pytest.approx(simple[cam].min_margin_um - 2.0, abs=1e-9)
    assert gb["A"].passed and not gb["B"].passed  # B's simple margin ≈ 1.75 µm < 2 µm
    start, end = gb["B"].failing_intervals_deg[0]
    assert 0.0 <= start < end < 120.0
    zero = decide(res, "guard-band", np.zeros_like(u_f))  # u_f = 0: the simple rule
    for cam in "AB":
        assert zero[cam].passed == simple[cam].passed
        assert zero[cam].min_margin_um == pytest.approx(simple[cam].min_margin_um, abs=1e-9)
    with pytest.raises(ValueError, match="guard-band"):
        decide(res, "guard-band")
    with pytest.raises(ValueError, match="decision='strict'"):
        decide(res, "strict")  # type: ignore[arg-type]


@pytest.mark.parametrize("command", ["conjugate", "report"])
def test_decision_option_on_conjugate_and_report(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rec = str(_record_csv())
    base = [command, "-e", "cw11-conjugate", "--record", rec, "--step", "0.5"]
    if command == "report":
        base += ["-o", str(tmp_path / "r.html")]
    assert main([*base, "--decision", "simple"]) == 0
    out = capsys.readouterr().out
    if command == "conjugate":
        assert decision_rule_text("simple") in " ".join(out.split())  # wrapped at 80 columns
    else:
        page = (tmp_path / "r.html").read_text(encoding="utf-8")
        assert decision_rule_text("simple") in page.replace("&#x27;", "'")
    assert main([*base, "--decision", "guard-band"]) == 1
    out = capsys.readouterr().out
    if command == "conjugate":
        assert "guard band (ISO 14253-1 proof of conformance)" in out
    else:
        assert out.startswith("FAIL: cw11-conjugate") and "guard band" in out
        page = (tmp_path / "r.html").read_text(encoding="utf-8")
        assert "Δf_mea ± u_f" in page  # the rule, stated; the u_f band is in the figure
    assert main([*base, "--decision", "guard-band", "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["decision_rule"]["rule"] == "guard-band"
    # guard band without a record (no u_f): one line, exit 2
    bad = [command, "-e", "cw11-conjugate", "--decision", "guard-band"]
    if command == "report":
        bad += ["-o", str(tmp_path / "x.html")]
    assert main(bad) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--record" in err
    assert not (tmp_path / "x.html").exists()


# ---------------------------------------------------------------------------------------
# Item 15: traceability, print CSS, radius table
# ---------------------------------------------------------------------------------------
def test_traceability_from_design_and_command_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (EXAMPLES_DIR / "roller-translating.toml").read_text(encoding="utf-8")
    design = tmp_path / "d.toml"
    design.write_text(
        text + '\n[traceability]\npart_number = "PN-4711"\nrevision = "C"\ninspector = "A. B."\n',
        encoding="utf-8",
    )
    assert load_design(design).extras["traceability"] == {
        "part_number": "PN-4711",
        "revision": "C",
        "inspector": "A. B.",
    }
    code, page = _report(tmp_path, str(design), "--revision", "D", "--serial", "S-0042")
    assert code == 0
    flat = page.replace("\n", "")
    assert "<h2>Traceability</h2>" in flat
    for label, value in (
        ("part number", "PN-4711"),
        ("revision", "D"),  # the command line wins
        ("serial number", "S-0042"),
        ("inspector", "A. B."),
    ):
        assert f"<td>{label}</td><td>{value}</td>" in flat
    design.write_text(text + '\n[traceability]\npart = "x"\n', encoding="utf-8")
    assert main(["report", str(design), "-o", str(tmp_path / "y.html")]) == 2
    assert "traceability.part is not a known field" in capsys.readouterr().err


def test_print_css() -> None:
    css = PRINT_CSS.replace(" ", "")
    assert "h1,h2,h3{break-after:avoid" in css
    assert "table,figure,.banner,ul{break-inside:avoid" in css
    assert "@page{size:A4" in css


def test_radius_table_matches_the_exported_profile(tmp_path: Path) -> None:
    d = load_example("roller-translating")
    table = radius_table(d)
    assert table.polar_deg.tolist() == list(range(360))
    assert set(table.columns) == {"R_mm", "R_pitch_mm"}
    # truth: the adaptively sampled profile (vertices on the analytic curve, 0.1 µm chords)
    prof = profile_points(d).profile
    ang = np.mod(np.degrees(np.arctan2(prof.y_mm, prof.x_mm)), 360.0)
    r = np.hypot(prof.x_mm, prof.y_mm)
    o = np.argsort(ang)
    ref = np.interp(table.polar_deg, ang[o], r[o], period=360.0)
    np.testing.assert_allclose(
        table.columns["R_mm"], ref, atol=5e-4
    )  # 0.5 µm: two linear interpolations
    assert np.all(table.columns["R_pitch_mm"] - table.columns["R_mm"] > 0)
    conj = radius_table(load_example("cw11-conjugate"))
    assert {"R_A_mm", "R_B_mm", "R_pitch_A_mm", "R_pitch_B_mm"} == set(conj.columns)
    code, page = _report(tmp_path, "-e", "roller-translating", "--radius-table")
    assert code == 0
    block = page[page.index("Appendix: radius table") :]
    rows = re.findall(r"<tr><td class=\"num\">(\d+)</td>", block)
    assert rows == [str(i) for i in range(360)]
    code, page = _report(tmp_path, "-e", "roller-translating")
    assert "radius-table" not in page
