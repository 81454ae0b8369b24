r"""Exact motion of flat-faced followers on any cam shape (THEORY §5; §2.1, §2.2).

A flat face only ever touches the convex hull of the cam, so its motion is a function of
the shape's support function h(ψ) alone (:mod:`camtol.contact.shapes`).

Translating oblique flat face (THEORY §2.1, CW06 §2.1): with the face normal
n = (cos(θ+φ), sin(θ+φ)) and the reference point P = e w + L t on the translation line,
P·n = L cos φ + e sin φ, so the face touches the cam when

.. math::

    L(θ) = \frac{h(θ + φ) - e \sin φ}{\cos φ},\qquad
    V = \frac{c·n'}{\cos φ},\qquad A = \frac{-c·n}{\cos φ}

where c is the centre of curvature of the shape at the supporting point (X = c + ρ n;
h' = c·n', h'' = ρ − h = −c·n). For the nominal profile h = r_b + S cos φ and this is
THEORY's L = r_b sec φ − e tan φ + S.

Oscillating flat face (THEORY §2.2, CW06 §2.2): the face normal points along
ψ = θ + 90° − ξ and the face line is n·X = f sin ξ + e, so ξ solves
G(θ, ξ) = h(θ + 90° − ξ) − f sin ξ − e = 0. With the supporting feature (vertex, arc, or
osculating circle of an analytic profile) frozen, the equation is
a sin ξ + b cos ξ = e − ρ with a = c·t − f, b = c·w, solved in closed form; iterating
"find the feature, solve for ξ" converges in finitely many steps on a polygon and
quadratically on a smooth profile (the osculating circle agrees with the curve to second
order), and the fixed point is a face tangent to the hull: the exact answer.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact.result import FollowerMotion, implicit_derivatives
from camtol.contact.shapes import AnalyticShape, PolygonShape, Support
from camtol.design.motion import MotionState
from camtol.exceptions import DesignError, GeometryError
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism
from camtol.mechanisms.elements import OscillatingFace, TranslatingFace

__all__ = ["follow_flat_oscillating", "follow_flat_translating"]

Shape = AnalyticShape | PolygonShape


def support(shape: Shape, psi_rad: FloatArray, left_limit: ArrayLike | None = None) -> Support:
    """Support function of either kind of shape (left limits used by analytic shapes)."""
    if isinstance(shape, AnalyticShape):
        return shape.support(psi_rad, left_limit=left_limit)
    return shape.support(psi_rad)


def _element(follower: Mechanism, kind: type[TranslatingFace] | type[OscillatingFace]) -> Any:
    el = follower.contact_element()
    if not isinstance(el, kind):
        raise DesignError(f"follower type {follower.kind!r} is not a {kind.__name__} follower")
    return el


def follow_flat_translating(
    shape: Shape,
    follower: Mechanism,
    theta_rad: ArrayLike,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
) -> FollowerMotion:
    """Exact lift of a translating oblique flat-faced follower on a shape.

    Parameters
    ----------
    shape : AnalyticShape or PolygonShape
        The cam.
    follower : Mechanism
        The actual follower, whose contact element is a
        :class:`~camtol.mechanisms.elements.TranslatingFace` (offset e, face angle φ).
    theta_rad : array_like
        Cam angles. [rad]
    reference : Mechanism, optional
        Follower whose base-circle position defines S = 0 (default: ``follower``);
        S = L − (r_b sec φ − e tan φ) of the reference.
    left_limit : array_like of bool, optional
        Rows taking one-sided (left) derivatives at profile boundaries.

    Returns
    -------
    FollowerMotion
        S [mm], V [mm/rad], A [mm/rad²] and the contact point.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    face: TranslatingFace = _element(follower, TranslatingFace)
    zero = _element(follower if reference is None else reference, TranslatingFace).zero
    phi, e = face.face_angle_rad, face.offset_mm
    cphi = math.cos(phi)
    psi = theta + phi
    sup = support(shape, psi, left_limit)
    c, s = sup.normal_x, sup.normal_y
    cx, cy = sup.centre_x_mm, sup.centre_y_mm
    # In place: on long grids every fresh array costs page faults.
    lift = sup.h_mm - e * math.sin(phi)
    lift /= cphi
    lift -= zero
    vel = cy * c
    vel -= cx * s
    vel /= cphi
    acc = cx * c
    acc += cy * s
    acc /= -cphi
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(lift, vel, acc, np.full_like(lift, np.nan)),
        contact_x_mm=sup.contact_x_mm,
        contact_y_mm=sup.contact_y_mm,
        feature=sup.feature,
        param_rad=sup.param_rad,
    )


