r"""V, A and J of a measured or tabulated lift, with a stated smoothing (THEORY §1, §6.1).

Differentiating a measured lift (a dial-indicator record of a real cam, a lift table, or
a cutting simulation) amplifies its noise: a second difference turns a noise σ into about
√6 σ/Δθ² of acceleration noise. :func:`derive_lift` therefore smooths first, with one of
two linear, periodic smoothers, and reports how much the noise is amplified so the user
knows how far to trust A and J:

- ``"spline"``: the periodic cubic smoothing spline (Reinsch): g minimises
  Σ(y_i − g_i)² + λ ∫ g''² dθ over periodic cubic splines with knots at the samples. On an
  equally spaced revolution its operator is circulant, diagonal in Fourier space,

  .. math:: \hat g_k = \frac{\hat y_k}{1 + λ K_k},\qquad
            K_k = \frac{6 (2 - 2\cos ω_k)^2}{Δθ^3 (4 + 2 \cos ω_k)},

  and V, A, J are the derivatives of the spline through g (periodic cubic spline
  interpolation of g, :class:`camtol.design.motion.LiftTable`).
- ``"savgol"``: a Savitzky-Golay filter (scipy) of polynomial order 3, applied around the
  revolution (``mode="wrap"``).

The smoothing parameter (λ, or the window) is chosen by generalised cross-validation
(GCV: minimise n·RSS/(n − tr H)²) or, when the noise level σ is given, by the unbiased risk
estimate RSS/n + 2σ² tr H/n. The noise amplification of each output is the rms gain of its
linear operator for white lift noise (Parseval: √(mean |m_k|²) for a Fourier multiplier
m_k, √Σ c_j² for filter coefficients c).

Smoothing also biases A: a smoother of multiplier M_k estimates A with the error
(M − D)ŝ on the true lift s, D_k being the exact A of the periodic cubic interpolant
(:class:`camtol.design.motion.LiftTable`). The noise gain says nothing of it, and a window
chosen by cross-validation for the *lift* leaves a bias in A of the size of its noise or
larger (issue 32: the Savitzky-Golay noise-only figure was a third of the actual error).
The bias is estimated by the plug-in rule with the cross-validated smoothing spline P as a
stand-in for s, its own noise taken out:

.. math:: \hat b^2 = \operatorname{mean}\big((M - D) P \hat y\big)^2
          - σ̂^2 \operatorname{mean}|(M - D) P|^2,

and the stated uncertainty of A is √(noise² + b̂²) (:attr:`DerivedMotion.acceleration_uncertainty`).
The stand-in cannot show what P itself smooths away (jerk jumps at segment ends, say), so
b̂ errs low rather than high; docs/theory.md §6.1 gives the measured figures.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import DesignError
from camtol.grid import uniform_table_step
from camtol.jet import FloatArray

__all__ = ["SMOOTHING_METHODS", "DerivedMotion", "SmoothingMethod", "derive_lift"]

SmoothingMethod = Literal["spline", "savgol"]
SMOOTHING_METHODS: tuple[str, ...] = get_args(SmoothingMethod)
TWO_PI = 2.0 * math.pi
#: Polynomial order of the Savitzky-Golay filter (cubic: gives S, V, A and J). [-]
SAVGOL_ORDER = 3
#: Largest |lift| accepted: far beyond any cam (1 km, or 10⁶°), and small enough that
#: sums of squares over any table stay finite (5e200 would overflow them). [mm or deg]
LIFT_LIMIT = 1e6


@dataclass(frozen=True)
class DerivedMotion:
    """Smoothed lift and its derivatives, with the smoothing used and its noise gains.

    Attributes
    ----------
    theta_rad : ndarray
        Sample angles. [rad]
    lift_measured, lift : ndarray
        Input and smoothed lift. [lift unit]
    velocity, acceleration, jerk : ndarray
        V, A, J at the samples (J of the spline interval that starts there). [lift unit/rad^k]
    method : {"spline", "savgol"}
        Smoother.
    parameter : float
        λ of the smoothing spline [lift unit²·rad³ per lift unit², i.e. rad³] or the
        Savitzky-Golay window length in samples.
    selection : {"gcv", "noise", "given"}
        How the parameter was chosen.
    effective_dof : float
        tr H, the smoother's degrees of freedom. [-]
    residual_rms : float
        rms(y − g). [lift unit]
    noise_estimate : float
        σ̂ = √(RSS/(n − tr H)), or the given σ. [lift unit]
    gains : tuple of float
        rms output per unit rms white lift noise for (S, V, A, J). [1/rad^k]
    acceleration_bias : float
        Estimated rms bias of A from the smoothing (module docstring). [lift unit/rad²]
    """

    theta_rad: FloatArray
    lift_measured: FloatArray
    lift: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray
    method: str
    parameter: float
    selection: str
    effective_dof: float
    residual_rms: float
    noise_estimate: float
    gains: tuple[float, float, float, float]
    acceleration_bias: float = 0.0

    @property
    def acceleration_noise(self) -> float:
        """1σ noise of A implied by the noise estimate: gain_A · σ̂. [lift unit/rad²]"""
        return self.gains[2] * self.noise_estimate

    @property
    def acceleration_uncertainty(self) -> float:
        """Uncertainty of A (1σ), noise and smoothing bias: √(noise² + bias²). [lift unit/rad²]"""
        return math.hypot(self.acceleration_noise, self.acceleration_bias)


def _spline_multipliers(n: int, h: float) -> tuple[FloatArray, ...]:
    """Fourier multipliers: penalty K_k and the interpolating spline's V, A, J at knots."""
    w = TWO_PI * np.fft.fftfreq(n)
    c = np.cos(w)
    k = 6.0 * (2.0 - 2.0 * c) ** 2 / (h**3 * (4.0 + 2.0 * c))
    a = 6.0 * (2.0 * c - 2.0) / (h**2 * (4.0 + 2.0 * c))  # M = A at knots
    e = np.exp(1j * w)  # shift: x_{i+1} -> e x_i
    v = (e - 1.0 / e) / (2.0 * h) - h * a * (e - 1.0 / e) / 12.0
    j = a * (e - 1.0) / h  # (M_{i+1} − M_i)/h on the interval starting at knot i
    return k, v, a, j


