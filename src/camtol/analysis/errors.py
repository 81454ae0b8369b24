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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import EllipsisType

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.design.sources import DESIGN_SOURCES
from camtol.jet import FloatArray, Jet, JetLike, broadcast_constant

__all__ = ["ErrorAnalysis", "SourceError", "error_analysis", "errors_from_sensitivities"]

#: Rows summed at a time by :meth:`ErrorAnalysis.worst` and :meth:`ErrorAnalysis.rms`:
#: their one temporary (256 KiB) stays in a core's L2 cache, and blocks of 8,192 rows
#: cost 0.5 ms more at 360,001 angles in numpy calls (the same sums either way).
_SUM_ROWS = 32_768


@dataclass(frozen=True)
class SourceError:
    """Output error caused by one source at its tolerance.

    Holds the sensitivity and its θ-derivatives; the errors ΔS_p = s_p·Δp and their
    derivatives are computed when asked for (no stored copies: a fine grid stays small).

    Attributes
    ----------
    key : str
        Source key.
    deviation : float
        Δp. [mm, or rad for angles]
    sensitivity : ndarray
        s_p = ΔS_p / Δp. [output unit per mm or per rad]
    sensitivity_d1, sensitivity_d2 : ndarray
        ds_p/dθ and d²s_p/dθ² (read-only; may be broadcast views of a constant).
        [output unit per mm or per rad, per rad^k]
    """

    key: str
    deviation: float
    sensitivity: FloatArray
    sensitivity_d1: FloatArray
    sensitivity_d2: FloatArray

    @property
    def delta_lift(self) -> FloatArray:
        """ΔS_p = s_p·Δp. [mm, or rad for an oscillating follower]"""
        return self.delta(0)

    @property
    def delta_velocity(self) -> FloatArray:
        """dΔS_p/dθ, per radian of cam angle. [mm/rad or rad/rad]"""
        return self.delta(1)

    @property
    def delta_acceleration(self) -> FloatArray:
        """d²ΔS_p/dθ². [mm/rad² or rad/rad²]"""
        return self.delta(2)

    def delta(self, order: int) -> FloatArray:
        """ΔS_p (order 0) or its θ-derivative of that order (1 or 2).

        Parameters
        ----------
        order : {0, 1, 2}
            Derivative order.

        Returns
        -------
        ndarray
            A new array. [output unit per rad^order]
        """
        s = (self.sensitivity, self.sensitivity_d1, self.sensitivity_d2)[order]
        return np.asarray(s * self.deviation, dtype=float)


