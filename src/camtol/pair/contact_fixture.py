r"""Exact simulation of the conjugate-cam measuring fixture (THEORY §4, §5; [CW11]).

The fixture holds the conjugate follower's pivot O3 on a slider along the line of centres,
so the centre distance f* is free: at each cam angle θ both rollers touch their cams, and
(ξ, f*) follow from the two contact conditions at once. An indicator reads
Δf = f* − f (THEORY §4). This module is the digital twin of that fixture: given the two
cam shapes (analytic profiles with any radial or normal error functions) and the
fixture's actual dimensions (arm lengths l_A, l_B, roller radii r_C, r_D, arm angle η), it
returns ξ(θ) and f*(θ) exactly.

With O3 = f*·t, t = (cos θ, sin θ), the roller centres are (THEORY §2.4)
C = f*·t − l_A (cos(θ − ξ), sin(θ − ξ)) and D = f*·t − l_B (cos(θ + η − ξ), sin(θ + η − ξ)).
The unknowns (t_A, t_B, ξ, f*) — t_A, t_B the profile parameters of the contact points —
solve, by Newton's method on a batch of 4×4 systems,

.. math::

    (C - P_A)·P_A' = 0,\\quad |C - P_A|^2 = r_C^2,\\quad
    (D - P_B)·P_B' = 0,\\quad |D - P_B|^2 = r_D^2 .

The solution is checked against the sampled profiles (no sample point closer to a roller
centre than its radius). dξ/dθ and df*/dθ follow from the implicit-function theorem on the
same system.

On polygons (measured or cut cams) each cam's roller position for a given pivot position
is exact (:mod:`camtol.contact.roller`, outermost contact over every feature): ξ_A(f*) on
cam A and ξ_B(f*) on cam B, and f* solves ξ_A(f*) = ξ_B(f*) by Newton's method with the
exact slopes ∂ξ/∂f* of the features in contact.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact.result import FollowerMotion
from camtol.contact.roller_path import RollerPath, check_clear
from camtol.contact.roller_polygon import solve_polygon
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design.motion import MotionState
from camtol.exceptions import GeometryError
from camtol.jet import FloatArray

if TYPE_CHECKING:
    from camtol.mechanisms.conjugate import ConjugatePair
    from camtol.pair.variation import FixtureErrors

__all__ = ["Fixture", "simulate_fixture"]


@dataclass(frozen=True)
class Fixture:
    """The measuring fixture's actual follower dimensions.

    Parameters
    ----------
    pivot_mm : float
        Nominal centre distance f (the indicator's zero: Δf = f* − f). [mm]
    arm_a_mm, arm_b_mm : float
        Arm lengths l_A, l_B. [mm]
    roller_c_mm, roller_d_mm : float
        Roller radii r_C (on cam A), r_D (on cam B). [mm]
    arm_angle_rad : float
        Angle η between the arms. [rad]
    """

    pivot_mm: float
    arm_a_mm: float
    arm_b_mm: float
    roller_c_mm: float
    roller_d_mm: float
    arm_angle_rad: float

    @classmethod
    def of(cls, pair: ConjugatePair, errors: FixtureErrors | None = None) -> Fixture:
        """Return the fixture of a pair, optionally with constant errors (THEORY §4.1).

        Parameters
        ----------
        pair : ConjugatePair
            The nominal conjugate pair whose follower dimensions the fixture takes.
        errors : FixtureErrors, optional
            Constant errors of the arm lengths, roller radii [mm] and arm angle [rad],
            added to the nominal dimensions; None for an ideal fixture.

        Returns
        -------
        Fixture
            The fixture's dimensions. [mm, rad]
        """
        dl_a = dl_b = drc = drd = deta = 0.0
        if errors is not None:
            dl_a, dl_b = errors.dl_a_mm, errors.dl_b_mm
            drc, drd, deta = errors.drr_c_mm, errors.drr_d_mm, errors.deta_rad
        return cls(
            pair.pivot_distance_mm,
            pair.arm_a_mm + dl_a,
            pair.arm_b_mm + dl_b,
            pair.roller_radius_mm + drc,
            pair.roller_d_mm + drd,
            pair.arm_angle_rad + deta,
        )


def _unit(beta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    return np.cos(beta), np.sin(beta), -np.sin(beta), np.cos(beta)


class _System:
    """The fixture's four contact conditions at (t_A, t_B, ξ, f*), with their Jacobian.

    C = f*·t − l_A b(θ − ξ) and D = f*·t − l_B b(θ + η − ξ), b(β) = (cos β, sin β), so
    ∂C/∂ξ = l_A b'(θ − ξ), ∂C/∂f* = t, ∂C/∂θ = f*·w − l_A b'(θ − ξ), and likewise for D.
    """

    def __init__(
        self,
        theta: FloatArray,
        shape_a: AnalyticShape,
        shape_b: AnalyticShape,
        fx: Fixture,
        ta: FloatArray,
        tb: FloatArray,
        xi: FloatArray,
        fs: FloatArray,
        left_limit: ArrayLike | None,
    ) -> None:
        self.fx = fx
        self.ct, self.st = np.cos(theta), np.sin(theta)
        self.pa_x, self.pa_y = shape_a.jets(ta, left_limit=left_limit)
        self.pb_x, self.pb_y = shape_b.jets(tb, left_limit=left_limit)
        ca, sa, self.dca, self.dsa = _unit(theta - xi)
        cb, sb, self.dcb, self.dsb = _unit(theta + fx.arm_angle_rad - xi)
        self.fs = fs
        self.cx, self.cy = fs * self.ct - fx.arm_a_mm * ca, fs * self.st - fx.arm_a_mm * sa
        self.dx, self.dy = fs * self.ct - fx.arm_b_mm * cb, fs * self.st - fx.arm_b_mm * sb
        self.ga = (self.cx - self.pa_x.v, self.cy - self.pa_y.v)
        self.gb = (self.dx - self.pb_x.v, self.dy - self.pb_y.v)

    def residual(self) -> FloatArray:
        """(C − P_A)·P_A', |C − P_A|² − r_C², and the same for D on cam B. [mm², mm²]"""
        (gax, gay), (gbx, gby) = self.ga, self.gb
        return np.stack(
            [
                gax * self.pa_x.d1 + gay * self.pa_y.d1,
                gax**2 + gay**2 - self.fx.roller_c_mm**2,
                gbx * self.pb_x.d1 + gby * self.pb_y.d1,
                gbx**2 + gby**2 - self.fx.roller_d_mm**2,
            ],
            axis=1,
        )

    def jacobian(self) -> FloatArray:
        """∂(residual)/∂(t_A, t_B, ξ, f*), shape (N, 4, 4)."""
        fx, ct, st = self.fx, self.ct, self.st
        n = ct.size
        jac = np.zeros((n, 4, 4))
        rows = (
            (0, self.pa_x, self.pa_y, self.ga, fx.arm_a_mm * self.dca, fx.arm_a_mm * self.dsa),
            (2, self.pb_x, self.pb_y, self.gb, fx.arm_b_mm * self.dcb, fx.arm_b_mm * self.dsb),
        )
        for r, px, py, (gx, gy), xi_x, xi_y in rows:
            col = 0 if r == 0 else 1
            jac[:, r, col] = -(px.d1**2 + py.d1**2) + gx * px.d2 + gy * py.d2
            jac[:, r, 2] = xi_x * px.d1 + xi_y * py.d1
            jac[:, r, 3] = ct * px.d1 + st * py.d1
            jac[:, r + 1, col] = -2.0 * (gx * px.d1 + gy * py.d1)
            jac[:, r + 1, 2] = 2.0 * (gx * xi_x + gy * xi_y)
            jac[:, r + 1, 3] = 2.0 * (gx * ct + gy * st)
        return jac

    def theta_partials(self) -> FloatArray:
        """∂(residual)/∂θ at fixed (t_A, t_B, ξ, f*), shape (N, 4)."""
        fx, wx, wy = self.fx, -self.st, self.ct
        out = []
        for px, py, (gx, gy), arm, d_c, d_s in (
            (self.pa_x, self.pa_y, self.ga, fx.arm_a_mm, self.dca, self.dsa),
            (self.pb_x, self.pb_y, self.gb, fx.arm_b_mm, self.dcb, self.dsb),
        ):
            th_x, th_y = self.fs * wx - arm * d_c, self.fs * wy - arm * d_s
            out += [th_x * px.d1 + th_y * py.d1, 2.0 * (gx * th_x + gy * th_y)]
        return np.stack(out, axis=1)


def simulate_fixture(
    theta_rad: ArrayLike,
    shape_a: AnalyticShape | PolygonShape,
    shape_b: AnalyticShape | PolygonShape,
    fixture: Fixture,
    *,
    initial_angle_rad: float,
    seed_lift: ArrayLike | None = None,
    left_limit: ArrayLike | None = None,
    max_iterations: int = 60,
) -> FollowerMotion:
    """Exact follower angle and centre distance of the fixture (THEORY §4, §5).

    Parameters
    ----------
    theta_rad : array_like
        Cam angles from the line of centres. [rad]
    shape_a, shape_b : AnalyticShape or PolygonShape
        Cams A and B, both analytic (their profile parameters seed the contact points:
        t = θ) or both polygons.
    fixture : Fixture
        Actual follower dimensions.
    initial_angle_rad : float
        ξ0 of the nominal pair: S = ξ − ξ0. On analytic shapes Newton's method starts
        from ξ0 + S(θ) and the nominal f; the fixture has other assembly branches, so a
        wrong ξ0 can converge to one of them. [rad]
    seed_lift : array_like, optional
        Starting S(θ) for analytic shapes (default: ``shape_a``'s program). [rad]
    left_limit : array_like of bool, optional
        Rows taking one-sided values at profile boundaries.
    max_iterations : int
        Newton iterations allowed.

    Returns
    -------
    FollowerMotion
        S = ξ − ξ0 [rad], V = dξ/dθ [rad/rad] (A is not computed: NaN), the contact point
        on cam A, and extras ``follower_angle_rad``, ``centre_distance_mm`` f*,
        ``delta_f_mm`` Δf = f* − f, ``delta_f_velocity_mm`` dΔf/dθ [mm/rad],
        ``contact_b_x_mm``/``contact_b_y_mm``, ``param_b_rad``.

    Raises
    ------
    GeometryError
        If the Newton iteration does not converge or a roller overlaps a cam.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    fx = fixture
    if isinstance(shape_a, PolygonShape) and isinstance(shape_b, PolygonShape):
        return _simulate_polygons(theta, shape_a, shape_b, fx, initial_angle_rad, max_iterations)
    if not (isinstance(shape_a, AnalyticShape) and isinstance(shape_b, AnalyticShape)):
        raise TypeError(
            "simulate_fixture needs two analytic shapes or two polygons; sample the analytic"
            " one (AnalyticShape.polygon) to mix them"
        )
    lift0 = (
        shape_a.program.evaluate(theta).lift
        if seed_lift is None
        else np.broadcast_to(np.asarray(seed_lift, dtype=float), theta.shape)
    )
    ta = np.mod(theta, 2 * math.pi)
    tb = ta.copy()
    xi = initial_angle_rad + lift0
    fs = np.full(theta.shape, fx.pivot_mm)
    step_t = 4.0 * 2 * math.pi / min(shape_a.samples, shape_b.samples)
    for _ in range(max_iterations):
        sys_ = _System(theta, shape_a, shape_b, fx, ta, tb, xi, fs, None)
        try:
            delta = -np.linalg.solve(sys_.jacobian(), sys_.residual()[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            raise GeometryError("the fixture's contact equations are singular") from None
        delta[:, 0] = np.clip(delta[:, 0], -step_t, step_t)
        delta[:, 1] = np.clip(delta[:, 1], -step_t, step_t)
        ta, tb = ta + delta[:, 0], tb + delta[:, 1]
        xi, fs = xi + delta[:, 2], fs + delta[:, 3]
        if np.max(np.abs(delta[:, :3])) < 1e-13 and np.max(np.abs(delta[:, 3])) < 1e-11:
            break
    else:
        raise GeometryError(
            f"the fixture simulation did not converge within {max_iterations} iterations"
        )
    ta, tb = shape_a.snap(ta), shape_b.snap(tb)
    sys_ = _System(theta, shape_a, shape_b, fx, ta, tb, xi, fs, left_limit)
    check_clear(shape_a, sys_.cx, sys_.cy, fx.roller_c_mm, theta)
    check_clear(shape_b, sys_.dx, sys_.dy, fx.roller_d_mm, theta)
    # Implicit-function theorem: J dz/dθ = −∂G/∂θ.
    dz = np.asarray(
        np.linalg.solve(sys_.jacobian(), -sys_.theta_partials()[:, :, None])[:, :, 0], dtype=float
    )
    n = theta.size
    cx, cy, dx, dy = sys_.cx, sys_.cy, sys_.dx, sys_.dy
    pa_x, pa_y, pb_x, pb_y = sys_.pa_x, sys_.pa_y, sys_.pb_x, sys_.pb_y
    lift = xi - initial_angle_rad
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(lift, dz[:, 2], np.full(n, np.nan), np.full(n, np.nan)),
        contact_x_mm=pa_x.v,
        contact_y_mm=pa_y.v,
        feature=np.full(n, -1, dtype=np.intp),
        param_rad=ta,
        extras={
            "follower_angle_rad": xi,
            "centre_distance_mm": fs,
            "delta_f_mm": fs - fx.pivot_mm,
            "delta_f_velocity_mm": dz[:, 3],
            "contact_b_x_mm": pb_x.v,
            "contact_b_y_mm": pb_y.v,
            "param_b_rad": tb,
            "roller_c_x_mm": cx,
            "roller_c_y_mm": cy,
            "roller_d_x_mm": dx,
            "roller_d_y_mm": dy,
        },
    )


def _pivot_slopes(
    path: RollerPath,
    theta: FloatArray,
    x: FloatArray,
    fs: FloatArray,
    ax: FloatArray,
    ay: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """∂x/∂θ and ∂x/∂f* with the feature in contact frozen (normal ν = C − A)."""
    p = RollerPath(path.kind, path.roller_mm, pivot_mm=fs, arm_mm=path.arm_mm, side=path.side)
    cx, cy = p.centre(theta, x)
    nx, ny = cx - ax, cy - ay
    (tx, ty), (xx, xy), *_ = p.partials(theta, x)
    g_x = nx * xx + ny * xy
    return -(nx * tx + ny * ty) / g_x, -(nx * np.cos(theta) + ny * np.sin(theta)) / g_x


def _simulate_polygons(
    theta: FloatArray,
    poly_a: PolygonShape,
    poly_b: PolygonShape,
    fx: Fixture,
    initial_angle_rad: float,
    max_iterations: int,
) -> FollowerMotion:
    """Simulate the fixture on two polygons (Newton on f* with exact slopes)."""
    path_a = RollerPath("circle", fx.roller_c_mm, pivot_mm=fx.pivot_mm, arm_mm=fx.arm_a_mm)
    path_b = RollerPath("circle", fx.roller_d_mm, pivot_mm=fx.pivot_mm, arm_mm=fx.arm_b_mm, side=1)
    eta = fx.arm_angle_rad
    fs = np.full(theta.shape, fx.pivot_mm)
    for _ in range(max_iterations):
        xa, _, _, aax, aay, fa = solve_polygon(theta, poly_a, path_a, pivot=fs)
        xb, _, _, bax, bay, fb = solve_polygon(theta, poly_b, path_b, pivot=fs)
        # ξ_A = x_A (cam A arm), ξ_B = η − x_B (cam B arm): both rollers touch when equal.
        resid = xa + xb - eta
        _, da_f = _pivot_slopes(path_a, theta, xa, fs, aax, aay)
        _, db_f = _pivot_slopes(path_b, theta, xb, fs, bax, bay)
        step = -resid / (da_f + db_f)
        fs = fs + step
        if np.max(np.abs(step)) < 1e-12 and np.max(np.abs(resid)) < 1e-13:
            break
    else:
        raise GeometryError(
            f"the fixture simulation on polygons did not converge within {max_iterations}"
            " iterations"
        )
    xa, xa_t, _, aax, aay, fa = solve_polygon(theta, poly_a, path_a, pivot=fs)
    xb, xb_t, _, bax, bay, fb = solve_polygon(theta, poly_b, path_b, pivot=fs)
    _, da_f = _pivot_slopes(path_a, theta, xa, fs, aax, aay)
    _, db_f = _pivot_slopes(path_b, theta, xb, fs, bax, bay)
    # F(θ, f*) = x_A + x_B − η = 0: f*' = −(x_A,θ + x_B,θ)/(x_A,f + x_B,f).
    f1 = -(xa_t + xb_t) / (da_f + db_f)
    xi = xa
    n = theta.size
    ca = RollerPath("circle", fx.roller_c_mm, pivot_mm=fs, arm_mm=fx.arm_a_mm).centre(theta, xa)
    cb = RollerPath("circle", fx.roller_d_mm, pivot_mm=fs, arm_mm=fx.arm_b_mm, side=1).centre(
        theta, xb
    )
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(
            xi - initial_angle_rad, xa_t + da_f * f1, np.full(n, np.nan), np.full(n, np.nan)
        ),
        contact_x_mm=aax,
        contact_y_mm=aay,
        feature=fa,
        param_rad=np.full(n, np.nan),
        extras={
            "follower_angle_rad": xi,
            "centre_distance_mm": fs,
            "delta_f_mm": fs - fx.pivot_mm,
            "delta_f_velocity_mm": f1,
            "contact_b_x_mm": bax,
            "contact_b_y_mm": bay,
            "feature_b": fb.astype(float),
            "roller_c_x_mm": ca[0],
            "roller_c_y_mm": ca[1],
            "roller_d_x_mm": cb[0],
            "roller_d_y_mm": cb[1],
        },
    )
