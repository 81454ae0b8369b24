"""Benchmark of the contact engine (THEORY §5): fast sweep against a fair brute force.

Run ``python bench/bench_contact.py``. The exact lift of a translating flat-faced follower
on a 36,000-vertex convex polygon (the CW06 Example 1 cam sampled at 36,000 points) at
36,000 cam angles, by the convex-hull sweep of :meth:`PolygonShape.support` (hull built
inside the timing) and by a brute-force O(N·M) evaluation of the same formula, in the same
run. The brute force is cache-blocked (blocks of directions × vertices whose dot products
fit in a core's cache, computed by matrix products, a running maximum per direction; the
fastest of a few block shapes is used), so the ratio is against a fair brute force, not a
deliberately slow one. Acceptance (issue 4): fast path ≥ 100× faster and ≤ 50 ms.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, print_figures  # noqa: E402

from camtol.config.design_file import load_example  # noqa: E402
from camtol.contact.engine import follow  # noqa: E402
from camtol.contact.flat import follow_flat_translating  # noqa: E402
from camtol.contact.shapes import AnalyticShape, PolygonShape  # noqa: E402

N_VERTICES = 36_000
N_ANGLES = 36_000


def best_of(fn: Callable[[], object], repeat: int) -> tuple[float, object]:
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def support_blocked(
    psi_rad: np.ndarray, vertices_mm: np.ndarray, rows: int, cols: int
) -> np.ndarray:
    """max over vertices of v·(cos ψ, sin ψ), cache-blocked brute force, O(N·M). [mm]"""
    d = np.stack([np.cos(psi_rad), np.sin(psi_rad)], axis=1)
    vt = np.ascontiguousarray(vertices_mm.T)
    out = np.full(psi_rad.size, -np.inf)
    buf = np.empty((rows, cols))
    for i in range(0, psi_rad.size, rows):
        di = d[i : i + rows]
        best = out[i : i + rows]
        for j in range(0, vt.shape[1], cols):
            blk = vt[:, j : j + cols]
            dots = np.matmul(di, blk, out=buf[: di.shape[0], : blk.shape[1]])
            np.maximum(best, dots.max(axis=1), out=best)
    return out


def main() -> list[Figure]:
    design = load_example("cw06-translating")
    mech = design.mechanism
    pts = AnalyticShape(mech, design.program, samples=N_VERTICES).polygon.vertices_mm
    theta = np.linspace(0.0, 2.0 * math.pi, N_ANGLES, endpoint=False)

    def fast() -> np.ndarray:
        shape = PolygonShape(pts)  # fresh: the hull is built inside the timing
        return follow_flat_translating(shape, mech, theta).lift  # type: ignore[arg-type]

    phi, e = mech.face_angle_rad, mech.offset_mm  # type: ignore[attr-defined]
    zero = mech.base_radius_mm / math.cos(phi) - e * math.tan(phi)  # type: ignore[attr-defined]
    psi = theta + phi
    # Pick the fastest block shape on a tenth of the directions (not timed below).
    shapes = [(64, 4096), (128, 2048), (256, 1024), (32, 8192)]
    pick = {b: best_of(partial(support_blocked, psi[::10], pts, *b), 1)[0] for b in shapes}
    block = min(pick, key=lambda b: pick[b])

    def brute() -> np.ndarray:
        h = support_blocked(psi, pts, *block)
        return np.asarray((h - e * math.sin(phi)) / math.cos(phi) - zero)

    t_fast, s_fast = best_of(fast, 7)
    t_brute, s_brute = best_of(brute, 1)
    diff = float(np.max(np.abs(np.asarray(s_fast) - np.asarray(s_brute))))
    ratio = t_brute / t_fast
    print(
        "contact engine benchmark: translating flat face,"
        f" {N_VERTICES} vertices x {N_ANGLES} angles"
    )
    print(f"  fast (hull + sweep):  {t_fast * 1e3:9.2f} ms  (best of 7)")
    print(f"  brute force O(N*M):   {t_brute * 1e3:9.2f} ms  (cache-blocked {block[0]}x{block[1]})")
    print(f"  ratio:                {ratio:9.1f} x   (required >= 100)")
    print(f"  max |fast - brute|:   {diff:.3e} mm")

    # Informational: the other solvers on the nominal analytic profiles.
    for name in ("cw06-oscillating",):
        d = load_example(name)
        th = np.linspace(0.0, 2.0 * math.pi, 3600, endpoint=False)
        shape = AnalyticShape(d.mechanism, d.program)
        shape.polygon  # noqa: B018  (sampling not timed)
        t, _ = best_of(lambda: follow(shape, d.mechanism, th), 3)  # noqa: B023
        print(f"  {name}: exact motion on the analytic profile, 3600 angles: {t * 1e3:.1f} ms")
    # Informational: a roller needs the true distance (no hull); a CMM-sized measured cam.
    dc = load_example("cw11-conjugate")
    cam_a = dc.cams()[0].mechanism  # a conjugate pair is two cams: follow cam A
    cam = AnalyticShape(cam_a, dc.program, samples=3600).polygon
    th = np.linspace(0.0, 2.0 * math.pi, 3600, endpoint=False)
    t_r, _ = best_of(lambda: follow(cam, cam_a, th), 1)
    print(f"  oscillating roller on a 3600-point polygon, 3600 angles: {t_r * 1e3:.0f} ms")
    # Does a compiled inner loop earn its place? Time a numba brute force of the same max.
    try:
        import numba
    except ImportError:  # pragma: no cover
        numba = None
    if numba is not None:

        @numba.njit(cache=False)  # type: ignore[misc]
        def brute_numba(psi: np.ndarray, v: np.ndarray) -> np.ndarray:
            out = np.empty(psi.size)
            for i in range(psi.size):
                c, s = math.cos(psi[i]), math.sin(psi[i])
                best = -np.inf
                for j in range(v.shape[0]):
                    d = v[j, 0] * c + v[j, 1] * s
                    if d > best:
                        best = d
                out[i] = best
            return out

        brute_numba(psi[:10], pts)  # compile
        t_nb, h_nb = best_of(lambda: brute_numba(psi, pts), 1)
        print(
            f"  brute force, numba:   {t_nb * 1e3:9.2f} ms  (compiled O(N*M) loop; "
            f"fast path still {t_nb / t_fast:.0f}x faster)"
        )
    assert diff < 1e-9, f"fast and brute-force lifts differ by {diff:.3g} mm"
    figures = [
        Figure("contact: hull sweep, 36,000 vertices x 36,000 angles", t_fast * 1e3, "ms", 50.0),
        Figure(
            "contact: cache-blocked brute force / hull sweep",
            ratio,
            "x",
            100.0,
            at_least=True,
            note=f"{t_brute * 1e3:.0f} ms vs {t_fast * 1e3:.1f} ms",
        ),
    ]
    print_figures("contact engine (bench_contact.py)", figures)
    return figures


if __name__ == "__main__":
    main()
