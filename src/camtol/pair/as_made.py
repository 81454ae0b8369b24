"""A conjugate pair as made, followed exactly (THEORY §4, §5).

Given a deviation of each of the pair's sources (:mod:`camtol.pair.sources`),
:func:`follow_pair_as_made` gives, without linearisation,

* ΔS of the follower when each cam holds its roller: the cam as made
  (:class:`~camtol.design.sources.AsMade`: its profile errors, its roller, its arm, the
  centre distance, the shaft's phase) followed by the contact engine
  (:func:`camtol.contact.as_made.follow_as_made`);
* Δf = f* − f of the assembled pair: both cams as made in the fixture with the follower
  as made (arms, rollers, η) and the centre distance free
  (:func:`camtol.pair.contact_fixture.simulate_fixture`).

:func:`fixture_reading_as_made_um` is what the measuring fixture reads on one cam as made
against the other cam's master, exactly.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact import AnalyticShape, FourierError
from camtol.contact.as_made import combined_error, follow_as_made
from camtol.contact.errors_profile import CallableError, ProfileError
from camtol.design.cam_design import CamDesign
from camtol.design.sources import AsMade, apply_source
from camtol.inspection.error_functions import ErrorFunction
from camtol.jet import FloatArray
from camtol.pair.contact_fixture import Fixture, simulate_fixture
from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec
from camtol.pair.kinematics import require_pair
from camtol.pair.sources import PairSource

__all__ = ["CamProfileErrors", "PairMotion", "fixture_reading_as_made_um", "follow_pair_as_made"]

#: The pair's sources that are the fixture's follower dimensions (FixtureErrors fields).
_FOLLOWER = {
    "l_a": "dl_a_mm",
    "l_b": "dl_b_mm",
    "rf_c": "drr_c_mm",
    "rf_d": "drr_d_mm",
    "eta": "deta_rad",
}


@dataclass(frozen=True)
class CamProfileErrors:
    """Further profile errors of one cam as made, beyond its constant ones.

    Attributes
    ----------
    radial, normal : tuple of ProfileError
        Errors along O2A and along the profile normal (e.g. a sampled random profile
        process, :class:`camtol.tolerancing.processes.ContactAngleError`). [mm]
    """

    radial: tuple[ProfileError, ...] = ()
    normal: tuple[ProfileError, ...] = ()


_NONE = CamProfileErrors()


@dataclass(frozen=True)
class PairMotion:
    """The exact outputs of a pair as made.

    Attributes
    ----------
    motion : dict of str to ndarray
        By cam letter: ΔS of the follower with that cam holding its roller. [rad]
    df_mm : ndarray
        Δf = f* − f of the assembled pair. [mm]
    """

    motion: dict[str, FloatArray]
    df_mm: FloatArray


def _shape(cam: CamDesign, as_made: AsMade, further: CamProfileErrors = _NONE) -> AnalyticShape:
    """Return the cam's profile as made (its constant and further profile errors)."""
    radial: list[ProfileError] = list(further.radial)
    normal: list[ProfileError] = list(further.normal)
    if as_made.radial_error_mm is not None:
        radial.insert(0, FourierError(as_made.radial_error_mm))
    if as_made.normal_error_mm is not None:
        normal.insert(0, FourierError(as_made.normal_error_mm))
    return AnalyticShape(cam.mechanism, cam.program, combined_error(radial), combined_error(normal))


def _in_mm(master: ErrorFunction) -> Callable[[FloatArray], FloatArray]:
    """Return a master's known error (µm) as a radial profile error in mm."""

    def error(theta_rad: FloatArray) -> FloatArray:
        return np.asarray(master(theta_rad)) * 1e-3

    return error


def _cams_as_made(
    design: CamDesign, sources: tuple[PairSource, ...], values: Mapping[str, float]
) -> dict[str, AsMade]:
    out = {}
    for cam in design.cams():
        state = AsMade(cam.mechanism)
        for s in sources:
            for letter, own in s.cams:
                if letter == cam.letter:
                    state = apply_source(state, own, values.get(s.key, 0.0))
        out[cam.letter] = state
    return out


