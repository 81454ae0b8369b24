"""Conjugate cam pair with an oscillating double-roller follower (THEORY §2.4; [CW11] §2).

Two cams A and B on one shaft drive one follower with two arms (lengths l_A, l_B, fixed
angle η between them) carrying rollers C and D. Cam A pushes the follower up (ξ grows),
cam B pushes it back. Each cam is a single-contact :class:`~camtol.mechanisms.base.Mechanism`
sharing the follower angle ξ(θ): :class:`~camtol.mechanisms.roller_oscillating.RollerOscillating`
for cam A and :class:`ConjugateCamB` (the mirrored closed forms) for cam B.
:class:`ConjugatePair` is the pair as written in a design file; its
:meth:`~ConjugatePair.cams` gives cams A and B, and every analysis runs per cam
(:meth:`camtol.design.cam_design.CamDesign.cams`). The pair's own physics (both cams together, the
measuring fixture) is in :mod:`camtol.pair.kinematics` and :mod:`camtol.pair.contact_fixture`.

Why one module: the pair is one follower type of design files, and its two halves cannot
be read apart. Cam B (:class:`ConjugateCamB`) exists only as the mirror of cam A on the
pair's follower (its initial angle is cam A's), and the pair (:class:`ConjugatePair`)
declares which of its tolerance keys move which cam's source; splitting them would put
the one mapping between the design file and the two cams in two places.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, in *Wide Spectra of Quality Control*, InTech, 2011,
   ch. 20. doi:10.5772/23665
.. [Wu03] L.-I. Wu, Proc. IMechE C 217(10):1117-1123, 2003. doi:10.1243/095440603322517126
"""

from __future__ import annotations

import dataclasses
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
    Mechanism,
    OutputKind,
    Parameter,
    RollerGuide,
    length,
    register_follower,
    require_positive,
)
from camtol.mechanisms.roller_common import RollerMechanism
from camtol.mechanisms.roller_oscillating import (
    RollerOscillating,
    check_arm_reaches_prime_circle,
    oscillating_roller_contact,
    oscillating_roller_lean_sensitivities,
    oscillating_roller_pitch_curvature_radius,
    oscillating_roller_sensitivities,
)

__all__ = ["ConjugateCamB", "ConjugatePair"]


