"""``camtol inspect --store``: CMM inspections recorded in the store, and their lot statistics.

Scans come from the digital twin (``camtol simulate cmm``) with the truth beside them. Each
test runs on SQLite and, when ``CAMTOL_TEST_POSTGRES_URL`` is set, on PostgreSQL
(tests/records/conftest.py).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.config.examples import example_text
from camtol.inspection.cmm import read_scan
from camtol.inspection.deviations import inspect_scan
from camtol.inspection.registration import Datum
from camtol.inspection.twin import error_from_truth
from camtol.records.lots import MAX_GAP_STEPS, deviation_on_grid, scan_on_grid
from camtol.records.store import design_identity, open_store

EX = "cw11-experiment"
NOISE_UM = 0.5
#: The twin places the cam at the CMM origin, unrotated: registering on that stated datum
#: leaves the probe noise as the only difference between the scan and the truth.
TRUE_DATUM = "centre:0,0,0"


def _scan(tmp: Path, name: str, seed: int, *extra: str, example: str = EX) -> Path:
    path = tmp / name
    args = ["simulate", "cmm", "-e", example, "-o", str(path), "--seed", str(seed)]
    assert main([*args, "--noise-um", str(NOISE_UM), "--error-rms-um", "5", *extra]) == 0
    return path


def _inspect(scan: Path, url: str, *extra: str, example: str = EX, cam: str = "B") -> int:
    args = ["inspect", "-e", example, "--points", str(scan), "--datum", TRUE_DATUM]
    if example == EX:
        args += ["--cam", cam]
    return main([*args, "--store", url, *extra])


def _count(url: str) -> int:
    with open_store(url) as s:
        return len(s.records())


def _truth_on_grid(scan: Path, n: int) -> np.ndarray[Any, np.dtype[np.float64]]:
    """The twin's radial error Δr at the measured points' polar angles, on the record grid."""
    err, kind = error_from_truth(json.loads(scan.with_suffix(".truth.json").read_text()))
    assert kind == "radial"
    insp = inspect_scan(
        load_example(EX),
        read_scan(str(scan), cam="B"),
        cam="B",
        datum=Datum(mode="centre", centre_mm=(0.0, 0.0), angle_deg=0.0),
    )
    t = insp.param_rad[insp.kept]
    k = np.arange(1, len(err.cos_mm) + 1)
    truth_um = 1e3 * (
        err.mean_mm + np.cos(np.outer(t, k)) @ err.cos_mm + np.sin(np.outer(t, k)) @ err.sin_mm
    )
    return deviation_on_grid(insp.theta_deg[insp.kept], truth_um, n)


def test_inspect_store_records_the_cmm_inspection(
    store_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scan = _scan(tmp_path, "b.csv", 2, "--cam", "B")
    capsys.readouterr()
    trace = ["--serial", "7", "--lot", "L1", "--part-number", "CAM-B", "--inspector", "ana"]
    trace += ["--instrument", "cmm-1", "--date", "2026-11-23T08:00:00Z"]
    code = _inspect(scan, store_url, *trace, "--json", "--spec-deg", "0.05")
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert code == (0 if out["verdict"] == "pass" else 1)
    assert "recorded as id 1" in captured.err  # stderr with --json: stdout stays JSON
    assert out["record_ids"] == [1]  # a script can link the JSON to the stored record

    with open_store(store_url) as s:
        (rec,) = s.records(with_curves=True)
    assert (rec.method, rec.cam, rec.verdict) == ("cmm", "B", out["verdict"])
    assert rec.tolerance_um == tuple(out["tolerance_um"])
    assert (rec.serial, rec.lot, rec.part_number, rec.inspector, rec.instrument) == (
        "7", "L1", "CAM-B", "ana", "cmm-1",
    )  # fmt: skip
    assert rec.inspected_at.isoformat() == "2026-11-23T08:00:00+00:00"
    assert (rec.design_name, rec.design_hash) == design_identity(load_example(EX), example_text(EX))
    # cam B swings its follower: max |ΔS| of the measured motion in degrees, in its own
    # column (issue 31: schema version 3; it was µrad under max_abs_ds_um)
    assert out["motion"]["unit"] == "deg" and rec.motion_unit == "deg"
    assert rec.max_abs_ds_deg == pytest.approx(out["motion"]["max_abs_ds_deg"], rel=1e-9)
    assert rec.max_abs_ds_um is None
    # the curve: Δr on the record grid (a 0.1° scan: 3600 points) against the truth. With
    # the true datum only the probe noise (σ = 0.5 µm along the normal) separates them;
    # a grid value interpolates two noisy neighbours, so its error has σ ≤ 0.5 µm:
    # rms ≤ 1.5 σ and max ≤ 6 σ over 3600 values (float32 storage: < 1e-5 µm).
    assert rec.n_points == 3600
    diff = rec.dr_um - _truth_on_grid(scan, 3600)
    assert float(np.sqrt(np.mean(diff**2))) <= 1.5 * NOISE_UM
    assert float(np.max(np.abs(diff))) <= 6 * NOISE_UM
    # and the stored curve really carries the 5 µm rms profile error, not a flat line
    assert float(np.std(rec.dr_um)) == pytest.approx(5.0, rel=0.2)


def test_single_translating_cam_records_cam_blank_and_um(
    store_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    ex = "roller-translating"
    scan = _scan(tmp_path, "a.csv", 4, example=ex)
    capsys.readouterr()
    code = _inspect(scan, store_url, "--step", "0.5", "--json", example=ex)
    out = json.loads(capsys.readouterr().out)
    assert code in (0, 1)
    with open_store(store_url) as s:
        (rec,) = s.records()
    # the record grid does not depend on --step (issue 31): the scan's 0.1° spacing
    assert rec.cam == "" and rec.method == "cmm" and rec.n_points == 3600
    assert rec.verdict == out["verdict"] and rec.tolerance_um == tuple(out["tolerance_um"])
    assert out["motion"]["unit"] == "um"  # a lift: max |ΔS| in µm, as the JSON prints it
    assert rec.max_abs_ds_um == pytest.approx(out["motion"]["max_abs_ds_um"], rel=1e-9)


def test_stats_over_stored_cmm_inspections(
    store_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    for serial in (1, 2, 3):
        scan = _scan(tmp_path, f"b{serial}.csv", 10 + serial, "--cam", "B")
        assert _inspect(scan, store_url, "--serial", str(serial), "--lot", "L1", "-q") in (0, 1)
    capsys.readouterr()
    curves = tmp_path / "lot.csv"
    args = ["records", "stats", "--store", store_url, "--design", EX, "--cam", "B"]
    assert main([*args, "--json", "--curves", str(curves)]) == 0
    st = json.loads(capsys.readouterr().out)
    assert st["command"] == "records stats" and st["methods"] == ["cmm"]
    assert st["n_parts"] == 3 and st["record_ids"] == [1, 2, 3]
    assert st["n_points"] == 3600 and st["record_n_points"] == [3600]
    with open_store(store_url) as s:
        recs = s.records(with_curves=True)
    table = np.vstack([r.dr_um for r in recs]).astype(np.float64)
    assert st["envelope_max_um"] == pytest.approx(float(table.max()), rel=1e-9)
    assert st["max_std_um"] == pytest.approx(float(table.std(axis=0, ddof=1).max()), rel=1e-9)
    with open(curves, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["theta_deg", "mean_um", "std_um", "max_um", "min_um"]
    assert len(rows) == 3601
    # --method selects; records of the other method are not there
    assert main([*args, "--method", "conjugate-fixture"]) == 2
    assert "no records match" in capsys.readouterr().err


def test_stats_mixes_grids_by_resampling_onto_the_finest(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A CMM record (3600 points) and a fixture record (360 points) of cam B: one lot."""
    url = str(tmp_path / "r.db")
    scan = _scan(tmp_path, "b.csv", 2, "--cam", "B")
    # judged against the fixture's radial band, as the fixture record is (one lot has one
    # tolerance; the CMM zone of cw11-experiment is ±110 µm on Δn since issue 31)
    band = ["--tolerance-um", "-220,220", "--tolerance-on", "dr"]
    assert _inspect(scan, url, "--serial", "1", "-q", *band) in (0, 1)
    fixture = ["conjugate", "-e", EX, "--df-mea", "0", "--step", "1", "-q", "--store", url]
    assert main([*fixture, "--serial", "2"]) in (0, 1)
    capsys.readouterr()
    args = ["records", "stats", "--store", url, "--design", EX, "--cam", "B", "--json"]
    assert main(args) == 0
    st = json.loads(capsys.readouterr().out)
    assert st["methods"] == ["cmm", "conjugate-fixture"]
    assert st["record_n_points"] == [360, 3600] and st["n_points"] == 3600
    with open_store(url) as s:
        fine, coarse = s.get(1), s.get(3)  # the fixture stored A (id 2) and B (id 3)
    assert (fine.method, coarse.method, coarse.cam) == ("cmm", "conjugate-fixture", "B")
    # linear interpolation never leaves its nodes' range: each part keeps its extremes
    assert st["record_ids"] == [1, 3]
    assert st["mean_of_max_um"] == pytest.approx(
        (float(fine.dr_um.max()) + float(coarse.dr_um.max())) / 2, rel=1e-6
    )
    assert st["envelope_min_um"] == pytest.approx(
        min(float(fine.dr_um.min()), float(coarse.dr_um.min())), rel=1e-6
    )


