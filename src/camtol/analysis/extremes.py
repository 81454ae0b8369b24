"""Locating the extremes of functions of the cam angle (THEORY §8.1's tables).

A quantity is first sampled on the analysis grid. A maximum (or minimum) that the
function holds over a run of grid points (a dwell) is reported as that angle range; an
isolated one is refined by re-evaluating the function on a few points around the best
sample (a parabola through them where the extremum is smooth), which locates it to
step/1000 or better (0.0001° at the default 0.1° step) with one or two evaluations of all
windows at once.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.exceptions import DesignError
from camtol.grid import run_bounds
from camtol.jet import FloatArray, broadcast_constant

ExtremeKind = Literal["max", "min"]

__all__ = ["Extreme", "find_extremes", "overflow_error", "scaled_extremes"]

#: Refinement samples per grid step (step/10 apart), and per coarse sample in the second
#: call (step/1000 apart).
_FINE = 10
#: Largest misfit of the outer samples to the parabola through the middle three, relative
#: to its curvature, for an extremum to count as smooth (a kink misfits by O(1)).
_SMOOTH = 0.05


@dataclass(frozen=True)
class Extreme:
    """The global maximum or minimum of one quantity over a revolution.

    Attributes
    ----------
    quantity : str
        Quantity key, e.g. ``"dS_worst"``.
    kind : {"max", "min"}
        Which extreme.
    value : float
        The extreme value, in the unit of the values searched (internal units for
        :attr:`camtol.analysis.result.Analysis.extremes`; see :mod:`camtol.report.display`).
    theta_deg : float
        Where it occurs (the first place, for a plateau). [deg]
    ranges_deg : tuple of (float, float)
        Angle ranges over which the value is held (empty for an isolated extreme). [deg]
    """

    quantity: str
    kind: ExtremeKind
    value: float
    theta_deg: float
    ranges_deg: tuple[tuple[float, float], ...] = ()

    @property
    def where(self) -> str:
        """Human form of the location: ``63.40°`` or ``120.00-190.00°``."""
        if self.ranges_deg:
            return ", ".join(
                f"{a:.2f}°" if b - a < 5e-3 else f"{a:.2f}-{b:.2f}°" for a, b in self.ranges_deg
            )
        return f"{self.theta_deg:.2f}°"


def overflow_error(label: str, value: float, theta_deg: float) -> DesignError:
    """Return the error of a quantity that is not finite (an overflow), saying where.

    Parameters
    ----------
    label : str
        The quantity as tables name it.
    value : float
        Its value there (inf or NaN).
    theta_deg : float
        Cam angle. [deg]

    Returns
    -------
    DesignError
        To be raised by the caller.
    """
    return DesignError(
        f"{label} is {value!r} at θ={theta_deg:.6g}°: the computation overflows; a"
        " dimension or tolerance of the design is far outside a plausible range"
    )


def scaled_extremes(
    pair: tuple[Extreme, Extreme], factor: float, label: str
) -> tuple[Extreme, Extreme]:
    """(max, min) of a quantity multiplied by ``factor`` (swapped when it is negative).

    Parameters
    ----------
    pair : (Extreme, Extreme)
        The quantity's max and min.
    factor : float
        The multiplier (a deviation, or a unit conversion).
    label : str
        The quantity as tables name it (for the error).

    Returns
    -------
    (Extreme, Extreme)
        Max and min of ``factor`` × the quantity.

    Raises
    ------
    DesignError
        A finite extreme becomes infinite (:func:`overflow_error`).
    """
    hi, lo = pair if factor >= 0.0 else pair[::-1]
    for e in (hi, lo):
        if math.isfinite(e.value) and not math.isfinite(e.value * factor):
            raise overflow_error(label, e.value * factor, e.theta_deg)
    return (
        dataclasses.replace(hi, kind="max", value=hi.value * factor),
        dataclasses.replace(lo, kind="min", value=lo.value * factor),
    )


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Index runs [i, j] (inclusive) of True values."""
    bounds = run_bounds(mask)  # each stretch between changes is all True or all False
    return [(a, b - 1) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if mask[a]]


