"""The store refuses what it must not touch, and readers never write (issue 29 item 4).

A foreign SQLite file, a file that is not SQLite, a directory, a newer schema, an empty or
damaged version table: refused with one line, exit 2, every file byte-identical and no
file added beside it. A refused command leaves no store behind; an id out of range is one
line; readers open read-only, never wait for a writer's lock and never create tables; a
record without its curve is still listed.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import sqlite3
import time
from collections.abc import Callable
from pathlib import Path

import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.exceptions import RecordError
from camtol.records.record import SCHEMA_VERSION
from camtol.records.store import open_store

PAIR = "cw11-conjugate"
STORE_RUN = ["conjugate", "-e", PAIR, "--df-mea", "20", "--step", "5", "-q"]


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


def _snapshot(folder: Path) -> dict[str, str]:
    """Every file under a folder with the SHA-256 of its bytes."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _foreign(path: Path) -> None:
    with sqlite3.connect(path) as conn:
        conn.execute("CREATE TABLE parts (id INTEGER PRIMARY KEY, name TEXT)")
        conn.execute("INSERT INTO parts (name) VALUES ('bracket')")
    conn.close()


def _camtol(path: Path, sql: str | None = None) -> None:
    assert _run([*STORE_RUN, "--store", str(path), "--serial", "1"])[0] in (0, 1)
    if sql is not None:
        with sqlite3.connect(path) as conn:
            conn.execute(sql)
        conn.close()


