"""The analytic engine's per-θ result (ARCHITECTURE.md; THEORY §2).

:func:`kinematics` evaluates a design's mechanism over a θ grid (through the engine,
:func:`camtol.analysis.engine.evaluate_engine`, without sensitivities), checks that the geometry
can work, and returns plain arrays with units in their names; a quantity that is the same
constant at every angle is a read-only broadcast array. :func:`contact_jets` gives the
contact geometry as jets (exact θ-derivatives seeded from S, V, A, J).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.analysis.state import (
    ContactPoints,
    Kinematics,
    beyond_pressure_angle_limit,
    check_velocity_ratio,
)
from camtol.design.cam_design import CamDesign
from camtol.design.motion import MotionState
from camtol.grid import check_step, sorted_unique
from camtol.jet import FloatArray, Jet
from camtol.mechanisms.base import ContactGeometry

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
    b = sorted_unique(np.concatenate([b, b + 2 * math.pi, [2 * math.pi]]))
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
    from camtol.analysis.engine import evaluate_engine

    kin, _ = evaluate_engine(
        design, theta_rad, left_limit, check=check, sensitivities=False, motion=motion
    )
    return kin
