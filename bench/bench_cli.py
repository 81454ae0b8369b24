"""Benchmark of the command line: start-up time and peak memory (issue 8, "Speed").

Run: ``python bench/bench_cli.py``. Each command runs in a fresh interpreter
(``python -m camtol ...``, as the ``camtol`` script does), so the figures include Python's
own start-up, measured alone in the same run for reference:

- wall time of ``camtol --help`` and ``camtol examples`` (best of 7; target 0.1 s);
- peak resident memory (``ru_maxrss`` of the child) of
  ``camtol analyze --example cw06-translating --step 0.001`` (360,001 angles; target
  120 MiB), with ``--step 1`` alongside: the interpreter and libraries alone.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, print_figures  # noqa: E402

CAMTOL = [sys.executable, "-m", "camtol"]
_RSS = (
    "import resource, subprocess, sys\n"
    "subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, check=True)\n"
    "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
)


def wall(cmd: list[str], repeat: int = 7) -> float:
    """Best wall time of running ``cmd`` to completion. [s]"""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, check=True)
        best = min(best, time.perf_counter() - t0)
    return best


def peak_rss_mib(cmd: list[str]) -> float:
    """Peak resident memory of ``cmd`` run in its own process (Linux ru_maxrss). [MiB]"""
    out = subprocess.run(
        [sys.executable, "-c", _RSS, *cmd], capture_output=True, text=True, check=True
    ).stdout
    return int(out.split()[-1]) / 1024.0  # KiB on Linux


def main() -> list[Figure]:
    """Run the benchmark, print its table, return its figures."""
    python = wall([sys.executable, "-c", "pass"])
    imports = wall([sys.executable, "-c", "import numpy, click"], repeat=3)
    help_s = wall([*CAMTOL, "--help"])
    examples_s = wall([*CAMTOL, "examples"])
    analyze = [*CAMTOL, "analyze", "--example", "cw06-translating", "--quiet"]
    rss_base = peak_rss_mib([*analyze, "--step", "1"])
    rss = peak_rss_mib([*analyze, "--step", "0.001"])
    print(f"python -c pass: {python:.3f} s; python -c 'import numpy, click': {imports:.3f} s")
    print(f"analyze --step 1 (interpreter and libraries): {rss_base:.1f} MiB peak RSS")
    print(f"load average while measuring: {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    figures = [
        Figure("camtol --help, wall", help_s, "s", 0.1),
        Figure("camtol examples, wall", examples_s, "s", 0.1),
        Figure("analyze cw06-translating --step 0.001, peak RSS", rss, "MiB", 120.0),
    ]
    print_figures("command line (bench_cli.py)", figures)
    return figures


if __name__ == "__main__":
    main()
