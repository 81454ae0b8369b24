"""Control chart constants d2, d3, c4 and the chart factors, computed from their definitions.

For a subgroup of n independent normal values (σ = 1), the range W has mean d2(n) and
standard deviation d3(n); the sample standard deviation s has mean c4(n). The factors of
the X̄-R, X̄-S and moving-range charts follow (Montgomery, *Introduction to Statistical
Quality Control*, appendix VI; ASTM E2587):

* A2 = 3 / (d2 √n), D3 = max(0, 1 − 3 d3/d2), D4 = 1 + 3 d3/d2;
* A3 = 3 / (c4 √n), B3 = max(0, 1 − 3 √(1 − c4²)/c4), B4 = 1 + 3 √(1 − c4²)/c4.

d2 and d3 are integrals over the normal distribution (Tippett 1925), evaluated here by a
fine trapezoidal rule on [−9, 9] (step 0.015: error about 2e-5, below the tables' 3 to 4 digits);
c4 is closed form. They are computed rather than copied so that the tests can check them
against the published tables.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np
from scipy.special import gammaln, ndtr

from camtol.exceptions import RecordError

__all__ = ["A2", "A3", "B3", "B4", "D3", "D4", "c4", "d2", "d3"]

_X = np.linspace(-9.0, 9.0, 1201)
_DX = float(_X[1] - _X[0])
#: Trapezoid weights on the grid (numpy 1.24 has no ``trapezoid``).
_W = np.full(_X.size, _DX)
_W[[0, -1]] *= 0.5


def _check(n: int) -> None:
    if not (isinstance(n, int) and n >= 2):
        raise RecordError(f"subgroup size n={n!r}: allowed an integer ≥ 2")


@cache
def d2(n: int) -> float:
    """Mean range of n standard normal values: ∫ 1 − Φ(x)ⁿ − (1 − Φ(x))ⁿ dx."""
    _check(n)
    phi = ndtr(_X)
    return float(_W @ (1.0 - phi**n - (1.0 - phi) ** n))


@cache
def d3(n: int) -> float:
    """Return the standard deviation of the range of n standard normal values.

    E[W²] = 2 ∬_{x<y} 1 − Φ(y)ⁿ − (1 − Φ(x))ⁿ + (Φ(y) − Φ(x))ⁿ dx dy (Tippett 1925), on
    the grid's upper triangle.
    """
    _check(n)
    phi = ndtr(_X)
    fx, fy = phi[:, None], phi[None, :]
    inner = 1.0 - fy**n - (1.0 - fx) ** n + np.clip(fy - fx, 0.0, None) ** n
    inner = np.triu(inner)  # x ≤ y; the diagonal carries the trapezoid's half weight
    w2 = 2.0 * float(_W @ inner @ _W - 0.5 * (_W**2 @ np.diag(inner)))
    return math.sqrt(max(w2 - d2(n) ** 2, 0.0))


def c4(n: int) -> float:
    """Mean of the sample standard deviation (ddof 1) of n standard normal values.

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    _check(n)
    return math.sqrt(2.0 / (n - 1)) * math.exp(gammaln(n / 2.0) - gammaln((n - 1) / 2.0))


def A2(n: int) -> float:  # noqa: N802 - the published names
    """X̄ chart factor on R̄: 3 / (d2 √n).

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    return 3.0 / (d2(n) * math.sqrt(n))


def D3(n: int) -> float:  # noqa: N802
    """R chart lower factor: max(0, 1 − 3 d3 / d2).

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    return max(0.0, 1.0 - 3.0 * d3(n) / d2(n))


def D4(n: int) -> float:  # noqa: N802
    """R chart upper factor: 1 + 3 d3 / d2.

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    return 1.0 + 3.0 * d3(n) / d2(n)


def A3(n: int) -> float:  # noqa: N802
    """X̄ chart factor on S̄: 3 / (c4 √n).

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    return 3.0 / (c4(n) * math.sqrt(n))


def B3(n: int) -> float:  # noqa: N802
    """S chart lower factor: max(0, 1 − 3 √(1 − c4²) / c4).

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    c = c4(n)
    return max(0.0, 1.0 - 3.0 * math.sqrt(1.0 - c * c) / c)


def B4(n: int) -> float:  # noqa: N802
    """S chart upper factor: 1 + 3 √(1 − c4²) / c4.

    Parameters
    ----------
    n : int
        Subgroup size (≥ 2).
    """
    c = c4(n)
    return 1.0 + 3.0 * math.sqrt(1.0 - c * c) / c
