"""Profile error functions Δ(θ) applied to an analytic cam shape (THEORY §0, §5).

A profile error is positive where material is added (THEORY §0). It is a function of the
*profile parameter* θ: the cam angle at which that point of the theoretical profile is in
contact with the nominal follower (the papers' convention for Δr(θ), CW06 §3, CW11 §3).
The contact engine needs the error and its first two derivatives (to find the contact
point by Newton's method and to give the follower's V and A exactly), so every error
function returns a :class:`~camtol.jet.Jet`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import InputFileError
from camtol.jet import FloatArray, Jet

__all__ = ["CallableError", "FourierError", "ProfileError", "TabulatedError"]

#: Angles × harmonics per chunk of :meth:`FourierError.__call__` (one table: 0.5 MB).
_TRIG_CHUNK = 1 << 16


class ProfileError(Protocol):
    """A profile error Δ(θ) with its θ-derivatives. [mm]"""

    def __call__(self, theta_rad: FloatArray) -> Jet:
        """Δ, dΔ/dθ and d²Δ/dθ² at the profile parameters ``theta_rad``. [mm, mm/rad^k]"""
        ...


@dataclass(frozen=True)
class FourierError:
    """Δ(θ) = a0 + Σ_k (a_k cos kθ + b_k sin kθ), a periodic profile error.

    Parameters
    ----------
    mean_mm : float
        Constant part a0. [mm]
    cos_mm : sequence of float
        a_1, a_2, ... [mm]
    sin_mm : sequence of float
        b_1, b_2, ... [mm]

    Examples
    --------
    The master cam A of CW11's simulated example (THEORY §8.3), 18.5 + 3.5 sin θ µm:

    >>> err = FourierError(18.5e-3, sin_mm=(3.5e-3,))
    >>> float(err(np.array([math.pi / 2])).v[0])
    0.022
    """

    mean_mm: float
    cos_mm: Sequence[float] = ()
    sin_mm: Sequence[float] = ()

    def __call__(self, theta_rad: FloatArray) -> Jet:
        """Δ and its derivatives. [mm, mm/rad, mm/rad²]

        Matrix products over the harmonics with non-zero coefficients,
        cos(kθ) · W_c + sin(kθ) · W_s with W_c, W_s the (K, 3) weights of Δ, Δ', Δ'', in
        chunks of angles so that the trigonometric tables stay in cache (0.5 MB each).
        """
        t = np.asarray(theta_rad, dtype=float)
        a = np.asarray(self.cos_mm, dtype=float)
        b = np.asarray(self.sin_mm, dtype=float)
        m = max(a.size, b.size)
        a, b = np.pad(a, (0, m - a.size)), np.pad(b, (0, m - b.size))
        live = np.flatnonzero((a != 0.0) | (b != 0.0))
        out = np.zeros((3, t.size))  # rows Δ, Δ', Δ'' (contiguous)
        out[0] = float(self.mean_mm)
        if live.size:
            k, a, b = (live + 1).astype(float), a[live], b[live]
            w_cos = np.stack([a, k * b, -k * k * a], axis=1)  # columns: Δ, Δ', Δ''
            w_sin = np.stack([b, -k * a, -k * k * b], axis=1)
            flat = t.ravel()
            step = max(1, _TRIG_CHUNK // k.size)
            for i in range(0, flat.size, step):
                arg = np.multiply.outer(flat[i : i + step], k)
                out[:, i : i + step] += (np.cos(arg) @ w_cos + np.sin(arg) @ w_sin).T
        v, d1, d2 = (row.reshape(t.shape) for row in out)
        return Jet(v, d1, d2)

    def scaled(self, factor: float) -> FourierError:
        """Return the same error multiplied by ``factor``.

        Parameters
        ----------
        factor : float
            Scale applied to the mean and every harmonic. [dimensionless]

        Returns
        -------
        FourierError
            The scaled error.
        """
        return FourierError(
            self.mean_mm * factor,
            tuple(a * factor for a in self.cos_mm),
            tuple(b * factor for b in self.sin_mm),
        )


@dataclass(frozen=True)
class TabulatedError:
    """Δ(θ) tabulated at equally spaced θ over a revolution (e.g. a CMM record).

    Interpolated by a periodic cubic spline whose derivatives give dΔ/dθ and d²Δ/dθ².

    Parameters
    ----------
    theta_rad : array_like
        Equally spaced profile parameters starting at 0, without the closing 2π. [rad]
    error_mm : array_like
        Δ at those parameters. [mm]

    Raises
    ------
    InputFileError
        Fewer than 8 values, unequal spacing, or non-finite values.
    """

    theta_rad: FloatArray
    error_mm: FloatArray
    _spline: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        t = np.asarray(self.theta_rad, dtype=float)
        d = np.asarray(self.error_mm, dtype=float)
        if t.ndim != 1 or t.shape != d.shape or t.size < 8:
            raise InputFileError(
                f"profile error table: need at least 8 (angle, error) pairs of equal length,"
                f" got {t.size} angles and {d.size} errors"
            )
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(d))):
            raise InputFileError("profile error table: angles and errors must be finite")
        step = 2 * math.pi / t.size
        if abs(t[0]) > 1e-9 or not np.allclose(np.diff(t), step, rtol=0, atol=1e-9):
            raise InputFileError(
                f"profile error table: angles must start at 0° and be equally spaced over"
                f" 360° (step {math.degrees(step):g}° for {t.size} values)"
            )
        from scipy.interpolate import CubicSpline

        sp = CubicSpline(np.append(t, 2 * math.pi), np.append(d, d[0]), bc_type="periodic")
        object.__setattr__(self, "_spline", sp)

    def __call__(self, theta_rad: ArrayLike) -> Jet:
        """Δ and its derivatives from the periodic spline. [mm, mm/rad, mm/rad²]"""
        t = np.mod(np.asarray(theta_rad, dtype=float), 2 * math.pi)
        sp = self._spline
        return Jet(sp(t), sp(t, 1), sp(t, 2))  # type: ignore[operator]


@dataclass(frozen=True)
class CallableError:
    """Δ(θ) from any vectorised function of θ, with derivatives by central differences.

    Use for error functions known only as values (formulas, tables of
    :class:`camtol.inspection.error_functions.ErrorFunction`). The derivatives enter the contact
    condition (the profile's tangent), so their accuracy matters: with the default step
    the truncation error of dΔ/dθ is about step²/6 · Δ''' (1e-9 relative for smooth
    errors); across a kink of a piecewise-linear table it is as large as the kink.

    Parameters
    ----------
    function : callable
        θ [rad] → Δ [mm], vectorised.
    step_rad : float
        Difference step h. [rad]
    """

    function: Callable[[FloatArray], FloatArray]
    step_rad: float = 1e-4

    def __call__(self, theta_rad: FloatArray) -> Jet:
        """Δ and its derivatives. [mm, mm/rad, mm/rad²]"""
        t = np.asarray(theta_rad, dtype=float)
        h = self.step_rad
        f0 = np.asarray(self.function(t), dtype=float)
        fp = np.asarray(self.function(t + h), dtype=float)
        fm = np.asarray(self.function(t - h), dtype=float)
        return Jet(f0, (fp - fm) / (2 * h), (fp - 2 * f0 + fm) / (h * h))
