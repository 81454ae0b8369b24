"""What a fused compiled pass could reach: ``python bench/fused_bound.py`` (needs numba).

An experiment, not camtol code: it measures how far the speed targets of issue 8 that
numpy misses could be met by compiled kernels (one pass per angle, no temporaries), to
decide whether camtol should take on a compiler dependency. Two kernels in numba,
written for this measurement only and checked against camtol's numbers:

1. The whole per-angle work of ``analyse`` on CW06 Example 1 (THEORY §8.1: motion,
   contact geometry, the four sensitivities with their θ-derivatives, worst case and RMS
   of ΔS ΔV ΔA, and the extremes' scan), at 360,001 angles, against the plain-numpy
   profile of ``bench_analyze.py`` measured in the same run: the ratio issue 8 asks to
   be ≤ 2. What it leaves out (the extremes' refinement on a few hundred points, the
   geometry checks) costs about 1 ms.
2. The engine of the oscillating roller (geometry, ρ, the lean sensitivities of THEORY
   §3.3 as jets) at 36,001 angles against ``camtol.analysis.engine.evaluate_engine``.

numba is not a camtol dependency; ``pip install -e ".[bench]"`` installs it.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from bench_analyze import B1, B2, D1, PHI, RB, E, H, plain_profile  # noqa: E402
from common import best_of  # noqa: E402

try:
    from numba import njit
except ModuleNotFoundError:  # pragma: no cover - optional
    sys.exit('fused_bound.py needs numba, which camtol does not: pip install -e ".[bench]"')

from camtol.analysis.engine import evaluate_engine  # noqa: E402
from camtol.analysis.kinematics import analysis_grid  # noqa: E402
from camtol.config.design_file import load_example  # noqa: E402

TWO_PI = 2.0 * math.pi


@njit(cache=True)
def _cw06_pass(theta, out, ext, dev):
    """Every per-angle quantity of ``analyse`` for CW06 Example 1, in one pass."""
    cphi, sphi, tphi = math.cos(PHI), math.sin(PHI), math.tan(PHI)
    big_l0 = RB / cphi - E * tphi
    ext[:, 0] = -np.inf
    ext[:, 1] = np.inf
    for i in range(theta.size):
        t = theta[i]
        s = v = a = j = 0.0
        if t < B1 or D1 <= t < D1 + B2:  # cycloidal rise or return (THEORY §1)
            beta, sign, start, level = (B1, 1.0, 0.0, 0.0) if t < B1 else (B2, -1.0, D1, H)
            x = (t - start) / beta
            sw, cw = math.sin(TWO_PI * x), math.cos(TWO_PI * x)
            s = level + sign * H * (x - sw / TWO_PI)
            v = sign * H / beta * (1.0 - cw)
            a = sign * H / beta**2 * TWO_PI * sw
            j = sign * H / beta**3 * TWO_PI**2 * cw
        elif t < D1:
            s = H
        big_l = big_l0 + s  # THEORY §2.1
        qa = big_l * cphi - (v - E) * sphi
        ax0, ay0 = qa * cphi, qa * sphi + v  # frame of θ = 0, then turned by θ
        st, ct = math.sin(t), math.cos(t)
        radius = math.hypot(ax0, ay0)
        # λ = asin(QA × O2A / (|QA| |O2A|)), Q = (0, V) in this frame: QA × O2A = V ax0
        shift = math.asin(v * ax0 / (math.hypot(ax0, ay0 - v) * radius))
        u = big_l * sphi + (v - E) * cphi
        # cos λ = p / sqrt(p² + p'²), p = S cos φ + r_b, as a jet (THEORY §3.1)
        p0, p1, p2 = s * cphi + RB, v * cphi, a * cphi
        q0, q1, q2 = v * cphi, a * cphi, j * cphi
        w0 = p0 * p0 + q0 * q0
        w1 = 2.0 * (p0 * p1 + q0 * q1)
        w2 = 2.0 * (p1 * p1 + p0 * p2 + q1 * q1 + q0 * q2)
        r0 = math.sqrt(w0)
        r1 = w1 / (2.0 * r0)
        r2 = (w2 - 2.0 * r1 * r1) / (2.0 * r0)
        c0 = p0 / r0
        c1 = (p1 - c0 * r1) / r0
        c2 = (p2 - 2.0 * c1 * r1 - c0 * r2) / r0
        sr = (c0 / cphi, c1 / cphi, c2 / cphi)  # ΔS_r per mm
        sp = (u / cphi, (v * sphi + a * cphi) / cphi, (a * sphi + j * cphi) / cphi)  # ΔS_φ
        dn, de = dev[1] / cphi, -dev[2] * tphi  # constants: Δn / cos φ, −Δe tan φ
        out[0, i] = ct * ax0 - st * ay0
        out[1, i] = st * ax0 + ct * ay0
        out[2, i] = -v * st
        out[3, i] = v * ct
        out[4, i] = radius
        out[5, i] = shift
        out[6, i] = u
        out[7, i] = RB + (s + a) * cphi
        for k in range(3):
            out[8 + k, i] = sr[k]
            out[11 + k, i] = sp[k]
        worst0 = abs(sr[0] * dev[0]) + abs(dn) + abs(de) + abs(sp[0] * dev[3])
        rms0 = math.sqrt((sr[0] * dev[0]) ** 2 + dn * dn + de * de + (sp[0] * dev[3]) ** 2)
        worst1 = abs(sr[1] * dev[0]) + abs(sp[1] * dev[3])
        rms1 = math.hypot(sr[1] * dev[0], sp[1] * dev[3])
        worst2 = abs(sr[2] * dev[0]) + abs(sp[2] * dev[3])
        rms2 = math.hypot(sr[2] * dev[0], sp[2] * dev[3])
        scanned = (sr[0], sr[1], sr[2], sp[0], sp[1], sp[2], worst0, worst1, worst2)
        scanned2 = (rms0, rms1, rms2, radius, shift, u, out[7, i], s, v, a, j)
        for k in range(len(scanned) + len(scanned2)):
            x = scanned[k] if k < len(scanned) else scanned2[k - len(scanned)]
            if x > ext[k, 0]:
                ext[k, 0], ext[k, 2] = x, i
            if x < ext[k, 1]:
                ext[k, 1], ext[k, 3] = x, i


@njit(inline="always")
def _mul(a0, a1, a2, b0, b1, b2):
    return a0 * b0, a1 * b0 + a0 * b1, a2 * b0 + 2.0 * a1 * b1 + a0 * b2


@njit(inline="always")
def _div(a0, a1, a2, b0, b1, b2):
    q0 = a0 / b0
    q1 = (a1 - q0 * b1) / b0
    return q0, q1, (a2 - 2.0 * q1 * b1 - q0 * b2) / b0


@njit(inline="always")
def _sqrt(a0, a1, a2):
    r0 = math.sqrt(a0)
    r1 = a1 / (2.0 * r0)
    return r0, r1, (a2 - 2.0 * r1 * r1) / (2.0 * r0)


@njit(cache=True)
def _roller_engine(theta, lift, vel, acc, jerk, xi0, f, arm, rf, side, out):
    """Oscillating roller (THEORY §2.4, §3.3): geometry, ρ and the lean sensitivities."""
    k = -side
    for i in range(theta.size):
        g0, g1, g2 = xi0 + lift[i], vel[i], acc[i]
        fq0, fq1, fq2 = _div(f, 0.0, 0.0, 1.0 - vel[i], -acc[i], -jerk[i])  # f + q
        sn, cs = math.sin(g0), math.cos(g0)
        sg = (sn, cs * g1, -sn * g1 * g1 + cs * g2)
        cg = (cs, -sn * g1, -cs * g1 * g1 - sn * g2)
        d0, d1, d2 = fq0 - arm * cg[0], fq1 - arm * cg[1], fq2 - arm * cg[2]
        ls0, ls1, ls2 = arm * sg[0], arm * sg[1], arm * sg[2]
        l20, l21, l22 = _mul(ls0, ls1, ls2, ls0, ls1, ls2)
        dd0, dd1, dd2 = _mul(d0, d1, d2, d0, d1, d2)
        rho0, rho1, rho2 = _sqrt(dd0 + l20, dd1 + l21, dd2 + l22)
        ir0, ir1, ir2 = _div(1.0, 0.0, 0.0, rho0, rho1, rho2)
        fs0, fs1, fs2 = _mul(fq0, fq1, fq2, sg[0], sg[1], sg[2])
        c = k / arm
        iv0, iv1, iv2 = _div(rho0 * c, rho1 * c, rho2 * c, fs0, fs1, fs2)
        a0, a1, a2 = _mul(d0, d1, d2, f - arm * cg[0], -arm * cg[1], -arm * cg[2])
        nc0, nc1, nc2 = _mul(a0 + l20, a1 + l21, a2 + l22, ir0, ir1, ir2)
        big = f * f + arm * arm + rf * rf
        rad0, rad1, rad2 = _sqrt(
            big - 2.0 * f * arm * cg[0] - 2.0 * rf * nc0,
            -2.0 * f * arm * cg[1] - 2.0 * rf * nc1,
            -2.0 * f * arm * cg[2] - 2.0 * rf * nc2,
        )
        t0, t1, t2 = _mul(fq0 - f, fq1, fq2, ls0, ls1, ls2)
        t0, t1, t2 = _mul(t0, t1, t2, ir0, ir1, ir2)
        ss0, ss1, ss2 = _div(t0, t1, t2, rad0, rad1, rad2)  # sin λ
        x0, x1, x2 = _mul(ss0, ss1, ss2, ss0, ss1, ss2)
        cl0, cl1, cl2 = _sqrt(1.0 - x0, -x1, -x2)  # cos λ
        r = _mul(cl0, cl1, cl2, iv0, iv1, iv2)
        m0, m1, m2 = _mul(fq0, fq1, fq2, cg[0], cg[1], cg[2])
        lv = _div(k * (m0 - arm), k * m1, k * m2, fs0 * arm, fs1 * arm, fs2 * arm)
        e0, e1, e2 = _mul(d0, d1, d2, ir0, ir1, ir2)
        fv = _mul(-e0, -e1, -e2, iv0, iv1, iv2)
        # geometry in the frame of the line of centres, turned by θ
        q = fq0 - f
        cx, cy = f - arm * cg[0], -side * ls0
        nx, ny = d0 / rho0, -side * ls0 / rho0
        ax, ay = cx - rf * nx, cy - rf * ny
        pressure = math.pi / 2.0 - math.atan2(-side * ny, nx) - g0
        radius = math.hypot(ax, ay)  # Q = (−q, 0): QA × O2A = q ay
        shift = math.asin(q * ay / (math.hypot(ax + q, ay) * radius))
        ux, uy = -arm * cg[1] - cy, -side * ls1 + cx  # pitch curve, follower frame
        wx = -arm * cg[2] + 2.0 * side * ls1 - cx
        wy = -side * ls2 - 2.0 * arm * cg[1] - cy
        speed = math.hypot(ux, uy)
        st, ct = math.sin(theta[i]), math.cos(theta[i])
        row = (
            ct * ax - st * ay,
            st * ax + ct * ay,
            -ct * q,
            -st * q,
            q,
            pressure,
            shift,
            radius,
            speed**3 / (ux * wy - uy * wx) - rf,
        )
        for n in range(9):
            out[n, i] = row[n]
        for n in range(3):
            out[9 + n, i] = r[n]
            out[12 + n, i] = (iv0, iv1, iv2)[n]
            out[15 + n, i] = lv[n]
            out[18 + n, i] = fv[n]


def full_pass() -> None:
    """Experiment 1: the whole per-angle work of analyse on CW06 Example 1."""
    theta = np.linspace(0.0, TWO_PI, 360_001)
    dev = np.array([19e-3, 0.0, 9e-3, math.radians(0.011)])  # IT6 r, e, φ (THEORY §8.1)

    def run() -> np.ndarray:
        out = np.empty((14, theta.size))
        _cw06_pass(theta, out, np.empty((20, 4)), dev)
        return out

    out = run()  # compiles (or loads the cache)
    ax, ay = plain_profile(theta)
    assert np.allclose(out[0], ax, rtol=0, atol=1e-9) and np.allclose(out[1], ay, atol=1e-9)
    t_pass, t_plain = best_of(run, 10), best_of(lambda: plain_profile(theta), 10)
    print(
        f"CW06 Example 1 @ 360,001: fused pass {t_pass * 1e3:.1f} ms, plain-numpy profile"
        f" {t_plain * 1e3:.1f} ms: ratio {t_pass / t_plain:.2f} (issue 8 asks <= 2 for all"
        " of analyse)"
    )


def roller_engine() -> None:
    """Experiment 2: the oscillating roller's engine at 36,001 angles."""
    warnings.simplefilter("ignore")
    design = load_example("roller-oscillating")
    m = design.mechanism
    theta, left = analysis_grid(0.01, design.program.boundaries_rad)
    mo = design.program.evaluate(theta, left_limit=left)
    args = (m.initial_angle_rad, m.pivot_distance_mm, m.arm_length_mm, m.roller_radius_mm)

    def run() -> np.ndarray:
        out = np.empty((21, theta.size))
        state = (mo.lift, mo.velocity, mo.acceleration, mo.jerk)
        _roller_engine(theta, *state, *args, float(m.side), out)
        return out

    out = run()
    kin, sens = evaluate_engine(design, theta, left, motion=mo, check=False)
    ours = (kin.contact_x_mm, kin.contact_y_mm, kin.centre_x_mm, kin.centre_y_mm, kin.q_mm)
    ours += (kin.pressure_angle_rad, kin.shift_angle_rad, kin.radius_mm)
    for n, ref in enumerate(ours):
        assert np.allclose(out[n], ref, rtol=1e-12, atol=1e-12 * 100), n
    assert np.allclose(out[8], kin.curvature_radius_mm, rtol=1e-9)
    for n, key in enumerate(("r", "n", "l", "f")):
        for p, part in enumerate((sens[key].v, sens[key].d1, sens[key].d2)):
            assert np.allclose(out[9 + 3 * n + p], part, rtol=1e-12, atol=1e-12 * abs(part).max())
    t_kernel = best_of(run, 10)
    t_engine = best_of(lambda: evaluate_engine(design, theta, left, motion=mo, check=False), 10)
    print(
        f"oscillating roller engine @ {theta.size:,}: fused kernel {t_kernel * 1e3:.2f} ms,"
        f" camtol.analysis.engine {t_engine * 1e3:.2f} ms:"
        f" {t_engine / t_kernel:.1f}x (same numbers)"
    )


if __name__ == "__main__":
    full_pass()
    roller_engine()
