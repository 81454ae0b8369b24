"""Exact motion of roller followers on any cam shape (THEORY §5; §2.3, §2.4).

A roller needs the true distance to the cam, not its hull: the roller centre C sits where
its distance to the cam equals r_f, on the follower's path for the cam angle θ:

- translating (THEORY §2.3): C = e·w + y·t on a line, t = (cos θ, sin θ),
  w = (−sin θ, cos θ); the output is y (S = y − s0 of the reference follower);
- oscillating (THEORY §2.4): C = f·t − l·(cos(θ + σγ), sin(θ + σγ)) on a circle about the
  pivot O3 = f·t, with γ the arm angle from O3O2 (σ = −1, γ = ξ for cam A; σ = +1,
  γ = η − ξ for cam B of a conjugate pair).

On a polygon the contact is found in closed form per feature
(:mod:`camtol.contact.roller_polygon`). On an analytic profile the contact (t, y) or
(t, γ) solves the two conditions (C − P(t))·P'(t) = 0 and |C − P(t)|² = r_f² by Newton's
method from the nominal contact, and the result is checked against the sampled profile
(no sample point may lie closer than r_f to the roller centre). V and A come from
implicit differentiation with the osculating circle frozen: exact one-sided derivatives.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact.result import FollowerMotion
from camtol.contact.roller_path import RollerPath, check_clear, roller_path
from camtol.contact.roller_polygon import derivatives_circle, derivatives_line, solve_polygon
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design.motion import MotionState
from camtol.exceptions import DesignError, GeometryError
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism

__all__ = ["follow_roller"]

TWO_PI = 2.0 * math.pi
Shape = AnalyticShape | PolygonShape


def _solve_analytic(
    theta: FloatArray,
    shape: AnalyticShape,
    path: RollerPath,
    t0: FloatArray,
    x0: FloatArray,
    left_limit: ArrayLike | None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """x, x', x'', contact point and profile parameter by 2×2 Newton from (t0, x0)."""
    t, x = t0.copy(), x0.copy()
    rf = path.roller_mm
    step_t = 4.0 * TWO_PI / shape.samples
    for _ in range(60):
        px, py = shape.jets(t)
        cx, cy = path.centre(theta, x)
        (_, (cxx, cxy), *_rest) = path.partials(theta, x)
        gx, gy = cx - px.v, cy - py.v
        g1 = gx * px.d1 + gy * py.d1
        g2 = gx * gx + gy * gy - rf * rf
        a11 = -(px.d1**2 + py.d1**2) + gx * px.d2 + gy * py.d2
        a12 = cxx * px.d1 + cxy * py.d1
        a21 = -2.0 * g1
        a22 = 2.0 * (gx * cxx + gy * cxy)
        det = a11 * a22 - a12 * a21
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = -(a22 * g1 - a12 * g2) / det
            dx = -(-a21 * g1 + a11 * g2) / det
        if not (np.all(np.isfinite(dt)) and np.all(np.isfinite(dx))):
            raise GeometryError("the roller contact on the analytic profile is singular")
        dt = np.clip(dt, -step_t, step_t)
        t, x = t + dt, x + dx
        if np.max(np.abs(dt)) < 1e-13 and np.max(np.abs(dx)) < 1e-12:
            break
    else:
        raise GeometryError("the roller contact on the analytic profile did not converge")
    t = shape.snap(t)
    px, py = shape.jets(t, left_limit=left_limit)
    cx, cy = path.centre(theta, x)
    check_clear(shape, cx, cy, rf, theta)
    speed = np.hypot(px.d1, py.d1)
    cross = px.d1 * py.d2 - py.d1 * px.d2
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = speed**3 / cross
    nx, ny = py.d1 / speed, -px.d1 / speed  # outward normal (counterclockwise profile)
    ccx, ccy = px.v - rho * nx, py.v - rho * ny
    flat = ~np.isfinite(rho) | (np.abs(rho) > 1e9)
    x1, x2 = derivatives_circle(path, theta, x, ccx, ccy)
    if np.any(flat):
        l1, l2 = derivatives_line(path, theta, x, nx, ny)
        x1, x2 = np.where(flat, l1, x1), np.where(flat, l2, x2)
    return x, x1, x2, px.v, py.v, t


def follow_roller(
    shape: Shape,
    follower: Mechanism,
    theta_rad: ArrayLike,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
) -> FollowerMotion:
    """Exact motion of any roller follower on a shape (THEORY §5).

    Parameters
    ----------
    shape : AnalyticShape or PolygonShape
        The cam.
    follower : Mechanism
        The actual follower; its :meth:`~camtol.mechanisms.base.Mechanism.contact_element`
        must be a :class:`~camtol.mechanisms.elements.RollerGuide` (translating, oscillating,
        cam B of a conjugate pair, or a new roller type).
    theta_rad : array_like
        Cam angles. [rad]
    reference : Mechanism, optional
        Follower whose datum (s0 or ξ0) defines S = 0 (default: ``follower``).
    left_limit : array_like of bool, optional
        Rows taking one-sided derivatives at profile boundaries.

    Returns
    -------
    FollowerMotion
        S [mm or rad], V, A, contact point, ``roller_x_mm``/``roller_y_mm`` and, on a
        circle, ``follower_angle_rad`` ξ.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    path, sign, shift, _ = roller_path(follower)
    zero = roller_path(follower if reference is None else reference)[3]
    param = np.full(theta.shape, np.nan)
    if isinstance(shape, AnalyticShape):
        seed = _analytic_seed(theta, shape, path)
        solved = None
        if seed is not None:
            try:
                solved = _solve_analytic(theta, shape, path, seed[0], seed[1], left_limit)
            except GeometryError:
                solved = None  # e.g. the error moved the contact: seed from the polygon
        if solved is None:
            # Global seed: the exact contact on the sampled polygon (vertex, or an edge's
            # first vertex), then Newton on the curve.
            xs, *_r, fid = solve_polygon(theta, shape.polygon, path)
            seed = (shape.vertex_param(fid), xs)
            solved = _solve_analytic(theta, shape, path, seed[0], seed[1], left_limit)
        x, x1, x2, ax, ay, param = solved
        fid = np.full(theta.shape, -1, dtype=np.intp)
    else:
        x, x1, x2, ax, ay, fid = solve_polygon(theta, shape, path)
    output = sign * x + shift
    lift = output - zero
    rx, ry = path.centre(theta, x)
    extras = {"roller_x_mm": rx, "roller_y_mm": ry}
    if path.kind == "circle":
        extras["follower_angle_rad"] = output
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(lift, sign * x1, sign * x2, np.full_like(lift, np.nan)),
        contact_x_mm=ax,
        contact_y_mm=ay,
        feature=fid,
        param_rad=param,
        extras=extras,
    )


def _analytic_seed(
    theta: FloatArray, shape: AnalyticShape, path: RollerPath
) -> tuple[FloatArray, FloatArray] | None:
    """(t0, x0) from the shape's own nominal mechanism when it is a roller of this path."""
    mech = shape.mechanism
    try:
        own_path, sign, shift, zero = roller_path(mech)
    except (DesignError, KeyError):
        return None
    if own_path.kind != path.kind or own_path.side != path.side:
        return None
    lift = shape.program.evaluate(theta).lift
    return np.mod(theta, TWO_PI), sign * (lift + zero - shift)
