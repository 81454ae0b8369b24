"""Run every camtol benchmark: ``python bench/run.py``.

Each benchmark prints its own table, then this runner prints every figure again with its
target, the ratio value/target and PASS or MISS (ratios against baselines are measured in
the same run). Timings depend on the machine and on its load: the load average is
printed alongside. Exit status 0 even when a target is missed: benchmarks report, tests
assert.
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))

from common import Figure  # noqa: E402

BENCHMARKS = [
    "bench_analyze",
    "bench_cli",
    "bench_startup",
    "bench_contact",
    "bench_inspection",
    "bench_manufacturing",
    "bench_record",
    "bench_store",
    "bench_spc",
    "bench_montecarlo",
    "bench_pair",
    "bench_dynamics",
]

if __name__ == "__main__":
    figures: list[Figure] = []
    for name in BENCHMARKS:
        print(f"\n== {name}.py")
        sys.stdout.flush()
        result = importlib.import_module(name).main()
        if isinstance(result, list):
            figures += result
        else:  # a benchmark that prints its own verdicts and returns an exit status
            figures.append(Figure(f"{name}: its targets (printed above)", result, "fail", 0))
    print("\n== summary (load average " + ", ".join(f"{x:.1f}" for x in os.getloadavg()) + ")")
    for f in figures:
        print(f.line())
    missed = [f for f in figures if not f.ok]
    print(f"{len(figures) - len(missed)} of {len(figures)} targets met")
