"""Long fuzz run of the command line: ``python bench/fuzz.py [--cases N] [--seed S]``.

Runs the bad-input seeds of ``tests/fuzz/seeds.py`` (issue 32: lift tables with missing,
repeated, decreasing or unequal rows, half or two revolutions, a closing 360° row that
disagrees, huge lifts; an IT grade on an offset of 0 through every command; ...), each of
which must be refused with one line and exit 2, then the four strategies of
``tests/fuzz`` (mutated examples, random designs with independently checked outputs,
random bytes and encodings, random flags) for N cases in total without stopping at the
first finding, and prints the number of runs, the exit codes, and every distinct finding
(traceback, accepted impossible geometry, NaN in an output, bad error line) with one
example each. Exit status 1 when anything was found.

Not a benchmark of speed: it is the long profile of the fuzz suite (issue 9), also
available as ``pytest -m fuzz`` (failing at the first finding, with shrinking).
"""

from __future__ import annotations

import argparse
import collections
import re
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "fuzz"))

import fuzz_harness as fh  # noqa: E402
import seeds as sd  # noqa: E402
import test_fuzz as tf  # noqa: E402
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


def _signature(problem: str) -> str:
    """Group findings: drop numbers and paths so one class counts once."""
    s = re.sub(r"'[^']*'", "'…'", problem)
    s = re.sub(r"-?\d+(\.\d+)?(e[-+]?\d+)?", "#", s)
    return s[:240]


def main() -> int:
    """Run the fuzz campaign and print its findings."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000, help="total cases (all strategies)")
    parser.add_argument("--seed", type=int, default=0, help="hypothesis seed")
    ns = parser.parse_args()
    per = max(1, ns.cases // 4)
    runs: collections.Counter[str] = collections.Counter()
    findings: dict[str, tuple[int, str]] = {}

    def record(what: str, outcomes: list[fh.Outcome]) -> None:
        for o in outcomes:
            runs[f"{o.args[0] if o.args else '?'} exit {o.code}"] += 1
            for p in getattr(o, "problems", []):
                key = _signature(f"{o.args[0]}: {p}")
                n, example = findings.get(key, (0, f"{what} :: {p}"))
                findings[key] = (n + 1, example)

    conf = settings(
        max_examples=per,
        deadline=None,
        database=None,
        derandomize=False,
        suppress_health_check=list(HealthCheck),
        phases=["generate"],
    )

    @conf
    @given(tf.mutated_example())
    def mutated(case: tuple[str, str, str]) -> None:
        record(case[0], fh.run_design(case[1], case[2]))

    @conf
    @given(tf.random_design())
    def designs(case: tuple[str, str]) -> None:
        for command in fh.COMMANDS[:3]:
            record(case[0][:300], fh.run_design(case[1], command))

    @conf
    @given(tf.design_bytes())
    def raw(data: bytes) -> None:
        record(repr(data[:60]), fh.run_design(data, "analyze"))

    @conf
    @given(st.data())
    def flags(data: Any) -> None:
        import tempfile

        with tempfile.TemporaryDirectory(prefix="camtol-fuzz-") as d:
            tmp = Path(d)
            (tmp / "d.toml").write_text(fh.example_text("cw11-conjugate"), encoding="utf-8")
            (tmp / "m.csv").write_text("theta_deg,um\n0,20\n180,22\n", encoding="utf-8")
            before = {p.name: p.read_bytes() for p in tmp.iterdir()}
            args = data.draw(tf.flag_line(tmp))
            o = fh.run_cli(args, tf._flag_outputs(args))
            o.problems = fh.judge(o)  # type: ignore[attr-defined]
            for name, content in before.items():
                if name in tf.flag_inputs(args, tmp) and (tmp / name).read_bytes() != content:
                    o.problems.append(f"input {name} was modified")  # type: ignore[attr-defined]
            record(" ".join(args)[:300], [o])

    import random

    random.seed(ns.seed)
    t0 = time.perf_counter()
    import tempfile

    t = time.perf_counter()
    all_seeds = sd.seeds()
    for seed in all_seeds:
        with tempfile.TemporaryDirectory(prefix="camtol-seed-") as d:
            o, problems = sd.run_seed(seed, Path(d))
        o.problems = problems  # type: ignore[attr-defined]
        record(f"seed {seed.name}", [o])
    print(f"{'seeds':8s} {len(all_seeds)} cases in {time.perf_counter() - t:.0f} s", flush=True)
    for name, fn in (("mutated", mutated), ("designs", designs), ("bytes", raw), ("flags", flags)):
        t = time.perf_counter()
        fn()
        print(f"{name:8s} {per} cases in {time.perf_counter() - t:.0f} s", flush=True)
    print(f"\n{sum(runs.values())} CLI runs in {time.perf_counter() - t0:.0f} s")
    for k, n in sorted(runs.items()):
        print(f"  {k:24s} {n}")
    print(f"\nfindings: {len(findings)} distinct")
    for _, (n, example) in sorted(findings.items(), key=lambda kv: -kv[1][0]):
        print(f"  [{n}x] {example[:600]}")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