def _apply(mult: ArrayLike, y_hat: np.ndarray) -> FloatArray:
    return np.asarray(np.real(np.fft.ifft(np.asarray(mult) * y_hat)), dtype=float)


def _rms_gain(mult: ArrayLike) -> float:
    return float(np.sqrt(np.mean(np.abs(np.asarray(mult)) ** 2)))


def _select_lambda(y_hat: np.ndarray, k: FloatArray, h: float, noise: float | None) -> float:
    """λ of the smoothing spline by GCV, or by the unbiased risk when σ is given. [rad³]"""
    n = y_hat.size
    # Scan λ on a log grid in units of Δθ³ (the penalty's natural scale).
    grid = h**3 * np.logspace(-6.0, 14.0, 241)
    filt = 1.0 / (1.0 + grid[:, None] * k[None, :])
    rss = np.sum(np.abs((1.0 - filt) * y_hat[None, :]) ** 2, axis=1) / n
    tr = np.sum(filt, axis=1)
    if noise is None:
        score = n * rss / np.maximum(n - tr, 1e-9) ** 2
    else:
        score = rss / n + 2.0 * noise**2 * tr / n
    return float(grid[int(np.argmin(score))])


def _acceleration_bias(
    y: FloatArray, h: float, multiplier: np.ndarray, sigma: float, noise: float | None
) -> float:
    """Plug-in rms bias of an A estimate of Fourier multiplier M (module docstring).

    Parameters
    ----------
    y : ndarray
        The lift samples. [lift unit]
    h : float
        Sample step Δθ. [rad]
    multiplier : ndarray
        M_k of the A estimate (complex, length n). [1/rad²]
    sigma : float
        Lift noise σ̂ (estimated or given). [lift unit]
    noise : float, optional
        The given noise, which chooses the stand-in's λ as it chose the estimate's.

    Returns
    -------
    float
        b̂ ≥ 0. [lift unit/rad²]
    """
    k, _, a_exact, _ = _spline_multipliers(y.size, h)
    y_hat = np.fft.fft(y)
    pilot = 1.0 / (1.0 + _select_lambda(y_hat, k, h, noise) * k)
    diff = (np.asarray(multiplier) - a_exact) * pilot
    b2 = float(np.mean(np.abs(diff * y_hat) ** 2)) / y.size  # Parseval: mean of the signal²
    b2 -= sigma**2 * float(np.mean(np.abs(diff) ** 2))
    return math.sqrt(max(b2, 0.0))


