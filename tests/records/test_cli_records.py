"""``camtol conjugate --store`` and ``camtol records list/show/stats`` (in-process)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.config.examples import example_text
from camtol.records.lots import lot_statistics
from camtol.records.store import design_identity, open_store
from camtol.report.units import json_ready

EX = "cw11-conjugate"


def _inspect(url: str, serial: str, df: str, lot: str = "L1", *extra: str) -> int:
    return main(
        [
            "conjugate", "-e", EX, "--df-mea", df, "--step", "1", "-q", "--store", url,
            "--serial", serial, "--lot", lot, "--part-number", "CAM-7", "--inspector", "ana",
            "--instrument", "fixture-2", *extra,
        ]
    )  # fmt: skip


def test_conjugate_store_records_both_cams(
    store_url: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code = _inspect(store_url, "1", "20 + 3*sin(theta)", "L1", "--date", "2026-11-23T08:00:00Z")
    assert code in (0, 1)
    assert (
        main(["conjugate", "-e", EX, "--df-mea", "20 + 3*sin(theta)", "--step", "1", "--json"])
        == code
    )
    ref = json.loads(capsys.readouterr().out)
    assert ref["record_ids"] == []  # this run had no --store
    assert main(["records", "list", "--store", store_url, "--json"]) == 0
    recs = json.loads(capsys.readouterr().out)["records"]
    assert [r["cam"] for r in recs] == ["A", "B"]
    a = recs[0]
    assert a["design_name"] == EX
    assert a["design_hash"] == design_identity(load_example(EX), example_text(EX))[1]
    assert (a["part_number"], a["serial"], a["lot"], a["inspector"], a["instrument"]) == (
        "CAM-7", "1", "L1", "ana", "fixture-2",
    )  # fmt: skip
    assert a["inspected_at"] == "2026-11-23T08:00:00+00:00"
    assert a["method"] == "conjugate-fixture" and a["n_points"] == 360
    assert a["tolerance_um"] == [-22.0, 22.0]
    assert a["verdict"] == ("pass" if ref["verdicts"]["A"]["passed"] else "fail")


def test_show_and_stats_against_the_library(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    url = str(tmp_path / "r.db")
    for serial, df in [("1", "20"), ("2", "21 + 2*sin(theta)"), ("3", "23 + 2*cos(theta)")]:
        assert _inspect(url, serial, df) in (0, 1)
    assert _inspect(url, "9", "20", "L2") in (0, 1)
    capsys.readouterr()

    curve = tmp_path / "c.csv"
    assert main(["records", "show", "3", "--store", url, "--json", "--curves", str(curve)]) == 0
    shown = json.loads(capsys.readouterr().out)
    with open_store(url) as s:
        rec = s.get(3)
        lot = s.records(design=EX, lot="L1", cam="A", with_curves=True)
        inputs = s.input_list(3)
    assert [i["role"] for i in inputs] == ["df_mea"] and inputs[0]["name"] == ""
    # floats are printed to 10 significant digits (issue 13 item 6)
    expected = rec.summary()
    # the JSON envelope leads; the record's own camtol version sits beside the envelope's
    expected["record_camtol_version"] = rec.camtol_version
    # what makes it re-runnable: the options, the method's results and the raw inputs
    expected.update(options=rec.options, results=rec.results, inputs=inputs)
    assert list(shown)[:3] == ["schema_version", "command", "camtol_version"]
    assert shown["command"] == "records show"
    assert set(shown) == set(expected) | {"schema_version", "command"}
    for key, value in expected.items():
        if isinstance(value, float):
            assert shown[key] == pytest.approx(value, rel=1e-9), key
        elif isinstance(value, dict):  # nested floats to 10 digits too
            assert shown[key] == json.loads(json.dumps(json_ready(value))), key
        else:
            assert shown[key] == value, key
    rows = list(csv.reader(curve.read_text().splitlines()))
    assert rows[0] == ["theta_deg", "dr_um"]
    np.testing.assert_allclose([float(r[1]) for r in rows[1:]], rec.dr_um, rtol=1e-9)
    np.testing.assert_allclose([float(r[0]) for r in rows[1:]], np.arange(360.0))

    stats_csv = tmp_path / "s.csv"
    args = ["records", "stats", "--store", url, "--design", EX, "--lot", "L1", "--cam", "A"]
    assert main([*args, "--json", "--curves", str(stats_csv)]) == 0
    got = json.loads(capsys.readouterr().out)
    ref = lot_statistics(
        [r.dr_um for r in lot], (-22.0, 22.0), [r.verdict == "fail" for r in lot],
        sequence=[1.0, 2.0, 3.0],
    )  # fmt: skip
    assert got["n_parts"] == 3 and got["record_ids"] == [r.id for r in lot]
    assert got["trend_basis"] == "serial"
    # max_dev has an upper limit only: Ppu on the parts' max deviations (schema 2.0)
    s_max = float(np.std(ref.part_max_um, ddof=1))
    assert got["ppu"]["value"] == pytest.approx((22.0 - ref.part_max_um.mean()) / (3 * s_max))
    assert got["trend_um_per_part"] == pytest.approx(ref.trend_um_per_part)
    assert got["fraction_failing_ci"] == pytest.approx(list(ref.fraction_failing_ci))
    rows = list(csv.reader(stats_csv.read_text().splitlines()))
    assert rows[0] == ["theta_deg", "mean_um", "std_um", "max_um", "min_um"]
    np.testing.assert_allclose([float(r[1]) for r in rows[1:]], ref.mean_um, rtol=1e-9)

    assert main(["records", "list", "--store", url, "--lot", "L2"]) == 0
    out = capsys.readouterr().out
    assert "2 record(s)" in out and " 9 " in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["records", "show", "99"], "record id 99: no such record"),
        (["records", "stats", "--design", EX], "records of cams A, B; give --cam"),
        (["records", "stats", "--design", "nope"], "--design='nope': no records match"),
        (
            ["records", "stats", "--design", EX, "--cam", "A", "--confidence", "2"],
            "--confidence=2.0",
        ),
        (["records", "show", "1", "--curves", "x.txt"], "--curves='x.txt'"),
    ],
)
def test_bad_input_exits_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    url = str(tmp_path / "r.db")
    assert _inspect(url, "1", "20") in (0, 1)
    capsys.readouterr()
    assert main([*args, "--store", url]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err


def test_store_errors_exit_2_before_any_work(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    missing = str(tmp_path / "none.db")
    assert main(["records", "list", "--store", missing]) == 2
    assert "no such file" in capsys.readouterr().err
    assert not Path(missing).exists()
    assert main(["records", "list", "--store", f"sqlite:///{missing}"]) == 2
    assert "no such file" in capsys.readouterr().err
    assert not Path(missing).exists()  # not created by a read
    assert main(["records", "list", "--store", str(tmp_path)]) == 2  # said "no such file"
    assert "a directory, not a store file" in capsys.readouterr().err
    assert main(["records", "list", "--store", "postgresql+psycopg://u:pw@127.0.0.1:1/x"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot open the store" in err and "pw" not in err

    # issue 31: the part's identity applies without a store; --allow-duplicate needs one
    assert main(["conjugate", "-e", EX, "--allow-duplicate"]) == 2
    assert "--allow-duplicate applies to a stored record" in capsys.readouterr().err
    url = str(tmp_path / "r.db")
    assert _inspect(url, "1", "20", "L1", "--date", "yesterday") == 2
    assert "--date='yesterday'" in capsys.readouterr().err
    # no measurement: nothing to record (cw11-experiment has no df_mea)
    code = main(["conjugate", "-e", "cw11-experiment", "--store", url, "--step", "1", "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "--store records an inspection" in err
    with open_store(url) as s:
        assert s.records() == []


def test_newer_schema_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import sqlite3

    url = str(tmp_path / "r.db")
    assert _inspect(url, "1", "20") in (0, 1)
    with sqlite3.connect(url) as conn:
        conn.execute("UPDATE schema_version SET version = 99")
    capsys.readouterr()
    assert main(["records", "list", "--store", url]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "schema version 99, newer than" in err
    assert _inspect(url, "2", "20") == 2  # an inspection refuses before analysing


def test_every_key_column_and_flag_is_documented(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import click

    from camtol.cli.conjugate import conjugate
    from camtol.cli.inspect import inspect
    from camtol.cli.records import records

    doc = (Path(__file__).resolve().parents[2] / "docs" / "records.md").read_text("utf-8")
    url = str(tmp_path / "r.db")
    assert _inspect(url, "1", "20") in (0, 1)
    assert _inspect(url, "2", "21") in (0, 1)  # lot statistics need two parts
    capsys.readouterr()
    assert main(["records", "show", "1", "--store", url, "--json"]) == 0
    keys = set(json.loads(capsys.readouterr().out))
    assert main(["records", "stats", "--store", url, "--design", EX, "--cam", "B", "--json"]) == 0
    keys |= set(json.loads(capsys.readouterr().out))
    keys |= {"theta_deg", "dr_um", "mean_um", "std_um", "max_um", "min_um"}  # CSV columns
    assert main(["records", "rerun", "1", "--store", url, "--json"]) == 0
    rerun = json.loads(capsys.readouterr().out)
    keys |= set(rerun) | set(rerun["stored"])
    assert main(["records", "show", "1", "--store", url, "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    keys |= set(shown["options"]) | set(shown["results"]) | set(shown["inputs"][0])
    from camtol.records.exports import COLUMNS, VOID_COLUMNS

    keys |= set(COLUMNS) | set(VOID_COLUMNS) | {"columns", "rows", "max_abs_difference_um"}
    for name in ("schema_version", "designs", "inspections", "curves", "tolerance_lower_um"):
        keys.add(name)
    keys |= {"raw_inputs", "inspection_inputs", "alembic_version", "ux_inspections_raw"}
    import re

    spans = re.findall(r"`([^`\n]+)`", doc)  # code spans, one line each
    words = set(re.findall(r"[\w-]+", " ".join(spans)))
    missing = sorted(keys - words)
    assert missing == [], f"not in docs/records.md: {missing}"
    assert isinstance(records, click.Group)
    flags = {
        opt
        for cmd in [*records.commands.values(), conjugate, inspect]
        for p in cmd.params
        for opt in p.opts
        if opt.startswith("--")
        and (cmd not in (conjugate, inspect) or str(p.name).startswith("store_"))
    }
    assert sorted(f for f in flags if f"`{f}" not in doc and f"{f} " not in doc) == []


def test_show_lays_out_nested_values_within_80_columns() -> None:
    from camtol.cli.records import _show_lines

    data = {
        "id": 7,
        "design_hash": "sha256:" + "ab" * 32,
        "cam": "",
        "form_um": 7.272972113,
        "options": {"datum": {"mode": "fit", "angle_deg": None}, "harmonics": 100},
        "results": {"failing_intervals_deg": [], "dx_mm": 1.939791e-05},
        "inputs": [{"role": "scan", "name": "b.csv", "sha256": "sha256:" + "cd" * 32}],
    }
    lines = _show_lines(data)
    assert max(len(line) for line in lines) <= 80
    assert "  sha256:" + "ab" * 32 in lines  # a hash too long for its line: next line, whole
    assert "form_um           7.27297" in lines  # 6 significant digits, no repr
    assert "cam               -" in lines
    assert "    mode          fit" in lines and "  harmonics       100" in lines
    assert "  failing_intervals_deg none" in lines
