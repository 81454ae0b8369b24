"""A cam profile and its offset curves as exact curves of θ (THEORY §2, §6.3).

A cutter of radius R that touches the profile at A(θ) has its centre on the profile's
outward offset C(θ) = A(θ) + R·N(θ). For a roller follower the profile is itself the pitch
curve offset inward by the roller radius r_f, so the cutter path is the pitch curve offset
by R − r_f (a cutter of the roller's size follows the pitch curve). Points, unit tangents,
speeds |dC/dθ| and signed radii of curvature come from the analytic engine's exact θ-jets
(:func:`camtol.analysis.kinematics.contact_jets`); the offset curve's radius is ρ + R.

The same offset is a cutter's centre path (:mod:`camtol.manufacturing.toolpath`) and a CMM
probe ball's (:mod:`camtol.inspection.deviations`): neither can follow a concave stretch
tighter than its radius (:func:`smallest_concave_radius`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.analysis.kinematics import contact_jets
from camtol.design.cam_design import CamDesign
from camtol.jet import FloatArray, Jet

__all__ = [
    "PathSample",
    "profile_path",
    "smallest_concave_radius",
]


@dataclass(frozen=True)
class PathSample:
    """A closed planar curve sampled at cam angles (counterclockwise as θ grows).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    x_mm, y_mm : ndarray
        Points in the cam frame. [mm]
    tx, ty : ndarray
        Unit tangent in the direction of growing θ. [-]
    speed_mm : ndarray
        |dP/dθ|. [mm/rad]
    rho_mm : ndarray
        Signed radius of curvature, > 0 where the curve is convex. [mm]
    """

    theta_rad: FloatArray
    x_mm: FloatArray
    y_mm: FloatArray
    tx: FloatArray
    ty: FloatArray
    speed_mm: FloatArray
    rho_mm: FloatArray

    @property
    def normal_x(self) -> FloatArray:
        """Outward unit normal, x component (the tangent turned clockwise). [-]"""
        return self.ty

    @property
    def normal_y(self) -> FloatArray:
        """Outward unit normal, y component. [-]"""
        return -self.tx


def profile_path(
    design: CamDesign,
    theta_rad: ArrayLike,
    *,
    offset_mm: float = 0.0,
    left_limit: ArrayLike | None = None,
) -> PathSample:
    """Evaluate the cam profile, or its outward offset by ``offset_mm`` (a cutter path).

    Parameters
    ----------
    design : CamDesign
        A single-cam design (one of :meth:`~camtol.design.cam_design.CamDesign.cams`).
    theta_rad : array_like
        Cam angles. [rad]
    offset_mm : float
        Outward offset R (cutter radius; wire radius + spark gap for wire EDM). [mm]
    left_limit : array_like of bool, optional
        Rows taking left limits at program boundaries.

    Returns
    -------
    PathSample
        The offset curve at ``theta_rad``. [mm]
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    motion = design.program.evaluate(theta, left_limit=left_limit)
    g = contact_jets(design, theta, motion)
    x, y = g.contact_x, g.contact_y
    if not (isinstance(x, Jet) and isinstance(y, Jet)):  # pragma: no cover - defensive
        raise TypeError("the mechanism's contact point is not a jet in θ")
    speed = np.hypot(x.d1, y.d1)
    cross = x.d1 * y.d2 - y.d1 * x.d2
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = speed**3 / cross
        tx, ty = x.d1 / speed, y.d1 / speed
    d = float(offset_mm)
    if d == 0.0:
        return PathSample(theta, x.v, y.v, tx, ty, speed, rho)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(np.isfinite(rho), (rho + d) / rho, 1.0)
    return PathSample(theta, x.v + d * ty, y.v - d * tx, tx, ty, speed * ratio, rho + d)


def smallest_concave_radius(
    design: CamDesign, *, step_deg: float = 0.05
) -> tuple[float, float] | None:
    """Return the smallest concave radius of curvature of a cam's profile and where, or None.

    What a round tool, a grinding wheel or a probe ball must not exceed to touch the
    profile everywhere.

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    step_deg : float
        Angular step of the search. [deg]

    Returns
    -------
    (float, float) or None
        |ρ| [mm] and the cam angle θ [deg] of the tightest concave stretch; None for a
        profile with no concave stretch.
    """
    n = int(round(360.0 / step_deg))
    theta = np.arange(n) * (2.0 * math.pi / n)
    rho = profile_path(design, theta).rho_mm
    concave = rho < 0
    if not np.any(concave):
        return None
    i = int(np.argmax(np.where(concave, rho, -np.inf)))
    return float(-rho[i]), math.degrees(theta[i])
