"""Benchmark of the inspection store and lot statistics (docs/records.md).

Run ``python bench/bench_store.py [PARTS] [INSPECTIONS]`` (default 200 parts and 10,000
inspections, 3,600-point curves, SQLite files in a temporary directory; needs
``camtol[store]``):

* ``record``: :meth:`InspectionStore.add`, one transaction per record (design look-up,
  record row, curve blob), against the fair floor: a plain ``sqlite3`` INSERT of the same
  blob in its own transaction on the same kind of file (both commit to disk);
* ``read``: all records with their curves (``records stats`` reads this);
* ``stats``: :func:`camtol.records.lots.lot_statistics` on them.

Targets (a shop records a part in seconds; a lot's statistics should feel instant):
a record ≤ 25 ms and ≤ 5× the plain sqlite3 insert; reading 200 curves ≤ 0.2 s; the
statistics of 200 parts × 3,600 angles ≤ 0.1 s.

And a year of a busy CMM (issue 29), INSPECTIONS records of 3,600 points each with their
raw data (a scan's text, 74 kB, kept zlib-compressed with its SHA-256) and options:

* ``insert``: through the Python API (``make_record``, ``InspectionStore.add`` with the
  scan as a ``RawInput``: one transaction per inspection, as a shop records them),
  against the fair floor in the same run: plain ``sqlite3`` writing the same row, curve
  blob and compressed raw blob in one transaction each (both commit to disk). Target
  ≤ 60 s for 10,000, and ≤ 3× the floor.
* ``records list`` over them: the command (a new process) minus the same command on a
  store of one record (its start-up: interpreter, imports, opening the store). Target
  ≤ 0.5 s.
* ``records export --format csv -o FILE``: the whole command. Target ≤ 2 s.
"""

from __future__ import annotations

import sqlite3
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, best_of, print_figures  # noqa: E402

N_POINTS = 3600


def _small(parts: int) -> list[Figure]:
    from camtol.records.lots import lot_statistics
    from camtol.records.store import Traceability, make_record, open_store

    rng = np.random.default_rng(1)
    curves = rng.normal(0.0, 5.0, size=(parts, N_POINTS))
    with tempfile.TemporaryDirectory() as tmp:
        raw = sqlite3.connect(Path(tmp) / "raw.db", isolation_level=None)
        raw.execute("CREATE TABLE c (id INTEGER PRIMARY KEY, data BLOB)")
        t0 = time.perf_counter()
        for c in curves:
            raw.execute("BEGIN IMMEDIATE")
            raw.execute("INSERT INTO c (data) VALUES (?)", (c.astype("<f4").tobytes(),))
            raw.execute("COMMIT")
        floor = (time.perf_counter() - t0) / parts
        raw.close()

        with open_store(str(Path(tmp) / "records.db")) as store:
            recs = [
                make_record(
                    design_name="bench",
                    design_hash="sha256:" + "0" * 64,
                    method="cmm",
                    cam="",
                    dr_um=c,
                    verdict="pass",
                    tolerance_um=(-22.0, 22.0),
                    traceability=Traceability(serial=str(i), lot="L1"),
                )
                for i, c in enumerate(curves)
            ]
            t0 = time.perf_counter()
            for r in recs:
                store.add(r)
            per_record = (time.perf_counter() - t0) / parts
            read = best_of(lambda: store.records(design="bench", with_curves=True), 3)
            stored = store.records(design="bench", with_curves=True)
        data = [r.dr_um for r in stored]
        stats = best_of(
            lambda: lot_statistics(data, (-22.0, 22.0), [False] * parts, sequence=None), 5
        )
    figures = [
        Figure("store: one record, 3,600 points (SQLite file)", per_record * 1e3, "ms", 25.0),
        Figure(
            "store: record / plain sqlite3 insert (same run)",
            per_record / floor,
            "x",
            5.0,
            note=f"floor {floor * 1e3:.2f} ms",
        ),
        Figure(f"store: read {parts} records with curves", read, "s", 0.2),
        Figure(f"lots: statistics of {parts} parts x {N_POINTS} angles", stats, "s", 0.1),
    ]
    return figures


def _scans(count: int, rng: np.random.Generator) -> list[bytes]:
    """Distinct CMM scan texts of 3,600 points (x_mm, y_mm), as a CMM writes them."""
    theta = np.linspace(0.0, 2 * np.pi, N_POINTS, endpoint=False)
    out = []
    for _ in range(count):
        r = 40.0 + rng.normal(0.0, 0.005, N_POINTS)
        rows = "".join(
            f"{x:.6f},{y:.6f}\n" for x, y in zip(r * np.cos(theta), r * np.sin(theta), strict=True)
        )
        out.append(("x_mm,y_mm\n" + rows).encode())
    return out


