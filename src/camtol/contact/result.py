"""Result type of the contact engine and the implicit-derivative helper (THEORY §5)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from camtol.design.motion import MotionState
from camtol.jet import FloatArray

__all__ = ["FollowerMotion", "implicit_derivatives"]


@dataclass(frozen=True)
class FollowerMotion:
    """Exact follower motion on a cam shape, over a θ grid (THEORY §5).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    motion : MotionState
        S, V, A of the follower in the analytic engine's result type: S in mm (translating)
        or rad (oscillating), measured from the *reference* follower's zero (so that S of a
        perturbed mechanism is directly comparable with the nominal program); V and A are
        the exact one-sided θ-derivatives of the contact in place at each θ. J is not
        computed (NaN). [mm or rad, per rad^k]
    contact_x_mm, contact_y_mm : ndarray
        Contact point on the shape. [mm]
    feature : ndarray of int
        Polygon feature in contact (vertex index, or M + edge index for an edge or arc);
        −1 on an analytic shape. V and A jump where it changes (real velocity jumps).
    param_rad : ndarray
        Profile parameter of the contact point on an analytic shape; NaN on a polygon.
        [rad]
    extras : dict of str to ndarray
        Follower-specific outputs, e.g. ``follower_angle_rad`` or ``centre_distance_mm``
        (conjugate fixture), ``roller_x_mm``/``roller_y_mm``.
    """

    theta_rad: FloatArray
    motion: MotionState
    contact_x_mm: FloatArray
    contact_y_mm: FloatArray
    feature: NDArray[np.intp]
    param_rad: FloatArray
    extras: dict[str, FloatArray] = field(default_factory=dict)

    @property
    def lift(self) -> FloatArray:
        """S(θ). [mm or rad]"""
        return self.motion.lift

    @property
    def velocity(self) -> FloatArray:
        """V = dS/dθ. [mm/rad or rad/rad]"""
        return self.motion.velocity

    @property
    def acceleration(self) -> FloatArray:
        """A = d²S/dθ². [mm/rad² or rad/rad²]"""
        return self.motion.acceleration


def implicit_derivatives(
    g_t: FloatArray,
    g_x: FloatArray,
    g_tt: FloatArray,
    g_tx: FloatArray,
    g_xx: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """First and second derivatives x', x'' of x(θ) defined by G(θ, x) = 0.

    Parameters
    ----------
    g_t, g_x, g_tt, g_tx, g_xx : ndarray
        Partial derivatives of G at the solution. [unit of G per unit of θ and x]

    Returns
    -------
    x1, x2 : ndarray
        x' = −G_θ/G_x and x'' = −(G_θθ + 2 G_θx x' + G_xx x'²)/G_x.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        x1 = -g_t / g_x
        x2 = -(g_tt + 2.0 * g_tx * x1 + g_xx * x1 * x1) / g_x
    return x1, x2