def follow_pair_as_made(
    design: CamDesign,
    sources: tuple[PairSource, ...],
    values: Mapping[str, float],
    theta_rad: ArrayLike,
    *,
    left_limit: ArrayLike | None = None,
    profile_errors: Mapping[str, CamProfileErrors] | None = None,
) -> PairMotion:
    """Follow both cams of a pair as made, and the assembled pair in the fixture.

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    sources : tuple of PairSource
        Its sources (:func:`camtol.pair.sources.pair_sources`).
    values : mapping of str to float
        Deviation of each source by its key; a missing one is zero. [mm or rad]
    theta_rad : array_like
        Shaft angles. [rad]
    left_limit : array_like of bool, optional
        Rows taking left limits at segment boundaries.
    profile_errors : mapping of str to CamProfileErrors, optional
        By cam letter: further profile errors of that cam (a sampled profile process).

    Returns
    -------
    PairMotion
    """
    pair = require_pair(design, "the exact pair needs")
    theta = np.asarray(theta_rad, dtype=float)
    nominal = design.program.evaluate(theta, left_limit=left_limit).lift
    states = _cams_as_made(design, sources, values)
    motion = {}
    shapes = {}
    further = profile_errors or {}
    for cam in design.cams():
        state = states[cam.letter]
        extra = further.get(cam.letter, _NONE)
        res = follow_as_made(
            state,
            cam.mechanism,
            design.program,
            theta,
            left_limit=left_limit,
            radial_errors=extra.radial,
            normal_errors=extra.normal,
        )
        motion[cam.letter] = np.asarray(res.lift - nominal)
        shapes[cam.letter] = _shape(cam.design, state, extra)
    errors = FixtureErrors(**{f: values.get(k, 0.0) for k, f in _FOLLOWER.items()})
    phase = states[design.cams()[0].letter].phase_rad  # one shaft: both cams late alike
    a, b = (shapes[c.letter] for c in design.cams())
    fixture = simulate_fixture(
        theta - phase,
        a,
        b,
        Fixture.of(pair, errors),
        initial_angle_rad=pair.initial_angle_rad,
        left_limit=left_limit,
    )
    return PairMotion(motion, np.asarray(fixture.extras["delta_f_mm"]))


def fixture_reading_as_made_um(
    design: CamDesign,
    sources: tuple[PairSource, ...],
    values: Mapping[str, float],
    spec: FixtureSpec,
    theta_rad: ArrayLike,
    *,
    profile_errors: Mapping[str, CamProfileErrors] | None = None,
) -> dict[str, FloatArray]:
    """Return what the fixture reads on each cam as made against the other cam's master.

    Cam A is measured against master cam B and cam B against master A (THEORY §4.3), in
    the fixture with its own constant errors (``spec.errors``); only the measured cam's
    profile is the sampled one.

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    sources : tuple of PairSource
        Its sources.
    values : mapping of str to float
        Deviation of each source by its key. [mm or rad]
    spec : FixtureSpec
        The masters' known errors and the fixture's constant errors.
    theta_rad : array_like
        Cam angles. [rad]
    profile_errors : mapping of str to CamProfileErrors, optional
        By cam letter: further profile errors of that cam (a sampled profile process).

    Returns
    -------
    dict of str to ndarray
        By cam letter: Δf read on the fixture. [µm]
    """
    pair = require_pair(design, "the fixture needs")
    theta = np.asarray(theta_rad, dtype=float)
    states = _cams_as_made(design, sources, values)
    cams = design.cams()
    masters = dict(zip((c.letter for c in cams), (spec.master_a, spec.master_b), strict=True))
    out = {}
    for inspected in cams:
        shapes = []
        for cam in cams:
            if cam.letter == inspected.letter:
                extra = (profile_errors or {}).get(cam.letter, _NONE)
                shapes.append(_shape(cam.design, states[cam.letter], extra))
            else:
                err: ProfileError = CallableError(_in_mm(masters[cam.letter]))
                shapes.append(AnalyticShape(cam.mechanism, design.program, radial_error=err))
        res = simulate_fixture(
            theta,
            shapes[0],
            shapes[1],
            Fixture.of(pair, spec.errors),
            initial_angle_rad=pair.initial_angle_rad,
        )
        out[inspected.letter] = np.asarray(res.extras["delta_f_mm"]) * 1e3
    return out