def _cli_time(args: list[str], repeat: int = 3) -> float:
    """Best wall time of a camtol command run as a new process. [s]"""

    def run() -> None:
        subprocess.run(
            [sys.executable, "-m", "camtol", *args], check=True, stdout=subprocess.DEVNULL
        )

    return best_of(run, repeat)


def _large(inspections: int) -> list[Figure]:
    from camtol.records.raw import RawInput
    from camtol.records.store import Traceability, make_record, open_store

    rng = np.random.default_rng(2)
    pool = _scans(50, rng)  # 50 distinct scans; each part's is made distinct by its serial
    curves = rng.normal(0.0, 5.0, size=(50, N_POINTS))
    raws = [b"# serial %d\n" % i + pool[i % 50] for i in range(inspections)]
    options = {"datum": {"mode": "fit"}, "step_deg": 0.1, "harmonics": 100, "n_points": N_POINTS}
    with tempfile.TemporaryDirectory() as tmp:
        floor_db = sqlite3.connect(Path(tmp) / "floor.db", isolation_level=None)
        floor_db.execute(
            "CREATE TABLE r (id INTEGER PRIMARY KEY, serial TEXT, lot TEXT, verdict TEXT,"
            " max_um REAL, min_um REAL, form_um REAL, sha TEXT, options TEXT)"
        )
        floor_db.execute("CREATE TABLE c (id INTEGER PRIMARY KEY, data BLOB)")
        floor_db.execute("CREATE TABLE b (sha TEXT PRIMARY KEY, data BLOB)")
        t0 = time.perf_counter()
        for i, raw in enumerate(raws):
            c = curves[i % 50].astype("<f4")
            sha = RawInput("scan", "s.csv", raw).sha256
            floor_db.execute("BEGIN IMMEDIATE")
            floor_db.execute(
                "INSERT INTO r VALUES (NULL, ?, 'L1', 'pass', ?, ?, ?, ?, ?)",
                (str(i), float(c.max()), float(c.min()), float(c.max() - c.min()), sha, "{}"),
            )
            floor_db.execute("INSERT INTO c VALUES (NULL, ?)", (c.tobytes(),))
            floor_db.execute("INSERT INTO b VALUES (?, ?)", (sha, zlib.compress(raw, 1)))
            floor_db.execute("COMMIT")
        floor = time.perf_counter() - t0
        floor_db.close()

        db = str(Path(tmp) / "records.db")
        with open_store(db) as store:
            t0 = time.perf_counter()
            for i, raw in enumerate(raws):
                scan = RawInput("scan", f"part-{i}.csv", raw)
                rec = make_record(
                    design_name="bench",
                    design_hash="sha256:" + "0" * 64,
                    method="cmm",
                    cam="",
                    dr_um=curves[i % 50],
                    verdict="pass",
                    tolerance_um=(-22.0, 22.0),
                    traceability=Traceability(serial=str(i), lot=f"L{i // 1000}"),
                    judged_on="dn",
                    decision_rule="simple",
                    raw_sha256=scan.sha256,
                    options=options,
                )
                store.add(rec, inputs=[scan])
            insert = time.perf_counter() - t0
        one = str(Path(tmp) / "one.db")
        with open_store(one) as store:
            store.add(rec, inputs=[scan])
        start_up = _cli_time(["records", "list", "--store", one])
        listing = _cli_time(["records", "list", "--store", db]) - start_up
        out = str(Path(tmp) / "all.csv")
        export = _cli_time(["records", "export", "--store", db, "--format", "csv", "-o", out])
        size = Path(db).stat().st_size
    n = f"{inspections:,}"
    return [
        Figure(
            f"store: insert {n} x 3,600 points with raw data",
            insert,
            "s",
            60.0 * inspections / 10_000,
            note=f"{insert / inspections * 1e3:.2f} ms each; {size / 2**20:.0f} MiB",
        ),
        Figure(
            "store: insert / plain sqlite3 of the same (same run)",
            insert / floor,
            "x",
            3.0,
            note=f"floor {floor:.1f} s",
        ),
        Figure(
            f"records list over {n}, beyond start-up",
            listing,
            "s",
            0.5,
            note=f"start-up {start_up:.2f} s",
        ),
        Figure(f"records export --format csv of {n}", export, "s", 2.0),
    ]


def main(parts: int = 200, inspections: int = 10_000) -> list[Figure]:
    figures = _small(parts) + _large(inspections)
    print_figures("inspection store and lot statistics", figures)
    return figures


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    main(*args)
