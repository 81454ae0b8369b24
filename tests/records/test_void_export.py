"""``records void`` (never a delete) and ``records export`` (one row per inspection).

A void keeps the record with who, when and why; lists, statistics and exports skip it
unless ``--all``. A refused void (already void, unknown id, no reason) changes nothing.
An export has the traceability, design, method, judged-on basis, verdict and figures with
the unit in each column name, as CSV or as JSON valid against its schema.
"""

from __future__ import annotations

import contextlib
import csv
import getpass
import hashlib
import io
import json
from importlib.resources import files
from pathlib import Path

import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.records.exports import COLUMNS, VOID_COLUMNS
from camtol.records.store import open_store

PAIR = "cw11-conjugate"


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


def _fill(url: str) -> None:
    """Four parts of the pair (8 records, lots L1 and L2) and a CMM record of a single cam."""
    for serial, lot in (("1", "L1"), ("2", "L1"), ("3", "L1"), ("4", "L2")):
        args = ["conjugate", "-e", PAIR, "--df-mea", f"1{serial}", "--step", "2", "-q"]
        assert _run([*args, "--store", url, "--serial", serial, "--lot", lot])[0] in (0, 1)


def _sha(url: str) -> str:
    return hashlib.sha256(Path(url).read_bytes()).hexdigest() if Path(url).is_file() else ""


def test_void_marks_and_never_deletes(store_url: str) -> None:
    _fill(store_url)
    code, out, err = _run(["records", "void", "3", "--store", store_url, "--reason", "wrong lot"])
    assert code == 0 and err == ""
    assert out.startswith("record 3 voided at ") and f"by {getpass.getuser()}: wrong lot" in out
    with open_store(store_url, readonly=True) as s:
        rec = s.get(3)  # still there, with who, when and why
        standing = [r.id for r in s.records()]
        every = [r.id for r in s.records(include_voided=True)]
    assert rec.voided and rec.voided_by == getpass.getuser() and rec.void_reason == "wrong lot"
    assert rec.voided_at is not None and rec.voided_at.utcoffset() is not None
    assert standing == [1, 2, 4, 5, 6, 7, 8] and every == list(range(1, 9))
    # lists, statistics and exports skip it; --all shows it marked
    code, out, _ = _run(["records", "list", "--store", store_url])
    assert code == 0 and "7 record(s)" in out and "VOID" not in out
    code, out, _ = _run(["records", "list", "--store", store_url, "--all"])
    assert "8 record(s), 1 void" in out
    assert [line.split()[0] for line in out.splitlines() if line.endswith("VOID")] == ["3"]
    code, out, _ = _run(["records", "list", "--store", store_url, "--all", "--json"])
    listed = json.loads(out)["records"]
    assert [r["id"] for r in listed if r["voided"]] == [3] and listed[2][
        "void_reason"
    ] == "wrong lot"
    args = ["records", "stats", "--store", store_url, "--design", PAIR, "--cam", "A", "--json"]
    code, out, _ = _run([*args, "--lot", "L1"])
    assert code == 0 and json.loads(out)["record_ids"] == [1, 5]
    code, out, _ = _run(["records", "show", "3", "--store", store_url, "--json"])
    shown = json.loads(out)
    assert shown["voided"] is True and shown["voided_by"] == getpass.getuser()
    code, out, _ = _run(["records", "rerun", "3", "--store", store_url])
    assert code == 0 and "identical" in out  # a voided record is still re-runnable


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["void", "3", "--reason", "again"], "record id 3 is already void (since "),
        (["void", "99", "--reason", "x"], "record id 99: no such record"),
        (["void", "1"], "Missing option '--reason'"),
        (["void", "1", "--reason", "  "], "allowed text of 1 to 500 characters without NUL"),
        (["void", "1", "--reason", "x" * 501], "allowed text of 1 to 500 characters"),
        (["void", "1", "--reason", "x", "--by", "y" * 201], "--by='yyyyyyyyyyyyyyyyyyyy'"),
    ],
)
def test_a_refused_void_changes_nothing(tmp_path: Path, args: list[str], message: str) -> None:
    url = str(tmp_path / "r.db")
    _fill(url)
    assert _run(["records", "void", "3", "--store", url, "--reason", "test", "--by", "qa"])[0] == 0
    before = _sha(url)
    code, out, err = _run(["records", *args, "--store", url])
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err
    assert _sha(url) == before
    with open_store(url, readonly=True) as s:
        assert [r.id for r in s.records(include_voided=True) if r.voided] == [3]