def _plateaus(
    theta_rad: FloatArray, runs: list[tuple[int, int]], step_deg: float
) -> tuple[tuple[float, float], ...]:
    """Angle ranges of index runs [i, j] of held samples; () unless one is longer than a step."""
    spans = [(math.degrees(theta_rad[i]), math.degrees(theta_rad[j])) for i, j in runs]
    # A run reaching the end of the grid continues into one starting at 0° (the grid may
    # or may not hold 360° itself).
    wraps = spans and spans[0][0] <= 1e-9 and spans[-1][1] >= 360.0 - 1.5 * step_deg
    if wraps and len(spans) == 1:
        spans = [(0.0, 360.0)]
    elif wraps:
        first = spans.pop(0)
        last = spans.pop()
        spans.append((last[0], 360.0 + first[1]))
    if not any(b - a > 1.5 * step_deg for a, b in spans):
        return ()
    return tuple(spans)


def find_extremes(
    theta_rad: FloatArray,
    values: Mapping[str, FloatArray],
    evaluate: Callable[[FloatArray, frozenset[str]], Mapping[str, FloatArray]],
    *,
    step_deg: float,
    on_nonfinite: Callable[[str, int], None] | None = None,
) -> dict[str, tuple[Extreme, Extreme]]:
    """Global max and min of each quantity, located to step/1000 or better.

    Every isolated extreme is refined in one call of ``evaluate`` on all windows at once:
    21 samples step/10 apart around the best grid sample. Where the five samples around
    the best one follow a parabola (a smooth extremum), its vertex gives the location
    and value (error O(h³) with h = step/10, far below step/1000); elsewhere (a kink,
    e.g. of a worst case Σ|ΔS_p|, or the best sample at a window edge) a second call
    samples ±step/10 around the best sample step/1000 apart. An extreme the grid already
    holds as a one-sided limit at a jump is kept as it is.

    Parameters
    ----------
    theta_rad : ndarray
        Analysis grid (may hold left/right limits at boundaries). [rad]
    values : mapping of str to ndarray
        Each quantity sampled on the grid (any unit; the extremes are in the same).
    evaluate : callable
        ``evaluate(theta_rad, names) -> {quantity: values}`` at arbitrary angles (right
        limits); called at most twice, on all refinement windows at once, and only the
        quantities in ``names`` (those refined by that call) are read from its result,
        so it may compute no others.
    step_deg : float
        Grid step. [deg]
    on_nonfinite : callable, optional
        Called as ``on_nonfinite(quantity, index)`` with the first grid index where a
        quantity is NaN or infinite (it may raise); the extremes are then those of the
        finite samples. The search finds this on the way (a max and min that are both
        finite mean every sample is), so a caller needs no pass of its own.

    Returns
    -------
    dict
        ``{quantity: (max, min)}``.
    """
    step = math.radians(step_deg)
    pending: list[tuple[str, ExtremeKind, float, float, tuple[tuple[float, float], ...]]] = []
    centres: dict[float, int] = {}  # window centre [rad] -> window index
    for name, vals in values.items():
        v = np.asarray(vals, dtype=float)
        c = broadcast_constant(v)
        if c is not None and math.isfinite(c):
            # Held over the whole grid: no pass over it (numpy would copy it first).
            whole = _plateaus(theta_rad, [(0, v.size - 1)], step_deg)
            for kind in ("max", "min"):
                pending.append((name, kind, c, float(theta_rad[0]), whole))
            if not whole:  # a grid of a single step: refine as any other extreme
                centres.setdefault(float(theta_rad[0]), len(centres))
            continue
        hi, lo = int(np.argmax(v)), int(np.argmin(v))  # NaN or ±inf would be picked
        if not (math.isfinite(v[hi]) and math.isfinite(v[lo])):
            finite = np.isfinite(v)
            if on_nonfinite is not None:
                on_nonfinite(name, int(np.argmin(finite)))
            hi = int(np.argmax(np.where(finite, v, -np.inf)))
            lo = int(np.argmin(np.where(finite, v, np.inf)))
        top, bottom = float(v[hi]), float(v[lo])
        # Dwell values are equal to rounding; a smooth approach to a dwell is not (a
        # looser tolerance would stretch the reported range by up to ~0.5°).
        tol = 1e-14 * max(abs(top), abs(bottom), 1e-300)
        extremes: tuple[tuple[ExtremeKind, int, float], ...] = (
            ("max", hi, top),
            ("min", lo, bottom),
        )
        for kind, i, target in extremes:
            held = v >= target - tol if kind == "max" else v <= target + tol
            ranges: tuple[tuple[float, float], ...] = ()
            if np.count_nonzero(held) > 1:
                ranges = _plateaus(theta_rad, _runs(held), step_deg)
            if not ranges:
                centres.setdefault(float(theta_rad[i]), len(centres))
            pending.append((name, kind, target, float(theta_rad[i]), ranges))
    names = frozenset(p[0] for p in pending if not p[4])
    coarse = _Windows(np.array(list(centres)), step / _FINE, _FINE, evaluate, names)
    found: dict[tuple[str, str], tuple[float, float, bool]] = {}
    retry: dict[float, int] = {}
    kinked: set[str] = set()
    for name, kind, _, theta_i, ranges in pending:
        if ranges:
            continue
        found[name, kind] = coarse.best(name, kind, centres[theta_i])
        if not found[name, kind][2]:
            retry.setdefault(found[name, kind][0], len(retry))
            kinked.add(name)
    fine = _Windows(np.array(list(retry)), step / _FINE**3, _FINE**2, evaluate, frozenset(kinked))
    out: dict[str, dict[str, Extreme]] = {}
    for name, kind, target, theta_i, ranges in pending:
        if ranges:
            ext = Extreme(name, kind, target, ranges[0][0], ranges)
        else:
            t_best, v_best, smooth = found[name, kind]
            if not smooth:
                t_best, v_best, _ = fine.best(name, kind, retry[t_best])
            better = v_best > target if kind == "max" else v_best < target
            if better:
                ext = Extreme(name, kind, v_best, math.degrees(t_best) % 360.0)
            else:  # a one-sided limit at a jump, or the grid already holds the extreme
                ext = Extreme(name, kind, target, math.degrees(theta_i) % 360.0)
        out.setdefault(name, {})[kind] = ext
    return {name: (d["max"], d["min"]) for name, d in out.items()}


