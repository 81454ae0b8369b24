"""Locating the extremes of functions of the cam angle (THEORY §8.1's tables).

A quantity is first sampled on the analysis grid. A maximum (or minimum) that the
function holds over a run of grid points (a dwell) is reported as that angle range; an
isolated one is refined by re-evaluating the function on a fine grid around the best
sample, which locates it to step/1000 (0.0001° at the default 0.1° step).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.jet import FloatArray

ExtremeKind = Literal["max", "min"]

__all__ = ["Extreme", "find_extremes"]

#: Fine points per side of a refinement window.
_REFINE = 1000


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
        The extreme value, in the quantity's display unit.
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


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Index runs [i, j] (inclusive) of True values."""
    if not np.any(mask):
        return []
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def _plateaus(
    theta_deg: FloatArray, values: FloatArray, target: float, tol: float, step_deg: float
) -> tuple[tuple[float, float], ...]:
    runs = _runs(np.abs(values - target) <= tol)
    spans = [(float(theta_deg[i]), float(theta_deg[j])) for i, j in runs]
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
    evaluate: Callable[[FloatArray], Mapping[str, FloatArray]],
    *,
    step_deg: float,
) -> dict[str, tuple[Extreme, Extreme]]:
    """Global max and min of each quantity, located to step/1000.

    Parameters
    ----------
    theta_rad : ndarray
        Analysis grid (may hold left/right limits at boundaries). [rad]
    values : mapping of str to ndarray
        Each quantity sampled on the grid, in its display unit.
    evaluate : callable
        ``evaluate(theta_rad) -> {quantity: values}`` at arbitrary angles (right limits);
        called once, on all refinement windows at once.
    step_deg : float
        Grid step. [deg]

    Returns
    -------
    dict
        ``{quantity: (max, min)}``.
    """
    theta_deg = np.degrees(theta_rad)
    step = math.radians(step_deg)
    offsets = np.linspace(-step, step, 2 * _REFINE + 1)
    pending: list[tuple[str, ExtremeKind, float, float, tuple[tuple[float, float], ...]]] = []
    windows: list[FloatArray] = []
    for name, vals in values.items():
        finite = np.where(np.isfinite(vals), vals, np.nan)
        scale = float(np.nanmax(np.abs(finite))) if np.any(np.isfinite(finite)) else 0.0
        # Dwell values are equal to rounding; a smooth approach to a dwell is not (a
        # looser tolerance would stretch the reported range by up to ~0.5°).
        tol = 1e-14 * max(scale, 1e-300)
        for kind in ("max", "min"):
            i = int(np.nanargmax(finite) if kind == "max" else np.nanargmin(finite))
            target = float(finite[i])
            ranges = _plateaus(theta_deg, finite, target, tol, step_deg)
            pending.append((name, kind, target, float(theta_rad[i]), ranges))
            windows.append(float(theta_rad[i]) + offsets)
    fine = evaluate(np.concatenate(windows)) if windows else {}
    out: dict[str, dict[str, Extreme]] = {}
    for k, (name, kind, target, theta_i, ranges) in enumerate(pending):
        if ranges:
            ext = Extreme(name, kind, target, ranges[0][0], ranges)
        else:
            w = np.asarray(fine[name][k * offsets.size : (k + 1) * offsets.size], dtype=float)
            j = int(np.nanargmax(w) if kind == "max" else np.nanargmin(w))
            better = w[j] > target if kind == "max" else w[j] < target
            if better:
                t = float(np.degrees(theta_i + offsets[j])) % 360.0
                ext = Extreme(name, kind, float(w[j]), t)
            else:  # a one-sided limit at a jump, or the grid already holds the extreme
                ext = Extreme(name, kind, target, math.degrees(theta_i) % 360.0)
        out.setdefault(name, {})[kind] = ext
    return {name: (d["max"], d["min"]) for name, d in out.items()}
