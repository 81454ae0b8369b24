"""Simulated dial-indicator records of the conjugate fixture (THEORY §4.4, §8.4).

A record of a known centre-distance variation Δf(θ), sampled at a constant rate with
Gaussian reading noise and an index mark at the start of every revolution, in the form
:func:`~camtol.inspection.record.read_indicator_csv` reads: for tests, trials and the
planning of a measurement.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction
from camtol.inspection.record import MIN_SAMPLES_PER_REVOLUTION, IndicatorRecord
from camtol.jet import FloatArray

__all__ = ["simulate_record"]


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
