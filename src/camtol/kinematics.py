"""The analytic engine's per-θ result (ARCHITECTURE.md; THEORY §2).

:func:`kinematics` evaluates a design's mechanism over a θ grid (through the engine,
:func:`camtol.engine.evaluate_engine`, without sensitivities), checks that the geometry
can work, and returns plain arrays with units in their names; a quantity that is the same
constant at every angle is a read-only broadcast array. :func:`contact_jets` gives the
contact geometry as jets (exact θ-derivatives seeded from S, V, A, J).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.design import CamDesign
from camtol.exceptions import GeometryError, PressureAngleWarning, UndercutError
from camtol.grid import check_step
from camtol.iso286 import ROUNDING_RTOL
from camtol.jet import FloatArray, Jet
from camtol.mechanisms.base import ContactGeometry
from camtol.motion import MotionState

__all__ = [
    "Kinematics",
    "ContactPoints",
    "analysis_grid",
    "beyond_pressure_angle_limit",
    "check_velocity_ratio",
    "contact_jets",
    "kinematics",
    "to_jet",
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


def analysis_grid(
    step_deg: float, boundaries_rad: ArrayLike = ()
) -> tuple[FloatArray, NDArray[np.bool_]]:
    """θ grid over 0..360° inclusive with each boundary angle duplicated (left, right).

    Parameters
    ----------
    step_deg : float
        Grid step; it must divide 360° into a whole number of steps, at most
        :data:`camtol.grid.MAX_GRID_POINTS` (:func:`camtol.grid.check_step`). [deg]
    boundaries_rad : array_like
        Angles where derivatives may jump. [rad]

    Returns
    -------
    theta_rad, left_limit
        The grid and the mask of left-limit rows (read-only: the same grid is shared by
        every call with the same arguments).

    Raises
    ------
    DesignError
        If the step is not allowed (named ``step_deg``, the callers' parameter).
    """
    # Every grid goes through the one rule, so no caller can build one whose last step
    # is not the others' (a step of 0.7° gives 514 steps of 0.7004°).
    check_step(step_deg, name="step_deg")
    b = np.asarray(boundaries_rad, dtype=float).ravel()
    return _grid(float(step_deg), tuple(b.tolist()))


#: A few grids (a fine one is 3 MB), reused by the analysis and its further cams.
@lru_cache(maxsize=8)
def _grid(
    step_deg: float, boundaries_rad: tuple[float, ...]
) -> tuple[FloatArray, NDArray[np.bool_]]:
    """Return the grid of :func:`analysis_grid`, built once per (step, boundaries)."""
    theta, left = _build_grid(step_deg, boundaries_rad)
    theta.setflags(write=False)
    left.setflags(write=False)
    return theta, left


def _build_grid(
    step_deg: float, boundaries_rad: tuple[float, ...]
) -> tuple[FloatArray, NDArray[np.bool_]]:
    n = int(round(360.0 / step_deg))
    theta = np.linspace(0.0, 2.0 * math.pi, n + 1)
    b = np.mod(np.asarray(boundaries_rad, dtype=float), 2.0 * math.pi)
    b = np.unique(np.concatenate([b, b + 2 * math.pi, [2 * math.pi]]))
    b = b[(b > 0) & (b <= 2 * math.pi + 1e-12)]
    # Snap boundaries onto existing grid points when they coincide.
    idx = np.searchsorted(theta, b)
    idx = np.clip(idx, 0, theta.size - 1)
    near = np.abs(theta[idx] - b) < 1e-9
    theta[idx[near]] = b[near]
    # Left limits go just before the right-limit row at the same angle (b is sorted, so
    # inserting at the left insertion points keeps the grid non-decreasing).
    at = np.searchsorted(theta, b, side="left")
    return np.insert(theta, at, b), np.insert(np.zeros(theta.size, bool), at, True)


def to_jet(x: FloatArray, d1: FloatArray, d2: FloatArray) -> Jet:
    """Build a jet from a value and its exact derivatives.

    Parameters
    ----------
    x : ndarray
        Value f(θ). [unit of f]
    d1 : ndarray
        First derivative df/dθ. [unit of f / rad]
    d2 : ndarray
        Second derivative d²f/dθ². [unit of f / rad²]

    Returns
    -------
    Jet
        The jet (f, f', f'') as float arrays.
    """
    return Jet(np.asarray(x, float), np.asarray(d1, float), np.asarray(d2, float))


def contact_jets(design: CamDesign, theta_rad: FloatArray, motion: MotionState) -> ContactGeometry:
    """Contact geometry of the design as jets in θ (exact first and second derivatives).

    Parameters
    ----------
    design : CamDesign
        The design whose mechanism is evaluated.
    theta_rad : ndarray
        Cam angles. [rad]
    motion : MotionState
        S, V, A, J of the design's program at ``theta_rad``; S is seeded as the jet
        (S, V, A) and V as (V, A, J). [mm, or rad for an oscillating follower, per rad^k]

    Returns
    -------
    ContactGeometry
        The mechanism's contact geometry with every field a :class:`~camtol.jet.Jet`
        in θ. [mm, rad]
    """
    theta = Jet.variable(theta_rad)
    lift = to_jet(motion.lift, motion.velocity, motion.acceleration)
    vel = to_jet(motion.velocity, motion.acceleration, motion.jerk)
    return design.mechanism.contact(theta, lift, vel)


def kinematics(
    design: CamDesign,
    theta_rad: ArrayLike,
    *,
    left_limit: ArrayLike | None = None,
    check: bool = True,
    motion: MotionState | None = None,
) -> Kinematics:
    """Evaluate the analytic engine over θ (THEORY §2).

    Parameters
    ----------
    design : CamDesign
        The design.
    theta_rad : array_like
        Cam angles. [rad]
    left_limit : array_like of bool, optional
        Rows that take the left limit at a segment boundary.
    check : bool
        Raise if the geometry cannot work (see Raises).
    motion : MotionState, optional
        The design's S, V, A, J at ``theta_rad`` (with ``left_limit``), when the caller
        has them: the cams of a conjugate pair share one program. Evaluated otherwise.
        [mm, or rad for an oscillating follower, per rad^k]

    Raises
    ------
    GeometryError
        V ≥ 1 for an oscillating follower, or |pressure angle| ≥ 90°.
    UndercutError
        Radius of curvature ≤ 0 (cusp or undercut) anywhere on the grid.
    """
    # One implementation of the analytic engine: evaluate_engine without sensitivities
    # (chunked, dwells evaluated once); it builds on this module's types.
    from camtol.engine import evaluate_engine

    kin, _ = evaluate_engine(
        design, theta_rad, left_limit, check=check, sensitivities=False, motion=motion
    )
    return kin


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
