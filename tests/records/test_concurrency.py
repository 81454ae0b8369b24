"""Concurrent writers and killed writers (issue 29's validation), on SQLite and PostgreSQL.

* 8 processes × 50 ``camtol conjugate --store`` runs each, starting from an empty
  database: every run succeeds (no error surfaced: the design row is inserted race-free,
  the tables created once) and every run that reported ids has exactly those records.
* 50 SIGKILLs at random moments of ``--store`` runs on SQLite: the file's integrity check
  is ok, foreign keys hold, no record lacks its curve or raw inputs, no pair lacks a cam.
* A run killed right after its commit (it never reported success), run again with the same
  data: refused as a duplicate, not stored twice.

The processes are forked from the test (camtol already imported) and run the command line
in-process, so the runs cost their work, not an interpreter's start-up each.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import random
import signal
import sqlite3
import time
import traceback
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")

from camtol.cli.app import main
from camtol.records.store import open_store

PAIR = "cw11-conjugate"
RUN = ["conjugate", "-e", PAIR, "--df-mea", "10", "--step", "30", "-q"]
N_PROCESSES, N_RUNS, N_KILLS = 8, 50, 50

if not hasattr(os, "fork"):  # pragma: no cover - Windows
    pytest.skip("the process tests fork", allow_module_level=True)


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


def _fork(body: Callable[[], None], errors: Path) -> int:
    """Run ``body`` in a forked child; its traceback (if any) goes to ``errors``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # fork with threads (3.12+)
        pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        status = 0
        try:
            body()
        except BaseException:
            errors.write_text(traceback.format_exc())
            status = 1
        finally:
            os._exit(status)
    return pid


def _wait(pid: int) -> int:
    _, status = os.waitpid(pid, 0)
    return status


def test_8_processes_x_50_runs_lose_nothing(store_url: str, tmp_path: Path) -> None:
    def writer(tag: int) -> Callable[[], None]:
        def body() -> None:
            out = []
            for k in range(N_RUNS):
                code, text, err = _run([*RUN, "--store", store_url, "--serial", f"{tag}-{k}"])
                out.append({"code": code, "out": text + err, "serial": f"{tag}-{k}"})
            (tmp_path / f"w{tag}.json").write_text(json.dumps(out))

        return body

    pids = [_fork(writer(t), tmp_path / f"w{t}.err") for t in range(N_PROCESSES)]
    statuses = [_wait(pid) for pid in pids]
    errors = [p.read_text() for p in sorted(tmp_path.glob("*.err"))]
    assert statuses == [0] * N_PROCESSES and errors == [], errors
    runs = [
        r for t in range(N_PROCESSES) for r in json.loads((tmp_path / f"w{t}.json").read_text())
    ]
    assert len(runs) == N_PROCESSES * N_RUNS
    assert [r for r in runs if r["code"] not in (0, 1) or r["out"]] == []  # quiet: no error
    with open_store(store_url, readonly=True) as s:
        recs = s.records()
    assert len(recs) == 2 * N_PROCESSES * N_RUNS == len({r.id for r in recs})
    by_serial: dict[str, list[str]] = {}
    for rec in recs:
        by_serial.setdefault(rec.serial, []).append(rec.cam)
    # every run that reported success has its records: cams A and B, once
    assert {r["serial"]: ["A", "B"] for r in runs} == {k: sorted(v) for k, v in by_serial.items()}


def _check_sqlite(path: Path) -> dict[str, int]:
    """Integrity, foreign keys, and no partial record; return the table counts."""
    conn = sqlite3.connect(path)
    try:
        assert conn.execute("PRAGMA integrity_check").fetchall() == [("ok",)]
        assert conn.execute("PRAGMA foreign_key_check").fetchall() == []
        no_curve = conn.execute(
            "SELECT id FROM inspections WHERE id NOT IN (SELECT inspection_id FROM curves)"
        ).fetchall()
        no_input = conn.execute(
            "SELECT id FROM inspections WHERE id NOT IN"
            " (SELECT inspection_id FROM inspection_inputs)"
        ).fetchall()
        half_pairs = conn.execute(
            "SELECT serial FROM inspections GROUP BY serial HAVING count(*) != 2"
        ).fetchall()
        assert (no_curve, no_input, half_pairs) == ([], [], [])
        return {
            t: int(conn.execute(f"SELECT count(*) FROM {t}").fetchone()[0])
            for t in ("inspections", "curves", "raw_inputs")
        }
    finally:
        conn.close()


def test_50_sigkills_during_store_leave_no_partial_record(tmp_path: Path) -> None:
    db = tmp_path / "r.db"
    rng = random.Random(29)
    assert _run([*RUN, "--store", str(db), "--serial", "first"])[0] in (0, 1)
    stored = 2
    for kill in range(N_KILLS):

        def body(kill: int = kill) -> None:
            for k in range(10_000):  # until killed
                _run([*RUN, "--store", str(db), "--serial", f"{kill}-{k}", "-q"])

        pid = _fork(body, tmp_path / f"k{kill}.err")
        time.sleep(rng.uniform(0.02, 0.3))
        os.kill(pid, signal.SIGKILL)
        assert os.WIFSIGNALED(_wait(pid))
        if db.exists():
            counts = _check_sqlite(db)
            assert counts["inspections"] == counts["curves"] >= stored
            stored = counts["inspections"]
    assert list(tmp_path.glob("*.err")) == []
    assert stored > 0  # the kills landed during runs that had stored some records
    code, out, _ = _run(["records", "list", "--store", str(db)])
    assert code == 0 and f"{stored} record(s)" in out


def test_a_run_killed_after_its_commit_is_refused_as_a_duplicate(
    store_url: str, tmp_path: Path
) -> None:
    args = [*RUN[:-1], "--json", "--store", store_url, "--serial", "42"]

    def body() -> None:
        import camtol.cli.conjugate as cc

        real = cc.add_records

        def commit_then_die(*a: Any, **k: Any) -> list[int]:
            ids = real(*a, **k)  # committed ...
            os.kill(os.getpid(), signal.SIGKILL)  # ... but never reported
            return ids

        cc.add_records = commit_then_die  # type: ignore[assignment]
        _run(args)

    assert os.WIFSIGNALED(_wait(_fork(body, tmp_path / "c.err")))
    with open_store(store_url, readonly=True) as s:
        assert [(r.serial, r.cam) for r in s.records()] == [("42", "A"), ("42", "B")]
    code, out, err = _run(args)  # the operator runs it again: refused, nothing stored twice
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "serial='42', cam A: the same raw data (sha256:" in err and "is already record 1" in err
    with open_store(store_url, readonly=True) as s:
        assert len(s.records()) == 2
    code, out, _ = _run([*args, "--allow-duplicate"])  # unless the operator says so
    assert code in (0, 1) and json.loads(out)["record_ids"] == [3, 4]
    with open_store(store_url, readonly=True) as s:
        assert [r.duplicate_allowed for r in s.records()] == [False, False, True, True]
