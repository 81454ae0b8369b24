"""The analytic engine's per-θ result and its checks (ARCHITECTURE.md; THEORY §2).

:class:`Kinematics` holds what the engine computes at every angle, in plain arrays with
units in their names (a quantity that is the same constant at every angle is a read-only
broadcast array); :class:`ContactPoints` the contact point in the cam frame.
:func:`check_geometry` and :func:`check_velocity_ratio` refuse geometry that cannot work
(undercut or cusp, pressure angle at or beyond its limit or 90°, V ≥ 1 of an oscillating
follower), naming the cam angle. Produced by :mod:`camtol.analysis.engine`, returned by
:func:`camtol.analysis.kinematics.kinematics`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from camtol.design.cam_design import CamDesign
from camtol.design.motion import MotionState
from camtol.exceptions import GeometryError, PressureAngleWarning, UndercutError
from camtol.iso286 import ROUNDING_RTOL
from camtol.jet import FloatArray

__all__ = [
    "ContactPoints",
    "Kinematics",
    "beyond_pressure_angle_limit",
    "check_geometry",
    "check_velocity_ratio",
]


@dataclass(frozen=True, eq=False)
class ContactPoints:
    """Contact point A and instant centre Q = I23 at every angle of a grid.

    A motion-only follower's points are computed once per motion state in the frame of
    the line of centres (θ = 0, THEORY §0) and turned by θ into the cam frame on first
    use (kinematic inversion): an analysis that never reads the profile does not pay for
    the turn, a sine and a cosine of every grid angle, the dearest step of such a cam.
    Nor for spreading a dwell's one stored row over the dwell's angles (``rows``).
    The points read are those the formulas give at θ, bit for bit (tests).

    Attributes
    ----------
    contact_x_mm, contact_y_mm, centre_x_mm, centre_y_mm : ndarray
        A and Q as computed: in the cam frame, or in the frame of the line of centres
        when ``turn_rad`` is given; one value per stored row when ``rows`` is given. [mm]
    turn_rad : ndarray or None
        The angles θ to turn each row by into the cam frame (None: already there). [rad]
    rows : ndarray of bool or None
        True at the grid rows whose points are stored, False at a row that repeats the
        stored row before it (a dwell, evaluated once); None: every row is stored.
    """

    contact_x_mm: FloatArray
    contact_y_mm: FloatArray
    centre_x_mm: FloatArray
    centre_y_mm: FloatArray
    turn_rad: FloatArray | None = None
    rows: NDArray[np.bool_] | None = None

    def _spread(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Return the four arrays with one value per grid row (stored rows spread)."""
        points = (self.contact_x_mm, self.contact_y_mm, self.centre_x_mm, self.centre_y_mm)
        if self.rows is None:
            return points
        index = np.cumsum(self.rows) - 1  # grid row -> its stored row
        n = self.rows.shape
        xa, ya, xq, yq = (
            np.broadcast_to(p[:1], n) if p.strides == (0,) else np.take(p, index) for p in points
        )
        return xa, ya, xq, yq

    @cached_property
    def cam_frame(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Return (x_A, y_A, x_Q, y_Q) in the cam frame, turned once and kept. [mm]"""
        xa, ya, xq, yq = self._spread()
        if self.turn_rad is None:
            return xa, ya, xq, yq
        c, s = np.cos(self.turn_rad), np.sin(self.turn_rad)
        return c * xa - s * ya, s * xa + c * ya, c * xq - s * yq, s * xq + c * yq

    def joined(self, other: ContactPoints) -> ContactPoints:
        """Return the points of ``self``'s rows followed by ``other``'s.

        Parameters
        ----------
        other : ContactPoints
            The rows to append; two deferred turns stay deferred.

        Returns
        -------
        ContactPoints
            Every row stored (``rows`` None).
        """
        a, b = self, other
        if (a.turn_rad is None) != (b.turn_rad is None):  # one side already turned
            a, b = ContactPoints(*a.cam_frame), ContactPoints(*b.cam_frame)
        turn = None
        if a.turn_rad is not None and b.turn_rad is not None:
            turn = np.concatenate([a.turn_rad, b.turn_rad])
        xa, ya, xq, yq = (
            np.concatenate(pair) for pair in zip(a._spread(), b._spread(), strict=True)
        )
        return ContactPoints(xa, ya, xq, yq, turn_rad=turn)


@dataclass(frozen=True)
class Kinematics:
    """Kinematics of a cam design on a θ grid.

    Treat the arrays as read-only: a quantity that is the same constant at every angle
    (the pressure angle of a translating flat face, say) is a read-only broadcast view,
    and arrays may be shared with the analysis grid's cache. Copy before changing one.

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles, non-decreasing; a segment boundary may appear twice (left limit,
        then right limit) so that jumps are represented exactly. [rad]
    left_limit : ndarray of bool
        True where the row is the left limit at a boundary.
    lift, velocity, acceleration, jerk : ndarray
        S, V, A, J of the motion program. [mm or rad, per rad^k]
    radius_mm : ndarray
        Radial dimension |O2A| of the contact point. [mm]
    q_mm : ndarray
        Signed distance q of the instant centre Q = I23. [mm]
    pressure_angle_rad, shift_angle_rad : ndarray
        Signed pressure angle φ and shift angle λ. [rad]
    curvature_radius_mm : ndarray
        Radius of curvature of the profile at A (> 0 convex). [mm]
    face_contact_mm : ndarray or None
        Flat faces: u, signed distance from the face reference point P to A. [mm]
    follower_angle_rad : ndarray or None
        Oscillating followers: ξ. [rad]
    contact_points : ContactPoints
        Contact point A and instant centre Q; read them in the cam frame as
        ``contact_x_mm``, ``contact_y_mm``, ``centre_x_mm`` and ``centre_y_mm``. [mm]
    """

    theta_rad: FloatArray
    left_limit: NDArray[np.bool_]
    lift: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray
    radius_mm: FloatArray
    q_mm: FloatArray
    pressure_angle_rad: FloatArray
    shift_angle_rad: FloatArray
    curvature_radius_mm: FloatArray
    contact_points: ContactPoints
    face_contact_mm: FloatArray | None = None
    follower_angle_rad: FloatArray | None = None

    @property
    def contact_x_mm(self) -> FloatArray:
        """Abscissa x of the contact point A in the cam frame. [mm]"""
        return self.contact_points.cam_frame[0]

    @property
    def contact_y_mm(self) -> FloatArray:
        """Ordinate y of the contact point A in the cam frame. [mm]"""
        return self.contact_points.cam_frame[1]

    @property
    def centre_x_mm(self) -> FloatArray:
        """Abscissa x of the instant centre Q = I23 in the cam frame. [mm]"""
        return self.contact_points.cam_frame[2]

    @property
    def centre_y_mm(self) -> FloatArray:
        """Ordinate y of the instant centre Q = I23 in the cam frame. [mm]"""
        return self.contact_points.cam_frame[3]


def check_velocity_ratio(design: CamDesign, theta_rad: FloatArray, motion: MotionState) -> None:
    """Raise unless an oscillating follower's V = dξ/dθ stays below 1 (THEORY §0).

    Parameters
    ----------
    design : CamDesign
        The design.
    theta_rad : ndarray
        Cam angles. [rad]
    motion : MotionState
        The design's motion at ``theta_rad``. [mm or rad, per rad^k]

    Raises
    ------
    GeometryError
        V ≥ 1 somewhere for an oscillating follower.
    """
    _velocity_ratio(design, theta_rad, motion.velocity)


def _velocity_ratio(design: CamDesign, theta_rad: FloatArray, velocity: FloatArray) -> None:
    if design.mechanism.output == "oscillating" and np.any(velocity >= 1.0):
        i = int(np.argmax(velocity))
        raise GeometryError(
            f"the follower's angular velocity ratio V reaches {velocity[i]:.4g} at"
            f" θ={math.degrees(theta_rad[i]):.2f}°; an oscillating follower needs V < 1"
            " everywhere (slow the motion: longer segments or a smaller swing)"
        )


def beyond_pressure_angle_limit(angle_deg: float, limit_deg: float | None) -> bool:
    """Whether |φ| = ``angle_deg`` is beyond the design limit (never without a limit).

    Parameters
    ----------
    angle_deg : float
        Largest |φ|. [deg]
    limit_deg : float or None
        The design's ``pressure_angle_limit_deg``. [deg]

    Returns
    -------
    bool
        True when ``angle_deg`` exceeds the limit by more than
        :data:`camtol.iso286.ROUNDING_RTOL` of it (a part in 10^12: rounding noise, as a
        face obliquity of 6° comes back as 6.000000000000001°); a pressure angle equal to
        the limit meets it.
    """
    return limit_deg is not None and angle_deg - limit_deg > ROUNDING_RTOL * abs(limit_deg)


def check_geometry(design: CamDesign, kin: Kinematics) -> None:
    """Raise if the design cannot produce its motion; warn past the pressure-angle limit.

    Parameters
    ----------
    design : CamDesign
        The design whose kinematics ``kin`` are.
    kin : Kinematics
        The engine's result on a grid.

    Raises
    ------
    UndercutError
        Radius of curvature ≤ 0 somewhere (THEORY §2.1: a flat face needs a convex cam).
    GeometryError
        V ≥ 1 of an oscillating follower, |pressure angle| ≥ 90°, or the geometry is
        undefined (NaN).
    """
    _velocity_ratio(design, kin.theta_rad, kin.velocity)
    deg = np.degrees(kin.theta_rad)
    bad = ~np.isfinite(kin.radius_mm) | ~np.isfinite(kin.pressure_angle_rad)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise GeometryError(
            f"the contact geometry is undefined at θ={deg[i]:.2f}° (follower cannot reach the"
            " cam there); check the dimensions"
        )
    undercut = design.mechanism.undercut_mask(kin.curvature_radius_mm)
    if np.any(undercut):
        i = int(np.argmin(np.where(undercut, kin.curvature_radius_mm, np.inf)))
        what = design.mechanism.undercut_message(float(kin.curvature_radius_mm[i]), deg[i])
        raise UndercutError(f"{what}: increase the base radius or lengthen the motion")
    pivot = design.mechanism.pivot_clearance_mm
    if pivot is not None:
        k = int(np.argmax(kin.radius_mm))
        if kin.radius_mm[k] >= pivot:
            raise GeometryError(
                f"the cam reaches {kin.radius_mm[k]:.4g} mm from its centre at θ={deg[k]:.2f}°,"
                f" at or beyond the follower pivot (pivot_distance_mm={pivot:g}): the cam would"
                " hit the pivot; increase the pivot distance or reduce the cam"
            )
    pa = np.abs(kin.pressure_angle_rad)
    # Of (near-)equal maxima, e.g. a symmetric rise and return, report the first angle.
    near = np.flatnonzero(pa >= np.max(pa) * (1.0 - 1e-9))
    at = np.mod(kin.theta_rad[near], 2.0 * math.pi)
    first = near[np.abs(at - at.min()) < math.radians(1.0)]  # the first peak's samples
    j = int(first[np.argmax(pa[first])])
    if pa[j] >= math.pi / 2:
        raise GeometryError(
            f"pressure angle {math.degrees(kin.pressure_angle_rad[j]):.2f}° at θ={deg[j]:.2f}°"
            " is at or beyond 90°: the follower would jam"
        )
    limit = design.pressure_angle_limit_deg
    if beyond_pressure_angle_limit(math.degrees(pa[j]), limit):
        warnings.warn(
            f"pressure angle reaches {math.degrees(kin.pressure_angle_rad[j]):.2f}° at"
            f" θ={deg[j]:.2f}°, beyond the design limit {limit:g}°",
            PressureAngleWarning,
            stacklevel=3,
        )
