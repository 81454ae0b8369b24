"""What every roller follower shares: the undercut rule and the drawing (THEORY §2.3).

A roller follower generates a profile unless its convex pitch curve is sharper than the
roller; a concave stretch is fine. :class:`RollerMechanism` carries that rule once.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from camtol.jet import FloatArray, Jet, JetLike, Real, hypot
from camtol.mechanisms.base import Mechanism
from camtol.mechanisms.elements import Outline, point

__all__ = ["RollerMechanism", "pitch_curvature_radius", "roller_undercut_mask"]


def roller_undercut_mask(
    curvature_radius_mm: FloatArray, roller_radius_mm: float
) -> NDArray[np.bool_]:
    """Where a roller cannot generate the profile (THEORY §2.3, undercut).

    Parameters
    ----------
    curvature_radius_mm : ndarray
        Signed profile radius of curvature ρ = ρ_pitch − r_f (> 0 convex). [mm]
    roller_radius_mm : float
        Roller radius r_f. [mm]

    Returns
    -------
    ndarray of bool
        True where the convex pitch curve is sharper than the roller, 0 < ρ_pitch ≤ r_f,
        i.e. −r_f < ρ ≤ 0. A concave pitch curve (ρ ≤ −r_f) is fine for a roller.
    """
    rho = np.asarray(curvature_radius_mm, dtype=float)
    return np.asarray((rho <= 0.0) & (rho > -roller_radius_mm))


def _parts(x: JetLike) -> tuple[Real, Real, Real]:
    """(f, f', f'') of a jet; a constant has zero derivatives."""
    return (x.v, x.d1, x.d2) if isinstance(x, Jet) else (x, 0.0, 0.0)


def pitch_curvature_radius(cx: JetLike, cy: JetLike) -> FloatArray:
    r"""Signed radius of curvature of the pitch curve from the follower's frame. [mm]

    Parameters
    ----------
    cx, cy : JetLike
        Roller centre c in the frame of the line of centres (x along O2 → follower), as
        θ-jets of the motion (a constant coordinate may be a float). [mm, mm/rad, mm/rad²]

    Returns
    -------
    ndarray
        ρ_pitch = |P'|³ / (P' × P''), > 0 where the pitch curve turns counterclockwise
        (convex, THEORY §0); ±inf at an inflection. [mm]

    Notes
    -----
    The cam frame sees the roller centre at P(θ) = R(θ) c(θ) (kinematic inversion,
    THEORY §0), so P' = R(θ)(c' + Jc) and P'' = R(θ)(c'' + 2Jc' − c) with J the
    quarter turn (x, y) → (−y, x). A rotation keeps lengths and cross products, hence

    .. math:: ρ = \frac{|c' + Jc|^3}{(c' + Jc) × (c'' + 2Jc' − c)}

    which depends on the motion state (S, V, A) alone: no sine or cosine of θ, and the
    same value wherever the follower dwells. For a translating roller, c = (s0 + S, e)
    gives the classical (V − e)(2V − e) − (s0 + S)(A − s0 − S) in the denominator.
    """
    x, x1, x2 = _parts(cx)
    y, y1, y2 = _parts(cy)
    ux, uy = x1 - y, y1 + x
    wx, wy = x2 - 2.0 * y1 - x, y2 + 2.0 * x1 - y
    speed = hypot(ux, uy)
    cross = ux * wy - uy * wx
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(speed**3 / cross)


class RollerMechanism(Mechanism):
    """A mechanism whose follower touches the cam through a roller (THEORY §2.3, §2.4).

    It carries the roller's undercut rule once for every roller follower: a concave
    stretch of the profile is fine, a convex pitch curve sharper than the roller is not.
    """

    #: Roller radius r_f, defined as a field by each concrete mechanism. [mm]
    roller_radius_mm: float

    def undercut_mask(self, curvature_radius_mm: FloatArray) -> NDArray[np.bool_]:
        """Undercut where the convex pitch curve is sharper than the roller (THEORY §2.3).

        Parameters
        ----------
        curvature_radius_mm : ndarray
            Signed profile radius of curvature ρ = ρ_pitch − r_f (> 0 convex). [mm]

        Returns
        -------
        ndarray of bool
            See :func:`roller_undercut_mask`.
        """
        return roller_undercut_mask(curvature_radius_mm, self.roller_radius_mm)

    def undercut_message(self, curvature_radius_mm: float, theta_deg: float) -> str:
        """Say why a roller undercuts: its convex pitch curve is too sharp (THEORY §2.3).

        Parameters
        ----------
        curvature_radius_mm : float
            Signed profile radius of curvature there. [mm]
        theta_deg : float
            Cam angle. [deg]

        Returns
        -------
        str
            The reason, without the remedy.
        """
        rho, roller = curvature_radius_mm, self.roller_radius_mm
        return (
            f"the roller undercuts the profile: radius of curvature {rho:.4g} mm at"
            f" θ={theta_deg:.2f}° (pitch-curve radius {rho + roller:.4g} mm, smaller than the"
            f" roller radius {roller:g} mm)"
        )

    def outline(self, theta_rad: float, lift: float, velocity: float, scale_mm: float) -> Outline:
        """Roller circle; stem along t (translating) or arm from the pivot O3 (see base)."""
        g = self.contact(np.array([theta_rad]), np.array([lift]), np.array([velocity]))
        c = (point(g.extras["pitch_x"]), point(g.extras["pitch_y"]))
        circle = ((c[0], c[1], self.roller_radius_mm),)
        pivot = self.pivot_clearance_mm
        t = (math.cos(theta_rad), math.sin(theta_rad))
        if pivot is None:
            stem = (c[0] + 0.8 * scale_mm * t[0], c[1] + 0.8 * scale_mm * t[1])
            return Outline(circles=circle, segments=((c, stem),))
        o3 = (pivot * t[0], pivot * t[1])
        return Outline(circles=circle, segments=((o3, c),), pivots=(o3,))