def test_export_csv_and_json(store_url: str, tmp_path: Path) -> None:
    import jsonschema

    _fill(store_url)
    scan = tmp_path / "s.csv"
    sim = ["simulate", "cmm", "-e", "roller-translating", "-o", str(scan), "--n-points", "720"]
    assert _run(sim)[0] == 0
    args = ["inspect", "-e", "roller-translating", "--points", str(scan), "--step", "1"]
    assert _run([*args, "-q", "--store", store_url, "--serial", "9", "--lot", "L2"])[0] in (0, 1)
    assert (
        _run(["records", "void", "2", "--store", store_url, "--reason", "x", "--by", "qa"])[0] == 0
    )
    code, out, _ = _run(["records", "export", "--store", store_url, "--format", "csv"])
    assert code == 0
    rows = list(csv.DictReader(io.StringIO(out)))
    assert list(rows[0]) == list(COLUMNS)
    assert [int(r["id"]) for r in rows] == [1, 3, 4, 5, 6, 7, 8, 9]  # the void one left out
    with open_store(store_url, readonly=True) as s:
        recs = {r.id: r for r in s.records()}
    for row in rows:
        rec = recs[int(row["id"])]
        assert (row["serial"], row["lot"], row["cam"], row["verdict"]) == (
            rec.serial, rec.lot, rec.cam, rec.verdict,
        )  # fmt: skip
        assert row["inspected_at_utc"].endswith("+00:00") and row["design_hash"] == rec.design_hash
        assert float(row["max_dev_um"]) == pytest.approx(rec.max_dev_um, rel=1e-9)
        # a fixture record is judged on Δr; a CMM one on Δn, its ISO 1101 zone (issue 31)
        on = "dn" if row["method"] == "cmm" else "dr"
        assert row["judged_on"] == on and row["raw_sha256"] == rec.raw_sha256
    cmm = rows[-1]
    assert cmm["method"] == "cmm" and cmm["max_abs_ds_deg"] == ""  # a lift: in µm
    assert float(cmm["max_abs_ds_um"]) == pytest.approx(recs[9].max_abs_ds_um, rel=1e-9)
    text_columns = {"part_number", "serial", "lot", "inspector", "instrument", "design_name"}
    text_columns |= {"design_hash", "method", "cam", "judged_on", "decision_rule", "verdict"}
    text_columns |= {"raw_sha256", "camtol_version", "id", "n_points", "inspected_at_utc"}
    assert all(c.endswith(("_um", "_deg")) for c in COLUMNS if c not in text_columns)
    # --lot, --all, JSON (valid against its schema), -o FILE
    code, out, _ = _run(["records", "export", "--store", store_url, "--format", "json", "--all"])
    data = json.loads(out)
    schema_text = (files("camtol") / "data" / "schemas" / "records-export.schema.json").read_text()
    jsonschema.validate(data, json.loads(schema_text))
    assert data["command"] == "records export" and data["columns"] == [*COLUMNS, *VOID_COLUMNS]
    assert [r["id"] for r in data["rows"] if r["voided"]] == [2] and len(data["rows"]) == 9
    target = tmp_path / "lot2.csv"
    args = ["records", "export", "--store", store_url, "--lot", "L2", "--format", "csv"]
    code, out, _ = _run([*args, "-o", str(target)])
    assert code == 0 and out == f"wrote {target} (3 record(s))\n"
    assert [r["serial"] for r in csv.DictReader(io.StringIO(target.read_text()))] == ["4", "4", "9"]
    code, _, err = _run([*args, "-o", str(tmp_path / "lot2.json")])
    assert code == 2 and "--output=" in err and "must end in .csv" in err