def _initial_angle(shape: Shape, face: OscillatingFace, theta: FloatArray) -> FloatArray:
    """Guess ξ to start the feature iteration. [rad]

    The nominal motion of the shape's own oscillating flat follower, else the angle on a
    circle of the shape's mean vertex radius.
    """
    if isinstance(shape, AnalyticShape):
        own = shape.mechanism.contact_element() if shape.mechanism.has_face else None
        if isinstance(own, OscillatingFace):
            return own.zero + shape.program.evaluate(theta).lift
    poly = shape.polygon if isinstance(shape, AnalyticShape) else shape
    r = float(np.mean(np.hypot(poly.vertices_mm[:, 0], poly.vertices_mm[:, 1])))
    ratio = (r - face.face_offset_mm) / face.pivot_distance_mm
    return np.full(theta.shape, math.asin(min(max(ratio, -0.999), 0.999)))


def follow_flat_oscillating(
    shape: Shape,
    follower: Mechanism,
    theta_rad: ArrayLike,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
    initial_rad: ArrayLike | None = None,
    max_iterations: int = 100,
) -> FollowerMotion:
    """Exact angle of an oscillating flat-faced follower on a shape.

    Parameters
    ----------
    shape : AnalyticShape or PolygonShape
        The cam.
    follower : Mechanism
        The actual follower, whose contact element is an
        :class:`~camtol.mechanisms.elements.OscillatingFace` (pivot distance f, offset e).
    theta_rad : array_like
        Cam angles. [rad]
    reference : Mechanism, optional
        Follower whose ξ0 = asin((r_b − e)/f) defines S = 0 (default: ``follower``).
    left_limit : array_like of bool, optional
        Rows taking one-sided (left) derivatives at profile boundaries.
    initial_rad : array_like, optional
        Starting guess for ξ (default: the shape's own nominal motion when it was
        synthesised for an oscillating flat face, else a circle of its mean radius). [rad]
    max_iterations : int
        Limit on feature iterations.

    Returns
    -------
    FollowerMotion
        S = ξ − ξ0 [rad], V [rad/rad], A [rad/rad²], contact point, and
        ``extras["follower_angle_rad"]`` = ξ.

    Raises
    ------
    GeometryError
        If the face cannot touch the shape (|e − ρ| > distance) or does not converge.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    face: OscillatingFace = _element(follower, OscillatingFace)
    zero = _element(follower if reference is None else reference, OscillatingFace).zero
    f, e = face.pivot_distance_mm, face.face_offset_mm
    xi = (
        _initial_angle(shape, face, theta)
        if initial_rad is None
        else np.broadcast_to(np.asarray(initial_rad, dtype=float), theta.shape).copy()
    )
    ct, st = np.cos(theta), np.sin(theta)
    reach = support(shape, theta).h_mm
    if np.any(reach >= f):
        i = int(np.argmax(reach - f))
        raise GeometryError(
            f"the cam reaches {reach[i]:.6g} mm towards the follower pivot at"
            f" θ={math.degrees(theta[i]):.2f}°, beyond the pivot distance f={f:g} mm:"
            " the face cannot touch it there"
        )
    feature = np.full(theta.shape, -2, dtype=np.intp)
    for _ in range(max_iterations):
        sup = support(shape, theta + 0.5 * math.pi - xi, left_limit)
        cx, cy, rho = sup.centre_x_mm, sup.centre_y_mm, sup.radius_mm
        a = cx * ct + cy * st - f
        b = -cx * st + cy * ct
        k = (e - rho) / np.hypot(a, b)
        if np.any(np.abs(k) > 1.0):
            i = int(np.argmax(np.abs(k)))
            raise GeometryError(
                f"the flat face cannot touch the cam at θ={math.degrees(theta[i]):.2f}°"
                " (the pivot is too close to the cam or the face offset too large)"
            )
        delta = np.arctan2(b, a)
        r1 = np.arcsin(k) - delta
        r2 = math.pi - np.arcsin(k) - delta
        d1 = np.mod(r1 - xi + math.pi, 2 * math.pi) - math.pi
        d2 = np.mod(r2 - xi + math.pi, 2 * math.pi) - math.pi
        step = np.where(np.abs(d1) <= np.abs(d2), d1, d2)
        xi = xi + step
        same = feature == sup.feature
        feature = sup.feature
        if np.max(np.abs(step)) < 1e-13 or (np.all(same) and np.max(np.abs(step)) < 1e-11):
            break
    else:
        raise GeometryError(
            "the oscillating flat face did not settle on the cam within"
            f" {max_iterations} iterations"
        )
    psi = theta + 0.5 * math.pi - xi
    sup = support(shape, psi, left_limit)
    n_x, n_y = sup.normal_x, sup.normal_y
    c_n = sup.centre_x_mm * n_x + sup.centre_y_mm * n_y
    c_dn = -sup.centre_x_mm * n_y + sup.centre_y_mm * n_x
    v, acc = implicit_derivatives(
        c_dn,
        -c_dn - f * np.cos(xi),
        -c_n,
        c_n,
        -c_n + f * np.sin(xi),
    )
    lift = xi - zero
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(lift, v, acc, np.full_like(lift, np.nan)),
        contact_x_mm=sup.contact_x_mm,
        contact_y_mm=sup.contact_y_mm,
        feature=sup.feature,
        param_rad=sup.param_rad,
        extras={"follower_angle_rad": xi},
    )
