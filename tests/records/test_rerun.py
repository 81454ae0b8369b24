"""``camtol records rerun``: every stored verdict judged again from its raw data, bit for bit.

A store of 20 records (6 CMM inspections, 7 fixture inspections of cams A and B) made with
the options a shop uses, on SQLite and PostgreSQL (tests/records/conftest.py); each record
re-run from the store alone is identical. A flipped byte in a raw blob is named; the stored
extremes are those of the measured points; ``records show --design`` prints the design.
"""

from __future__ import annotations

import contextlib
import io
import json
import zlib
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.config.examples import example_text
from camtol.inspection.cmm_run import CmmInputs, run_cmm
from camtol.inspection.registration import Datum
from camtol.records.store import open_store

EX, PAIR, SINGLE = "cw11-experiment", "cw11-conjugate", "roller-translating"


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Simulated scans of cams A and B and of a single cam, an indicator record, CSVs."""
    tmp = tmp_path_factory.mktemp("rerun")
    paths = {}
    for name, args in {
        "a": ["-e", EX, "--cam", "A", "--seed", "1"],
        "b": ["-e", EX, "--cam", "B", "--seed", "2"],
        "single": ["-e", SINGLE, "--seed", "3", "--stylus-radius-mm", "1"],
    }.items():
        paths[name] = tmp / f"{name}.csv"
        sim = ["simulate", "cmm", *args, "-o", str(paths[name]), "--noise-um", "0.5"]
        assert _run([*sim, "--error-rms-um", "5"])[0] == 0
    paths["record"] = tmp / "indicator.csv"
    rec = ["simulate", "record", "-e", EX, "-o", str(paths["record"]), "--revolutions", "3"]
    rec += ["--samples", "720", "--truth-a", str(paths["a"].with_suffix(".truth.json"))]
    assert _run([*rec, "--truth-b", str(paths["b"].with_suffix(".truth.json"))])[0] == 0
    theta = np.arange(0, 360, 5)
    paths["df"] = tmp / "df.csv"
    paths["df"].write_text(
        "theta_deg,um\n" + "".join(f"{t},{20 + 2 * np.sin(np.radians(t)):.4f}\n" for t in theta)
    )
    paths["master"] = tmp / "master.csv"
    paths["master"].write_text(
        "theta_deg,um\n" + "".join(f"{t},{18 + np.cos(np.radians(t)):.4f}\n" for t in theta)
    )
    design_dir = tmp / "design"
    design_dir.mkdir()
    (design_dir / "df_design.csv").write_text(paths["df"].read_text())
    text = example_text(PAIR).replace("df_mea_um = 22 ", 'df_mea_um = "df_design.csv" ')
    assert '"df_design.csv"' in text
    paths["design"] = design_dir / "pair.toml"
    paths["design"].write_text(text)
    return paths


def _fill(url: str, p: dict[str, Path]) -> list[int]:
    """The 20 records: 6 CMM inspections and 7 fixture inspections (cams A and B)."""
    b, a, single = str(p["b"]), str(p["a"]), str(p["single"])
    runs = [
        ["inspect", "-e", EX, "--points", b, "--cam", "B"],
        ["inspect", "-e", EX, "--points", b, "--cam", "B", "--datum", "centre:0,0,0"]
        + ["--tolerance-um", "-15,15"],  # judged on Δn
        ["inspect", "-e", EX, "--points", a, "--cam", "A", "--tolerance-um", "-20,20"]
        + ["--tolerance-on", "dr", "--harmonics", "50", "--step", "0.5"],
        ["inspect", "-e", SINGLE, "--points", single, "--stylus-radius-mm", "1"]
        + ["--spec-um", "30"],
        ["inspect", "-e", SINGLE, "--points", single, "--stylus-radius-mm", "1"]
        + ["--datum", "fit-rotation", "--step", "1", "--loss", "huber"],
        ["inspect", "-e", EX, "--points", b, "--cam", "B", "--spec-deg", "0.05"],
        ["conjugate", "-e", PAIR, "--df-mea", "20", "--step", "1"],
        ["conjugate", "-e", PAIR, "--df-mea", str(p["df"]), "--step", "2"],
        ["conjugate", "-e", PAIR, "--df-mea", "21 + 2*sin(theta)", "--step", "1"]
        + ["--master-a", str(p["master"]), "--master-b", "1.5"],
        ["conjugate", "-e", PAIR, "--step", "1"],  # the design's own df_mea_um
        ["conjugate", str(p["design"]), "--step", "1"],  # its df_mea_um a CSV it names
        ["conjugate", "-e", EX, "--record", str(p["record"]), "--step", "1"],
        ["conjugate", "-e", EX, "--record", str(p["record"]), "--step", "1"]
        + ["--decision", "guard-band"],
    ]
    ids: list[int] = []
    for serial, args in enumerate(runs, start=1):
        code, out, err = _run([*args, "--json", "--store", url, "--serial", str(serial)])
        assert code in (0, 1), (args, err)
        ids += json.loads(out)["record_ids"]
    assert ids == list(range(1, 21))
    return ids


def test_rerun_reproduces_every_verdict_bit_for_bit(
    store_url: str, inputs: dict[str, Path]
) -> None:
    import jsonschema

    schema = json.loads(
        (files("camtol") / "data" / "schemas" / "records-rerun.schema.json").read_text("utf-8")
    )
    ids = _fill(store_url, inputs)
    with open_store(store_url, readonly=True) as s:
        recs = {r.id: r for r in s.records()}
        bases = {r.id: r.judged_on for r in recs.values()}
        assert {s.get(i).method for i in ids} == {"cmm", "conjugate-fixture"}
    assert bases[2] == "dn" and bases[3] == "dr" and bases[7] == "dr"  # what it was judged on
    assert recs[20].decision_rule == "guard-band" and recs[18].decision_rule == "simple"
    verdicts = set()
    for i in ids:
        code, out, err = _run(["records", "rerun", str(i), "--store", store_url, "--json"])
        data = json.loads(out)
        assert code == 0 and data["identical"] is True, (i, data["differences"], err)
        assert data["differences"] == [] and data["stored"] == data["rerun"]
        jsonschema.validate(data, schema)
        verdicts.add(data["stored"]["verdict"])
    assert verdicts == {"pass", "fail"}  # both kinds of verdict are reproduced
    code, out, _ = _run(["records", "rerun", "4", "--store", store_url])
    assert code == 0 and "identical" in out and "re-run with camtol" in out


def test_stored_extremes_are_those_of_the_measured_points(
    tmp_path: Path, inputs: dict[str, Path]
) -> None:
    url = str(tmp_path / "r.db")
    args = ["inspect", "-e", EX, "--points", str(inputs["b"]), "--cam", "B", "-q"]
    assert _run([*args, "--store", url, "--serial", "1"])[0] in (0, 1)
    with open_store(url, readonly=True) as s:
        rec = s.get(1)
    run = run_cmm(load_example(EX), CmmInputs(str(inputs["b"]), cam="B", datum=Datum()))
    dr = run.inspection.dr_um[run.inspection.kept]
    assert (rec.max_dev_um, rec.min_dev_um) == (float(dr.max()), float(dr.min()))
    assert rec.form_um == float(dr.max()) - float(dr.min())
    # the resampled curve never reaches beyond the points it interpolates
    assert float(rec.dr_um.max()) <= rec.max_dev_um and float(rec.dr_um.min()) >= rec.min_dev_um
    assert rec.options is not None and rec.options["datum"]["mode"] == "fit"
    assert rec.results is not None and rec.results["max_dn_um"] == run.inspection.max_dn_um


def _blob(url: str, sha: str, data: bytes | None = None) -> bytes:
    """Read (and with ``data`` replace) the stored blob of a raw input."""
    from sqlalchemy import create_engine, text

    from camtol.records.store import store_url as to_url

    engine = create_engine(to_url(url))
    with engine.begin() as conn:
        old = bytes(
            conn.execute(
                text("SELECT data FROM raw_inputs WHERE sha256 = :s"), {"s": sha}
            ).scalar_one()
        )
        if data is not None:
            conn.execute(
                text("UPDATE raw_inputs SET data = :d WHERE sha256 = :s"), {"d": data, "s": sha}
            )
    engine.dispose()
    return old


def test_a_flipped_byte_in_a_raw_blob_is_named(store_url: str, inputs: dict[str, Path]) -> None:
    scan = str(inputs["b"])
    args = ["inspect", "-e", EX, "--points", scan, "--cam", "B", "-q", "--store", store_url]
    assert _run([*args, "--serial", "1"])[0] in (0, 1)
    with open_store(store_url, readonly=True) as s:
        (raw,) = [r for r in s.input_list(1) if r["role"] == "scan"]
    assert raw["name"] == scan and raw["sha256"].startswith("sha256:")
    stored = _blob(store_url, raw["sha256"])
    plain = bytearray(zlib.decompress(stored))
    plain[len(plain) // 2] ^= 0x01  # one bit of the scan's text, recompressed: SHA-256 differs
    _blob(store_url, raw["sha256"], zlib.compress(bytes(plain)))
    code, out, err = _run(["records", "rerun", "1", "--store", store_url, "--json"])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert f"record 1: raw input 'scan' ({scan}) is corrupt: its SHA-256 is sha256:" in err
    assert f"stored as {raw['sha256']}" in err
    flipped = bytearray(stored)
    flipped[len(flipped) // 2] ^= 0xFF  # a byte of the compressed blob itself
    _blob(store_url, raw["sha256"], bytes(flipped))
    code, _, err = _run(["records", "rerun", "1", "--store", store_url])
    assert code == 2 and "record 1: raw input 'scan'" in err and "is corrupt" in err
    _blob(store_url, raw["sha256"], stored)  # restored: identical again
    assert _run(["records", "rerun", "1", "--store", store_url])[0] == 0


def test_show_design_prints_the_stored_design_file(tmp_path: Path, inputs: dict[str, Path]) -> None:
    url = str(tmp_path / "r.db")
    design = inputs["design"]
    assert _run(["conjugate", str(design), "--step", "2", "-q", "--store", url])[0] in (0, 1)
    code, out, _ = _run(["records", "show", "1", "--store", url, "--design"])
    assert code == 0 and out == design.read_text()
    with open_store(url, readonly=True) as s:
        roles = [r["role"] for r in s.input_list(1)]
    assert roles == ["design:df_design.csv"]  # the measurement: the CSV the design names
    code, _, err = _run(["records", "show", "1", "--store", url, "--design", "--json"])
    assert code == 2 and "--design prints the design file alone" in err


def test_a_record_without_raw_data_says_so(tmp_path: Path) -> None:
    from camtol.records.store import Traceability, record_inspection

    url = str(tmp_path / "r.db")
    record_inspection(
        url,
        load_example(SINGLE),
        method="cmm",
        cam="",
        dr_um=np.zeros(36),
        verdict="pass",
        tolerance_um=(-1.0, 1.0),
        traceability=Traceability(serial="1"),
    )
    code, out, err = _run(["records", "rerun", "1", "--store", url, "--json"])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "record 1 (cmm, made by camtol" in err and "without its raw data" in err
