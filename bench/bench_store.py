"""Benchmark of the inspection store and lot statistics (docs/records.md).

Run ``python bench/bench_store.py [PARTS]`` (default 200 parts, 3,600-point curves, a
SQLite file in a temporary directory; needs ``camtol[store]``):

* ``record``: :meth:`InspectionStore.add`, one transaction per record (design look-up,
  record row, curve blob), against the fair floor: a plain ``sqlite3`` INSERT of the same
  blob in its own transaction on the same kind of file (both commit to disk);
* ``read``: all records with their curves (``records stats`` reads this);
* ``stats``: :func:`camtol.records.lots.lot_statistics` on them.

Targets (a shop records a part in seconds; a lot's statistics should feel instant):
a record ≤ 25 ms and ≤ 5× the plain sqlite3 insert; reading 200 curves ≤ 0.2 s; the
statistics of 200 parts × 3,600 angles ≤ 0.1 s.
"""

from __future__ import annotations

import sqlite3
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, best_of, print_figures  # noqa: E402

N_POINTS = 3600


def main(parts: int = 200) -> list[Figure]:
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
    print_figures("inspection store and lot statistics", figures)
    return figures


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 200)
