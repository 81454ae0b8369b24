"""``camtol records stats``: capability, control chart and run rules of a lot; the lot report.

Two kinds of lot:

* the 30-part lot of issue 30, simulated the way tests/records/test_inspect_store.py
  simulates parts (the CMM twin: ``simulate cmm`` then ``inspect --store``), one part
  carrying a material excess so that it fails and lies beyond the control limit;
* synthetic lots written through the Python API (``make_record``): fast, with chosen
  values, for the bad inputs, the frozen limits and the subgroup charts (on SQLite and,
  with ``CAMTOL_TEST_POSTGRES_URL``, PostgreSQL).
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from scipy import stats

from camtol.cli.app import main
from camtol.records.store import Traceability, make_record, open_store

EX = "cw11-experiment"
#: The failing part of the 30-part lot: its profile carries 12 µm of material more.
BAD_SERIAL = 17


@pytest.fixture(scope="module")
def lot30(tmp_path_factory: pytest.TempPathFactory) -> str:
    """30 CMM inspections of cam B against a ±30 µm radial zone (about 40 s to build)."""
    tmp = tmp_path_factory.mktemp("lot30")
    url = str(tmp / "lot30.db")
    for serial in range(1, 31):
        scan = tmp / f"s{serial}.csv"
        twin = ["simulate", "cmm", "-e", EX, "--cam", "B", "-o", str(scan)]
        twin += ["--seed", str(serial), "--noise-um", "0.5", "--error-rms-um", "10"]
        twin += ["--points", "1440"]
        if serial == BAD_SERIAL:
            twin += ["--error-mean-um", "12"]
        assert main(twin) == 0
        insp = ["inspect", "-e", EX, "--cam", "B", "--points", str(scan)]
        insp += ["--datum", "centre:0,0,0", "--step", "1", "--tolerance-um", "-30,30"]
        insp += ["--tolerance-on", "dr", "-q", "--store", url, "--serial", str(serial)]
        assert main([*insp, "--lot", "L30"]) in (0, 1)
    return url


def _stats(capsys: pytest.CaptureFixture[str], *args: str) -> dict[str, Any]:
    capsys.readouterr()
    assert main(["records", "stats", *args, "--json"]) == 0
    return dict(json.loads(capsys.readouterr().out))


def test_thirty_part_lot(lot30: str, capsys: pytest.CaptureFixture[str]) -> None:
    doc = _stats(capsys, "--store", lot30, "--design", EX, "--cam", "B")
    assert doc["schema_version"] == "2.0" and doc["characteristic"] == "max_dev"
    with open_store(lot30) as s:
        recs = sorted(s.records(), key=lambda r: int(r.serial))
    x = np.array([r.max_dev_um for r in recs])
    n = x.size
    assert n == doc["count"] == 30
    # one-sided (upper limit only): Ppu and Cpu, no Cp/Pp spreading over a two-sided zone
    assert {"ppu", "cpu"} <= set(doc) and not {"cp", "cpk", "pp", "ppk"} & set(doc)
    ppu = (30.0 - x.mean()) / (3 * x.std(ddof=1))
    assert doc["ppu"]["value"] == pytest.approx(ppu, rel=1e-9)
    half = stats.norm.ppf(0.975) * math.sqrt(1 / (9 * n) + ppu**2 / (2 * (n - 1)))
    assert doc["ppu"]["ci95"] == pytest.approx([ppu - half, ppu + half], rel=1e-9)
    sigma_mr = np.abs(np.diff(x)).mean() / 1.128379  # d2(2) = 2/√π
    assert doc["sigma"]["within"] == pytest.approx(sigma_mr, rel=1e-5)
    assert doc["cpu"]["value"] == pytest.approx((30.0 - x.mean()) / (3 * sigma_mr), rel=1e-5)
    # the part with the material excess fails, and stands beyond the individuals' UCL
    bad = next(r for r in recs if int(r.serial) == BAD_SERIAL)
    assert bad.verdict == "fail" and bad.max_dev_um > doc["chart"]["ucl"]
    assert {"record_id": bad.id, "serial": str(BAD_SERIAL), "rule": "WE1"} in doc["out_of_control"]
    # this lot (seeds 1-30): Ppu 0.56 [0.37, 0.74], Cpu 0.53, σ 4.42 overall and 4.65
    # within: not the figures (its seeds are not known), see test_spc's Bissell test
    assert doc["ppu"]["value"] == pytest.approx(0.56, abs=0.005)
    assert doc["capable"] is False and doc["capable_at"] == 1.33
    k = sum(r.verdict == "pass" for r in recs)
    ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="exact")
    assert doc["yield"]["value"] == pytest.approx(k / n)
    assert doc["yield"]["ci95"] == pytest.approx([ci.low, ci.high])


def test_thirty_part_lot_table_plot_and_report(
    lot30: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "80")
    png, html = tmp_path / "lot.png", tmp_path / "lot.html"
    args = ["records", "stats", "--store", lot30, "--design", EX, "--cam", "B"]
    capsys.readouterr()
    assert main([*args, "--plot", str(png), "--report", str(html)]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert max(len(line) for line in lines) <= 80, max(lines, key=len)
    assert any(line.startswith("Ppu ") for line in lines)
    assert f"serial {BAD_SERIAL}" in out and "WE1" in out and "NOT capable" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    page = html.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "<script" not in page
    assert not re.search(r'(src|href)="(https?:)?//', page)  # nothing fetched
    assert 'class="control-chart"' in page and 'class="histogram"' in page
    assert "@page" in page  # printable
    # the parts, each linking to its record's row in the appendix
    for rid in range(1, 31):
        assert f'<a href="#record-{rid}">{rid}</a>' in page and f'id="record-{rid}"' in page
    # records list fits 80 columns; --wide keeps the design and part number
    capsys.readouterr()
    assert main(["records", "list", "--store", lot30]) == 0
    listed = capsys.readouterr().out.splitlines()
    assert max(len(line) for line in listed) <= 80 and listed[-1] == "30 record(s)"
    assert main(["records", "list", "--store", lot30, "--wide"]) == 0
    assert EX in capsys.readouterr().out


def _curve(max_um: float, min_um: float) -> np.ndarray[Any, np.dtype[np.float64]]:
    theta = np.arange(360) * np.pi / 180
    mid, amp = (max_um + min_um) / 2, (max_um - min_um) / 2
    return np.asarray(mid + amp * np.cos(theta))


def _synthetic(
    url: str,
    lots: dict[str, list[float]],
    *,
    judged_on: str = "dr",
    tolerance: tuple[float, float] = (-30.0, 30.0),
    spec_um: float | None = None,
) -> None:
    with open_store(url) as s:
        serial = 1 + len(s.records())
        for lot, values in lots.items():
            for v in values:
                dr = _curve(v, v - 40.0)
                rec = make_record(
                    design_name="syn",
                    design_hash="sha256:" + "1" * 64,
                    method="cmm",
                    cam="",
                    dr_um=dr,
                    verdict="pass" if v <= tolerance[1] else "fail",
                    tolerance_um=tolerance,
                    traceability=Traceability(serial=str(serial), lot=lot),
                    judged_on=judged_on,
                    max_abs_ds_um=None if spec_um is None else v / 10,
                    motion_unit=None if spec_um is None else "um",
                    options=None if spec_um is None else {"spec_um": spec_um},
                    results={"max_dn_um": v, "min_dn_um": v - 40.0, "form_dn_um": 40.0},
                )
                s.add(rec)
                serial += 1


RNG_VALUES = [float(v) for v in np.random.default_rng(5).normal(20.0, 2.0, 24)]


def test_frozen_limits_and_subgroup_charts(
    store_url: str, capsys: pytest.CaptureFixture[str]
) -> None:
    shifted = [v + 4.0 for v in RNG_VALUES[:12]]
    _synthetic(store_url, {"REF": RNG_VALUES, "NEW": shifted})
    base = ["--store", store_url, "--design", "syn", "--cam", "single"]
    ref = _stats(capsys, *base, "--lot", "REF")
    new = _stats(capsys, *base, "--lot", "NEW", "--limits-from", "REF")
    assert new["chart"]["frozen"] and not ref["chart"]["frozen"]
    for key in ("center", "lcl", "ucl", "dispersion_ucl"):
        assert new["chart"][key] == ref["chart"][key]
    # 4 µm up is 2σ: against the reference's centre line every point sits above it
    assert {o["rule"] for o in new["out_of_control"]} >= {"WE4"}
    # subgroups of 4: X̄-R by default, X̄-S on request; pooled σ within
    xr = _stats(capsys, *base, "--lot", "REF", "--subgroup", "4")
    assert xr["chart"]["kind"] == "xbar-r" and xr["sigma"]["within_method"] == "pooled subgroups"
    groups = np.array(RNG_VALUES).reshape(6, 4)
    assert xr["chart"]["dispersion_center"] == pytest.approx(np.ptp(groups, axis=1).mean())
    assert xr["sigma"]["dof_within"] == 18
    xs = _stats(capsys, *base, "--lot", "REF", "--subgroup", "4", "--chart", "xbar-s")
    assert xs["chart"]["dispersion_center"] == pytest.approx(groups.std(axis=1, ddof=1).mean())
    nelson = _stats(capsys, *base, "--lot", "NEW", "--limits-from", "REF", "--rules", "nelson")
    assert nelson["rules"] == "nelson" and {"N2"} <= {o["rule"] for o in nelson["out_of_control"]}
    # form: upper limit only, the zone's width
    form = _stats(capsys, *base, "--lot", "REF", "--characteristic", "form")
    assert form["spec"] == {"lsl": None, "usl": 60.0}
    assert form["mean"] == pytest.approx(40.0, abs=1e-4)  # float32 curves


def test_planted_western_electric_violations_through_the_command(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Each WE rule planted once in a lot charted against a hand-computed reference.

    Reference lot: 19, 21, 19, 21, ... (20 parts): centre 20 µm, every moving range 2 µm,
    σ = 2/d2(2) = 2/1.128379 = 1.772454 µm, UCL = 25.317 µm. The new lot is
    20 + z σ with the z of each pattern (µm rounded to 1e-6: far from every zone edge).
    """
    sigma = 2.0 / 1.1283791670955126
    z = (
        [0.2, 0.2, -0.2, -0.2] * 2
        + [3.5]  # part 9: WE1
        + [0.2, 0.2, -0.2, -0.2] * 2
        + [2.5, 0.1, 2.4]  # parts 18-20: WE2 at 20
        + [0.2, 0.2, -0.2, -0.2] * 2
        + [-1.5, -1.2, 0.0, -1.8, -1.1]  # parts 29-33: WE3 at 33
        + [0.2, 0.2, -0.2, -0.2] * 2
        + [0.5] * 8  # parts 42-49: WE4 at 49
        + [-0.2, -0.2]
    )
    url = str(tmp_path / "we.db")
    _synthetic(url, {"REF": [19.0, 21.0] * 10})
    _synthetic(url, {"NEW": [round(20.0 + v * sigma, 6) for v in z]})
    ref = _stats(capsys, "--store", url, "--design", "syn", "--lot", "REF")
    assert ref["chart"]["ucl"] == pytest.approx(20.0 + 3 * sigma, rel=1e-9)
    assert ref["chart"]["dispersion_ucl"] == pytest.approx(3.267 * 2.0, abs=1e-3)  # D4 MR̄
    doc = _stats(capsys, "--store", url, "--design", "syn", "--lot", "NEW", "--limits-from", "REF")
    # serials continue after the reference's 20 parts: part k of NEW is serial 20 + k
    got = [(int(o["serial"]) - 20, o["rule"]) for o in doc["out_of_control"]]
    assert got == [(9, "WE1"), (20, "WE2"), (33, "WE3"), (49, "WE4")]


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = [e for e in capsys.readouterr().err.strip().splitlines() if e]
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--lot", "NOPE"], "--lot='NOPE': no records match"),
        (["--lot", "A", "--characteristic", "max_abs_ds"], "has no measured |ΔS|"),
        (["--lot", "MIXED"], "judged on different deviations"),
        (["--lot", "A", "--subgroup", "9"], "--subgroup=9: larger than the lot (8 parts)"),
        (["--lot", "A", "--limits-from", "NOPE"], "--limits-from='NOPE': no records"),
        (["--lot", "A", "--chart", "xbar-r"], "--chart=xbar-r needs --subgroup"),
        (["--lot", "A", "--capable-at", "0"], "--capable-at=0.0"),
        (["--lot", "ONE"], "a single record"),
    ],
)
def test_bad_input_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    url = str(tmp_path / "bad.db")
    _synthetic(url, {"A": RNG_VALUES[:8], "MIXED": RNG_VALUES[:3], "ONE": [20.0]})
    _synthetic(url, {"MIXED": RNG_VALUES[3:6]}, judged_on="dn")
    capsys.readouterr()
    code = main(["records", "stats", "--store", url, "--design", "syn", *args])
    assert code == 2
    line = _one_line(capsys)
    assert message in line, line


def test_serve_refuses_a_non_local_host_without_token(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("flask", reason="camtol serve needs camtol[serve] (Flask)")
    url = str(tmp_path / "s.db")
    _synthetic(url, {"A": RNG_VALUES[:3]})
    capsys.readouterr()
    assert main(["serve", "--store", url, "--host", "0.0.0.0"]) == 2
    assert "--host='0.0.0.0': not a local address" in _one_line(capsys)
    assert main(["serve", "--store", str(tmp_path / "none.db")]) == 2
    assert "no such file" in _one_line(capsys)
