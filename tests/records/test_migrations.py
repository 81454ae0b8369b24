"""Alembic migrations of the store, applied when a writer opens it (issue 29 item 5).

``data/store-v1.db`` was written by camtol at commit bcb84ab, schema version 1, before
the migrations existed (``data/make_store_v1.py`` made it). A reader reads it as it is
without changing a byte; the first writer upgrades it to the current schema in one
transaction; every record reads back with the same figures and curve; records without
raw data say so on ``rerun``, new ones re-run identically.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import shutil
import sqlite3
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")
pytest.importorskip("alembic", reason="the store's migrations need camtol[store] (Alembic)")

from camtol.cli.app import main
from camtol.records.migrate import MIGRATIONS, REVISIONS
from camtol.records.record import SCHEMA_VERSION
from camtol.records.store import open_store

V1 = Path(__file__).parent / "data" / "store-v1.db"
PAIR = "cw11-conjugate"


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _listed(db: Path) -> list[dict[str, Any]]:
    code, out, err = _run(["records", "list", "--store", str(db), "--all", "--json"])
    assert code == 0, err
    records: list[dict[str, Any]] = json.loads(out)["records"]
    return records


def test_the_revisions_end_at_this_schema_version() -> None:
    from alembic.config import Config
    from alembic.script import ScriptDirectory

    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("path_separator", "os")
    script = ScriptDirectory.from_config(cfg)
    assert script.get_current_head() == REVISIONS[SCHEMA_VERSION]
    chain = [s.revision for s in script.walk_revisions("base", "heads")]
    assert sorted(chain) == [REVISIONS[v] for v in range(1, SCHEMA_VERSION + 1)]


def test_a_version_1_file_is_read_as_it_is_then_upgraded_by_a_writer(tmp_path: Path) -> None:
    db = tmp_path / "old.db"
    shutil.copyfile(V1, db)
    before = _sha(db)
    old = _listed(db)  # a reader reads version 1 as it is ...
    assert [r["id"] for r in old] == [1, 2, 3, 4, 5, 6]
    assert all(r["judged_on"] is None and r["raw_sha256"] is None for r in old)
    code, _, err = _run(["records", "rerun", "1", "--store", str(db)])
    assert code == 2 and "without its raw data" in err
    with open_store(str(db), readonly=True) as s:
        assert s.version == 1
        curves = {r.id: r.dr_um.tobytes() for r in s.records(with_curves=True)}
    assert _sha(db) == before  # ... without changing a byte

    with open_store(str(db)) as s:  # a writer upgrades it
        assert s.version == SCHEMA_VERSION
    conn = sqlite3.connect(db)
    assert conn.execute("SELECT version FROM schema_version").fetchall() == [(SCHEMA_VERSION,)]
    assert conn.execute("SELECT version_num FROM alembic_version").fetchall() == [
        (REVISIONS[SCHEMA_VERSION],)
    ]
    assert conn.execute("PRAGMA integrity_check").fetchall() == [("ok",)]
    conn.close()
    new = _listed(db)
    for a, b in zip(old, new, strict=True):  # every record readable, as it was
        changed = {k for k in a if a[k] != b[k]}
        assert changed <= {"judged_on"}, changed
        assert b["judged_on"] == ("dr" if a["method"] == "conjugate-fixture" else None)
    with open_store(str(db), readonly=True) as s:
        assert {r.id: r.dr_um.tobytes() for r in s.records(with_curves=True)} == curves
        assert s.design_text(new[0]["design_hash"]) is not None
    for rid in range(1, 7):
        assert _run(["records", "show", str(rid), "--store", str(db), "--json"])[0] == 0
        code, _, err = _run(["records", "rerun", str(rid), "--store", str(db)])
        assert code == 2 and f"record {rid} (" in err and "without its raw data" in err
    args = ["records", "stats", "--store", str(db), "--design", PAIR, "--cam", "A", "--json"]
    code, out, _ = _run(args)
    assert code == 0 and json.loads(out)["record_ids"] == [1, 3]
    # new records in the upgraded store keep their raw data and re-run identically
    run = ["conjugate", "-e", PAIR, "--df-mea", "19", "--step", "1", "-q", "--store", str(db)]
    assert _run([*run, "--serial", "5", "--lot", "L1"])[0] in (0, 1)
    code, out, _ = _run(["records", "rerun", "8", "--store", str(db), "--json"])
    assert code == 0 and json.loads(out)["identical"] is True
    code, out, _ = _run(args)
    assert json.loads(out)["record_ids"] == [1, 3, 7]  # old and new records pool


def test_a_store_made_before_the_migrations_is_stamped_then_upgraded(store_url: str) -> None:
    """On either engine: revision 0001's tables without alembic_version (a pre-0.1 store)."""
    from alembic import command
    from alembic.config import Config
    from sqlalchemy import create_engine, inspect, text

    from camtol.records.store import store_url as to_url

    engine = create_engine(to_url(store_url))
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("path_separator", "os")
    with engine.begin() as conn:
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, REVISIONS[1])
        conn.execute(text("DROP TABLE alembic_version"))
        conn.execute(text("INSERT INTO designs VALUES ('sha256:" + "0" * 64 + "', 'd', NULL)"))
        conn.execute(
            text(
                "INSERT INTO inspections (design_name, design_hash, method, cam, part_number,"
                " serial, lot, inspector, instrument, inspected_at, verdict, max_dev_um,"
                " min_dev_um, form_um, max_abs_ds_um, tolerance_lower_um, tolerance_upper_um,"
                " camtol_version) VALUES ('d', 'sha256:" + "0" * 64 + "', 'cmm', '', '', '7',"
                " '', '', '', '2026-01-01 00:00:00', 'pass', 1.5, -1.0, 2.5, NULL, -5, 5, '0.1.0')"
            )
        )
        conn.execute(text("INSERT INTO curves VALUES (1, 'dr_um', 1, :d)"), {"d": b"\0\0\0\0"})
    with open_store(store_url) as s:
        assert s.version == SCHEMA_VERSION
        (rec,) = s.records(with_curves=True)
    assert (rec.serial, rec.max_dev_um, rec.n_points, rec.judged_on) == ("7", 1.5, 1, None)
    assert {"raw_inputs", "inspection_inputs", "alembic_version"} <= set(
        inspect(engine).get_table_names()
    )
    engine.dispose()


def test_a_revision_this_camtol_does_not_know_is_refused(tmp_path: Path) -> None:
    db = tmp_path / "r.db"
    assert _run(["conjugate", "-e", PAIR, "--df-mea", "19", "--store", str(db), "-q"])[0] in (0, 1)
    conn = sqlite3.connect(db)
    with conn:
        conn.execute("UPDATE alembic_version SET version_num = 'ffff'")
    conn.close()
    before = _sha(db)
    code, _, err = _run(["conjugate", "-e", PAIR, "--df-mea", "18", "--store", str(db), "-q"])
    assert (
        code == 2 and err.count("\n") == 1 and "its migration history is not this camtol's" in err
    )
    assert _sha(db) == before
