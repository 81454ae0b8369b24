"""Benchmark of a lot's statistical process control and the quality page (issue 30).

Run ``python bench/bench_spc.py [INSPECTIONS] [POINTS]`` (default 10,000 inspections of
one lot with 3,600-point curves, a SQLite file in a temporary directory; needs
``camtol[store]`` and, for the page, ``camtol[serve]``):

* ``records stats`` over them (capability with intervals, normality, I-MR chart, Western
  Electric rules, per-angle curves, yield, trend): the command in a new process minus
  the same command on a lot of 3 records (its start-up: interpreter, imports, opening
  the store). Target ≤ 1 s (issue 30; 2.4 s over 1,000 before it). The fair floor in the
  same run: reading the records with their curves through the Python API, which the
  command cannot avoid.
* ``records stats --json`` the same way (the JSON lists every part).
* the statistics alone (:func:`summarise_lot` on records already read).
* the quality page's lot page (``GET /lot?...``, Flask's test client in this process,
  after one warm-up request): target ≤ 0.5 s; its floor: the records read without curves
  (the query the page makes).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, best_of, print_figures  # noqa: E402


def _build(path: str, n: int, points: int, lot: str) -> None:
    from camtol.records.store import Traceability, make_record, open_store

    rng = np.random.default_rng(3)
    theta = np.arange(points) * (2 * np.pi / points)
    shape = 20.0 * np.cos(theta) + 3.0 * np.sin(3 * theta)
    offsets = rng.normal(0.0, 2.0, n)
    recs = [
        make_record(
            design_name="bench",
            design_hash="sha256:" + "0" * 64,
            method="cmm",
            cam="",
            dr_um=shape + off,
            verdict="pass" if off + 23.0 <= 30.0 else "fail",
            tolerance_um=(-30.0, 30.0),
            traceability=Traceability(serial=str(i + 1), lot=lot),
            judged_on="dr",
        )
        for i, off in enumerate(offsets)
    ]
    with open_store(path) as store:
        for k in range(0, n, 1000):  # a few large transactions: set-up, not measured
            store.add_all(recs[k : k + 1000])


def _command(args: list[str], repeat: int) -> float:
    def run() -> None:
        subprocess.run(
            [sys.executable, "-m", "camtol", *args], check=True, stdout=subprocess.DEVNULL
        )

    return best_of(run, repeat)


def main(inspections: int = 10_000, points: int = 3600) -> list[Figure]:
    from camtol.records.lot_summary import summarise_lot
    from camtol.records.store import open_store

    figures: list[Figure] = []
    with tempfile.TemporaryDirectory() as tmp:
        db, small = str(Path(tmp) / "lot.db"), str(Path(tmp) / "small.db")
        t0 = time.perf_counter()
        _build(db, inspections, points, "BIG")
        _build(small, 3, points, "BIG")
        print(f"  (set-up: {inspections} records in {time.perf_counter() - t0:.1f} s)")
        stats = ["records", "stats", "--design", "bench", "--lot", "BIG"]
        start_up = _command([*stats, "--store", small], 3)
        whole = _command([*stats, "--store", db], 3)
        whole_json = _command([*stats, "--store", db, "--json"], 3)

        def read() -> object:
            with open_store(db, create=False, readonly=True) as s:
                return s.records(design="bench", lot="BIG", with_curves=True, with_details=True)

        floor = best_of(read, 3)
        with open_store(db, create=False, readonly=True) as s:
            recs = s.records(design="bench", lot="BIG", with_curves=True, with_details=True)
        compute = best_of(lambda: summarise_lot(recs, design="bench", lot="BIG"), 3)
        recs.clear()  # free the curves before the page is measured
        figures += [
            Figure(
                f"records stats over {inspections} x {points}, beyond start-up",
                whole - start_up,
                "s",
                1.0,
                note=f"start-up {start_up:.2f} s; reading the curves alone {floor:.2f} s,"
                f" ratio {(whole - start_up) / floor:.2f}",
            ),
            Figure(
                f"records stats --json over {inspections}, beyond start-up",
                whole_json - start_up,
                "s",
                1.0,
            ),
            Figure(f"summarise_lot on {inspections} records read", compute, "s", 0.5),
        ]
        try:
            from camtol.web.app import create_app
        except ImportError:
            print("  (the lot page needs camtol[serve]: skipped)")
        else:
            client = create_app(db).test_client()
            url = "/lot?design=bench&cam=single&lot=BIG"
            assert client.get(url).status_code == 200  # warm-up: imports, first query

            def query() -> object:
                with open_store(db, create=False, readonly=True) as s:
                    return s.records(design="bench", lot="BIG", cam="", with_details=True)

            page = best_of(lambda: client.get(url), 3)
            q = best_of(query, 3)
            figures.append(
                Figure(
                    f"quality page: lot page over {inspections}",
                    page,
                    "s",
                    0.5,
                    note=f"its query alone {q:.2f} s, ratio {page / q:.2f}",
                )
            )
    print_figures("lot statistics (SPC) and the quality page", figures)
    return figures


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:3]]
    main(*args)
