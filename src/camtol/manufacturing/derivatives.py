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
"""

from __future__ import annotations

import math
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

    @property
    def acceleration_uncertainty(self) -> float:
        """1σ noise of A implied by the noise estimate: gain_A · σ̂. [lift unit/rad²]"""
        return self.gains[2] * self.noise_estimate


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


def _spline(
    y: FloatArray, h: float, lam: float | None, noise: float | None
) -> tuple[FloatArray, tuple[FloatArray, ...], float, str, float, tuple[float, ...]]:
    n = y.size
    k, v, a, j = _spline_multipliers(n, h)
    y_hat = np.fft.fft(y)
    if lam is None:
        # Scan λ on a log grid in units of Δθ³ (the penalty's natural scale).
        grid = h**3 * np.logspace(-6.0, 14.0, 241)
        filt = 1.0 / (1.0 + grid[:, None] * k[None, :])
        rss = np.sum(np.abs((1.0 - filt) * y_hat[None, :]) ** 2, axis=1) / n
        tr = np.sum(filt, axis=1)
        if noise is None:
            score = n * rss / np.maximum(n - tr, 1e-9) ** 2
        else:
            score = rss / n + 2.0 * noise**2 * tr / n
        lam = float(grid[int(np.argmin(score))])
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

    Returns
    -------
    DerivedMotion
        Derivatives per radian of cam angle. [lift unit/rad^k]

    Raises
    ------
    InputFileError
        Angles with a gap, a repeat or an unequal step.
    DesignError
        Unknown method, non-finite lifts, or a smoothing parameter out of range.

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
    if not np.all(np.isfinite(y)):
        i = int(np.argmax(~np.isfinite(y)))
        raise DesignError(f"{source}: lift at {t[i]:g}° is not a finite number")
    step_deg, n = uniform_table_step(t, source=source)
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
    rss = float(np.sum((y - g) ** 2))
    sigma = noise if noise is not None else math.sqrt(rss / max(n - dof, 1.0))
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
    )
