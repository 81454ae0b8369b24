"""The measuring fixture's digital twin (THEORY §4.4, §5, §8.4).

:func:`fixture_delta_f` gives the centre-distance variation Δf(θ) that the fixture reads
on parts with known profile errors (exact simulation,
:func:`~camtol.pair.contact_fixture.simulate_fixture`, with the cams' errors and the
fixture's actual arm lengths, roller radii and arm angle): the same parts that
:func:`camtol.inspection.twin.simulate_scan` scans, so a simulated CMM pair and a
simulated indicator record describe the same cams.

:func:`simulate_record` turns a Δf into a dial-indicator record: a record of a known
centre-distance variation Δf(θ), sampled at a constant rate with Gaussian reading noise
and an index mark at the start of every revolution, in the form
:func:`~camtol.pair.indicator.read_indicator_csv` reads: for tests, trials and the
planning of a measurement.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact import AnalyticShape, FourierError
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction
from camtol.inspection.twin import ErrorKind
from camtol.jet import FloatArray
from camtol.pair.contact_fixture import Fixture, simulate_fixture
from camtol.pair.fixture_spec import FixtureErrors
from camtol.pair.indicator import MIN_SAMPLES_PER_REVOLUTION, IndicatorRecord

__all__ = ["fixture_delta_f", "simulate_record"]


def simulate_record(
    df_um: Callable[[FloatArray], ArrayLike] | ErrorFunction,
    *,
    revolutions: int = 10,
    samples_per_revolution: int | Sequence[int] = 4500,
    noise_um: float = 0.5,
    rng: np.random.Generator | int = 0,
    sample_rate_hz: float = 5.0,
    leading_samples: int = 0,
    trailing_samples: int = 0,
) -> IndicatorRecord:
    """Simulate a dial-indicator record of a known Δf(θ) (THEORY §4.4, §8.4).

    Parameters
    ----------
    df_um : callable or ErrorFunction
        The true centre-distance variation: θ [rad] (array) → Δf [µm] (array), e.g. an
        :class:`~camtol.inspection.error_functions.ErrorFunction`.
    revolutions : int
        Complete revolutions (the published experiment: 10).
    samples_per_revolution : int or sequence of int
        Samples per revolution, one number for all or one per revolution (speed drift
        between revolutions); 4 rev/h at 5 Hz gives 4500.
    noise_um : float
        Standard deviation of the Gaussian reading noise, independent per sample. [µm]
    rng : numpy.random.Generator or int
        Random generator, or a seed for :func:`numpy.random.default_rng`.
    sample_rate_hz : float
        Sampling rate, for the ``time_s`` column. [Hz]
    leading_samples : int
        Samples before the first index mark (the end of a previous revolution).
    trailing_samples : int
        Samples after the closing index mark (which starts an incomplete revolution).

    Returns
    -------
    IndicatorRecord
        ``leading_samples`` + the revolutions + the closing mark + ``trailing_samples``;
        the samples of each revolution at θ = 2π·k/n, the index marks at θ = 0.
    """
    if isinstance(revolutions, bool) or not isinstance(revolutions, int) or revolutions < 1:
        raise DesignError(f"revolutions={revolutions!r} is not allowed; give an integer ≥ 1")
    counts = (
        [samples_per_revolution] * revolutions
        if isinstance(samples_per_revolution, int)
        else list(samples_per_revolution)
    )
    if len(counts) != revolutions or any(
        isinstance(c, bool) or not isinstance(c, int | np.integer) or c < MIN_SAMPLES_PER_REVOLUTION
        for c in counts
    ):
        raise DesignError(
            f"samples_per_revolution={samples_per_revolution!r} is not allowed; give an"
            f" integer ≥ {MIN_SAMPLES_PER_REVOLUTION} or one per revolution ({revolutions})"
        )
    for name, value in (
        ("leading_samples", leading_samples),
        ("trailing_samples", trailing_samples),
    ):
        if not isinstance(value, int) or value < 0:
            raise DesignError(f"{name}={value!r} is not allowed; give an integer ≥ 0")
    if not (math.isfinite(noise_um) and noise_um >= 0):
        raise DesignError(f"noise_um={noise_um!r} is not allowed; give a number ≥ 0 µm")
    if not (math.isfinite(sample_rate_hz) and sample_rate_hz > 0):
        raise DesignError(f"sample_rate_hz={sample_rate_hz!r} is not allowed; give a number > 0")
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    n_lead, n_trail = leading_samples, trailing_samples + 1  # the closing mark starts it
    parts = [2 * math.pi * (np.arange(counts[0] - n_lead, counts[0]) / counts[0])]
    parts += [2 * math.pi * np.arange(c) / c for c in counts]
    parts.append(2 * math.pi * np.arange(n_trail) / counts[-1])
    theta = np.concatenate(parts)
    index = np.zeros(theta.size, dtype=bool)
    index[n_lead + np.concatenate([[0], np.cumsum(counts)])] = True
    truth = np.broadcast_to(np.asarray(df_um(theta), dtype=float), theta.shape)
    df = truth + (gen.normal(0.0, noise_um, theta.size) if noise_um > 0 else 0.0)
    time_s = np.arange(theta.size) / sample_rate_hz
    return IndicatorRecord(np.asarray(df, dtype=float), index, time_s, "simulated")


def fixture_delta_f(
    design: CamDesign,
    error_a: FourierError | None,
    error_b: FourierError | None,
    errors: FixtureErrors | None = None,
    *,
    error_kind: ErrorKind = "radial",
    step_deg: float = 0.1,
) -> ErrorFunction:
    """Δf(θ) the fixture reads on cams with the given profile errors (exact, THEORY §5).

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    error_a, error_b : FourierError or None
        Profile errors of cams A and B (mm) as in :func:`simulate_scan`.
    errors : FixtureErrors, optional
        Constant errors of the fixture's follower (arm lengths, roller radii, η).
    error_kind : {"radial", "normal"}
        How the errors are applied.
    step_deg : float
        Grid of the exact simulation; Δf is interpolated linearly between. [deg]

    Returns
    -------
    ErrorFunction
        Δf(θ) in µm, ready for :func:`simulate_record`.
    """
    from camtol.mechanisms.conjugate import ConjugatePair

    pair = design.mechanism
    if not isinstance(pair, ConjugatePair):
        raise DesignError(f"follower.type={pair.kind!r}: the fixture needs a conjugate design")
    radial = error_kind == "radial"
    sa = AnalyticShape(
        pair.cam_a,
        design.program,
        radial_error=error_a if radial else None,
        normal_error=None if radial else error_a,
    )
    sb = AnalyticShape(
        pair.cam_b,
        design.program,
        radial_error=error_b if radial else None,
        normal_error=None if radial else error_b,
    )
    n = int(round(360.0 / step_deg))
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    res = simulate_fixture(
        theta, sa, sb, Fixture.of(pair, errors), initial_angle_rad=pair.initial_angle_rad
    )
    df = res.extras["delta_f_mm"] * 1e3
    return ErrorFunction.table(np.degrees(theta), df, name="simulated fixture Δf")
