"""Where ``analyse`` spends its time: ``python bench/profile_analyze.py [ANGLES] [DESIGN ...]``.

Not a benchmark with targets (``bench_analyze.py`` has them): it splits the best of
several ``analyse`` calls of each built-in design (or the ones named) into its stages, so
that work on the speed targets of issue 8 starts from measurements:

- ``grid engine``: the engine on the analysis grid (cam A: kinematics and sensitivities);
- ``checks``: the design's geometry checks (every cam, on grids of their own);
- ``other cams``: the kinematics of cam B of a conjugate pair on the same grid;
- ``refinement``: the engine calls on the extremes' windows;
- ``extremes scan``: the rest of the extremes' search (curves, argmax, windows);
- ``rest``: everything else (tolerances, geometry figures, motion peaks, checks).

Each stage is timed by wrapping the function ``camtol.analysis.result`` calls for it; the call
with the smallest total is reported. [ms]
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from collections.abc import Callable
from typing import Any

import camtol.analysis.result as analysis_module
import camtol.analysis.validity as validity_module
from camtol.config.design_file import example_names, load_example

STAGES = ("checks", "grid engine", "other cams", "refinement", "extremes scan", "rest")


def _timed(
    fn: Callable[..., Any], record: Callable[[float, tuple[Any, ...]], None]
) -> Callable[..., Any]:
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t0 = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            record(time.perf_counter() - t0, args)

    return wrapper


def profile(name: str, angles: int, repeat: int) -> dict[str, float]:
    """Stage times of the fastest of ``repeat`` analyses of one design. [ms]"""
    design = load_example(name)
    step = 360.0 / (angles - 1)
    times: dict[str, float] = {}
    inside_extremes = [False]

    def engine(dt: float, args: tuple[Any, ...]) -> None:
        key = "refinement" if inside_extremes[0] else "grid engine"
        times[key] = times.get(key, 0.0) + dt

    def other(dt: float, args: tuple[Any, ...]) -> None:
        times["other cams"] = times.get("other cams", 0.0) + dt

    def checks(dt: float, args: tuple[Any, ...]) -> None:
        times["checks"] = times.get("checks", 0.0) + dt

    def extremes(dt: float, args: tuple[Any, ...]) -> None:
        times["extremes"] = times.get("extremes", 0.0) + dt

    originals = {
        key: getattr(analysis_module, key) for key in ("evaluate_engine", "kinematics", "_extremes")
    }
    extremes_fn = originals["_extremes"]

    def flagged_extremes(*args: Any, **kwargs: Any) -> Any:
        inside_extremes[0] = True
        try:
            return extremes_fn(*args, **kwargs)
        finally:
            inside_extremes[0] = False

    setattr(analysis_module, "evaluate_engine", _timed(originals["evaluate_engine"], engine))  # noqa: B010
    # analyse calls kinematics for the further cams only (cam A comes from the engine).
    setattr(analysis_module, "kinematics", _timed(originals["kinematics"], other))  # noqa: B010
    check = validity_module.check_design_geometry
    setattr(validity_module, "check_design_geometry", _timed(check, checks))  # noqa: B010
    setattr(analysis_module, "_extremes", _timed(flagged_extremes, extremes))  # noqa: B010
    try:
        analysis_module.analyse(design, step_deg=step)  # warm-up: caches, imports
        best: dict[str, float] | None = None
        for _ in range(repeat):
            times.clear()
            t0 = time.perf_counter()
            analysis_module.analyse(design, step_deg=step)
            total = time.perf_counter() - t0
            if best is None or total < best["total"]:
                best = {**times, "total": total}
    finally:
        for key, fn in originals.items():
            setattr(analysis_module, key, fn)
        setattr(validity_module, "check_design_geometry", check)  # noqa: B010
    assert best is not None
    best["extremes scan"] = best.pop("extremes", 0.0) - best.get("refinement", 0.0)
    best["rest"] = best["total"] - sum(best.get(s, 0.0) for s in STAGES if s != "rest")
    return {key: value * 1e3 for key, value in best.items()}


def main(argv: list[str]) -> None:
    """Print the stage table for the designs and grid size of ``argv``."""
    parser = argparse.ArgumentParser(
        prog="profile_analyze.py", description="Where analyse() spends its time, by stage."
    )
    parser.add_argument(
        "words",
        nargs="*",
        metavar="[ANGLES] DESIGN",
        help="grid size (default 36,001), then built-in designs (default: all)",
    )
    words = parser.parse_args(argv).words
    angles = 36_001
    if words and words[0].isdigit():
        angles = int(words.pop(0))
    if angles < 2:
        parser.error(f"ANGLES must be at least 2, got {angles}")
    unknown = sorted(set(words) - set(example_names()))
    if unknown:
        parser.error(f"no built-in design {unknown}; choose from {', '.join(example_names())}")
    warnings.simplefilter("ignore")  # pressure-angle warnings of demonstration designs
    names = words or example_names()
    repeat = 20 if angles <= 40_000 else 5
    print(f"analyse at {angles:,} angles, best of {repeat}: stage times [ms]")
    print(f"{'design':<20} {'total':>8}" + "".join(f" {s:>13}" for s in STAGES))
    for name in names:
        t = profile(name, angles, repeat)
        row = "".join(f" {t.get(s, 0.0):13.2f}" for s in STAGES)
        print(f"{name:<20} {t['total']:8.2f}{row}")


if __name__ == "__main__":
    main(sys.argv[1:])
