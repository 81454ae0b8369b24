"""The profile and the cutter-centre path of a design as exact curves of θ (THEORY §2, §6.3).

A cutter of radius R that touches the profile at A(θ) has its centre on the profile's
outward offset C(θ) = A(θ) + R·N(θ). For a roller follower the profile is itself the pitch
curve offset inward by the roller radius r_f, so the cutter path is the pitch curve offset
by R − r_f (a cutter of the roller's size follows the pitch curve). Points, unit tangents,
speeds |dC/dθ| and signed radii of curvature come from the analytic engine's exact θ-jets
(:func:`camtol.kinematics.contact_jets`); the offset curve's radius is ρ + R.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.design import CamDesign
from camtol.exceptions import UndercutError
from camtol.jet import FloatArray, Jet
from camtol.kinematics import contact_jets

__all__ = [
    "PathSample",
    "check_gouge",
    "profile_path",
    "single_cams",
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


def single_cams(design: CamDesign) -> list[tuple[str, CamDesign]]:
    """Return the single cams of a design: itself, or cams A and B of a conjugate pair.

    Parameters
    ----------
    design : CamDesign
        Any design.

    Returns
    -------
    list of (str, CamDesign)
        (label, design of one cam with its own follower); the label is "" for a single
        cam, "A" and "B" for a conjugate pair.
    """
    return [(cam.label, cam.design) for cam in design.cams()]


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
        A single-cam design (see :func:`single_cams` for conjugate pairs).
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


def check_gouge(design: CamDesign, tool_radius_mm: float, *, step_deg: float = 0.05) -> None:
    """Raise if a tool of this radius cannot follow the profile (concave ρ smaller than R).

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    tool_radius_mm : float
        Tool radius R (wire radius + spark gap for wire EDM). [mm]
    step_deg : float
        Angular step of the check. [deg]

    Raises
    ------
    UndercutError
        Naming the smallest concave radius of curvature, the cam angle where it occurs,
        and the largest tool radius that cuts the profile without gouging.
    """
    tight = smallest_concave_radius(design, step_deg=step_deg) if tool_radius_mm > 0 else None
    if tight is not None and tight[0] < tool_radius_mm:
        rho, at = tight
        if math.isinf(tool_radius_mm):
            raise UndercutError(
                f"a flat tool cannot cut this profile: it is concave (radius of curvature"
                f" {rho:.4g} mm) at θ={at:.2f}° and the tool would gouge there; use a"
                f" cylindrical tool of radius at most {rho:.4g} mm"
            )
        raise UndercutError(
            f"tool radius {tool_radius_mm:g} mm is larger than the concave radius of curvature"
            f" {rho:.4g} mm of the profile at θ={at:.2f}°: the tool would gouge there; use a"
            f" tool radius of at most {rho:.4g} mm"
        )