@dataclass(frozen=True)
class ConjugateCamB(RollerMechanism):
    r"""Cam B of a conjugate pair, seen as a single-contact mechanism; output ξ in radians.

    Parameters
    ----------
    pivot_distance_mm : float
        Centre distance f. [mm]
    arm_length_mm : float
        Arm length l_B = |O3D|. [mm]
    roller_radius_mm : float
        Radius r_D of roller D. [mm]
    arm_angle_rad : float
        Fixed angle η between the arms O3C and O3D. [rad]
    initial_angle_rad : float
        ξ0 of the follower (fixed by cam A's base circle). [rad]

    Notes
    -----
    THEORY §2.4: D = O3 + l_B (cos(θ+180°+η−ξ), sin(θ+180°+η−ξ)),
    B = (QD − r_D)(cos(θ − α_B), sin(θ − α_B)) − q (cos θ, sin θ), φ_B = 90° − α_B − (η − ξ).
    Cam B pushes ξ *down*, so its sensitivities carry the opposite sign of cam A's
    (:func:`~camtol.mechanisms.roller_oscillating.oscillating_roller_sensitivities`);
    ΔS_η = +Δη (turning arm D by Δη with the contact kept turns the follower by Δη).
    """

    pivot_distance_mm: float
    arm_length_mm: float
    roller_radius_mm: float
    arm_angle_rad: float
    initial_angle_rad: float

    kind: ClassVar[str] = "conjugate_cam_b"
    motion_only: ClassVar[bool] = True
    output: ClassVar[OutputKind] = "oscillating"
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr_B", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn_B", "mm", profile="normal"),
        ErrorSource("rf", "roller-radius error Δr_rD", "mm", "roller_radius_mm"),
        ErrorSource("l", "arm-length error Δl_B", "mm", "arm_length_mm"),
        ErrorSource("f", "pivot-distance error Δf", "mm", "pivot_distance_mm"),
        ErrorSource("eta", "arm-angle error Δη", "rad", "arm_angle_rad"),
    )
    side: ClassVar[int] = 1

    def arm_angle(self, lift: JetLike) -> JetLike:
        """γ_B = η − ξ = η − ξ0 − S. [rad]

        Parameters
        ----------
        lift : JetLike
            Follower output S = ξ − ξ0, as an array or a jet. [rad]

        Returns
        -------
        JetLike
            Angle γ_B of arm O3D, a jet when ``lift`` is one. [rad]
        """
        return (self.arm_angle_rad - self.initial_angle_rad) - lift

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry of cam B (THEORY §2.4); extras also ``follower_angle`` ξ [rad]."""
        g = oscillating_roller_contact(
            theta,
            self.arm_angle(lift),
            velocity,
            self.pivot_distance_mm,
            self.arm_length_mm,
            self.roller_radius_mm,
            self.side,
        )
        g.extras["follower_angle"] = self.initial_angle_rad + lift
        return g

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """Δξ per unit error of cam B's sources, rad per mm or rad per rad (see class Notes)."""
        out = oscillating_roller_sensitivities(geometry, self.arm_length_mm, self.side)
        out["eta"] = jet.value(theta) * 0.0 + 1.0
        return out

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """Lean form of :meth:`sensitivities` (:func:`oscillating_roller_lean_sensitivities`)."""
        out = oscillating_roller_lean_sensitivities(
            self.arm_angle(lift),
            velocity,
            self.pivot_distance_mm,
            self.arm_length_mm,
            self.roller_radius_mm,
            self.side,
        )
        out["eta"] = jet.value(theta) * 0.0 + 1.0
        return out

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Signed profile radius of curvature ρ = ρ_pitch − r_D (> 0 convex). [mm]"""
        s = Jet(
            np.asarray(lift, float), np.asarray(velocity, float), np.asarray(acceleration, float)
        )
        gamma = self.arm_angle(s)
        assert isinstance(gamma, Jet)
        rho_pitch = oscillating_roller_pitch_curvature_radius(
            gamma, self.pivot_distance_mm, self.arm_length_mm, self.side
        )
        return rho_pitch - self.roller_radius_mm

    def contact_element(self) -> RollerGuide:
        """Return roller D on arm B (ξ = η − γ); S = 0 at ξ0 of the pair."""
        return RollerGuide(
            "circle",
            self.roller_radius_mm,
            pivot_mm=self.pivot_distance_mm,
            arm_mm=self.arm_length_mm,
            side=1,
            sign=-1.0,
            shift=self.arm_angle_rad,
            zero=self.initial_angle_rad,
        )

    @property
    def pivot_clearance_mm(self) -> float:
        """The pivot distance f, which the cam must not reach. [mm]"""
        return self.pivot_distance_mm

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes: max radial dimension, r_D, l_B, f; η takes none.

        The arm angle is a deviation the design states (``eta_deg``), like the cam's phase:
        an IT grade of an angle between two arms is no drawing's convention.
        """
        if key == "eta":
            raise ValueError("the arm angle η takes an explicit deviation (eta_deg), not a grade")
        return {
            "r": max_radius_mm,
            "n": max_radius_mm,
            "rf": self.roller_radius_mm,
            "l": self.arm_length_mm,
            "f": self.pivot_distance_mm,
        }[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", "conjugate cam B (oscillating roller D)"),
            ("roller radius r_D", f"{self.roller_radius_mm:g} mm"),
            ("pivot distance f", f"{self.pivot_distance_mm:g} mm"),
            ("arm length l_B", f"{self.arm_length_mm:g} mm"),
            ("arm angle η", f"{math.degrees(self.arm_angle_rad):g}°"),
        ]


