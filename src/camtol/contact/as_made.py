"""The follower's exact motion on a cam as made (THEORY §5).

:func:`follow_as_made` turns a :class:`~camtol.design.sources.AsMade` (the follower as
made, the cam's constant profile errors, its phase on the shaft) and any further profile
errors (e.g. a sampled random profile process) into the follower's exact motion, with the
nominal follower as the reference of S = 0. ``camtol verify`` and Monte Carlo in exact
mode both re-simulate through it, so a new error source is re-simulated by both once it
says how it moves the cam (:func:`camtol.design.sources.apply_source`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact.engine import follow
from camtol.contact.errors_profile import FourierError, ProfileError
from camtol.contact.result import FollowerMotion
from camtol.contact.shapes import AnalyticShape
from camtol.design.motion import MotionProgram
from camtol.design.sources import AsMade
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, Jet
from camtol.mechanisms.base import Mechanism

__all__ = ["combined_error", "follow_as_made"]


@dataclass(frozen=True)
class _Sum:
    """Several profile errors of one direction, added."""

    parts: tuple[ProfileError, ...]

    def __call__(self, theta_rad: FloatArray) -> Jet:
        out = self.parts[0](theta_rad)
        for p in self.parts[1:]:
            out = out + p(theta_rad)
        return out


def combined_error(errors: Sequence[ProfileError]) -> ProfileError | None:
    """Return several profile errors of one direction as one (their sum), None if none.

    Parameters
    ----------
    errors : sequence of ProfileError
        Errors along the same direction (radial or normal). [mm]
    """
    return None if not errors else errors[0] if len(errors) == 1 else _Sum(tuple(errors))


def follow_as_made(
    as_made: AsMade,
    nominal: Mechanism,
    program: MotionProgram,
    theta_rad: ArrayLike,
    *,
    left_limit: ArrayLike | None = None,
    radial_errors: Sequence[ProfileError] = (),
    normal_errors: Sequence[ProfileError] = (),
    nominal_shape: AnalyticShape | None = None,
) -> FollowerMotion:
    """Follow the cam as made with the follower as made (THEORY §5).

    Parameters
    ----------
    as_made : AsMade
        Follower, constant profile errors and phase as made.
    nominal : Mechanism
        The nominal follower: it defines the nominal profile and S = 0.
    program : MotionProgram
        The nominal motion program.
    theta_rad : array_like
        Shaft angles. [rad]
    left_limit : array_like of bool, optional
        Rows taking left limits at segment boundaries.
    radial_errors, normal_errors : sequence of ProfileError
        Further profile errors of the cam, after the constant ones. [mm]
    nominal_shape : AnalyticShape, optional
        The error-free profile of ``nominal`` and ``program``: the cam as made is derived
        from it (:meth:`AnalyticShape.with_errors`), sharing its nominal geometry, so that
        many calls (Monte Carlo samples) compute that geometry once. Same result.

    Returns
    -------
    FollowerMotion
        The exact motion; its lift minus the nominal lift is the exact ΔS.
    """
    radial: list[ProfileError] = []
    normal: list[ProfileError] = []
    if as_made.radial_error_mm is not None:
        radial.append(FourierError(as_made.radial_error_mm))
    if as_made.normal_error_mm is not None:
        normal.append(FourierError(as_made.normal_error_mm))
    radial += radial_errors
    normal += normal_errors
    if nominal_shape is None:
        shape = AnalyticShape(nominal, program, combined_error(radial), combined_error(normal))
    else:
        if nominal_shape.mechanism is not nominal or nominal_shape.program is not program:
            raise DesignError("nominal_shape must be the error-free profile of nominal, program")
        shape = nominal_shape.with_errors(
            radial_error=combined_error(radial), normal_error=combined_error(normal)
        )
    theta = np.asarray(theta_rad, dtype=float) - as_made.phase_rad
    return follow(shape, as_made.mechanism, theta, reference=nominal, left_limit=left_limit)
