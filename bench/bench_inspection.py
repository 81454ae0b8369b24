"""Benchmark of CMM inspection (issue 12): registration, deviations, functional ΔS.

Run ``python bench/bench_inspection.py``. Cam A of the CW11 experiment (THEORY §8.4),
simulated scans (1 µm probe noise, 40 µm eccentricity, 10° rotation, 50 µm rms profile
error, 5 outliers). Targets (issue 12):

- registration (robust best fit, outliers) and deviations Δn, Δr of 3,600 points ≤ 50 ms;
- the same for 10⁶ points ≤ 2 s;
- the functional ΔS of a 3,600-point scan at 0.1° (Fourier smoothing + exact contact
  motion) ≤ 100 ms.

The nominal profile table (built once per cam, :mod:`camtol.inspection.profile_table`) is
timed separately. Baselines measured in the same run: the closest points of the 3,600-point
scan by Newton's method on the exact profile jets (what the table replaces), and the
normal equations of the Fourier smoothing (3,600 points, 100 harmonics) formed from the
design matrix A as AᵀA, O(N·K²), against the trigonometric moments, O(N·K).
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, print_figures  # noqa: E402

from camtol.config.design_file import load_example  # noqa: E402
from camtol.contact import AnalyticShape  # noqa: E402
from camtol.inspection.deviations import cam_profile  # noqa: E402
from camtol.inspection.functional import (  # noqa: E402
    _normal_equations,
    functional_deviation,
    harmonic_table,
)
from camtol.inspection.registration import Datum, register  # noqa: E402
from camtol.inspection.twin import random_profile_error, simulate_scan  # noqa: E402

CPU: dict[str, float] = {}


def best_of(fn: Callable[[], object], repeat: int, key: str = "") -> tuple[float, object]:
    """Best wall time of ``repeat`` runs (and, under ``key``, the best CPU time)."""
    best, best_cpu, out = math.inf, math.inf, None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        best = min(best, time.perf_counter() - t)
        best_cpu = min(best_cpu, time.process_time() - c)
    if key:
        CPU[key] = best_cpu
    return best, out


def _newton_on_jets(shape: AnalyticShape, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Baseline: closest points by Newton's method on the exact jets (no table)."""
    t = np.mod(np.arctan2(py, px), 2 * math.pi)
    for _ in range(30):
        x, y = shape.jets(t)
        ex, ey = x.v - px, y.v - py
        f = ex * x.d1 + ey * y.d1
        fp = x.d1**2 + y.d1**2 + ex * x.d2 + ey * y.d2
        dt = np.clip(-f / fp, -0.01, 0.01)
        t = t + dt
        if np.max(np.abs(dt)) < 1e-13:
            break
    return t


def _normal_equations_from_a(t: np.ndarray, v: np.ndarray, k_max: int) -> object:
    """Baseline: AᵀA and Aᵀv formed from the design matrix A = [1, cos kt, sin kt].

    A's trigonometric table is made as the library makes it (the same recurrence), so the
    ratio measures the O(N·K) moments against the O(N·K²) product alone.
    """
    c, s = harmonic_table(t, k_max)
    a = np.concatenate([np.ones((t.size, 1)), c, s], axis=1)
    return a.T @ a, a.T @ v


def main() -> list[Figure]:
    d = load_example("cw11-experiment")
    t_table, prof = best_of(lambda: cam_profile(d, "A"), 3)
    table = prof.table  # type: ignore[attr-defined]
    err = random_profile_error(50.0, seed=1)

    def scan(n: int) -> tuple[np.ndarray, np.ndarray]:
        s = simulate_scan(
            d,
            points=n,
            noise_um=1.0,
            seed=2,
            rotation_deg=10.0,
            eccentricity_um=40.0,
            outliers=5,
            profile_error=err,
        )
        return s.x_mm, s.y_mm

    def work(x: np.ndarray, y: np.ndarray) -> object:
        reg = register(table, x, y, Datum())  # fit, outliers, closest points of all
        p = reg.points
        assert p is not None
        return table.radial(p.x_mm, p.y_mm, p.param_rad), reg

    x1, y1 = scan(3600)
    t_small, (_, reg) = best_of(lambda: work(x1, y1), 7, "small")  # type: ignore[misc]
    shape = AnalyticShape(prof.mechanism, d.program)  # type: ignore[attr-defined]
    xc, yc = reg.to_cam(x1, y1)
    t_base, _ = best_of(lambda: _newton_on_jets(shape, xc, yc), 3)
    t_tab, _ = best_of(lambda: table.closest(xc, yc), 7)
    x6, y6 = scan(1_000_000)
    t_big, _ = best_of(lambda: work(x6, y6), 2, "big")
    insp = _inspection(d, prof, x1, y1)
    functional_deviation(prof, insp, step_deg=0.1)  # type: ignore[arg-type]  (warm-up)
    t_func, _ = best_of(lambda: functional_deviation(prof, insp, step_deg=0.1), 5, "func")  # type: ignore[arg-type]
    t_fit = np.mod(insp.param_rad, 2 * math.pi)  # type: ignore[attr-defined]
    v_fit = insp.dn_um * 1e-3  # type: ignore[attr-defined]
    best_of(lambda: _normal_equations(t_fit, v_fit, 100), 9, "moments")
    best_of(lambda: _normal_equations_from_a(t_fit, v_fit, 100), 9, "gram")
    t_mom, t_gram = CPU["moments"], CPU["gram"]  # CPU time: the machine may be shared
    print("CMM inspection benchmark: cam A of cw11-experiment, simulated scans")
    print(f"  profile table (once per cam, not in the figures): {t_table * 1e3:.1f} ms")
    print(
        f"  closest points of 3,600: table {t_tab * 1e3:.1f} ms, Newton on the exact jets"
        f" {t_base * 1e3:.1f} ms"
    )
    figures = [
        Figure(
            "inspection: register + dn + dr, 3,600 points",
            t_small * 1e3,
            "ms",
            50.0,
            note=f"CPU {CPU['small'] * 1e3:.1f} ms",
        ),
        Figure(
            "inspection: register + dn + dr, 10^6 points",
            t_big * 1e3,
            "ms",
            2000.0,
            note=f"CPU {CPU['big'] * 1e3:.0f} ms",
        ),
        Figure(
            "inspection: functional dS, 3,600 points at 0.1 deg",
            t_func * 1e3,
            "ms",
            100.0,
            note=f"CPU {CPU['func'] * 1e3:.1f} ms",
        ),
        Figure(
            "inspection: Fourier normal equations, A^T A / moments",
            t_gram / t_mom,
            "x",
            2.0,
            at_least=True,
            note=f"CPU {t_mom * 1e3:.1f} ms vs {t_gram * 1e3:.1f} ms",
        ),
        Figure(
            "inspection: closest points, exact-jet Newton / table",
            t_base / t_tab,
            "x",
            10.0,
            at_least=True,
        ),
    ]
    print_figures("CMM inspection (bench_inspection.py)", figures)
    return figures


def _inspection(d: object, prof: object, x: np.ndarray, y: np.ndarray) -> object:
    from camtol.inspection.cmm import Scan
    from camtol.inspection.deviations import inspect_scan

    scan = Scan("bench", x, y, np.zeros(x.size, dtype=bool), np.arange(x.size))
    return inspect_scan(d, scan, profile=prof)  # type: ignore[arg-type]


if __name__ == "__main__":
    main()
