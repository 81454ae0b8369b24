"""Run every camtol benchmark: ``python bench/run.py``.

Each benchmark runs in an interpreter of its own (a peak-memory figure is the process's
high-water mark, and one benchmark's heap must not slow or inflate the next) and prints
its own table; then this runner prints every figure again with its target, the ratio
value/target and PASS or MISS (ratios against baselines are measured in the same run).
Timings depend on the machine and on its load: the load average is printed alongside.
Exit status 0 even when a target is missed: benchmarks report, tests assert.
"""

from __future__ import annotations

import dataclasses
import importlib
import json
import os
import subprocess
import sys
import tempfile
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


def run_one(name: str, figures_path: str) -> None:
    """Run one benchmark in this interpreter and write its figures as JSON."""
    result = importlib.import_module(name).main()
    if isinstance(result, list):
        figures = result
    else:  # a benchmark that prints its own verdicts and returns an exit status
        figures = [Figure(f"{name}: its targets (printed above)", result, "fail", 0)]
    Path(figures_path).write_text(
        json.dumps([dataclasses.asdict(f) for f in figures], default=float)
    )


def run_isolated(name: str) -> list[Figure]:
    """Run one benchmark in a fresh interpreter and return its figures."""
    with tempfile.TemporaryDirectory(prefix="camtol-bench-") as tmp:
        path = str(Path(tmp) / "figures.json")
        subprocess.run([sys.executable, __file__, "--one", name, path], check=True)
        return [Figure(**f) for f in json.loads(Path(path).read_text())]


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--one":
        run_one(sys.argv[2], sys.argv[3])
        sys.exit(0)
    figures: list[Figure] = []
    for name in BENCHMARKS:
        print(f"\n== {name}.py")
        sys.stdout.flush()
        figures += run_isolated(name)
    print("\n== summary (load average " + ", ".join(f"{x:.1f}" for x in os.getloadavg()) + ")")
    for f in figures:
        print(f.line())
    missed = [f for f in figures if not f.ok]
    print(f"{len(figures) - len(missed)} of {len(figures)} targets met")
