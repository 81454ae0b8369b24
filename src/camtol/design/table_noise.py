r"""How rounding a lift table moves the acceleration of its interpolant (THEORY §1, §6.1).

A lift table rounded to a quantum Q carries a deviation d_i with |d_i| ≤ Q/2 at every
tabulated angle. The acceleration camtol derives from a table is the second derivative of
the periodic cubic spline through it (:class:`camtol.design.motion.LiftTable`), which is linear in
the data: at the knots A = G d / Δθ² with G a circulant matrix, and between knots A is the
linear interpolation of its knot values. The largest change of A over *every* admissible
deviation is therefore exactly

.. math:: \max |ΔA| = \frac{Q}{2}\,\frac{\|G\|_\infty}{Δθ^2},

the row-sum norm of G (attained by d_j = (Q/2) sign G_0j). G is computed once per table
size from the spline's own linear operator (its response to a unit impulse).

For the periodic spline, G = 6 T⁻¹ D with T = circ(1, 4, 1) and D = circ(1, −2, 1); T⁻¹
has entries proportional to λ^|k|, λ = −(2 − √3), so G_0k alternates in sign and the worst
case is the alternating sequence ±Q/2. Its eigenvalue at the Nyquist frequency is
6·(−4)/(4 − 2) = −12, so for an even number of entries ‖G‖∞ = 12 and

.. math:: \max |ΔA| = 6\,Q/Δθ^2,

three times the second-difference bound 2Q/Δθ² ([CDH] eq. 10.4 with s = Q/2). THEORY §6.1
says this ("about 6Q/Δθ² for a cubic spline"); this module makes it exact for any N.

References
----------
.. [CDH] H. A. Rothbart (ed.), *Cam Design Handbook*, McGraw-Hill, 2004, §10, p. 298.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "second_difference_gain",
    "spline_acceleration_gain",
    "spline_acceleration_response",
    "table_resolution",
]


def spline_acceleration_response(n_points: int) -> np.ndarray:
    """Row 0 of G: Δθ²·A at knot 0 of the periodic spline per unit lift at each knot.

    Parameters
    ----------
    n_points : int
        Number of tabulated angles N (at least 3). [-]

    Returns
    -------
    ndarray, shape (N,)
        G_0j: the spline's second derivative at knot 0, times Δθ², for a unit deviation
        at knot j. [-]
    """
    return np.asarray(_response(int(n_points)), dtype=float).copy()


@cache
def _response(n: int) -> tuple[float, ...]:
    if n < 3:
        from camtol.exceptions import DesignError

        raise DesignError(f"n_points={n} is not allowed; a periodic table needs at least 3 points")
    # The periodic spline's knot second derivatives solve T M = 6 D y / Δθ²: circulant
    # systems, diagonal in Fourier space. Column j of G is row 0 reversed (circulant).
    w = 2.0 * np.pi * np.fft.fftfreq(n)
    eig = 6.0 * (2.0 * np.cos(w) - 2.0) / (4.0 + 2.0 * np.cos(w))
    col = np.real(np.fft.ifft(eig))  # response at every knot to a unit impulse at knot 0
    row = np.roll(col[::-1], 1)  # G_0j = col[-j]
    return tuple(float(v) for v in row)


def spline_acceleration_gain(n_points: int) -> float:
    """‖G‖∞: the largest Δθ²·|ΔA| of the periodic spline per unit deviation bound.

    The bound on the spline's acceleration change for deviations |d_i| ≤ s is
    ``spline_acceleration_gain(N) * s / Δθ²``; 12 for an even N, slightly less for an odd
    one.

    Parameters
    ----------
    n_points : int
        Number of tabulated angles N. [-]

    Returns
    -------
    float
        Σ_j |G_0j|. [-]
    """
    return float(np.sum(np.abs(_response(int(n_points)))))


def second_difference_gain() -> float:
    """Gain of the central second difference, |1| + |−2| + |1| = 4 ([CDH] eq. 10.4). [-]

    Returns
    -------
    float
        4.0: alternating deviations of size s change a second difference by 4 s/Δθ².
    """
    return 4.0


def table_resolution(values: ArrayLike, *, max_decimals: int = 12) -> float | None:
    """Return the rounding quantum of tabulated values: the largest 10^-k dividing all.

    Parameters
    ----------
    values : array_like
        Tabulated lifts as written in the file. [mm or deg]
    max_decimals : int
        Beyond this many decimals the values count as carrying full precision.

    Returns
    -------
    float or None
        Q = 10^-k, or None for full precision.
    """
    v = np.asarray(values, dtype=float)
    scale = max(float(np.max(np.abs(v))), 1.0)
    eps = np.finfo(float).eps
    for k in range(max_decimals + 1):
        scaled = v * 10.0**k
        # within a millionth of the quantum, plus the values' own representation error
        tol = 1e-6 + 16.0 * eps * scale * 10.0**k
        if np.all(np.abs(scaled - np.round(scaled)) <= tol):
            return 10.0**-k
    return None
