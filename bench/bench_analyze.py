"""Benchmark of ``analyse`` (issue 8, "Speed"): every built-in design, three grid sizes.

Run: ``python bench/bench_analyze.py``. Prints, for every built-in design, the full
``analyse`` (kinematics, every error source's ΔS ΔV ΔA, worst case and RMS, every extreme
refined, max radius) at 3,601 and 36,001 angles (targets 3 ms and 10 ms), and at 360,001
angles the ratio of ``analyse`` to a plain-numpy closed-form synthesis of the same cam
profile (THEORY §2.1, CW06 Example 1) measured in the same run (target <= 2).
A per-angle Python loop of the ΔS formulas checks that both paths give the same numbers.
"""

from __future__ import annotations

import math
import sys
import warnings
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, best_of_both, print_figures  # noqa: E402

from camtol.analysis.result import analyse  # noqa: E402
from camtol.config.design_file import example_names, load_example  # noqa: E402

TARGETS_MS = {3_601: 3.0, 36_001: 10.0}
RATIO_TARGET = 2.0

# CW06 Example 1 (THEORY §8.1): r_b 40 mm, e 10 mm, φ 15°, cycloidal rise 22 mm over
# 0-120°, dwell to 190°, cycloidal return over 190-290°, dwell.
RB, E, PHI, H = 40.0, 10.0, math.radians(15.0), 22.0
B1, D1, B2 = math.radians(120.0), math.radians(190.0), math.radians(100.0)


def plain_profile(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Profile points of CW06 Example 1 in plain numpy (closed form, THEORY §2.1). [mm]"""
    s = np.zeros_like(theta)
    v = np.zeros_like(theta)
    rise = theta < B1
    x = theta[rise] / B1
    w = 2.0 * math.pi * x
    s[rise] = H * (x - np.sin(w) / (2.0 * math.pi))
    v[rise] = H / B1 * (1.0 - np.cos(w))
    s[(theta >= B1) & (theta < D1)] = H
    ret = (theta >= D1) & (theta < D1 + B2)
    x = (theta[ret] - D1) / B2
    w = 2.0 * math.pi * x
    s[ret] = H - H * (x - np.sin(w) / (2.0 * math.pi))
    v[ret] = -H / B2 * (1.0 - np.cos(w))
    qa = (RB / math.cos(PHI) - E * math.tan(PHI) + s) * math.cos(PHI) - (v - E) * math.sin(PHI)
    sin_t, cos_t = np.sin(theta), np.cos(theta)
    cos_p = cos_t * math.cos(PHI) - sin_t * math.sin(PHI)  # cos(θ + φ)
    sin_p = sin_t * math.cos(PHI) + cos_t * math.sin(PHI)  # sin(θ + φ)
    return qa * cos_p - v * sin_t, qa * sin_p + v * cos_t


def loop_delta_s_r(theta: np.ndarray, dev_r: float) -> list[float]:
    """ΔS_r = Δr cos λ / cos φ per angle in plain Python (the same formulas, a reference)."""
    out = []
    for t in theta.tolist():
        if t < B1:
            x = t / B1
            s = H * (x - math.sin(2 * math.pi * x) / (2 * math.pi))
            v = H / B1 * (1 - math.cos(2 * math.pi * x))
        elif t < D1:
            s, v = H, 0.0
        elif t < D1 + B2:
            x = (t - D1) / B2
            s = H - H * (x - math.sin(2 * math.pi * x) / (2 * math.pi))
            v = -H / B2 * (1 - math.cos(2 * math.pi * x))
        else:
            s, v = 0.0, 0.0
        p, dp = RB + s * math.cos(PHI), v * math.cos(PHI)
        out.append(dev_r * p / math.hypot(p, dp) / math.cos(PHI))
    return out


def main() -> list[Figure]:
    """Run the benchmark, print its table, return its figures."""
    warnings.simplefilter("ignore")  # pressure-angle warnings of demonstration designs
    figures: list[Figure] = []
    print("wall time, best of n (CPU time of the thread in brackets: without waiting for a core)")
    print(f"{'design':<20} {'3,601 angles':>22} {'36,001 angles':>22} {'360,001 angles':>22}")
    for name in example_names():
        design = load_example(name)
        row = []
        for n, repeat in ((3_601, 30), (36_001, 10), (360_001, 3)):
            wall, cpu = best_of_both(partial(analyse, design, step_deg=360.0 / (n - 1)), repeat)
            row.append(f"{wall * 1e3:8.2f} ({cpu * 1e3:7.2f}) ms")
            if n in TARGETS_MS:
                figures.append(
                    Figure(
                        f"analyse {name} @ {n:,} angles",
                        wall * 1e3,
                        "ms",
                        TARGETS_MS[n],
                        note=f"CPU {cpu * 1e3:.2f} ms",
                    )
                )
        print(f"{name:<20} {row[0]:>22} {row[1]:>22} {row[2]:>22}")

    design = load_example("cw06-translating")
    theta = np.linspace(0.0, 2.0 * math.pi, 360_001)
    t_plain, c_plain = best_of_both(lambda: plain_profile(theta), 5)
    t_full, c_full = best_of_both(lambda: analyse(design, step_deg=0.001), 3)
    figures.append(
        Figure(
            "analyse / plain-numpy profile, cw06-translating @ 360,001",
            t_full / t_plain,
            "x",
            RATIO_TARGET,
            note=f"{t_full * 1e3:.0f} ms vs {t_plain * 1e3:.1f} ms; CPU {c_full / c_plain:.2f}x",
        )
    )
    # Same numbers (sanity, not timing): profile points and ΔS_r against the references.
    a = analyse(design, step_deg=0.1)
    k = a.kinematics
    right = ~k.left_limit
    ax, ay = plain_profile(k.theta_rad[right])
    assert np.allclose(k.contact_x_mm[right], ax, atol=1e-9)
    assert np.allclose(k.contact_y_mm[right], ay, atol=1e-9)
    dev_r = next(t.deviation for t in a.tolerances if t.key == "r")
    ref = loop_delta_s_r(k.theta_rad[right][::7], dev_r)
    assert np.allclose(a.errors.sources["r"].delta_lift[right][::7], ref, rtol=1e-12)
    print_figures("analyse (bench_analyze.py)", figures)
    return figures


if __name__ == "__main__":
    main()
