"""Derivatives of a measured lift with a stated smoothing (THEORY §6.1)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from camtol.design.motion import LiftTable
from camtol.exceptions import DesignError, InputFileError
from camtol.manufacturing.derivatives import derive_lift

E_MM = 5.0
THETA_DEG = np.arange(0.0, 360.0, 1.0)
PHI = np.radians(THETA_DEG)
LIFT = E_MM * (1 - np.cos(PHI))


def test_vanishing_smoothing_is_camtols_periodic_spline() -> None:
    d = derive_lift(THETA_DEG, LIFT, smoothing=1e-30)
    m = LiftTable(PHI, LIFT).evaluate(PHI)
    assert_allclose(d.lift, LIFT, atol=1e-12)
    assert_allclose(d.velocity, m.velocity, atol=1e-10)
    assert_allclose(d.acceleration, m.acceleration, atol=1e-8)
    assert_allclose(d.jerk, m.jerk, atol=1e-6)
    assert d.selection == "given"


@pytest.mark.parametrize("method", ["spline", "savgol"])
@pytest.mark.parametrize("sigma", [1e-3, 1e-4])
def test_noisy_lift_recovers_a_within_the_stated_uncertainty(
    method: str, sigma: float, rng: np.random.Generator
) -> None:
    y = LIFT + rng.normal(0.0, sigma, LIFT.size)
    raw_a = (np.roll(y, 1) + np.roll(y, -1) - 2 * y) / math.radians(1.0) ** 2
    for noise in (None, sigma):
        d = derive_lift(THETA_DEG, y, method=method, noise=noise)  # type: ignore[arg-type]
        err = d.acceleration - E_MM * np.cos(PHI)
        # Smoothing buys at least a factor 5 over raw second differences...
        assert np.max(np.abs(err)) < 0.2 * np.max(np.abs(raw_a - E_MM * np.cos(PHI)))
        # ...and the printed 1σ uncertainty is honest: the rms error (noise + smoothing
        # bias) is within a factor 2 of it.
        rms = float(np.sqrt(np.mean(err**2)))
        assert 0.3 * d.acceleration_uncertainty < rms < 2.0 * d.acceleration_uncertainty
        assert d.noise_estimate == pytest.approx(sigma, rel=0.15)


@pytest.mark.parametrize("method", ["spline", "savgol"])
def test_noise_gains_match_a_monte_carlo(method: str, rng: np.random.Generator) -> None:
    base = derive_lift(THETA_DEG, LIFT, method=method, smoothing=3e-4 if method == "spline" else 21)  # type: ignore[arg-type]
    noise = rng.normal(0.0, 1.0, (200, LIFT.size))
    outs = np.array(
        [
            derive_lift(THETA_DEG, n, method=method, smoothing=base.parameter).acceleration  # type: ignore[arg-type]
            for n in noise
        ]
    )
    assert float(np.std(outs)) == pytest.approx(base.gains[2], rel=0.05)


def test_gaps_and_unequal_steps_are_refused() -> None:
    gap = np.delete(THETA_DEG, 100)
    with pytest.raises(InputFileError, match="a gap, repeat or unequal step"):
        derive_lift(gap, np.delete(LIFT, 100))
    uneven = THETA_DEG.copy()
    uneven[5] += 0.3
    with pytest.raises(InputFileError, match="equal steps"):
        derive_lift(uneven, LIFT)
    with pytest.raises(DesignError, match="not a finite number"):
        derive_lift(THETA_DEG, np.where(THETA_DEG == 7, np.nan, LIFT))
    with pytest.raises(DesignError, match="smoothing=4 is not allowed for the Savitzky-Golay"):
        derive_lift(THETA_DEG, LIFT, method="savgol", smoothing=4)
    # A fractional window was rounded in silence (4.5 became 4, and said so as window=4).
    with pytest.raises(DesignError, match="smoothing=4.5 .* odd whole number"):
        derive_lift(THETA_DEG, LIFT, method="savgol", smoothing=4.5)