def _spline(
    y: FloatArray, h: float, lam: float | None, noise: float | None
) -> tuple[FloatArray, tuple[FloatArray, ...], float, str, float, tuple[float, ...]]:
    n = y.size
    k, v, a, j = _spline_multipliers(n, h)
    y_hat = np.fft.fft(y)
    if lam is None:
        lam = _select_lambda(y_hat, k, h, noise)
        selection = "gcv" if noise is None else "noise"
    else:
        selection = "given"
    filt = 1.0 / (1.0 + lam * k)
    g_hat = filt * y_hat
    outs = (_apply(1.0, g_hat), _apply(v, g_hat), _apply(a, g_hat), _apply(j, g_hat))
    gains = tuple(_rms_gain(m * filt) for m in (np.ones(n), v, a, j))
    return outs[0], outs[1:], lam, selection, float(np.sum(filt)), gains


def _savgol(
    y: FloatArray, h: float, window: int | None, noise: float | None
) -> tuple[FloatArray, tuple[FloatArray, ...], float, str, float, tuple[float, ...]]:
    from scipy.signal import savgol_coeffs, savgol_filter

    n = y.size
    largest = min(n - 1 if n % 2 == 0 else n - 2, 401)
    if window is None:
        best: tuple[float, int] | None = None
        for w in range(SAVGOL_ORDER + 2 + (SAVGOL_ORDER + 1) % 2, largest + 1, 2):
            g = savgol_filter(y, w, SAVGOL_ORDER, mode="wrap")
            rss = float(np.sum((y - g) ** 2))
            tr = n * float(savgol_coeffs(w, SAVGOL_ORDER)[w // 2])
            if noise is None:
                score = n * rss / max(n - tr, 1e-9) ** 2
            else:
                score = rss / n + 2.0 * noise**2 * tr / n
            if best is None or score < best[0]:
                best = (score, w)
        assert best is not None
        window, selection = best[1], "gcv" if noise is None else "noise"
    else:
        selection = "given"
        if not (SAVGOL_ORDER + 2 <= window <= largest and window % 2 == 1):
            raise DesignError(
                f"smoothing={window:g} is not allowed for the Savitzky-Golay filter; give an"
                f" odd number of samples between {SAVGOL_ORDER + 2} and {largest}"
            )
    outs = [savgol_filter(y, window, SAVGOL_ORDER, deriv=d, delta=h, mode="wrap") for d in range(4)]
    gains = tuple(
        float(np.sqrt(np.sum(savgol_coeffs(window, SAVGOL_ORDER, deriv=d, delta=h) ** 2)))
        for d in range(4)
    )
    tr = n * float(savgol_coeffs(window, SAVGOL_ORDER)[window // 2])
    return outs[0], tuple(outs[1:]), float(window), selection, tr, gains


def derive_lift(
    theta_deg: ArrayLike,
    lift: ArrayLike,
    *,
    method: SmoothingMethod = "spline",
    smoothing: float | None = None,
    noise: float | None = None,
    source: str = "lift table",
    line_of: Callable[[int], int] | None = None,
) -> DerivedMotion:
    """Smooth a lift over one revolution and differentiate it (module docstring).

    Parameters
    ----------
    theta_deg : array_like
        Cam angles: one revolution from 0° in equal steps, without the closing 360°.
        [deg]
    lift : array_like
        Lift at those angles. [mm, or deg for an oscillating follower]
    method : {"spline", "savgol"}
        Periodic smoothing spline or Savitzky-Golay filter.
    smoothing : float, optional
        λ of the spline [rad³] or the Savitzky-Golay window (odd number of samples);
        default: chosen by GCV, or by the unbiased risk when ``noise`` is given.
    noise : float, optional
        Known rms noise of the lift (e.g. the indicator's resolution). [lift unit]
    source : str
        Name of the data, for messages.
    line_of : callable, optional
        Maps a row index to its line in the file, for messages
        (:meth:`camtol.tables.Table.line_of`).

    Returns
    -------
    DerivedMotion
        Derivatives per radian of cam angle. [lift unit/rad^k]

    Raises
    ------
    InputFileError
        Angles with a gap, a repeat, a decrease or an unequal step, or not one revolution.
    DesignError
        Unknown method, non-finite lifts or lifts beyond :data:`LIFT_LIMIT`, or a
        smoothing parameter out of range.

    Examples
    --------
    >>> import numpy as np
    >>> th = np.arange(360.0)
    >>> d = derive_lift(th, 5 * (1 - np.cos(np.radians(th))))
    >>> bool(np.allclose(d.acceleration, 5 * np.cos(np.radians(th)), atol=1e-3))
    True
    """
    if method not in SMOOTHING_METHODS:
        raise DesignError(f"method={method!r} is unknown; allowed: {', '.join(SMOOTHING_METHODS)}")
    t = np.asarray(theta_deg, dtype=float)
    y = np.asarray(lift, dtype=float)
    if t.shape != y.shape or t.ndim != 1:
        raise DesignError(f"{source}: angles and lifts must be two columns of equal length")
    step_deg, n = uniform_table_step(t, source=source, line_of=line_of)
    bad = ~(np.abs(y) <= LIFT_LIMIT)  # NaN and ±inf included
    if np.any(bad):
        i = int(np.argmax(bad))
        line = line_of(i) if line_of is not None else 0
        where = f"line {line}" if line > 0 else f"row {i + 1}"
        raise DesignError(
            f"{source}, {where}: lift {y[i]:g} at {t[i]:g}° is not allowed; give a finite"
            f" lift of at most {LIFT_LIMIT:g} in size"
        )
    if n < 16:
        raise DesignError(f"{source}: {n} samples is too few to differentiate; give at least 16")
    for name, val in (("smoothing", smoothing), ("noise", noise)):
        if val is not None and not (math.isfinite(val) and val > 0):
            raise DesignError(f"{name}={val:g} is not allowed; give a positive value")
    h = math.radians(step_deg)
    if method == "spline":
        g, (v, a, j), par, sel, dof, gains = _spline(y, h, smoothing, noise)
    else:
        if smoothing is not None and smoothing != round(smoothing):
            raise DesignError(
                f"smoothing={smoothing:g} is not allowed for the Savitzky-Golay filter; give"
                " an odd whole number of samples (its window)"
            )
        window = None if smoothing is None else int(smoothing)
        g, (v, a, j), par, sel, dof, gains = _savgol(y, h, window, noise)
    if method == "spline":  # the A multiplier of the estimate, for its bias
        penalty, _, a_knots, _ = _spline_multipliers(n, h)
        mult_a: np.ndarray = a_knots / (1.0 + par * penalty)
    else:
        from scipy.signal import savgol_filter

        impulse = np.zeros(n)
        impulse[0] = 1.0  # the wrapped filter is circulant: its response to δ is its kernel
        mult_a = np.fft.fft(
            savgol_filter(impulse, int(par), SAVGOL_ORDER, deriv=2, delta=h, mode="wrap")
        )
    rss = float(np.sum((y - g) ** 2))
    if not (math.isfinite(rss) and all(np.all(np.isfinite(o)) for o in (g, v, a, j))):
        raise DesignError(  # cannot happen within LIFT_LIMIT; never report inf as a result
            f"{source}: the smoothed lift or its derivatives are not finite; give lifts of"
            f" at most {LIFT_LIMIT:g} in size"
        )
    sigma = noise if noise is not None else math.sqrt(rss / max(n - dof, 1.0))
    bias = _acceleration_bias(y, h, mult_a, sigma, noise)
    return DerivedMotion(
        theta_rad=np.radians(t),
        lift_measured=y,
        lift=g,
        velocity=v,
        acceleration=a,
        jerk=j,
        method=method,
        parameter=par,
        selection=sel,
        effective_dof=dof,
        residual_rms=math.sqrt(rss / n),
        noise_estimate=sigma,
        gains=(gains[0], gains[1], gains[2], gains[3]),
        acceleration_bias=bias,
    )