CASES: dict[str, tuple[Callable[[Path], None], str]] = {
    "foreign SQLite file": (
        _foreign,
        "is not a camtol inspection store: it holds other tables (parts)",
    ),
    "not SQLite at all": (
        lambda p: p.write_text("serial,lot\n1,L1\n"),
        "not a camtol inspection store (not a SQLite database)",
    ),
    "newer schema": (
        lambda p: _camtol(p, f"UPDATE schema_version SET version = {SCHEMA_VERSION + 1}"),
        f"has schema version {SCHEMA_VERSION + 1}, newer than this camtol reads",
    ),
    "missing version row": (
        lambda p: _camtol(p, "DELETE FROM schema_version"),
        "its schema_version table is empty (one row, the schema version, is expected): a"
        " damaged store",
    ),
    "two version rows": (
        lambda p: _camtol(p, "INSERT INTO schema_version VALUES (7)"),
        "its schema_version table holds 2 rows",
    ),
    "a version that is not one": (
        lambda p: _camtol(p, "UPDATE schema_version SET version = 0"),
        "its schema_version table holds 0, not a schema version",
    ),
    "a table missing": (
        lambda p: _camtol(p, "DROP TABLE curves"),
        "but its table(s) curves are missing: a damaged store",
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_what_is_not_a_good_store_is_refused_untouched(tmp_path: Path, case: str) -> None:
    make, message = CASES[case]
    db = tmp_path / "other.db"
    make(db)
    before = _snapshot(tmp_path)
    curves = tmp_path / "c.csv"
    for args in (
        [*STORE_RUN, "--store", str(db), "--serial", "2", "--curves", str(curves)],
        ["records", "list", "--store", str(db)],
        ["records", "show", "1", "--store", str(db)],
        ["records", "stats", "--store", str(db), "--design", PAIR, "--cam", "A"],
        ["records", "export", "--store", str(db), "--format", "csv"],
        ["records", "void", "1", "--store", str(db), "--reason", "test"],
        ["records", "rerun", "1", "--store", str(db)],
    ):
        code, out, err = _run(args)
        assert code == 2, (args, out, err)
        assert err.count("\n") == 1 and message in err and "Traceback" not in err, (args, err)
        assert _snapshot(tmp_path) == before, args  # byte-identical, no journal left
    with pytest.raises(RecordError, match="left untouched|newer than"):
        open_store(str(db))  # the Python API refuses it as well
    assert _snapshot(tmp_path) == before


def test_a_directory_is_refused(tmp_path: Path) -> None:
    before = _snapshot(tmp_path)
    for args in (
        [*STORE_RUN, "--store", str(tmp_path)],
        ["records", "list", "--store", str(tmp_path)],
        ["records", "void", "1", "--store", str(tmp_path), "--reason", "x"],
    ):
        code, _, err = _run(args)
        assert code == 2 and err.count("\n") == 1 and "a directory, not a store file" in err
    assert _snapshot(tmp_path) == before


def test_a_refused_command_leaves_no_store_behind(tmp_path: Path) -> None:
    db = tmp_path / "new.db"
    for args in (
        ["conjugate", "-e", PAIR, "--df-mea", "nan", "--step", "5"],  # a measurement of NaN
        ["conjugate", "-e", "cw11-experiment", "--step", "5"],  # nothing measured
        ["conjugate", "-e", PAIR, "--step", "7"],  # a bad grid
        [*STORE_RUN[:-1], "--date", "yesterday"],
    ):
        code, _, err = _run([*args, "--store", str(db)])
        assert code == 2 and err.count("\n") == 1, (args, err)
        assert list(tmp_path.iterdir()) == [], args
    code, _, err = _run([*STORE_RUN, "--store", str(tmp_path / "no" / "r.db")])
    assert code == 2 and "does not exist" in err and list(tmp_path.iterdir()) == []
    assert _run([*STORE_RUN, "--store", str(db)])[0] in (0, 1)  # a good one creates it
    assert db.is_file()


@pytest.mark.parametrize("rid", ["99999999999999999999", "0", "9223372036854775808"])
def test_an_id_out_of_range_is_one_line(store_url: str, rid: str) -> None:
    assert _run([*STORE_RUN, "--store", store_url])[0] in (0, 1)
    for command in (["show", rid], ["rerun", rid], ["void", rid, "--reason", "x"]):
        code, out, err = _run(["records", *command, "--store", store_url])
        assert code == 2 and out == "" and err.count("\n") == 1, (command, err)
        assert f"record id {rid}: no such record" in err and "Traceback" not in err
    code, _, err = _run(["records", "show", "3", "--store", store_url])
    assert code == 2 and "record id 3: no such record" in err


def test_readers_never_wait_for_a_writer_nor_create_tables(tmp_path: Path) -> None:
    db = tmp_path / "r.db"
    assert _run([*STORE_RUN, "--store", str(db), "--serial", "1"])[0] in (0, 1)
    writer = sqlite3.connect(db, isolation_level=None, timeout=0.1)
    writer.execute("BEGIN IMMEDIATE")  # another writer holds the write lock
    writer.execute("INSERT INTO schema_version VALUES (99)")  # ... in the middle of a write
    try:
        start = time.perf_counter()
        code, out, err = _run(["records", "list", "--store", str(db)])
        assert code == 0 and "2 record(s)" in out, err
        assert _run(["records", "show", "1", "--store", str(db)])[0] == 0
        assert _run(["records", "export", "--store", str(db), "--format", "csv"])[0] == 0
        assert time.perf_counter() - start < 10.0  # no waiting for the lock (it was 32 s)
    finally:
        writer.execute("ROLLBACK")
        writer.close()
    empty = tmp_path / "empty.db"
    empty.write_bytes(b"")  # an empty file is an empty SQLite database
    code, _, err = _run(["records", "list", "--store", str(empty)])
    assert code == 2 and "holds no inspection records" in err
    assert empty.read_bytes() == b""  # no table created by a read


def test_a_record_without_its_curve_is_listed(store_url: str) -> None:
    from sqlalchemy import create_engine, text

    from camtol.records.store import store_url as to_url

    assert _run([*STORE_RUN, "--store", store_url])[0] in (0, 1)
    engine = create_engine(to_url(store_url))
    with engine.begin() as conn:
        conn.execute(text("DELETE FROM curves WHERE inspection_id = 2"))
    engine.dispose()
    code, out, _ = _run(["records", "list", "--store", store_url])
    assert code == 0 and "2 record(s)" in out
    with open_store(store_url, readonly=True) as s:
        rec = s.get(2)
    assert rec.n_points == 0 and rec.dr_um.size == 0


def test_a_fresh_postgres_database_is_not_touched_by_readers(store_url: str) -> None:
    """On either engine: reading an empty database creates nothing; a foreign one is kept."""
    from sqlalchemy import create_engine, inspect, text

    from camtol.records.store import store_url as to_url

    url = to_url(store_url)
    if url.startswith("sqlite"):
        Path(url.removeprefix("sqlite:///")).write_bytes(b"")
    code, _, err = _run(["records", "list", "--store", store_url])
    assert code == 2 and "holds no inspection records" in err
    engine = create_engine(url)
    assert inspect(engine).get_table_names() == []
    with engine.begin() as conn:
        conn.execute(text("CREATE TABLE parts (id INTEGER PRIMARY KEY, name TEXT)"))
    code, _, err = _run([*STORE_RUN, "--store", store_url])
    assert code == 2 and "is not a camtol inspection store" in err
    with pytest.raises(RecordError, match="it holds other tables \\(parts\\)"):
        open_store(store_url)  # a writer opened through the API refuses it too
    assert inspect(engine).get_table_names() == ["parts"]
    engine.dispose()


KILLED_WRITER = """
import sqlite3, sys, time
c = sqlite3.connect(sys.argv[1], isolation_level=None)
c.execute("PRAGMA cache_size = 1")  # spill uncommitted pages into the file itself
c.execute("BEGIN IMMEDIATE")
for i in range(2000):
    c.execute("INSERT INTO designs VALUES (?, 'x', ?)", ("sha256:%064x" % i, "y" * 5000))
print("ready", flush=True)
time.sleep(60)
"""


def test_a_reader_after_a_killed_writer_reads_the_last_commit(tmp_path: Path) -> None:
    import signal
    import subprocess
    import sys

    db = tmp_path / "r.db"
    assert _run([*STORE_RUN, "--store", str(db), "--serial", "1"])[0] in (0, 1)
    proc = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(db)], stdout=subprocess.PIPE)
    assert proc.stdout is not None and proc.stdout.readline() == b"ready\n"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    proc.stdout.close()
    assert (tmp_path / "r.db-journal").exists()  # a hot journal: read-only SQLite cannot read
    code, out, err = _run(["records", "list", "--store", str(db)])
    assert code == 0 and "2 record(s)" in out, err  # SQLite's own recovery, then read
    with sqlite3.connect(db) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchall() == [("ok",)]
        assert conn.execute("SELECT count(*) FROM designs").fetchone() == (1,)
    conn.close()
