"""What a designer reads first: nominal motion peaks and the geometry figures of each cam.

:func:`motion_peaks` gives the follower's peak velocity, acceleration and jerk (THEORY §0:
V, A, J per radian of cam angle, times ω, ω², ω³ at the design speed), and
:func:`cam_geometry` the figures that decide whether a cam can be made and run: the
signed pressure-angle range against the design limit, the smallest *convex* and the
smallest *concave* radius of curvature (a single "minimum radius of curvature" is
meaningless on a cam with concave stretches: near an inflection ρ runs to ±∞), what
limits each, and the largest radial dimension. Both take the analytic engine's
:class:`~camtol.analysis.kinematics.Kinematics` of one cam; the report layer formats them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.kinematics import Kinematics, beyond_pressure_angle_limit
from camtol.design.motion import LiftTable, MotionProgram
from camtol.jet import FloatArray, broadcast_constant
from camtol.mechanisms.base import Mechanism

__all__ = [
    "CamGeometry",
    "LiftTablePrecision",
    "MotionPeaks",
    "Peak",
    "cam_geometry",
    "lift_table_precision",
    "motion_peaks",
]

#: Degrees per radian: the factor of ``np.degrees`` and ``math.degrees``, bit for bit.
_DEG_PER_RAD = 180.0 / math.pi

#: Standard gravity, for accelerations quoted in g. [m/s²]
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class Peak:
    """Largest and smallest value of a curve, with the cam angles where they occur.

    Attributes
    ----------
    max, min : float
        Extremes, in the unit of the curve.
    max_at_deg, min_at_deg : float
        Cam angles of the extremes (the first occurrence). [deg]
    """

    max: float
    min: float
    max_at_deg: float
    min_at_deg: float

    @property
    def abs_max(self) -> float:
        """Max |value|, in the unit of the curve."""
        return max(abs(self.max), abs(self.min))

    def scaled(self, factor: float) -> Peak:
        """Return the same peak with its values multiplied by ``factor`` (> 0).

        Parameters
        ----------
        factor : float
            Positive scale factor, e.g. ω for a time derivative. [unit conversion]

        Returns
        -------
        Peak
            Values times ``factor``, angles unchanged.
        """
        return Peak(self.max * factor, self.min * factor, self.max_at_deg, self.min_at_deg)


def _peak(values: FloatArray, theta_rad: FloatArray, *, scale: float = 1.0) -> Peak:
    """Max and min of ``values`` × ``scale`` (> 0) and their angles in degrees.

    Only the two values found are scaled and converted (``math.degrees`` is numpy's
    ``degrees``, bit for bit), not the whole grid.
    """
    if broadcast_constant(values) is not None:  # one value: no pass (numpy would copy it)
        i = j = 0  # what argmax and argmin give (NaN included)
    else:
        i, j = int(np.argmax(values)), int(np.argmin(values))
    return Peak(
        float(values[i]) * scale,
        float(values[j]) * scale,
        math.degrees(theta_rad[i]),
        math.degrees(theta_rad[j]),
    )


@dataclass(frozen=True)
class MotionPeaks:
    """Peaks of the nominal follower motion (THEORY §0, §1).

    Attributes
    ----------
    output : {"translating", "oscillating"}
        Follower output: S in mm, or in rad.
    velocity, acceleration, jerk : Peak
        V, A, J per radian of cam angle. [mm/rad^k, or rad/rad^k]
    omega_rad_s : float or None
        Cam speed ω when the design gives one. [rad/s]
    """

    output: Literal["translating", "oscillating"]
    velocity: Peak
    acceleration: Peak
    jerk: Peak
    omega_rad_s: float | None

    def at_speed(self) -> tuple[Peak, Peak, Peak] | None:
        """V, A, J at the design speed in SI units, or None without a speed.

        Returns
        -------
        tuple of Peak or None
            Translating: m/s, m/s², m/s³; oscillating: rad/s, rad/s², rad/s³.
        """
        w = self.omega_rad_s
        if w is None:
            return None
        to_si = 1e-3 if self.output == "translating" else 1.0
        return (
            self.velocity.scaled(w * to_si),
            self.acceleration.scaled(w**2 * to_si),
            self.jerk.scaled(w**3 * to_si),
        )


def motion_peaks(
    kin: Kinematics, *, output: Literal["translating", "oscillating"], omega_rad_s: float | None
) -> MotionPeaks:
    """Peak V, A, J of the nominal motion over the grid (one-sided limits included).

    Parameters
    ----------
    kin : Kinematics
        Analytic-engine kinematics of the design (any cam: the motion is shared). [mm, rad]
    output : {"translating", "oscillating"}
        The follower's output kind.
    omega_rad_s : float or None
        Cam speed ω, or None. [rad/s]

    Returns
    -------
    MotionPeaks
        Per-radian peaks, convertible to time derivatives with :meth:`MotionPeaks.at_speed`.
    """
    theta = kin.theta_rad
    return MotionPeaks(
        output,
        _peak(kin.velocity, theta),
        _peak(kin.acceleration, theta),
        _peak(kin.jerk, theta),
        omega_rad_s,
    )


@dataclass(frozen=True)
class CamGeometry:
    """Geometry figures of one cam.

    Attributes
    ----------
    label : str
        ``""`` for a single cam, ``"A"``/``"B"`` for a conjugate pair.
    max_radius_mm : float
        Largest radial dimension |O2A| on the grid. [mm]
    pressure_angle_deg : Peak
        Signed pressure angle φ. [deg]
    pressure_angle_limit_deg : float or None
        The design limit on |φ|. [deg]
    min_convex_radius_mm, min_convex_radius_at_deg : float
        Smallest convex radius of curvature of the profile (inf without a convex
        stretch) and its angle (nan then). [mm, deg]
    min_concave_radius_mm, min_concave_radius_at_deg : float
        Smallest concave radius of curvature as a positive number (inf without a concave
        stretch) and its angle (nan then). [mm, deg]
    undercut : bool
        The follower cannot generate the profile somewhere (its own rule, THEORY §2.1/§2.3).
    convex_limit : str
        What the smallest convex radius limits (e.g. the roller radius).
    concave_limit : str
        What the smallest concave radius limits (the cutter or grinding-wheel radius).
    """

    label: str
    max_radius_mm: float
    pressure_angle_deg: Peak
    pressure_angle_limit_deg: float | None
    min_convex_radius_mm: float
    min_convex_radius_at_deg: float
    min_concave_radius_mm: float
    min_concave_radius_at_deg: float
    undercut: bool
    convex_limit: str
    concave_limit: str

    @property
    def max_abs_pressure_angle_deg(self) -> float:
        """Max |φ|. [deg]"""
        return self.pressure_angle_deg.abs_max

    @property
    def exceeds_pressure_angle_limit(self) -> bool:
        """True when max |φ| is beyond the design limit (False without a limit)."""
        return beyond_pressure_angle_limit(
            self.max_abs_pressure_angle_deg, self.pressure_angle_limit_deg
        )


def _smallest(
    rho: FloatArray, rows: NDArray[np.bool_], theta_rad: FloatArray, *, concave: bool = False
) -> tuple[float, float]:
    """Smallest finite |ρ| among ``rows`` and its angle in degrees, or (inf, nan) if none.

    The first such row is taken. Masked reductions, no full-length copy of ρ (a fresh
    array costs page faults on long grids); ``rows`` never holds NaN rows.
    """
    if concave:  # ρ < 0: the smallest |ρ| is the largest ρ
        m = float(np.max(rho, where=rows, initial=-math.inf))
        if not m > -math.inf:
            return math.inf, math.nan
    else:
        m = float(np.min(rho, where=rows, initial=math.inf))
        if not m < math.inf:
            return math.inf, math.nan
    i = int(np.argmax(rho == m))  # m is in ``rows``' range: equal rows are among them
    return abs(m), math.degrees(theta_rad[i])


def cam_geometry(
    label: str,
    mechanism: Mechanism,
    kin: Kinematics,
    *,
    pressure_angle_limit_deg: float | None = None,
) -> CamGeometry:
    """Geometry figures of one cam from its kinematics (THEORY §2).

    Parameters
    ----------
    label : str
        ``""`` for a single cam, ``"A"``/``"B"`` for a conjugate pair.
    mechanism : Mechanism
        The cam's single-contact mechanism (its undercut rule and roller radius).
    kin : Kinematics
        The cam's kinematics on a grid. [mm, rad]
    pressure_angle_limit_deg : float, optional
        The design limit on |φ|. [deg]

    Returns
    -------
    CamGeometry
        Pressure-angle range, smallest convex and concave radii with their angles, undercut.
    """
    theta, rho = kin.theta_rad, kin.curvature_radius_mm
    # A comparison with NaN is False: NaN rows count as neither side, as ±inf ones.
    convex, convex_at = _smallest(rho, rho > 0.0, theta)
    concave, concave_at = _smallest(rho, rho < 0.0, theta, concave=True)
    roller = getattr(mechanism, "roller_radius_mm", None)
    if roller is None:
        convex_limit = "a flat face needs ρ > 0 everywhere (cusp or undercut otherwise)"
    else:
        convex_limit = (
            f"pitch-curve radius ρ + r_f = {convex + roller:.4g} mm must exceed the roller"
            f" radius {roller:g} mm"
            if math.isfinite(convex)
            else "no convex stretch"
        )
    concave_limit = (
        f"largest cutter or grinding-wheel radius {concave:.4g} mm (a larger one gouges)"
        if math.isfinite(concave)
        else "no concave stretch: any cutter radius"
    )
    return CamGeometry(
        label=label,
        max_radius_mm=float(np.nanmax(kin.radius_mm)),
        pressure_angle_deg=_peak(kin.pressure_angle_rad, theta, scale=_DEG_PER_RAD),
        pressure_angle_limit_deg=pressure_angle_limit_deg,
        min_convex_radius_mm=convex,
        min_convex_radius_at_deg=convex_at,
        min_concave_radius_mm=concave,
        min_concave_radius_at_deg=concave_at,
        undercut=bool(np.any(mechanism.undercut_mask(rho))),
        convex_limit=convex_limit,
        concave_limit=concave_limit,
    )


@dataclass(frozen=True)
class LiftTablePrecision:
    """How the precision of a lift table limits its derivatives (THEORY §1, §6.1).

    V, A and J of a lift table are the derivatives of a periodic cubic spline through
    it: rounding the table to a quantum Q alone can change A by up to 6Q/Δθ²
    (alternating ±Q/2; 3× the second-difference bound 2Q/Δθ² of [CDH] eq. 10.4).

    Attributes
    ----------
    step_deg : float
        Step of the table. [deg]
    unit : str
        Unit of the lift: ``mm``, or ``rad`` for an oscillating follower.
    resolution : float or None
        Quantum Q the table is rounded to, None when its values carry full precision.
        [mm, or rad]
    acceleration_noise_bound : float or None
        6Q/Δθ², the largest change of A that the rounding can cause, None without a
        resolution. [mm/rad², or rad/rad²]
    max_abs_acceleration : float
        max |A| of the spline on the analysis grid. [mm/rad², or rad/rad²]
    """

    step_deg: float
    unit: str
    resolution: float | None
    acceleration_noise_bound: float | None
    max_abs_acceleration: float

    @property
    def derivatives_reliable(self) -> bool:
        """False when the rounding bound exceeds 5 % of max |A| (ΔV, ΔA not reliable)."""
        bound = self.acceleration_noise_bound
        return bound is None or not bound > 0.05 * self.max_abs_acceleration


def lift_table_precision(
    program: MotionProgram, kin: Kinematics, *, output: Literal["translating", "oscillating"]
) -> LiftTablePrecision | None:
    """Return what the precision of a lift table does to its derivatives (THEORY §6.1).

    Parameters
    ----------
    program : MotionProgram
        The design's motion program.
    kin : Kinematics
        The analytic engine's kinematics of the design on the analysis grid.
    output : {"translating", "oscillating"}
        The follower's output: the lift is in mm or rad.

    Returns
    -------
    LiftTablePrecision or None
        For a :class:`~camtol.design.motion.LiftTable`: its step, resolution, rounding bound
        on A and max |A|; None for a program of motion laws.
    """
    if not isinstance(program, LiftTable):
        return None
    return LiftTablePrecision(
        step_deg=math.degrees(program.step_rad),
        unit="mm" if output == "translating" else "rad",
        resolution=program.resolution,
        acceleration_noise_bound=program.acceleration_noise_bound,
        max_abs_acceleration=float(np.max(np.abs(kin.acceleration))),
    )
