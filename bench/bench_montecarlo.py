"""Monte Carlo and allocation benchmarks (issue 11): ``python bench/bench_montecarlo.py``.

Targets (this 2-core machine): linear 1e6 samples × 3600 angles × all sources of
cw06-translating with max |ΔS| and per-angle quantiles ≤ 10 s and ≤ 1 GiB; exact mode
≥ 1000 samples × 3600 angles per minute for a roller follower; allocation of 5 sources
over IT5-IT12 ≤ 5 s (worst case / RSS) and ≤ 60 s (Monte Carlo). The fair baselines are
measured in the same run: the machine's GEMM speed (float32 matrix product of the same
shape) and memory bandwidth (a large array copy).
"""

from __future__ import annotations

import os
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from common import Figure  # noqa: E402

from camtol.config.design_file import load_example
from camtol.design.cam_design import ToleranceSpec
from camtol.tolerancing import allocate, monte_carlo


def _rss_gib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def machine_speed() -> tuple[float, float]:
    """(GEMM GFLOP/s of a 3605×3×512 float32 product on one BLAS thread, copy GB/s)."""
    g = np.random.default_rng(0).standard_normal((3605, 3)).astype(np.float32)
    x = np.random.default_rng(1).standard_normal((3, 512)).astype(np.float32)
    out = np.empty((3605, 512), np.float32)
    reps = 200
    from camtol.tolerancing.montecarlo import single_threaded_blas

    with single_threaded_blas():  # the conditions of the Monte Carlo engine
        t = time.perf_counter()
        for _ in range(reps):
            np.matmul(g, x, out=out)
    gemm = 2 * 3605 * 3 * 512 * reps / (time.perf_counter() - t) / 1e9
    a = np.ones(2**24)
    b = np.empty_like(a)
    t = time.perf_counter()
    for _ in range(5):
        np.copyto(b, a)
    bw = 2 * a.nbytes * 5 / (time.perf_counter() - t) / 1e9
    return gemm, bw


def bench_linear(samples: int) -> list[Figure]:
    d = load_example("cw06-translating")
    gemm, bw = machine_speed()
    workers = os.cpu_count() or 1
    t = time.perf_counter()
    r = monte_carlo(d, samples, seed=1, spec=0.022, workers=workers)
    dt = time.perf_counter() - t
    n = r.theta_deg.size
    m = 3  # columns: r, e, phi
    flops = 2 * samples * n * m  # the GEMM ΔS = G Xᵀ
    bytes_ = samples * n * 4  # the float32 ΔS matrix, written once (then reduced in cache)
    scaled = dt * 1e6 / samples
    print(
        f"linear: {samples:.0e} samples × {n} angles in {dt:.2f} s on {workers} threads"
        f" (scaled to 1e6: {scaled:.1f} s, target ≤ 10 s, ratio {scaled / 10:.2f});"
        f" peak RSS {_rss_gib():.2f} GiB (target ≤ 1 GiB)"
    )
    print(
        f"  machine (same run): GEMM {gemm:.2f} GFLOP/s (3605×3 @ 3×512 float32, one BLAS"
        f" thread), copy {bw:.2f} GB/s; achieved {flops / dt / 1e9 / gemm:.1%} of GEMM and"
        f" {bytes_ / dt / 1e9 / bw:.1%} of copy bandwidth (ΔS written once)"
    )
    return [
        Figure(
            "linear MC 1e6 × 3600 × cw06 sources" + ("" if samples == 1_000_000 else " (scaled)"),
            scaled,
            "s",
            10.0,
        ),
        Figure("linear MC peak memory", _rss_gib(), "GiB", 1.0),
    ]


def bench_exact(samples: int) -> list[Figure]:
    d = load_example("roller-translating")
    t = time.perf_counter()
    r = monte_carlo(d, samples, mode="exact", seed=1)
    dt = time.perf_counter() - t
    rate = samples * r.theta_deg.size / dt * 60
    print(
        f"exact: {samples} samples × {r.theta_deg.size} angles in {dt:.2f} s ="
        f" {rate / 3600:.0f} samples × 3600 angles/min (target ≥ 1000, ratio"
        f" {rate / 3600 / 1000:.2f})"
    )
    return [Figure("exact MC roller, samples × 3600 angles/min", rate / 3600, "/min", 1000, True)]


def bench_allocation() -> list[Figure]:
    import dataclasses
    import math

    d = load_example("roller-oscillating")  # 5 sources: r, n, rf, l, f
    keys = [s.key for s in d.mechanism.sources]
    d = dataclasses.replace(d, tolerances=tuple(ToleranceSpec(k, grade="IT7") for k in keys))
    out = []
    for crit, samples in (("worst_case", 1), ("rss", 1), ("monte_carlo", 4000)):
        t = time.perf_counter()
        a = allocate(d, math.radians(0.08), criterion=crit, samples=samples, verify_samples=20000)
        dt = time.perf_counter() - t
        target = 60 if crit == "monte_carlo" else 5
        print(
            f"allocation {crit}: {len(keys)} sources × 8 grades in {dt:.2f} s (target ≤"
            f" {target} s, ratio {dt / target:.2f}); {a.evaluated} combinations;"
            f" grades {a.grades}"
        )
        out.append(Figure(f"allocation {crit}, 5 sources IT5-IT12", dt, "s", float(target)))
    return out


def main() -> list[Figure]:
    """Run the benchmarks (``--quick``: 1e5 linear samples, 50 exact) and return figures."""
    quick = "--quick" in sys.argv
    figures = bench_linear(100_000 if quick else 1_000_000)
    figures += bench_exact(50 if quick else 200)
    figures += bench_allocation()
    for f in figures:
        print(f.line())
    return figures


if __name__ == "__main__":
    main()
