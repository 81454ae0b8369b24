"""Second-order Taylor arithmetic ("jets") over the cam-angle grid.

A :class:`Jet` carries a quantity and its first and second derivatives with respect to
the cam angle θ, as three arrays over the θ grid. Mechanism formulas (THEORY §2, §3) are
written once with the functions of this module; fed with plain arrays they return plain
arrays, fed with jets (θ, S, V seeded with their exact derivatives from the motion
program) they return the exact first and second θ-derivatives as well.

This is how camtol obtains the velocity and acceleration errors of THEORY §3.5 and the
profile's radius of curvature *analytically*: the derivatives come from V, A and J of the
motion law through the chain rule, evaluated one-sidedly at segment boundaries, so the
jumps the papers describe are reproduced exactly instead of being smeared by a stencil.

Why one module: it is one type, :class:`Jet`, and the elementary functions on it. Each
function is the chain rule of one operation, written against the jet's private ``_chain``
and its cached sine and cosine, and a mechanism needs the whole set to write a formula once
for arrays and jets alike.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import Union, overload

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Real = Union[float, FloatArray]

__all__ = [
    "Jet",
    "JetLike",
    "arccos",
    "arcsin",
    "arctan",
    "arctan2",
    "broadcast_constant",
    "cos",
    "hypot",
    "reused_sincos",
    "sin",
    "sincos",
    "sqrt",
    "tan",
    "value",
]


@dataclass(frozen=True, slots=True)
class Jet:
    """A quantity f(θ) with its derivatives f'(θ) and f''(θ) on a grid.

    Parameters
    ----------
    v : ndarray
        Value f. [unit of f]
    d1 : ndarray
        First derivative df/dθ. [unit of f / rad]
    d2 : ndarray
        Second derivative d²f/dθ². [unit of f / rad²]
    unit : bool, keyword-only
        True when d1 ≡ 1 and d2 ≡ 0 (θ itself, or θ plus a constant), as
        :meth:`variable` sets it; the chain rule then needs no arithmetic.
    """

    v: FloatArray
    d1: FloatArray
    d2: FloatArray
    #: True when f' = 1 and f'' = 0 exactly (θ itself, or θ plus a constant): the chain
    #: rule then needs no arithmetic.
    unit: bool = field(default=False, kw_only=True, repr=False, compare=False)
    #: sin and cos of ``v``, computed once by :func:`sin`/:func:`cos` and shared by both.
    _sincos: tuple[FloatArray, FloatArray] | None = field(
        default=None, init=False, repr=False, compare=False
    )

    # Make ``ndarray * Jet`` defer to Jet.__rmul__ instead of building an object array.
    __array_ufunc__ = None

    @classmethod
    def variable(cls, theta_rad: FloatArray) -> Jet:
        """Return the independent variable θ itself (θ' = 1, θ'' = 0).

        Parameters
        ----------
        theta_rad : ndarray
            Cam angles θ. [rad]

        Returns
        -------
        Jet
            The jet (θ, 1, 0). [rad, dimensionless, 1/rad]
        """
        t = np.asarray(theta_rad, dtype=float)
        return cls(t, np.ones_like(t), np.zeros_like(t), unit=True)

    @classmethod
    def constant(cls, c: Real, like: FloatArray) -> Jet:
        """Return a constant broadcast to the shape of ``like``.

        Parameters
        ----------
        c : float or ndarray
            Constant value, broadcastable to the shape of ``like``. [unit of c]
        like : ndarray
            Array whose shape the jet takes; its values are not used.

        Returns
        -------
        Jet
            The jet (c, 0, 0).
        """
        v = np.broadcast_to(np.asarray(c, dtype=float), np.shape(like)).astype(float)
        return cls(v, np.zeros_like(v), np.zeros_like(v))

    # --- arithmetic -------------------------------------------------------------------
    def _chain(self, g0: FloatArray, g1: FloatArray, g2: FloatArray) -> Jet:
        """Compose g∘f given g(f), g'(f), g''(f)."""
        if self.unit:  # f' = 1, f'' = 0: (g∘f)' = g'(f), (g∘f)'' = g''(f)
            return Jet(g0, g1, g2)
        d2 = g2 * self.d1
        d2 *= self.d1
        d2 += g1 * self.d2
        return Jet(g0, g1 * self.d1, d2)

    def __add__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):
            return Jet(self.v + other.v, self.d1 + other.d1, self.d2 + other.d2)
        return Jet(self.v + other, self.d1, self.d2, unit=self.unit)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.v, -self.d1, -self.d2)

    def __sub__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):
            return Jet(self.v - other.v, self.d1 - other.d1, self.d2 - other.d2)
        return Jet(self.v - other, self.d1, self.d2, unit=self.unit)

    def __rsub__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):  # pragma: no cover - Jet - Jet uses __sub__
            return other - self
        return Jet(other - self.v, -self.d1, -self.d2)

    def __mul__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):
            # (fg)' = f'g + fg',  (fg)'' = f''g + 2f'g' + fg''; in-place to spare temporaries
            d1 = self.d1 * other.v
            d1 += self.v * other.d1
            d2 = self.d1 * other.d1
            d2 *= 2.0
            d2 += self.d2 * other.v
            d2 += self.v * other.d2
            return Jet(self.v * other.v, d1, d2)
        return Jet(self.v * other, self.d1 * other, self.d2 * other)

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        """Return 1/f."""
        return self.__rtruediv__(1.0)

    def __truediv__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):
            # The quotient rule on q = f/g itself: q' = (f' − q g')/g,
            # q'' = (f'' − 2q'g' − q g'')/g; fewer operations than f·(1/g).
            h = 1.0 / other.v
            q = self.v * h
            d1 = q * other.d1
            np.subtract(self.d1, d1, out=d1)
            d1 *= h
            d2 = d1 * other.d1
            d2 *= -2.0
            d2 += self.d2
            d2 -= q * other.d2
            d2 *= h
            return Jet(q, d1, d2)
        return Jet(self.v / other, self.d1 / other, self.d2 / other)

    def __rtruediv__(self, other: JetLike) -> Jet:
        if isinstance(other, Jet):  # pragma: no cover - Jet / Jet uses __truediv__
            return other / self
        # c/g: q' = −q g'/g, q'' = −(2q'g' + q g'')/g
        h = 1.0 / self.v
        q = other * h
        d1 = q * self.d1
        d1 *= -h
        d2 = d1 * self.d1
        d2 *= 2.0
        d2 += q * self.d2
        d2 *= -h
        return Jet(np.asarray(q), d1, d2)

    def __pow__(self, n: float) -> Jet:
        return self._chain(self.v**n, n * self.v ** (n - 1), n * (n - 1) * self.v ** (n - 2))