@dataclass(frozen=True)
class ErrorAnalysis:
    """Per-source and combined output errors on a θ grid (internal units).

    The combinations are computed when asked for (each access returns a new array).

    Attributes
    ----------
    theta_rad : ndarray
        Grid. [rad]
    left_limit : ndarray of bool
        Rows holding left limits at segment boundaries.
    sources : dict of str to SourceError
        In the order of the tolerances; design-level sources (:mod:`camtol.design.sources`)
        included.
    worst_lift, worst_velocity, worst_acceleration : ndarray
        Σ_p |ΔS_p|, Σ_p |ΔV_p|, Σ_p |ΔA_p|. [output unit per rad^k]
    rms_lift, rms_velocity, rms_acceleration : ndarray
        sqrt(Σ_p ΔS_p²) and likewise. [output unit per rad^k]
    """

    theta_rad: FloatArray
    left_limit: NDArray[np.bool_]
    sources: dict[str, SourceError]

    def worst(self, order: int, *, out: FloatArray | None = None) -> FloatArray:
        """Worst case Σ_p |d^k ΔS_p/dθ^k| of derivative order k (0, 1, 2).

        Parameters
        ----------
        order : {0, 1, 2}
            Derivative order.
        out : ndarray, optional
            Array of the grid's shape to write the result into (a caller scanning many
            curves reuses one); a new array by default.

        Returns
        -------
        ndarray
            [output unit per rad^order]
        """
        return self._sum(order, squares=False, out=out)

    def rms(self, order: int, *, out: FloatArray | None = None) -> FloatArray:
        """RMS sqrt(Σ_p (d^k ΔS_p/dθ^k)²) of derivative order k (0, 1, 2).

        Parameters
        ----------
        order : {0, 1, 2}
            Derivative order.
        out : ndarray, optional
            As for :meth:`worst`.

        Returns
        -------
        ndarray
            [output unit per rad^order]
        """
        result = self._sum(order, squares=True, out=out)
        return np.sqrt(result, out=result)

    def _sum(self, order: int, *, squares: bool, out: FloatArray | None) -> FloatArray:
        """Σ_p |d^k ΔS_p| (or Σ_p (d^k ΔS_p)² with ``squares``), one array pass per source."""
        # The first array term is the sum's start (0 + p is p: every term is ≥ +0 or NaN),
        # the constants are added as scalars, in the sources' order as ever.
        steps: list[tuple[FloatArray, float] | float] = []  # array terms and constants
        held = 0.0  # constant terms met before the first array term
        for src in self.sources.values():
            s = (src.sensitivity, src.sensitivity_d1, src.sensitivity_d2)[order]
            c = broadcast_constant(s)
            if c is None:
                steps.append((s, src.deviation))
            elif c != 0.0:  # a broadcast constant: one scalar, not an array pass
                d = c * src.deviation
                term = d * d if squares else abs(c) * abs(src.deviation)
                if steps:
                    steps.append(term)
                else:
                    held += term
        result = np.empty(self.theta_rad.shape) if out is None else out
        if not steps:
            result[...] = held
            return result
        # Row blocks with one cache-sized temporary: the same operations in the same order
        # on every row (the same numbers), and no full-length temporary, whose fresh pages
        # cost more than the arithmetic on long grids.
        n = result.shape[0] if result.ndim == 1 else 0
        blocks: list[slice | EllipsisType] = [
            slice(a, min(n, a + _SUM_ROWS)) for a in range(0, n, _SUM_ROWS)
        ] or [...]  # not one-dimensional: one block
        part = np.empty(result[blocks[0]].shape)
        for rows in blocks:
            acc = result[rows]
            tmp = part if rows is Ellipsis else part[: acc.shape[0]]
            first = True
            for step in steps:
                if isinstance(step, float):
                    acc += step
                    continue
                sens, dev = step
                into = acc if first else tmp
                if squares:
                    np.multiply(sens[rows], dev, out=into)
                    into *= into
                else:
                    np.abs(sens[rows], out=into)
                    into *= abs(dev)
                if first:
                    first = False
                    if held != 0.0:
                        acc += held
                else:
                    acc += tmp
        return result

    @property
    def worst_lift(self) -> FloatArray:
        """Σ_p |ΔS_p|. [mm, or rad]"""
        return self.worst(0)

    @property
    def worst_velocity(self) -> FloatArray:
        """Σ_p |ΔV_p|. [mm/rad, or rad/rad]"""
        return self.worst(1)

    @property
    def worst_acceleration(self) -> FloatArray:
        """Σ_p |ΔA_p|. [mm/rad², or rad/rad²]"""
        return self.worst(2)

    @property
    def rms_lift(self) -> FloatArray:
        """sqrt(Σ_p ΔS_p²). [mm, or rad]"""
        return self.rms(0)

    @property
    def rms_velocity(self) -> FloatArray:
        """sqrt(Σ_p ΔV_p²). [mm/rad, or rad/rad]"""
        return self.rms(1)

    @property
    def rms_acceleration(self) -> FloatArray:
        """sqrt(Σ_p ΔA_p²). [mm/rad², or rad/rad²]"""
        return self.rms(2)


def _as_jet(x: JetLike, like: FloatArray) -> Jet:
    """Return a sensitivity as a jet; a plain value is constant in θ (zero derivatives, no copy)."""
    if isinstance(x, Jet):
        return x
    v = np.broadcast_to(np.asarray(x, dtype=float), like.shape)
    zero = np.broadcast_to(0.0, like.shape)
    return Jet(v, zero, zero)


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
    sens = dict(design.mechanism.error_sensitivities(theta_j, lift_j, velocity_j))
    for tol in tolerances:
        if tol.key not in sens:  # a design-level source (camtol.design.sources)
            sens[tol.key] = DESIGN_SOURCES[tol.key].sensitivity(
                design.mechanism, theta_j, lift_j, velocity_j
            )
    return errors_from_sensitivities(theta, left, sens, tolerances)


def errors_from_sensitivities(
    theta_rad: FloatArray,
    left_limit: NDArray[np.bool_],
    sensitivities: Mapping[str, JetLike],
    tolerances: Sequence[ResolvedTolerance],
) -> ErrorAnalysis:
    """Per-source and combined errors from sensitivities already evaluated as jets.

    Lets a caller that evaluated the mechanism once (:func:`camtol.analysis.result.analyse`)
    combine its sensitivities without evaluating them again.

    Parameters
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    left_limit : ndarray of bool
        Rows taking left limits at segment boundaries.
    sensitivities : mapping of str to JetLike
        ΔS per unit deviation of each source with its θ-derivatives, as returned by
        :meth:`~camtol.mechanisms.base.Mechanism.error_sensitivities` for jet inputs.
        [output unit per mm or per rad]
    tolerances : sequence of ResolvedTolerance
        Deviations Δp in internal units.

    Returns
    -------
    ErrorAnalysis
        As :func:`error_analysis`.
    """
    sources: dict[str, SourceError] = {}
    for tol in tolerances:
        s = _as_jet(sensitivities[tol.key], theta_rad)
        sources[tol.key] = SourceError(tol.key, tol.deviation, s.v, s.d1, s.d2)
    return ErrorAnalysis(theta_rad, left_limit, sources)
