"""Oscillating flat-faced follower (THEORY §2.2, §3.2; [CW06] §2.2, §3).

References
----------
.. [CW06] W.-T. Chang, L.-I. Wu, "Mechanical error analysis of disk cam mechanisms with a
   flat-faced follower", J. Mech. Sci. Technol. 20(3):345-357, 2006.
   doi:10.1007/BF02916465
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from camtol import jet
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, JetLike
from camtol.mechanisms.base import (
    ContactGeometry,
    ErrorSource,
    Mechanism,
    OscillatingFace,
    Outline,
    OutputKind,
    Parameter,
    face_segment,
    length,
    offset,
    point,
    register_follower,
    require_finite,
    require_positive,
    shift_angle,
)

__all__ = ["FlatOscillating"]


@register_follower
@dataclass(frozen=True)
class FlatOscillating(Mechanism):
    r"""Oscillating flat-faced follower; output ξ in radians.

    Parameters
    ----------
    base_radius_mm : float
        Base-circle radius r_b. [mm]
    pivot_distance_mm : float
        Centre distance f = |O2O3|. [mm]
    face_offset_mm : float
        Distance e of the face from the pivot O3; positive when the face is offset away
        from the cam centre (THEORY §2.2). [mm]

    Notes
    -----
    THEORY §2.2 (CW06 eqs. 18-21; CW06 eq. 18's "+q(cos θ, sin θ)" is a misprint):

    .. math::

        ξ = \arcsin\frac{r_b - e}{f} + S,\quad q = \frac{fV}{1 - V},\quad
        QE = (f + q)\sin ξ,\quad α = 90° - ξ

    A = ((QE + e) cos(θ+α) − q cos θ, (QE + e) sin(θ+α) − q sin θ),
    tan φ = e / ((f + q) cos ξ), u = (f + q) cos ξ. The follower turns in the same sense
    as the cam during a rise (THEORY §0), so V < 1 is required everywhere.

    The face normal points along ψ = θ + α, so dψ/dθ = 1 − V, and the profile's support
    function is p = A·n = f sin ξ + e. Hence the radius of curvature in closed form:

    .. math::

        ρ = p + \frac{d^2p}{dψ^2}
          = f\sin ξ + e + f\left(\frac{A\cos ξ}{(1-V)^3}
            - \frac{V^2 \sin ξ}{(1-V)^2}\right)
    """

    base_radius_mm: float
    pivot_distance_mm: float
    face_offset_mm: float = 0.0

    kind: ClassVar[str] = "flat_oscillating"
    motion_only: ClassVar[bool] = True
    listing_order: ClassVar[int] = 2
    output: ClassVar[OutputKind] = "oscillating"
    title: ClassVar[str] = "oscillating flat-faced"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / u"
    has_face: ClassVar[bool] = True
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("base_radius_mm", "base-circle radius r_b"),
        length("pivot_distance_mm", "centre distance f = |O2O3|"),
        offset("face_offset_mm", "offset e of the face from the pivot"),
    )
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn", "mm", profile="normal"),
        ErrorSource("f", "pivot-distance error Δf", "mm", "pivot_distance_mm"),
        ErrorSource("e", "face-offset error Δe", "mm", "face_offset_mm"),
    )

    def __post_init__(self) -> None:
        require_positive("follower.base_radius_mm", self.base_radius_mm)
        require_positive("follower.pivot_distance_mm", self.pivot_distance_mm)
        require_finite("follower.face_offset_mm", self.face_offset_mm)
        ratio = (self.base_radius_mm - self.face_offset_mm) / self.pivot_distance_mm
        if not -1.0 < ratio < 1.0:
            raise DesignError(
                f"follower.pivot_distance_mm={self.pivot_distance_mm:g} is too short: the face"
                f" at e={self.face_offset_mm:g} mm cannot touch a base circle of"
                f" {self.base_radius_mm:g} mm; need f > |r_b − e| ="
                f" {abs(self.base_radius_mm - self.face_offset_mm):g} mm"
            )

    @property
    def initial_angle_rad(self) -> float:
        """ξ0 = asin((r_b − e)/f), the follower angle on the base circle. [rad]"""
        return math.asin((self.base_radius_mm - self.face_offset_mm) / self.pivot_distance_mm)

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2.2).

        Extras: ``face_contact`` u = (f+q) cos ξ [mm]; ``follower_angle`` ξ [rad].
        """
        f, e = self.pivot_distance_mm, self.face_offset_mm
        xi = self.initial_angle_rad + lift
        q = f * velocity / (1.0 - velocity)
        sx, cx = jet.sincos(xi)
        qe = (f + q) * sx
        c, s = jet.cos(theta), jet.sin(theta)
        # (cos, sin)(θ + α) with α = 90° − ξ, from sin ξ and cos ξ: no further sine
        ax = (qe + e) * (c * sx - s * cx) - q * c
        ay = (qe + e) * (s * sx + c * cx) - q * s
        qx, qy = -q * c, -q * s
        u = (f + q) * cx
        pressure = jet.arctan2(e + 0.0 * u, u)
        return ContactGeometry(
            ax,
            ay,
            qx,
            qy,
            q,
            pressure,
            shift_angle(ax, ay, qx, qy),
            {"face_contact": u, "follower_angle": xi},
        )

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """Δξ per unit error, rad per mm (THEORY §3.2, CW06 eqs. 31-36, 43).

        ΔS_n = Δn/u, ΔS_f = −Δf sin ξ/u, ΔS_e = −Δe/u, ΔS_r = Δr cos λ/u, from
        ΔS = Δξ = −Δθ3 and ∂F/∂θ3 = −u. CW06 prints eq. 34 as +Δf sin ξ/u and eq. 35 as
        +Δe/u; both are misprints (THEORY §3.2; proved by exact re-simulation in the tests).
        """
        u = geometry.extras["face_contact"]
        xi = geometry.extras["follower_angle"]
        inv_u = 1.0 / u
        return {
            "r": jet.cos(geometry.shift_angle) * inv_u,
            "n": inv_u,
            "f": -jet.sin(xi) * inv_u,
            "e": -inv_u,
        }

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """Lean form of :meth:`sensitivities` through the support function.

        p = f sin ξ + e and dp/dψ = q cos ξ = f V cos ξ/(1 − V) give |O2A| = sqrt(p² + p'²)
        and cos λ = p/|O2A| (THEORY §2.5: sin λ = f V cos ξ / ((1 − V)|O2A|)).
        """
        f = self.pivot_distance_mm
        xi = lift + self.initial_angle_rad
        sx, cx = jet.sincos(xi)
        q = velocity * f / (1.0 - velocity)
        p = sx * f + self.face_offset_mm
        dp = q * cx
        inv_u = 1.0 / ((q + f) * cx)
        return {
            "r": p / jet.sqrt(p * p + dp * dp) * inv_u,
            "n": inv_u,
            "f": -sx * inv_u,
            "e": -inv_u,
        }

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Closed-form ρ (see class Notes). [mm]"""
        f, e = self.pivot_distance_mm, self.face_offset_mm
        xi = self.initial_angle_rad + lift
        sin_xi, cos_xi = jet.sincos(xi)  # once: transcendentals dominate
        one_v = 1.0 - velocity
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.asarray(
                f * sin_xi
                + e
                + f * (acceleration * cos_xi / one_v**3 - velocity**2 * sin_xi / one_v**2)
            )

    def contact_element(self) -> OscillatingFace:
        """Return the face for the contact engine; S = 0 at ξ0."""
        return OscillatingFace(self.pivot_distance_mm, self.face_offset_mm, self.initial_angle_rad)

    @property
    def pivot_clearance_mm(self) -> float:
        """The pivot distance f, which the cam must not reach. [mm]"""
        return self.pivot_distance_mm

    def outline(self, theta_rad: float, lift: float, velocity: float, scale_mm: float) -> Outline:
        """Face through A, arm from O3 to the face's foot, pivot O3 (see base class)."""
        g = self.contact(np.array([theta_rad]), np.array([lift]), np.array([velocity]))
        a = (point(g.contact_x), point(g.contact_y))
        f = self.pivot_distance_mm
        o3 = (f * math.cos(theta_rad), f * math.sin(theta_rad))
        psi = theta_rad + math.pi / 2.0 - (self.initial_angle_rad + lift)
        d = (-math.sin(psi), math.cos(psi))
        k = (o3[0] - a[0]) * d[0] + (o3[1] - a[1]) * d[1]
        foot = (a[0] + k * d[0], a[1] + k * d[1])
        return Outline(segments=(face_segment(a, foot, d, scale_mm), (o3, foot)), pivots=(o3,))

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes: max radial dimension for r and n, f, |e|."""
        return {
            "r": max_radius_mm,
            "n": max_radius_mm,
            "f": self.pivot_distance_mm,
            "e": abs(self.face_offset_mm),
        }[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", self.title),
            ("base radius r_b", f"{self.base_radius_mm:g} mm"),
            ("pivot distance f", f"{self.pivot_distance_mm:g} mm"),
            ("face offset e", f"{self.face_offset_mm:g} mm"),
            ("initial follower angle ξ0", f"{math.degrees(self.initial_angle_rad):.4f}°"),
        ]