@register_follower
@dataclass(frozen=True)
class ConjugatePair(Mechanism):
    r"""Conjugate cams A and B with an oscillating double-roller follower (THEORY §2.4).

    Parameters
    ----------
    base_radius_mm : float
        Base-circle radius r_b of cam A. [mm]
    roller_radius_mm : float
        Radius r_C of roller C (on cam A). [mm]
    pivot_distance_mm : float
        Centre distance f = |O2O3|. [mm]
    arm_a_mm, arm_b_mm : float
        Arm lengths l_A = |O3C| and l_B = |O3D|. [mm]
    arm_angle_rad : float
        Fixed angle η between the arms, 0 < η < 180°. [rad]
    roller_b_radius_mm : float, optional
        Radius r_D of roller D; defaults to r_C. [mm]

    Notes
    -----
    The pair is two cams, not one: :meth:`cams` gives cam A (:attr:`cam_a`) and cam B
    (:attr:`cam_b`), and every single-contact evaluation (contact, sensitivities,
    curvature, contact engine) goes through them; the pair's own ones raise.
    :func:`camtol.pair.kinematics.conjugate_kinematics` evaluates both together. Its error
    sources and their IT nominal sizes are cam A's. The follower turns with the cam during a
    rise (THEORY §0), q = fV/(1 − V).
    """

    base_radius_mm: float
    roller_radius_mm: float
    pivot_distance_mm: float
    arm_a_mm: float
    arm_b_mm: float
    arm_angle_rad: float
    roller_b_radius_mm: float | None = None

    kind: ClassVar[str] = "conjugate"
    listing_order: ClassVar[int] = 5
    output: ClassVar[OutputKind] = "oscillating"
    title: ClassVar[str] = "conjugate cams, oscillating double roller"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / (l cos φ)"
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("base_radius_mm", "base-circle radius r_b of cam A"),
        length("roller_radius_mm", "radius r_C of roller C (on cam A)"),
        length(
            "roller_b_radius_mm", "radius r_D of roller D (on cam B); default r_C", optional=True
        ),
        length("pivot_distance_mm", "centre distance f = |O2O3|"),
        length("arm_a_mm", "arm length l_A = |O3C|"),
        length("arm_b_mm", "arm length l_B = |O3D|"),
        Parameter(
            "arm_angle_deg",
            "arm_angle_rad",
            "angle η between the arms",
            0.0,
            180.0,
            exclusive=True,
        ),
    )
    #: The pair's sources: per cam (``_a``/``_b``), per roller (``_c``/``_d``), the arm
    #: angle η and the centre distance f the cams share. ``r``, ``n``, ``rf``, ``l`` give the
    #: same tolerance to both cams' (independent) sources; see :meth:`cam_source_keys`.
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr (each cam)", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn (each cam)", "mm", profile="normal"),
        ErrorSource("rf", "roller-radius error Δr_f (each roller)", "mm", "roller_radius_mm"),
        ErrorSource("l", "arm-length error Δl (each arm)", "mm", "arm_a_mm"),
        ErrorSource("f", "centre-distance error Δf0 of the machine", "mm", "pivot_distance_mm"),
        ErrorSource("r_a", "radial profile error Δr_A of cam A", "mm", profile="radial"),
        ErrorSource("r_b", "radial profile error Δr_B of cam B", "mm", profile="radial"),
        ErrorSource("n_a", "normal profile error Δn_A of cam A", "mm", profile="normal"),
        ErrorSource("n_b", "normal profile error Δn_B of cam B", "mm", profile="normal"),
        ErrorSource("rf_c", "radius error Δr_rC of roller C", "mm", "roller_radius_mm"),
        ErrorSource("rf_d", "radius error Δr_rD of roller D", "mm", "roller_b_radius_mm"),
        ErrorSource("l_a", "arm-length error Δl_A", "mm", "arm_a_mm"),
        ErrorSource("l_b", "arm-length error Δl_B", "mm", "arm_b_mm"),
        ErrorSource("eta", "arm-angle error Δη", "rad", "arm_angle_rad"),
    )
    #: Design key -> the source of cam A, of cam B it is (:meth:`cam_source_keys`).
    _CAM_KEYS: ClassVar[dict[str, dict[str, str]]] = {
        "A": {"r": "r", "n": "n", "rf": "rf", "l": "l", "f": "f"}
        | {"r_a": "r", "n_a": "n", "rf_c": "rf", "l_a": "l"},
        "B": {"r": "r", "n": "n", "rf": "rf", "l": "l", "f": "f"}
        | {"r_b": "r", "n_b": "n", "rf_d": "rf", "l_b": "l", "eta": "eta"},
    }

    def __post_init__(self) -> None:
        require_positive("follower.base_radius_mm", self.base_radius_mm)
        require_positive("follower.roller_radius_mm", self.roller_radius_mm)
        require_positive("follower.pivot_distance_mm", self.pivot_distance_mm)
        require_positive("follower.arm_a_mm", self.arm_a_mm)
        require_positive("follower.arm_b_mm", self.arm_b_mm)
        if self.roller_b_radius_mm is not None:
            require_positive("follower.roller_b_radius_mm", self.roller_b_radius_mm)
        if not 0.0 < self.arm_angle_rad < math.pi:
            raise DesignError(
                f"follower.arm_angle_deg={math.degrees(self.arm_angle_rad):g} is not allowed;"
                " the angle η between the arms must lie strictly between 0 and 180"
            )
        # cam A's arm must reach its prime circle; named as the file names it (arm_a_mm)
        check_arm_reaches_prime_circle(
            self.pivot_distance_mm,
            self.arm_a_mm,
            self.base_radius_mm + self.roller_radius_mm,
            "arm_a_mm",
        )

    def perturbed(self, source: str, delta: float) -> Mechanism:
        """Return a copy with a source of cam A moved (see :meth:`Mechanism.perturbed`).

        ``rf`` is roller C alone: when r_D defaults to r_C it is pinned at the nominal
        value, so that cam B's roller does not move with it. ``f`` moves the shared pivot.

        Parameters
        ----------
        source : str
            ``"rf"``, ``"l"`` (arm A) or ``"f"``.
        delta : float
            Deviation added to that dimension. [mm]

        Returns
        -------
        ConjugatePair
            The perturbed pair.
        """
        if source == "rf_d" and self.roller_b_radius_mm is None:  # r_D defaults to r_C
            return dataclasses.replace(self, roller_b_radius_mm=self.roller_radius_mm + delta)
        out = super().perturbed(source, delta)
        if source in ("rf", "rf_c") and self.roller_b_radius_mm is None:
            out = dataclasses.replace(out, roller_b_radius_mm=self.roller_radius_mm)  # type: ignore[type-var]
        return out

    def cams(self) -> tuple[tuple[str, Mechanism], ...]:
        """Cam A (:attr:`cam_a`) and cam B (:attr:`cam_b`), labelled ``"A"`` and ``"B"``."""
        return (("A", self.cam_a), ("B", self.cam_b))

    #: Sources that are one for both cams (the machine's centre distance).
    SHARED_KEYS: ClassVar[tuple[str, ...]] = ("f",)

    def per_cam_key(self, label: str, own: str) -> str:
        """Return the pair's own key of source ``own`` of cam ``label`` (B's ``rf``: ``rf_d``).

        Parameters
        ----------
        label : {"A", "B"}
            The cam.
        own : str
            The cam's source key (``r``, ``n``, ``rf``, ``l``, ``f``, ``eta``).

        Returns
        -------
        str
        """
        if own in self.SHARED_KEYS:
            return own
        for key, value in self._CAM_KEYS[label].items():
            if value == own and key not in ("r", "n", "rf", "l"):
                return key
        return own

    def cam_source_keys(self, label: str) -> dict[str, str]:
        """Design key -> source of cam ``label``: ``r_a`` is cam A's ``r``, ``rf_d`` cam B's ``rf``.

        ``r``, ``n``, ``rf`` and ``l`` name both cams' sources (the same tolerance on each
        cam's own, independent source); ``f`` (the centre distance) is one source of both
        cams; ``eta`` is cam B's (it turns arm B against arm A).

        Parameters
        ----------
        label : {"A", "B"}
            The cam.

        Returns
        -------
        dict of str to str
        """
        return dict(self._CAM_KEYS[label])

    @property
    def roller_d_mm(self) -> float:
        """Radius r_D of roller D. [mm]"""
        return self.roller_radius_mm if self.roller_b_radius_mm is None else self.roller_b_radius_mm

    @property
    def cam_a(self) -> RollerOscillating:
        """Cam A with roller C as a single-contact mechanism."""
        return RollerOscillating(
            self.base_radius_mm, self.roller_radius_mm, self.pivot_distance_mm, self.arm_a_mm
        )

    @property
    def cam_b(self) -> ConjugateCamB:
        """Cam B with roller D as a single-contact mechanism."""
        return ConjugateCamB(
            self.pivot_distance_mm,
            self.arm_b_mm,
            self.roller_d_mm,
            self.arm_angle_rad,
            self.cam_a.initial_angle_rad,
        )

    @property
    def initial_angle_rad(self) -> float:
        """ξ0 of the follower (cam A's base circle). [rad]"""
        return self.cam_a.initial_angle_rad

    def _not_a_cam(self) -> DesignError:
        return DesignError(
            "a conjugate pair is two cams: evaluate each through design.cams() (cam A:"
            " .cam_a, cam B: .cam_b)"
        )

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Not defined for the pair: it has two contacts (use :meth:`cams`).

        Raises
        ------
        DesignError
            Always.
        """
        raise self._not_a_cam()

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """Not defined for the pair (use :meth:`cams`).

        Raises
        ------
        DesignError
            Always.
        """
        raise self._not_a_cam()

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Not defined for the pair (use :meth:`cams`).

        Raises
        ------
        DesignError
            Always.
        """
        raise self._not_a_cam()

    def contact_element(self) -> RollerGuide:
        """Not defined for the pair: the fixture holds both rollers (use :meth:`cams`).

        Raises
        ------
        DesignError
            Always.
        """
        raise self._not_a_cam()

    @property
    def pivot_clearance_mm(self) -> float:
        """The pivot distance f, which the cams must not reach. [mm]"""
        return self.pivot_distance_mm

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes of the pair's keys (Δη takes an explicit deviation only).

        Per-cam keys take the size of that cam's own source; ``max_radius_mm`` is the
        profile size of the cam the tolerance is resolved for (each cam resolves its own:
        :meth:`camtol.design.cam_design.CamDesign.cams`).
        """
        for label, cam in self.cams():  # cam A first: a shared key takes cam A's size
            own = self._CAM_KEYS[label].get(key)
            if own is not None:
                return cam.nominal_size(own, max_radius_mm)
        raise KeyError(key)

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", self.title),
            ("base radius r_b (cam A)", f"{self.base_radius_mm:g} mm"),
            ("roller radii r_C, r_D", f"{self.roller_radius_mm:g} mm, {self.roller_d_mm:g} mm"),
            ("pivot distance f", f"{self.pivot_distance_mm:g} mm"),
            ("arm lengths l_A, l_B", f"{self.arm_a_mm:g} mm, {self.arm_b_mm:g} mm"),
            ("arm angle η", f"{math.degrees(self.arm_angle_rad):g}°"),
            ("initial follower angle ξ0", f"{math.degrees(self.initial_angle_rad):.4f}°"),
        ]
