"""Normalised motion laws s(x), x ∈ [0, 1], with derivatives (THEORY §1).

Each law maps the segment's normalised angle x to the normalised lift s and its first
three derivatives with respect to x; :class:`camtol.design.motion.Segment` scales them by the
segment's height and duration.

References
----------
.. [1] R. L. Norton, *Cam Design and Manufacturing Handbook*, 2nd ed., Industrial Press,
   2009, ch. 3 (modified trapezoid and modified sine laws).
.. [2] H. A. Rothbart (ed.), *Cam Design Handbook*, McGraw-Hill, 2004, ch. 3 (modified
   constant velocity: a constant-velocity stretch entered and left by acceleration ramps).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np
from numpy.typing import NDArray

from camtol.exceptions import DesignError

FloatArray = NDArray[np.float64]

MotionLawName = Literal[
    "cycloidal",
    "simple_harmonic",
    "polynomial_345",
    "polynomial_4567",
    "modified_trapezoid",
    "modified_sine",
    "modified_constant_velocity",
]
MOTION_LAWS: tuple[str, ...] = get_args(MotionLawName)
TWO_PI = 2.0 * math.pi

__all__ = [
    "MCV_RAMP_FRACTION",
    "MOTION_LAWS",
    "MotionLawName",
    "NormalizedLaw",
    "RETIRED_LAWS",
    "normalized_law",
]

#: Length of each of the two cycloidal ramps of ``modified_constant_velocity``, as a
#: fraction of the segment: 1/4 in, 1/2 at constant velocity, 1/4 out (the "cycloidal
#: CV50" of industrial practice). [-]
MCV_RAMP_FRACTION = 0.25

#: Names once listed but refused, with the reason and the law to use instead. A pure
#: constant velocity meets a dwell, and every other law (all start and end at rest), with
#: a velocity jump: a corner of the cam that analyze refuses, so no design could use it.
RETIRED_LAWS: dict[str, str] = {
    "constant_velocity": (
        "motion law 'constant_velocity' is not allowed: a constant velocity meets a dwell or"
        " any other law with a velocity jump (a corner of the cam); use"
        " 'modified_constant_velocity' (constant velocity over the middle half, cycloidal"
        " ramps of 1/4 of the segment at each end)"
    ),
}

# ---------------------------------------------------------------------------------------
# Normalised laws: s(x), v = ds/dx, a = d²s/dx², j = d³s/dx³, with s(0)=0, s(1)=1.
# ---------------------------------------------------------------------------------------
NormalizedLaw = Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray, FloatArray]]


def _cycloidal(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    w = TWO_PI * x
    sin_w, cos_w = np.sin(w), np.cos(w)  # once each: transcendentals dominate the cost
    return (
        x - sin_w / TWO_PI,
        1.0 - cos_w,
        TWO_PI * sin_w,
        TWO_PI**2 * cos_w,
    )


def _simple_harmonic(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    w = math.pi * x
    sin_w, cos_w = np.sin(w), np.cos(w)
    return (
        0.5 * (1.0 - cos_w),
        0.5 * math.pi * sin_w,
        0.5 * math.pi**2 * cos_w,
        -0.5 * math.pi**3 * sin_w,
    )


def _polynomial(coefficients: Sequence[float]) -> NormalizedLaw:
    """Return a law s(x) = Σ c_k x^k with its analytic derivatives."""
    # d/dx Σ c_k x^k = Σ k c_k x^(k-1), as numpy's polyder computes it (without importing
    # numpy.polynomial, a few ms of every command's start-up).
    polys = [tuple(float(c) for c in coefficients)]
    for _ in range(3):
        polys.append(tuple(k * c for k, c in enumerate(polys[-1]) if k > 0) or (0.0,))

    def law(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        s, v, a, j = (_horner(c, x) for c in polys)
        return s, v, a, j

    return law


def _horner(coefficients: tuple[float, ...], x: FloatArray) -> FloatArray:
    """Σ c_k x^k by Horner's rule in one array (numpy's polyval, without its temporaries).

    The same operations in the same order as ``np.polynomial.polynomial.polyval``
    (c ← c_k + c·x from the highest degree), hence the same numbers bit for bit (tested).
    """
    out = np.full(np.shape(x), coefficients[-1])
    for c in reversed(coefficients[:-1]):
        out *= x
        out += c  # also c = 0: −0.0 + 0.0 is +0.0, as polyval gives it
    return out


@dataclass(frozen=True)
class _SinePiece:
    """Acceleration a(x) = c + q sin(k x + p) on [x0, x1), integrated exactly."""

    x0: float
    c: float
    q: float
    k: float
    p: float
    v0: float = 0.0
    s0: float = 0.0

    def evaluate(self, x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        d = x - self.x0
        if self.k == 0.0:
            a = np.full_like(x, self.c + self.q * math.sin(self.p))
            return self.s0 + self.v0 * d + 0.5 * a * d * d, self.v0 + a * d, a, np.zeros_like(x)
        ph = self.k * x + self.p
        ph0 = self.k * self.x0 + self.p
        sin_ph, cos_ph = np.sin(ph), np.cos(ph)  # once each: transcendentals dominate
        a = self.c + self.q * sin_ph
        j = self.q * self.k * cos_ph
        v = self.v0 + self.c * d - self.q / self.k * (cos_ph - math.cos(ph0))
        s = (
            self.s0
            + self.v0 * d
            + 0.5 * self.c * d * d
            - self.q / self.k * ((sin_ph - math.sin(ph0)) / self.k - math.cos(ph0) * d)
        )
        return s, v, a, j


def _piecewise_sine_law(
    pieces: Sequence[tuple[float, float, float, float, float]],
) -> NormalizedLaw:
    """Build a law from acceleration pieces (x0, c, q, k, p), normalised to s(1) = 1.

    Velocity and displacement are carried exactly across piece ends, and the whole law
    is then scaled so that s(1) = 1; the peak factors of Norton's tables (e.g. 4.8881 for
    the modified trapezoid) follow from the shape instead of being typed in.
    """
    built: list[_SinePiece] = []
    v0 = s0 = 0.0
    for i, (x0, c, q, k, p) in enumerate(pieces):
        piece = _SinePiece(x0, c, q, k, p, v0, s0)
        built.append(piece)
        x1 = pieces[i + 1][0] if i + 1 < len(pieces) else 1.0
        s1, v1, _, _ = piece.evaluate(np.array([x1]))
        s0, v0 = float(s1[0]), float(v1[0])
    scale = 1.0 / s0
    starts = np.array([pc.x0 for pc in built])

    def law(x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        idx = np.clip(np.searchsorted(starts, x, side="right") - 1, 0, len(built) - 1)
        out = np.empty((4, *np.shape(x)))
        for i, piece in enumerate(built):
            rows = np.flatnonzero(idx == i)
            if rows.size == 0:
                continue
            lo, hi = int(rows[0]), int(rows[-1]) + 1  # one run of rows (a sorted grid): a view
            m: slice | NDArray[np.intp] = slice(lo, hi) if hi - lo == rows.size else rows
            for arr, val in zip(out, piece.evaluate(x[m]), strict=True):
                if isinstance(m, slice):
                    np.multiply(val, scale, out=arr[m])  # straight into the block
                else:
                    arr[m] = val * scale
        return out[0], out[1], out[2], out[3]

    return law


_FOUR_PI = 4.0 * math.pi
# Modified trapezoid (Norton): sine ramps of 1/8 around constant-acceleration flats.
_MODIFIED_TRAPEZOID = _piecewise_sine_law(
    [
        (0.0, 0.0, 1.0, _FOUR_PI, 0.0),
        (0.125, 1.0, 0.0, 0.0, 0.0),
        (0.375, 0.0, 1.0, _FOUR_PI, math.pi / 2 - _FOUR_PI * 0.375),
        (0.625, -1.0, 0.0, 0.0, 0.0),
        (0.875, 0.0, -1.0, -_FOUR_PI, _FOUR_PI),
    ]
)
# Modified sine (Norton): quarter-period sine of 1/8, then a sine three times longer.
_MODIFIED_SINE = _piecewise_sine_law(
    [
        (0.0, 0.0, 1.0, _FOUR_PI, 0.0),
        (0.125, 0.0, 1.0, _FOUR_PI / 3.0, math.pi / 2 - _FOUR_PI / 3.0 * 0.125),
        (0.875, 0.0, -1.0, -_FOUR_PI, _FOUR_PI),
    ]
)


def _modified_constant_velocity(ramp: float) -> NormalizedLaw:
    """Constant velocity blended into rest by half-cycloid ramps of ``ramp`` each ([2]).

    The acceleration is a half sine wave over [0, r], zero over [r, 1 − r] (constant
    velocity 1/(1 − r)) and a negative half sine wave over [1 − r, 1]: S, V and A are
    continuous everywhere, at rest at both ends (so the law meets a dwell or any other
    law without a jump of V or A), and J jumps at the four ramp ends, as the cycloidal
    law's does at its two. Peak factors: V = 1/(1 − r), A = π/(2r(1 − r)); r = 1/2 is the
    cycloidal law itself.
    """
    k = math.pi / ramp
    return _piecewise_sine_law(
        [
            (0.0, 0.0, 1.0, k, 0.0),
            (ramp, 0.0, 0.0, 0.0, 0.0),
            (1.0 - ramp, 0.0, -1.0, k, -k * (1.0 - ramp)),
        ]
    )


_LAWS: dict[str, NormalizedLaw] = {
    "cycloidal": _cycloidal,
    "simple_harmonic": _simple_harmonic,
    "polynomial_345": _polynomial([0, 0, 0, 10, -15, 6]),
    "polynomial_4567": _polynomial([0, 0, 0, 0, 35, -84, 70, -20]),
    "modified_trapezoid": _MODIFIED_TRAPEZOID,
    "modified_sine": _MODIFIED_SINE,
    "modified_constant_velocity": _modified_constant_velocity(MCV_RAMP_FRACTION),
}


def normalized_law(name: str) -> NormalizedLaw:
    """Return the normalised law ``x -> (s, ds/dx, d²s/dx², d³s/dx³)``.

    Parameters
    ----------
    name : str
        One of :data:`MOTION_LAWS`.

    Raises
    ------
    DesignError
        If the law is unknown.
    """
    try:
        return _LAWS[name]
    except KeyError:
        if name in RETIRED_LAWS:
            raise DesignError(RETIRED_LAWS[name]) from None
        raise DesignError(
            f"motion law {name!r} is unknown; allowed: {', '.join(MOTION_LAWS)}"
        ) from None