def _one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    err = [e for e in err if not e.startswith("camtol: warning:")]
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


def _gap_scan(tmp: Path, lo_deg: float, hi_deg: float) -> Path:
    """The twin's scan with the points between two polar angles removed."""
    full = _scan(tmp, "full.csv", 2, "--cam", "B")
    lines = full.read_text().splitlines()
    n_head = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    head = lines[n_head].split(",")
    ix, iy = head.index("x_mm"), head.index("y_mm")
    keep = lines[: n_head + 1]
    for line in lines[n_head + 1 :]:
        v = line.split(",")
        phi = math.degrees(math.atan2(float(v[iy]), float(v[ix]))) % 360.0
        if not lo_deg < phi < hi_deg:
            keep.append(line)
    out = tmp / "gap.csv"
    out.write_text("\n".join(keep) + "\n")
    return out


def test_scan_with_a_gap_is_refused_before_any_output(
    store_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # Issue 31: the record grid no longer follows --step; the finest grid whose 5 steps
    # cover the scan's largest gap is chosen. A 2° gap: > 5 steps of 0.1°, 0.2°, 0.25°,
    # ≤ 5 of 0.5°: recorded on 720 points at the default --step 0.1.
    scan = _gap_scan(tmp_path, 100.0, 102.0)
    curves, motion = tmp_path / "c.csv", tmp_path / "m.csv"
    outputs = ["--curves", str(curves), "--motion", str(motion)]
    capsys.readouterr()
    assert _inspect(scan, store_url, *outputs, "-q") in (0, 1)
    assert curves.exists() and motion.exists()
    with open_store(store_url) as s:
        (rec,) = s.records()
    assert rec.n_points == 720
    gap = float(np.max(np.diff(np.sort(rec.theta_deg))))
    assert gap == pytest.approx(0.5)


def test_scan_on_grid_rule() -> None:
    theta = np.linspace(0.0, 360.0, 721)[:-1]  # every 0.5°
    values = np.sin(np.radians(theta))
    grid = scan_on_grid(theta, values, 3600, max_gap_steps=MAX_GAP_STEPS)  # 0.5° = 5 steps
    assert np.max(np.abs(grid - np.sin(np.radians(np.arange(3600) * 0.1)))) < 4e-5
    with pytest.raises(ValueError, match=r"a gap of 0\.5°, at most 4 grid steps = 0\.4°"):
        scan_on_grid(theta, values, 3600, max_gap_steps=4.0)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--date", "yesterday"], "--date='yesterday': allowed ISO 8601"),
        (["--serial", "9" * 201], "--serial='99999999999999999999'... (201 characters)"),
        (["--lot", "a\x00b"], "with control character U+0000"),
        (["--date", "2026-11-23T08:00:00"], "give a time zone"),
    ],
)
def test_bad_traceability_is_refused_before_any_output(
    store_url: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    extra: list[str],
    message: str,
) -> None:
    scan = _scan(tmp_path, "b.csv", 2, "--cam", "B")
    curves = tmp_path / "c.csv"
    capsys.readouterr()
    assert _inspect(scan, store_url, "--curves", str(curves), *extra) == 2
    assert message in _one_line_error(capsys)
    assert not curves.exists()
    assert _count(store_url) == 0


