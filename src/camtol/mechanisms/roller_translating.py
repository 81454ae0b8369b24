"""Offset translating roller follower (THEORY §2.3, §3.3; [Wu03], [WC05]).

References
----------
.. [Wu03] L.-I. Wu, "Calculating conjugate cam profiles by vector equations",
   Proc. IMechE C 217(10):1117-1123, 2003. doi:10.1243/095440603322517126
.. [WC05] L.-I. Wu, W.-T. Chang, "Analysis of mechanical errors in disc cam mechanisms",
   Proc. IMechE C 219(2):209-224, 2005. doi:10.1243/095440605X8478
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from camtol import jet
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, Jet, JetLike
from camtol.mechanisms.base import (
    ContactGeometry,
    ErrorSource,
    OutputKind,
    Parameter,
    RollerGuide,
    length,
    offset,
    register_follower,
    require_finite,
    require_positive,
    shift_angle,
)
from camtol.mechanisms.roller_common import (
    RollerMechanism,
    pitch_curvature_radius,
    roller_undercut_mask,
)

__all__ = ["RollerTranslating", "roller_undercut_mask"]


@register_follower
@dataclass(frozen=True)
class RollerTranslating(RollerMechanism):
    r"""Offset translating roller follower; output S in mm.

    Parameters
    ----------
    base_radius_mm : float
        Base-circle radius r_b of the cam *profile*. [mm]
    roller_radius_mm : float
        Roller radius r_f. [mm]
    offset_mm : float
        Offset e of the translation line along w = (−sin θ, cos θ) (THEORY §2.3). [mm]

    Notes
    -----
    THEORY §2.3 ([Wu03]): prime radius r_p = r_b + r_f, s0 = sqrt(r_p² − e²),
    t = (cos θ, sin θ), w = (−sin θ, cos θ), roller centre (pitch point)
    C = e·w + (s0 + S)·t, instant centre Q = V·w, contact point
    A = C + r_f (Q − C)/|Q − C|, signed pressure angle tan φ = (V − e)/(s0 + S).

    The profile's signed radius of curvature is ρ = ρ_p − r_f with ρ_p the pitch curve's
    (computed exactly from θ-jets of C, which depends on S only). Undercut where
    0 < ρ_p ≤ r_f (:func:`roller_undercut_mask`).
    """

    base_radius_mm: float
    roller_radius_mm: float
    offset_mm: float = 0.0

    kind: ClassVar[str] = "roller_translating"
    motion_only: ClassVar[bool] = True
    listing_order: ClassVar[int] = 3
    output: ClassVar[OutputKind] = "translating"
    title: ClassVar[str] = "translating roller"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / cos φ"
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("base_radius_mm", "base-circle radius r_b of the cam profile"),
        length("roller_radius_mm", "roller radius r_f"),
        offset("offset_mm", "offset e of the translation line"),
    )
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn", "mm", profile="normal"),
        ErrorSource("rf", "roller-radius error Δr_f", "mm", "roller_radius_mm"),
        ErrorSource("e", "offset error Δe", "mm", "offset_mm"),
    )

    def __post_init__(self) -> None:
        require_positive("follower.base_radius_mm", self.base_radius_mm)
        require_positive("follower.roller_radius_mm", self.roller_radius_mm)
        require_finite("follower.offset_mm", self.offset_mm)
        if not abs(self.offset_mm) < self.prime_radius_mm:
            raise DesignError(
                f"follower.offset_mm={self.offset_mm:g} is not allowed; |e| must be smaller than"
                f" the prime radius r_b + r_f = {self.prime_radius_mm:g} mm"
            )

    @property
    def prime_radius_mm(self) -> float:
        """Prime-circle radius r_p = r_b + r_f. [mm]"""
        return self.base_radius_mm + self.roller_radius_mm

    @property
    def s0_mm(self) -> float:
        """s0 = sqrt(r_p² − e²), the roller centre's axial position on the base circle. [mm]"""
        return math.sqrt(self.prime_radius_mm**2 - self.offset_mm**2)

    def pitch_point(self, theta: JetLike, lift: JetLike) -> tuple[JetLike, JetLike]:
        """Roller centre C = e·w + (s0 + S)·t in the cam frame (THEORY §2.3). [mm]

        Parameters
        ----------
        theta : JetLike
            Cam angle θ, as an array or a jet. [rad]
        lift : JetLike
            Follower lift S(θ), as an array or a jet. [mm]

        Returns
        -------
        cx, cy : JetLike
            Coordinates of the roller centre C in the cam frame, jets where the inputs
            are jets. [mm]
        """
        c, s = jet.cos(theta), jet.sin(theta)
        axial = self.s0_mm + lift
        return -self.offset_mm * s + axial * c, self.offset_mm * c + axial * s

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2.3).

        Extras: ``pitch_x``, ``pitch_y`` roller centre C [mm]; ``normal_x``, ``normal_y``
        unit outward profile normal (A → C) [-].
        """
        e, rf = self.offset_mm, self.roller_radius_mm
        cx, cy = self.pitch_point(theta, lift)
        c, s = jet.cos(theta), jet.sin(theta)
        q = velocity
        qx, qy = -q * s, q * c
        dx, dy = qx - cx, qy - cy
        dist = jet.hypot(dx, dy)
        ux, uy = dx / dist, dy / dist
        ax, ay = cx + rf * ux, cy + rf * uy
        pressure = jet.arctan2(velocity - e, self.s0_mm + lift)
        return ContactGeometry(
            ax,
            ay,
            qx,
            qy,
            q,
            pressure,
            shift_angle(ax, ay, qx, qy),
            {"pitch_x": cx, "pitch_y": cy, "normal_x": -ux, "normal_y": -uy},
        )

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        r"""ΔS per unit error, mm per mm (THEORY §3.3, [WC05]).

        Derivation (implicit differentiation of the contact constraint): the roller centre
        C = e·w + (s0 + S)·t stays at distance r_f from the profile, i.e. along the outward
        unit normal n = cos φ·t − sin φ·w (angle −φ from t, since C − Q = (s0+S)·t + (e−V)·w),

        .. math:: n \cdot ΔC = Δn + Δr_f,\qquad ΔC = ΔS\,t + Δe\,w

        so ΔS cos φ − Δe sin φ = Δn + Δr_f and

        ΔS_n = Δn / cos φ, ΔS_rf = Δr_f / cos φ, ΔS_r = Δr cos λ / cos φ (Δn = Δr cos λ,
        THEORY §2.5), **ΔS_e = +Δe tan φ**.

        THEORY §3.3 expects ΔS_e = −Δe tan φ; with §2.3's signed φ (tan φ = (V−e)/(s0+S))
        the sign is +: on the base circle (s0+S)² + e² = r_p², so dS/de = −e/s0 = tan φ.
        Exact re-solution in the tests confirms the + sign.
        """
        inv_c = 1.0 / jet.cos(geometry.pressure_angle)
        return {
            "r": jet.cos(geometry.shift_angle) * inv_c,
            "n": inv_c,
            "rf": inv_c,
            "e": jet.tan(geometry.pressure_angle),
        }

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """Lean form of :meth:`sensitivities`: no trigonometry, no contact point.

        In the frame (t, w) turning with θ, C = (a, e) and Q = (0, V) with a = s0 + S,
        so C − Q = (a, −b), b = V − e, ρ = |C − Q|: cos φ = a/ρ and tan φ = b/a
        (THEORY §2.3). With n = (C − Q)/ρ and A = C − r_f n, sin λ = n × C / |A| =
        aV / (ρ|A|) and |A|² = a² + e² − 2 r_f (a² − b e)/ρ + r_f² (THEORY §2.5); cos λ ≥ 0
        as the arcsin of §2.5 gives it.
        """
        e, rf = self.offset_mm, self.roller_radius_mm
        a = lift + self.s0_mm
        b = velocity - e
        a2 = a * a
        rho = jet.sqrt(a2 + b * b)
        inv_a = 1.0 / a
        inv_cos = rho * inv_a
        radius = jet.sqrt(a2 - 2.0 * rf * (a2 - e * b) / rho + (e * e + rf * rf))
        sin_shift = a * velocity / (rho * radius)
        cos_shift = jet.sqrt(1.0 - sin_shift * sin_shift)
        return {"r": cos_shift * inv_cos, "n": inv_cos, "rf": inv_cos, "e": b * inv_a}

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Signed profile radius of curvature ρ = ρ_pitch − r_f (> 0 convex). [mm]

        The roller centre in the follower's frame is c = (s0 + S, e)
        (:func:`~camtol.mechanisms.roller_common.pitch_curvature_radius`).
        """
        axial = Jet(
            self.s0_mm + np.asarray(lift, float),
            np.asarray(velocity, float),
            np.asarray(acceleration, float),
        )
        return pitch_curvature_radius(axial, self.offset_mm) - self.roller_radius_mm

    def contact_element(self) -> RollerGuide:
        """Return the roller on its line of motion; S = 0 at the axial position s0."""
        return RollerGuide("line", self.roller_radius_mm, offset_mm=self.offset_mm, zero=self.s0_mm)

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes: max radial dimension for r and n, r_f, |e|."""
        return {
            "r": max_radius_mm,
            "n": max_radius_mm,
            "rf": self.roller_radius_mm,
            "e": abs(self.offset_mm),
        }[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", self.title),
            ("base radius r_b", f"{self.base_radius_mm:g} mm"),
            ("roller radius r_f", f"{self.roller_radius_mm:g} mm"),
            ("offset e", f"{self.offset_mm:g} mm"),
        ]