JetLike = Union[Jet, Real]


def value(x: JetLike) -> FloatArray:
    """Return the value part of a jet, or the array itself.

    Parameters
    ----------
    x : JetLike
        A jet, or a plain float or array. [any unit]

    Returns
    -------
    ndarray
        ``x.v`` for a jet, otherwise ``x`` as a float array. [unit of x]
    """
    return x.v if isinstance(x, Jet) else np.asarray(x, dtype=float)


def broadcast_constant(a: FloatArray) -> float | None:
    """Return the value of a broadcast constant (a zero-stride line), else None.

    camtol keeps a quantity that is the same at every angle (ΔS_e of a translating
    follower, a flat face's pressure angle) as a read-only broadcast; sums and searches
    take its one value instead of a pass over it (numpy would even copy it first).

    Parameters
    ----------
    a : ndarray
        A grid quantity. [any unit]

    Returns
    -------
    float or None
        Its value, or None when it is not a broadcast constant. [unit of a]
    """
    if a.ndim == 1 and a.size and a.strides == (0,):
        return float(a[0])
    return None


#: Inside a :func:`reused_sincos` block: the last angles :func:`sincos` was given (a
#: copy), with their sines and cosines.
_LAST_SINCOS: ContextVar[list[tuple[FloatArray, FloatArray, FloatArray]] | None] = ContextVar(
    "camtol_last_sincos", default=None
)