def test_traceability_without_store_and_unreachable_store(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scan = _scan(tmp_path, "b.csv", 2, "--cam", "B")
    curves = tmp_path / "c.csv"
    capsys.readouterr()
    base = ["inspect", "-e", EX, "--points", str(scan), "--cam", "B", "--curves", str(curves)]
    # issue 31: the part's identity applies without a store too (reports, JSON); only
    # --allow-duplicate needs one
    assert main([*base, "--allow-duplicate"]) == 2
    assert "--allow-duplicate applies to a stored record: give --store DB" in _one_line_error(
        capsys
    )
    assert not curves.exists()
    assert main([*base, "--serial", "3", "-q"]) in (0, 1) and curves.exists()
    curves.unlink()
    assert main([*base, "--store", str(tmp_path / "missing" / "r.db")]) == 2
    assert "does not exist" in _one_line_error(capsys)
    url = "postgresql+psycopg://camtol:secret@127.0.0.1:1/none"
    assert main([*base, "--store", url]) == 2
    line = _one_line_error(capsys)
    assert "cannot open the store" in line and "secret" not in line
    assert not curves.exists()


def test_store_failure_mid_insert_stores_nothing_and_leaves_complete_outputs(
    store_url: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The store is written last, in one transaction: a failure after the record row (its
    curve's insert) rolls the row back; the output files written before are complete."""
    from sqlalchemy import event

    from camtol.records import schema as _store_sql

    make_engine = _store_sql.make_engine

    def failing_engine(url: str, **kw: Any) -> Any:
        engine = make_engine(url, **kw)

        @event.listens_for(engine, "before_cursor_execute")
        def boom(conn: Any, cursor: Any, statement: str, *args: Any) -> None:
            if statement.startswith("INSERT INTO curves"):
                raise RuntimeError("disk full (simulated)")

        return engine

    scan = _scan(tmp_path, "b.csv", 2, "--cam", "B")
    ok = tmp_path / "ok.csv"
    plain = ["inspect", "-e", EX, "--points", str(scan), "--cam", "B", "--curves", str(ok)]
    assert main(plain) in (0, 1)
    monkeypatch.setattr(_store_sql, "make_engine", failing_engine)
    curves = tmp_path / "c.csv"
    capsys.readouterr()
    assert _inspect(scan, store_url, "--curves", str(curves), "--datum", "fit") == 2
    line = _one_line_error(capsys)
    assert "nothing was stored" in line and "disk full" in line
    monkeypatch.undo()
    assert _count(store_url) == 0
    assert curves.read_text() == ok.read_text()  # complete, as without --store
    assert _inspect(scan, store_url, "-q") in (0, 1)  # the store takes the next record
    assert _count(store_url) == 1


def test_conjugate_store_is_checked_before_and_written_after_its_outputs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """`conjugate --store` follows the same order as `inspect --store`."""
    url = str(tmp_path / "r.db")
    curves = tmp_path / "c.csv"
    base = ["conjugate", "-e", EX, "--step", "1", "--curves", str(curves), "--store", url]
    assert main(base) == 2  # no measured Δf: nothing to record, refused before any output
    assert "give the measured Δf" in _one_line_error(capsys)
    assert not curves.exists() and _count(url) == 0
    order: list[str] = []
    import camtol.cli.conjugate as cc
    import camtol.report.conjugate as rc

    write, add = rc.write_fixture_curves_csv, cc.add_records

    def spy_write(*a: Any, **k: Any) -> None:
        order.append("curves")
        write(*a, **k)

    def spy_add(*a: Any, **k: Any) -> list[int]:
        order.append("store")
        return add(*a, **k)

    monkeypatch.setattr(rc, "write_fixture_curves_csv", spy_write)
    monkeypatch.setattr(cc, "add_records", spy_add)
    assert main([*base, "--df-mea", "20", "-q"]) in (0, 1)
    assert order == ["curves", "store"] and _count(url) == 2
