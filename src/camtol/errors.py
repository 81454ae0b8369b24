"""Mechanical error analysis by the equivalent linkage (THEORY §3; [CW06] §3, [WC05]).

Each error source p contributes ΔS_p = s_p(θ)·Δp, with the closed-form sensitivity s_p of
the mechanism module. Velocity and acceleration errors (THEORY §3.5) are the exact
θ-derivatives of ΔS_p, carried through the formulas by second-order jets seeded with the
motion's V, A, J, one-sided at segment boundaries: they show the jumps of the published
figures instead of smearing them. Sources combine into the worst case Σ|ΔS_p| and the RMS
sqrt(Σ ΔS_p²) (THEORY §3.4, CW06 eqs. 44-47).

References
----------
.. [CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006.
.. [WC05] L.-I. Wu, W.-T. Chang, Proc. IMechE C 219(2):209-224, 2005.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.design import CamDesign, ResolvedTolerance
from camtol.jet import FloatArray, Jet, JetLike
from camtol.sources import DESIGN_SOURCES

__all__ = ["ErrorAnalysis", "SourceError", "error_analysis"]


@dataclass(frozen=True)
class SourceError:
    """Output error caused by one source at its tolerance.

    Attributes
    ----------
    key : str
        Source key.
    deviation : float
        Δp. [mm, or rad for angles]
    delta_lift : ndarray
        ΔS_p. [mm, or rad for an oscillating follower]
    delta_velocity : ndarray
        dΔS_p/dθ, per radian of cam angle. [mm/rad or rad/rad]
    delta_acceleration : ndarray
        d²ΔS_p/dθ². [mm/rad² or rad/rad²]
    sensitivity : ndarray
        ΔS_p / Δp. [output unit per mm or per rad]
    """

    key: str
    deviation: float
    delta_lift: FloatArray
    delta_velocity: FloatArray
    delta_acceleration: FloatArray
    sensitivity: FloatArray


@dataclass(frozen=True)
class ErrorAnalysis:
    """Per-source and combined output errors on a θ grid (internal units).

    Attributes
    ----------
    theta_rad : ndarray
        Grid. [rad]
    left_limit : ndarray of bool
        Rows holding left limits at segment boundaries.
    sources : dict of str to SourceError
        In the order of the tolerances; design-level sources (:mod:`camtol.sources`)
        included.
    worst_lift, worst_velocity, worst_acceleration : ndarray
        Σ_p |ΔS_p|, Σ_p |ΔV_p|, Σ_p |ΔA_p|. [output unit per rad^k]
    rms_lift, rms_velocity, rms_acceleration : ndarray
        sqrt(Σ_p ΔS_p²) and likewise. [output unit per rad^k]
    """

    theta_rad: FloatArray
    left_limit: NDArray[np.bool_]
    sources: dict[str, SourceError]
    worst_lift: FloatArray
    worst_velocity: FloatArray
    worst_acceleration: FloatArray
    rms_lift: FloatArray
    rms_velocity: FloatArray
    rms_acceleration: FloatArray


def _as_jet(x: JetLike, like: FloatArray) -> Jet:
    if isinstance(x, Jet):
        return x
    v = np.broadcast_to(np.asarray(x, dtype=float), like.shape).astype(float)
    return Jet(v, np.zeros_like(v), np.zeros_like(v))


def _combine(parts: Sequence[FloatArray], like: FloatArray) -> tuple[FloatArray, FloatArray]:
    if not parts:
        z = np.zeros_like(like)
        return z, z.copy()
    worst = np.abs(parts[0])
    square = parts[0] * parts[0]
    for p in parts[1:]:
        worst += np.abs(p)
        square += p * p
    return worst, np.sqrt(square, out=square)


def error_analysis(
    design: CamDesign,
    tolerances: Sequence[ResolvedTolerance],
    theta_rad: ArrayLike,
    *,
    left_limit: ArrayLike | None = None,
) -> ErrorAnalysis:
    """Output errors of every toleranced source (THEORY §3.1-3.5).

    Parameters
    ----------
    design : CamDesign
        The design.
    tolerances : sequence of ResolvedTolerance
        Deviations Δp in internal units (see :meth:`CamDesign.resolve_tolerances`).
    theta_rad : array_like
        Cam angles. [rad]
    left_limit : array_like of bool, optional
        Rows taking left limits at segment boundaries.

    Returns
    -------
    ErrorAnalysis
        Errors per source and combined, per radian of cam angle (multiply ΔV by ω and
        ΔA by ω² for time derivatives).
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    left = np.zeros(theta.shape, bool) if left_limit is None else np.asarray(left_limit, bool)
    motion = design.program.evaluate(theta, left_limit=left)
    theta_j = Jet.variable(theta)
    lift_j = Jet(motion.lift, motion.velocity, motion.acceleration)
    velocity_j = Jet(motion.velocity, motion.acceleration, motion.jerk)
    sens = design.mechanism.error_sensitivities(theta_j, lift_j, velocity_j)
    sources: dict[str, SourceError] = {}
    for tol in tolerances:
        if tol.key not in sens:  # a design-level source (camtol.sources)
            sens[tol.key] = DESIGN_SOURCES[tol.key].sensitivity(
                design.mechanism, theta_j, lift_j, velocity_j
            )
        s = _as_jet(sens[tol.key], theta)
        d = tol.deviation
        sources[tol.key] = SourceError(tol.key, d, s.v * d, s.d1 * d, s.d2 * d, s.v)
    w_s, r_s = _combine([e.delta_lift for e in sources.values()], theta)
    w_v, r_v = _combine([e.delta_velocity for e in sources.values()], theta)
    w_a, r_a = _combine([e.delta_acceleration for e in sources.values()], theta)
    return ErrorAnalysis(theta, left, sources, w_s, w_v, w_a, r_s, r_v, r_a)
