"""Benchmark the analytic engine on the THEORY §8.1 design (issue: foundation).

Run: ``python bench/bench_analyze.py``. Prints, at 3,601 and 36,001 angles:
- every error source's ΔS, ΔV, ΔA (jets: exact derivatives) via ``error_analysis``;
- ΔS only, on plain arrays (the closed forms of THEORY §3.1);
- the full ``analyse`` (kinematics, curves, extremes refined, max radius);
- a deliberately plain per-angle Python loop of the same ΔS formulas, measured in the
  same run, and the ratio. Target (not a test): all sources at 36,001 angles ≤ 10 ms.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from camtol.analysis import analyse, max_radius_mm
from camtol.config import load_example
from camtol.errors import error_analysis
from camtol.kinematics import analysis_grid


def best_of(fn: Callable[[], object], repeat: int = 7) -> float:
    """Best wall time of ``repeat`` calls. [s]"""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    design = load_example("cw06-translating")
    tols = design.resolve_tolerances(max_radius_mm(design))
    mech = design.mechanism
    dev = {t.key: t.deviation for t in tols}

    def delta_s_plain_arrays(theta: np.ndarray) -> np.ndarray:
        m = design.program.evaluate(theta)
        s = mech.error_sensitivities(theta, m.lift, m.velocity)
        return np.stack([np.asarray(s[k]) * d for k, d in dev.items()])

    def python_loop(theta: np.ndarray) -> list[tuple[float, float, float]]:
        rb, e, phi = 40.0, 10.0, math.radians(15.0)
        h, b1, b2 = 22.0, math.radians(120), math.radians(100)
        out = []
        for t in theta:
            t = float(t)
            if t < b1:
                x = t / b1
                s, v = (
                    h * (x - math.sin(2 * math.pi * x) / (2 * math.pi)),
                    h / b1 * (1 - math.cos(2 * math.pi * x)),
                )
            elif t < math.radians(190):
                s, v = h, 0.0
            elif t < math.radians(290):
                x = (t - math.radians(190)) / b2
                s = h - h * (x - math.sin(2 * math.pi * x) / (2 * math.pi))
                v = -h / b2 * (1 - math.cos(2 * math.pi * x))
            else:
                s, v = 0.0, 0.0
            big_l = rb / math.cos(phi) - e * math.tan(phi) + s
            qa = big_l * math.cos(phi) - (v - e) * math.sin(phi)
            ax = qa * math.cos(t + phi) - v * math.sin(t)
            ay = qa * math.sin(t + phi) + v * math.cos(t)
            u = big_l * math.sin(phi) + (v - e) * math.cos(phi)
            lam = math.asin(v * math.cos(phi) / math.hypot(ax, ay))
            out.append(
                (
                    dev["r"] * math.cos(lam) / math.cos(phi),
                    -dev["e"] * math.tan(phi),
                    u * dev["phi"] / math.cos(phi),
                )
            )
        return out

    print(
        f"{'angles':>8} {'ΔS,ΔV,ΔA jets':>15} {'ΔS arrays':>10} {'analyse()':>10}"
        f" {'python loop':>12} {'loop/arrays':>12} {'loop/jets':>10}"
    )
    for n in (3_601, 36_001):
        step = 360.0 / (n - 1)
        theta, left = analysis_grid(step, design.program.boundaries_rad)
        t_jets = best_of(partial(error_analysis, design, tols, theta, left_limit=left))
        t_plain = best_of(partial(delta_s_plain_arrays, theta))
        t_full = best_of(partial(analyse, design, step_deg=step), repeat=3)
        t_loop = best_of(partial(python_loop, theta), repeat=3)
        # same numbers from both paths (sanity, not timing)
        ref = np.array(python_loop(theta[:2000:7])).T
        assert np.allclose(delta_s_plain_arrays(theta[:2000:7]), ref, rtol=1e-9, atol=1e-15)
        print(
            f"{n:>8} {t_jets * 1e3:>12.2f} ms {t_plain * 1e3:>7.2f} ms {t_full * 1e3:>7.1f} ms"
            f" {t_loop * 1e3:>9.1f} ms {t_loop / t_plain:>11.0f}x {t_loop / t_jets:>9.0f}x"
        )
    print("target: all error sources at 36,001 angles <= 10 ms (ΔS, ΔV, ΔA columns above)")


if __name__ == "__main__":
    main()
