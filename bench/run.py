"""Run every camtol benchmark: ``python bench/run.py``.

Each benchmark prints its figures and ratios (measured in the same run against a plain or
brute-force reference); this runner only calls them one after the other.
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

HERE = Path(__file__).parent
BENCHMARKS = [
    "bench_analyze.py",
    "bench_contact.py",
    "bench_manufacturing.py",
    "bench_montecarlo.py",
]

if __name__ == "__main__":
    for name in BENCHMARKS:
        print(f"\n== {name}")
        sys.stdout.flush()
        runpy.run_path(str(HERE / name), run_name="__main__")