class _Windows:
    """Samples of the quantities on windows ``centre + k·h``, k = −n..n, in one call."""

    def __init__(
        self,
        centres: FloatArray,
        h: float,
        n: int,
        evaluate: Callable[[FloatArray, frozenset[str]], Mapping[str, FloatArray]],
        names: frozenset[str],
    ) -> None:
        self.centres, self.h, self.size = centres, h, 2 * n + 1
        self.offsets = np.arange(-n, n + 1) * h
        if centres.size:
            got = evaluate((centres[:, None] + self.offsets).ravel(), names)
            self.samples = {k: np.asarray(got[k], dtype=float) for k in names}
        else:
            self.samples = {}

    def best(self, name: str, kind: ExtremeKind, w: int) -> tuple[float, float, bool]:
        """(angle [rad], value, smooth) of the best sample of window ``w``, refined.

        ``smooth``: the five samples around the best follow a parabola, whose vertex is
        returned; otherwise the best sample itself.
        """
        y = self.samples[name][w * self.size : (w + 1) * self.size].tolist()
        sign = 1.0 if kind == "max" else -1.0
        z = [sign * v if math.isfinite(v) else -math.inf for v in y]  # few points: plain floats
        j = max(range(len(z)), key=z.__getitem__)
        t = float(self.centres[w] + self.offsets[j])
        if not 2 <= j <= self.size - 3 or not all(math.isfinite(v) for v in z[j - 2 : j + 3]):
            return t, y[j], False
        ym2, ym1, y0, y1, y2 = z[j - 2 : j + 3]
        a = 0.5 * (y1 - 2.0 * y0 + ym1)  # z ≈ y0 + b·u + a·u² (u in samples)
        b = 0.5 * (y1 - ym1)
        # The outer samples must follow the same parabola: a kink or a jump does not.
        miss = max(abs(y2 - (y0 + 2 * b + 4 * a)), abs(ym2 - (y0 - 2 * b + 4 * a)))
        if not a < 0.0 or miss > _SMOOTH * -a:
            return t, y[j], False
        u = -b / (2.0 * a)  # |u| <= 1/2 since y0 is the best sample
        return t + u * self.h, sign * (y0 - b * b / (4.0 * a)), True
