"""Offset translating oblique flat-faced follower (THEORY §2.1, §3.1; [CW06] §2.1, §3).

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
    Outline,
    OutputKind,
    Parameter,
    TranslatingFace,
    face_segment,
    length,
    offset,
    point,
    register_follower,
    require_finite,
    require_positive,
)

__all__ = ["FlatTranslating"]


@register_follower
@dataclass(frozen=True)
class FlatTranslating(Mechanism):
    r"""Offset translating oblique flat-faced follower.

    Parameters
    ----------
    base_radius_mm : float
        Base-circle radius r_b. [mm]
    offset_mm : float
        Offset e of the translation line; e > 0 puts the offset point E on the side of Q
        when q > 0 (THEORY §2.1). [mm]
    face_angle_rad : float
        Face obliquity φ, the constant pressure angle; φ > 0 turns the face normal
        counterclockwise. [rad]

    Notes
    -----
    In the cam frame (THEORY §2.1) the translation direction is t = (cos θ, sin θ) and the
    face normal n = (cos(θ+φ), sin(θ+φ)):

    .. math::

        L = r_b \sec φ - e \tan φ + S,\quad q = V,\quad
        QA = L\cos φ - (q - e)\sin φ,\quad u = L \sin φ + (q - e)\cos φ

    and A = (QA cos(θ+φ) − q sin θ, QA sin(θ+φ) + q cos θ). The support function of the
    profile in the face-normal direction is p = A·n = r_b + S cos φ, which gives the radius
    of curvature of the profile in closed form, ρ = p + d²p/dψ² = r_b + (S + A) cos φ
    (ψ = θ + φ); with φ = 0 this is THEORY's r_b + S + A.
    """

    base_radius_mm: float
    offset_mm: float = 0.0
    face_angle_rad: float = 0.0

    kind: ClassVar[str] = "flat_translating"
    motion_only: ClassVar[bool] = True
    listing_order: ClassVar[int] = 1
    output: ClassVar[OutputKind] = "translating"
    title: ClassVar[str] = "translating oblique flat-faced"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / cos φ"
    has_face: ClassVar[bool] = True
    # Its formulas keep few arrays alive: 32,768 angles still fit in a 2 MiB L2 cache and
    # take 6 % less time than 16,384 at 360,001 angles (the rollers' take more).
    chunk_angles: ClassVar[int] = 32_768
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("base_radius_mm", "base-circle radius r_b"),
        offset("offset_mm", "offset e of the translation line"),
        Parameter(
            "face_angle_deg",
            "face_angle_rad",
            "face obliquity φ (the constant pressure angle)",
            -90.0,
            90.0,
            0.0,
            required=False,
            exclusive=True,
        ),
    )
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn", "mm", profile="normal"),
        ErrorSource("e", "offset error Δe", "mm", "offset_mm"),
        ErrorSource("phi", "face-angle error Δφ", "rad", "face_angle_rad"),
    )

    def __post_init__(self) -> None:
        require_positive("follower.base_radius_mm", self.base_radius_mm)
        require_finite("follower.offset_mm", self.offset_mm)
        require_finite("follower.face_angle_deg", self.face_angle_rad)
        if not abs(self.face_angle_rad) < math.pi / 2:
            raise DesignError(
                f"follower.face_angle_deg={math.degrees(self.face_angle_rad):g} is not allowed;"
                " the face obliquity is the pressure angle and must lie strictly between"
                " -90 and 90"
            )

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact point, instant centre, λ and u (THEORY §2.1, CW06 eqs. 1-10).

        Extras: ``face_contact`` u = |PA|, signed distance along the face from the
        reference point P to the contact point [mm]; ``radius`` |O2A| [mm].
        """
        phi, e = self.face_angle_rad, self.offset_mm
        cphi, sphi = math.cos(phi), math.sin(phi)
        big_l = self.base_radius_mm / cphi - e * math.tan(phi) + lift
        q = velocity
        qa = big_l * cphi - (q - e) * sphi
        s, c = jet.sin(theta), jet.cos(theta)
        ax = qa * jet.cos(theta + phi) - q * s
        ay = qa * jet.sin(theta + phi) + q * c
        qx, qy = -q * s, q * c
        u = big_l * sphi + (q - e) * cphi
        pressure = jet.value(theta) * 0.0 + phi
        # λ and |O2A| from the support function p = r_b + S cos φ and p' = V cos φ (class
        # Notes): sin λ = p'/|O2A| with |O2A| = √(p² + p'²), THEORY §2.5. The same angle
        # as shift_angle() of the points (tested), in a third of its operations.
        p, dp = lift * cphi + self.base_radius_mm, q * cphi
        radius = jet.hypot(p, dp)
        return ContactGeometry(
            ax,
            ay,
            qx,
            qy,
            q,
            pressure,
            jet.arcsin(dp / radius),
            {"face_contact": u, "radius": radius},
        )

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """ΔS per unit error (THEORY §3.1, CW06 eqs. 22-30).

        ΔS_r = Δr cos λ / cos φ, ΔS_n = Δn / cos φ, ΔS_e = −Δe tan φ,
        ΔS_φ = u Δφ / cos φ. Outputs in mm per mm, or mm per rad for φ.
        """
        cphi = math.cos(self.face_angle_rad)
        zero = jet.value(theta) * 0.0
        return {
            "r": jet.cos(geometry.shift_angle) / cphi,
            "n": zero + 1.0 / cphi,
            "e": zero - math.tan(self.face_angle_rad),
            "phi": geometry.extras["face_contact"] / cphi,
        }

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """Lean form of :meth:`sensitivities` through the support function.

        p = r_b + S cos φ is the support value and p' = V cos φ its derivative along the
        face-normal angle, so |O2A| = sqrt(p² + p'²) and cos λ = p/|O2A| (THEORY §2.5:
        sin λ = V cos φ / |O2A|).
        """
        phi, e = self.face_angle_rad, self.offset_mm
        cphi, sphi = math.cos(phi), math.sin(phi)
        p = lift * cphi + self.base_radius_mm
        dp = velocity * cphi
        cos_lambda = p / jet.sqrt(p * p + dp * dp)
        u = (lift + (self.base_radius_mm / cphi - e * math.tan(phi))) * sphi + (velocity - e) * cphi
        zero = jet.value(theta) * 0.0
        return {
            "r": cos_lambda / cphi,
            "n": zero + 1.0 / cphi,
            "e": zero - math.tan(phi),
            "phi": u / cphi,
        }

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """ρ = r_b + (S + A) cos φ (closed form, see class Notes). [mm]"""
        return np.asarray(
            self.base_radius_mm + (lift + acceleration) * math.cos(self.face_angle_rad)
        )

    def contact_element(self) -> TranslatingFace:
        """Return the face for the contact engine; S = 0 at L = r_b sec φ − e tan φ."""
        phi, e = self.face_angle_rad, self.offset_mm
        return TranslatingFace(phi, e, self.base_radius_mm / math.cos(phi) - e * math.tan(phi))

    def outline(self, theta_rad: float, lift: float, velocity: float, scale_mm: float) -> Outline:
        """Face through A and P, stem along t from P, line of motion (see base class)."""
        phi, e = self.face_angle_rad, self.offset_mm
        g = self.contact(np.array([theta_rad]), np.array([lift]), np.array([velocity]))
        a = (point(g.contact_x), point(g.contact_y))
        t = (math.cos(theta_rad), math.sin(theta_rad))
        w = (-t[1], t[0])
        big_l = self.contact_element().zero + lift
        p = (e * w[0] + big_l * t[0], e * w[1] + big_l * t[1])
        d = (-math.sin(theta_rad + phi), math.cos(theta_rad + phi))
        stem = (p[0] + 0.8 * scale_mm * t[0], p[1] + 0.8 * scale_mm * t[1])
        base = (e * w[0], e * w[1])
        far = (base[0] + 2.0 * scale_mm * t[0], base[1] + 2.0 * scale_mm * t[1])
        return Outline(
            segments=(face_segment(a, p, d, scale_mm), (p, stem)),
            guides=((base, far),),
            labels=(("P", p[0], p[1]),),
        )

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes: max radial dimension for r and n, |e|, |φ| in degrees."""
        return {
            "r": max_radius_mm,
            "n": max_radius_mm,
            "e": abs(self.offset_mm),
            "phi": abs(math.degrees(self.face_angle_rad)),
        }[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", self.title),
            ("base radius r_b", f"{self.base_radius_mm:g} mm"),
            ("offset e", f"{self.offset_mm:g} mm"),
            ("face angle φ", f"{math.degrees(self.face_angle_rad):g}°"),
        ]