@contextmanager
def reused_sincos() -> Iterator[None]:
    """Within the block, :func:`sincos` of the same angles as its last call is not recomputed.

    One follower's closed forms take the sine and cosine of the same angle several
    times: an oscillating follower's arm angle in its contact point, its radius of
    curvature and its sensitivities, each a formula of its own. numpy's sine and cosine
    cost 5-10 ns an element, some twenty products' worth. Inside the block
    :func:`sincos` keeps its last angles and returns their sines and cosines again for
    angles equal bit for bit (−0.0 is not 0.0): the same numbers, computed once.
    The kept results are read-only, so no formula can change them for the next caller.
    The engine opens a block per chunk of angles.

    Yields
    ------
    None
    """
    token = _LAST_SINCOS.set([])
    try:
        yield
    finally:
        _LAST_SINCOS.reset(token)


def _array_sincos(a: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Return sin a and cos a of an array (reused inside :func:`reused_sincos`)."""
    last = _LAST_SINCOS.get()
    if last is None or a.ndim != 1:
        return np.sin(a), np.cos(a)
    # Bitwise equal: -0.0 and 0.0 have sines of different signs.
    if (
        last
        and last[0][0].shape == a.shape
        and np.array_equal(last[0][0].view(np.int64), a.view(np.int64))
    ):
        return last[0][1], last[0][2]
    s, c = np.sin(a), np.cos(a)
    s.flags.writeable = c.flags.writeable = False
    last[:] = [(a.copy(), s, c)]
    return s, c


def _sincos(x: Jet) -> tuple[FloatArray, FloatArray]:
    """Return sin and cos of a jet's value, computed once per jet (formulas take both)."""
    sc = x._sincos
    if sc is None:
        sc = _array_sincos(np.asarray(x.v, dtype=float))
        object.__setattr__(x, "_sincos", sc)
    return sc


@overload
def sincos(x: Jet) -> tuple[Jet, Jet]: ...


@overload
def sincos(x: FloatArray | float) -> tuple[FloatArray, FloatArray]: ...


def sincos(x: JetLike) -> tuple[JetLike, JetLike]:
    """Sine and cosine of one angle, for arrays or jets.

    Cheaper than :func:`sin` and :func:`cos` apart for a jet (the chain rule shares
    them), and reused for the same angles inside a :func:`reused_sincos` block.

    Parameters
    ----------
    x : JetLike
        Angle, as an array or a jet. [rad]

    Returns
    -------
    tuple of JetLike
        (sin x, cos x), jets when ``x`` is one. [dimensionless]
    """
    if isinstance(x, Jet):
        return sin(x), cos(x)  # one sine and cosine of the value per jet (_sincos)
    a = np.asarray(x, dtype=float)
    if a.ndim == 0:
        return np.sin(x), np.cos(x)
    return _array_sincos(a)


def sin(x: JetLike) -> JetLike:
    """Sine, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Angle, as an array or a jet. [rad]

    Returns
    -------
    JetLike
        sin x, a jet when ``x`` is one. [dimensionless]
    """
    if isinstance(x, Jet):
        s, c = _sincos(x)
        return x._chain(s, c, -s)
    return np.sin(x)


def cos(x: JetLike) -> JetLike:
    """Cosine, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Angle, as an array or a jet. [rad]

    Returns
    -------
    JetLike
        cos x, a jet when ``x`` is one. [dimensionless]
    """
    if isinstance(x, Jet):
        s, c = _sincos(x)
        return x._chain(c, -s, -c)
    return np.cos(x)


def tan(x: JetLike) -> JetLike:
    """Tangent, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Angle, as an array or a jet. [rad]

    Returns
    -------
    JetLike
        tan x, a jet when ``x`` is one. [dimensionless]
    """
    if isinstance(x, Jet):
        t = np.tan(x.v)
        sec2 = 1.0 + t * t
        return x._chain(t, sec2, 2.0 * t * sec2)
    return np.tan(x)


def sqrt(x: JetLike) -> JetLike:
    """Square root, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Non-negative radicand, as an array or a jet. [unit of x]

    Returns
    -------
    JetLike
        √x, a jet when ``x`` is one; NaN where x < 0. [√(unit of x)]
    """
    if isinstance(x, Jet):
        # r = √f: r' = f'/(2r), r'' = (f''/2 − r'²)/r
        r = np.sqrt(x.v)
        h = 1.0 / r
        d1 = x.d1 * h
        d1 *= 0.5
        d2 = d1 * d1
        np.subtract(0.5 * x.d2, d2, out=d2)
        d2 *= h
        return Jet(r, d1, d2)
    return np.sqrt(x)


def arcsin(x: JetLike) -> JetLike:
    """Inverse sine, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Sine value in [-1, 1], as an array or a jet. [dimensionless]

    Returns
    -------
    JetLike
        arcsin x in [-π/2, π/2], a jet when ``x`` is one; NaN outside [-1, 1]. [rad]
    """
    if isinstance(x, Jet):
        w = 1.0 / np.sqrt(1.0 - x.v * x.v)
        return x._chain(np.arcsin(x.v), w, x.v * w**3)
    return np.arcsin(x)


def arccos(x: JetLike) -> JetLike:
    """Inverse cosine, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Cosine value in [-1, 1], as an array or a jet. [dimensionless]

    Returns
    -------
    JetLike
        arccos x in [0, π], a jet when ``x`` is one; NaN outside [-1, 1]. [rad]
    """
    if isinstance(x, Jet):
        w = 1.0 / np.sqrt(1.0 - x.v * x.v)
        return x._chain(np.arccos(x.v), -w, -x.v * w**3)
    return np.arccos(x)


def arctan(x: JetLike) -> JetLike:
    """Inverse tangent, for arrays or jets.

    Parameters
    ----------
    x : JetLike
        Tangent value, as an array or a jet. [dimensionless]

    Returns
    -------
    JetLike
        arctan x in (-π/2, π/2), a jet when ``x`` is one. [rad]
    """
    if isinstance(x, Jet):
        w = 1.0 / (1.0 + x.v * x.v)
        return x._chain(np.arctan(x.v), w, -2.0 * x.v * w * w)
    return np.arctan(x)


def arctan2(y: JetLike, x: JetLike) -> JetLike:
    """Four-quadrant inverse tangent of y/x, for arrays or jets.

    Parameters
    ----------
    y : JetLike
        Ordinate, as an array or a jet. [same unit as x]
    x : JetLike
        Abscissa, as an array or a jet. [same unit as y]

    Returns
    -------
    JetLike
        Angle of the point (x, y) in [-π, π], a jet when either input is one. [rad]
    """
    if not isinstance(y, Jet) and not isinstance(x, Jet):
        return np.arctan2(y, x)
    yj = y if isinstance(y, Jet) else Jet.constant(y, value(x))
    xj = x if isinstance(x, Jet) else Jet.constant(x, value(y))
    # d atan2 = (x dy - y dx)/(x²+y²); the second derivative follows by the product rule.
    r2 = xj * xj + yj * yj
    num = Jet(
        np.zeros_like(xj.v),
        xj.v * yj.d1 - yj.v * xj.d1,
        xj.v * yj.d2 - yj.v * xj.d2,
    )
    d1 = num.d1 / r2.v
    d2 = (num.d2 * r2.v - num.d1 * r2.d1) / (r2.v * r2.v)
    return Jet(np.arctan2(yj.v, xj.v), d1, d2)


def hypot(x: JetLike, y: JetLike) -> JetLike:
    """Euclidean norm sqrt(x² + y²), for arrays or jets.

    Parameters
    ----------
    x, y : JetLike
        Components, as arrays or jets. [same unit for both]

    Returns
    -------
    JetLike
        √(x² + y²), a jet when either input is one. [unit of x and y]

    Notes
    -----
    Arrays are summed and rooted in place, not through ``np.hypot``: that calls the C
    library's ``hypot`` element by element, eight times slower, to guard against
    overflow of x² beyond 1e308, which lengths in mm never reach. Both round to within
    2 ulp of the exact norm (tested).
    """
    if not isinstance(x, Jet) and not isinstance(y, Jet):
        return _norm(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    return sqrt(x * x + y * y)


def _norm(x: FloatArray, y: FloatArray) -> FloatArray:
    """√(x² + y²) of arrays, with one result array and no other temporary."""
    xx, yy = np.multiply(x, x), np.multiply(y, y)
    for out, other in ((yy, xx), (xx, yy)):
        if out.ndim and out.shape == np.broadcast_shapes(out.shape, other.shape):
            np.add(out, other, out=out)
            return np.sqrt(out, out=out)
    norm: FloatArray = np.sqrt(xx + yy)  # 0-d inputs, or a broadcast of both
    return norm
