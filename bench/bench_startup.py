"""Start-up of ``camtol analyze`` and ``camtol report`` against their libraries (issue 32).

Run: ``python bench/bench_startup.py [--rounds N]``. Measured side by side in one run,
interleaved round by round so that a change of load hits every command alike:

- ``camtol analyze --example cw06-translating`` against ``python -c "import numpy"``
  (target: at most 2.5 times);
- ``camtol report --example cw06-translating -o r.html`` against
  ``python -c "import matplotlib.pyplot"`` (target: at most 2 times).

Each command runs in a fresh interpreter (``python -m camtol``, as the ``camtol`` script
does). The figure is the best wall time of the rounds; the CPU time of the child (user +
system, which waiting for a core does not inflate) is printed beside it. Every command
runs once first, unmeasured, with the bytecode cache in a temporary directory
(``PYTHONPYCACHEPREFIX``, and ``PYTHONDONTWRITEBYTECODE`` cleared), so that camtol is
measured as installed (pip compiles it) and not recompiled from source on every run, and
the baselines alike.

Beside the targets, the run measures the floors the libraries set: a bare interpreter
importing what ``analyze`` cannot do without (numpy, click, rich's console and table), the
same plus camtol's design-file layer (the tables of fields every design file is validated
with, and the design and mechanism modules they build), and what ``report`` adds
(matplotlib.pyplot with the same libraries). Their ratios say how much of each target is
spent before camtol's own work starts.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, print_figures  # noqa: E402

CAMTOL = [sys.executable, "-m", "camtol"]
#: What ``camtol analyze`` imports from other projects and cannot do without.
ANALYZE_LIBRARIES = "numpy, click, rich.console, rich.table"


def _run(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall time and child CPU time (user + system) of one run of ``cmd``. [s]"""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, env=env, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def measure(rounds: int = 7) -> dict[str, tuple[float, float]]:
    """Best wall and best CPU time of each command over interleaved rounds. [s]"""
    with tempfile.TemporaryDirectory(prefix="camtol-bench-startup-") as tmp:
        env = dict(os.environ)
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(Path(tmp) / "pycache")
        report = str(Path(tmp) / "r.html")
        commands = {
            "numpy": [sys.executable, "-c", "import numpy"],
            "analyze": [*CAMTOL, "analyze", "--example", "cw06-translating"],
            "pyplot": [sys.executable, "-c", "import matplotlib.pyplot"],
            "report": [*CAMTOL, "report", "--example", "cw06-translating", "-o", report],
            "libraries": [sys.executable, "-c", f"import {ANALYZE_LIBRARIES}"],
            "design layer": [
                sys.executable,
                "-c",
                f"import {ANALYZE_LIBRARIES}; import camtol.config.design_file",
            ],
            "report libraries": [
                sys.executable,
                "-c",
                f"import {ANALYZE_LIBRARIES}, matplotlib.pyplot",
            ],
        }
        for cmd in commands.values():  # warm-up: fill the bytecode cache
            _run(cmd, env)
        best = {name: (float("inf"), float("inf")) for name in commands}
        for _ in range(rounds):
            for name, cmd in commands.items():
                wall, cpu = _run(cmd, env)
                best[name] = (min(best[name][0], wall), min(best[name][1], cpu))
    return best


def main(rounds: int = 7) -> list[Figure]:
    """Run the benchmark, print its table, return its figures."""
    best = measure(rounds)
    for name, (wall, cpu) in best.items():
        print(f"  {name:8s} best wall {wall:.3f} s, best CPU {cpu:.3f} s")
    print(f"load average while measuring: {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    cpu_note = "CPU-time ratio x{:.2f}"
    figures = [
        Figure(
            "analyze cw06 start-up / import numpy",
            best["analyze"][0] / best["numpy"][0],
            "x",
            2.5,
            note=cpu_note.format(best["analyze"][1] / best["numpy"][1]),
        ),
        Figure(
            "report cw06 -o r.html / import matplotlib.pyplot",
            best["report"][0] / best["pyplot"][0],
            "x",
            2.0,
            note=cpu_note.format(best["report"][1] / best["pyplot"][1]),
        ),
    ]
    print_figures("start-up (bench_startup.py)", figures)
    numpy, pyplot = best["numpy"][0], best["pyplot"][0]
    print("library floors (wall time against the same baselines):")
    for name, what, base, base_name in (
        ("libraries", ANALYZE_LIBRARIES, numpy, "import numpy"),
        ("design layer", "those + camtol.config.design_file", numpy, "import numpy"),
        ("report libraries", "those + matplotlib.pyplot", pyplot, "import matplotlib.pyplot"),
    ):
        wall = best[name][0]
        print(f"  import {what}: {wall:.3f} s, x{wall / base:.2f} {base_name}")
    return figures


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7, help="interleaved rounds")
    main(parser.parse_args().rounds)
