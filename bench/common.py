"""Shared helpers of the benchmarks: timing, and figures printed with target and verdict."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Figure", "best_of", "best_of_both", "print_figures"]


def best_of(fn: Callable[[], object], repeat: int) -> float:
    """Best wall time of ``repeat`` calls. [s]"""
    return best_of_both(fn, repeat)[0]


def best_of_both(fn: Callable[[], object], repeat: int) -> tuple[float, float]:
    """Best wall time and best CPU time of this thread over ``repeat`` calls. [s]

    On a loaded machine the wall time includes waiting for a core; the thread's CPU time
    does not, so it shows what the code itself costs.

    Each call's result is held until the next call has returned, as a caller holds what
    it asked for. A result dropped at once leaves the whole of its memory free at the top
    of the C library's heap, which glibc then returns to the kernel (its trim threshold
    is twice the largest block freed so far), and the next call faults every page back
    in: half of an analysis at 36,001 angles (docs/performance.md). Held, the previous
    result is freed below the new one and its memory is reused. Every side of a ratio
    is timed by this function, so baselines are held alike.
    """
    wall = cpu = math.inf
    result: object = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.thread_time()
        result = fn()  # the previous result lives until this one is returned
        cpu = min(cpu, time.thread_time() - c0)
        wall = min(wall, time.perf_counter() - t0)
    del result
    return wall, cpu


@dataclass(frozen=True)
class Figure:
    """A measured figure with its target (at most ``target``, or at least if ``at_least``)."""

    name: str
    value: float
    unit: str
    target: float
    at_least: bool = False
    note: str = ""

    @property
    def ok(self) -> bool:
        """Whether the figure meets its target."""
        return self.value >= self.target if self.at_least else self.value <= self.target

    def line(self) -> str:
        """One printed row: figure, target, value/target and PASS or MISS."""
        sign = ">=" if self.at_least else "<="
        ratio = self.value / self.target if self.target else math.inf
        verdict = "PASS" if self.ok else "MISS"
        note = f"  ({self.note})" if self.note else ""
        return (
            f"  {self.name:<52s} {self.value:10.4g} {self.unit:<4s} target {sign} {self.target:<8g}"
            f" x{ratio:5.2f}  {verdict}{note}"
        )


def print_figures(title: str, figures: list[Figure]) -> None:
    """Print a block of figures under a title."""
    print(title)
    for f in figures:
        print(f.line())
