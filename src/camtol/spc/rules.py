"""Run rules on a control chart's location points: Western Electric and Nelson.

Zones are ±1σ, ±2σ, ±3σ about the centre line, σ that of one plotted point
(:attr:`camtol.spc.charts.ChartLimits.sigma`). A rule flags the point that completes its
pattern (as Minitab does), each point once per rule:

========  ======  ===============================================================
WE        Nelson  pattern
========  ======  ===============================================================
WE1       N1      one point beyond 3σ (outside the control limits)
WE2       N5      2 of 3 consecutive points beyond 2σ, on the same side
WE3       N6      4 of 5 consecutive points beyond 1σ, on the same side
WE4       —       8 consecutive points on the same side of the centre line
—         N2      9 consecutive points on the same side of the centre line
—         N3      6 consecutive points steadily increasing or decreasing
—         N4      14 consecutive points alternating up and down
—         N7      15 consecutive points within 1σ (either side)
—         N8      8 consecutive points with none within 1σ (either side)
========  ======  ===============================================================

(Western Electric *Statistical Quality Control Handbook*, 1956; Nelson, *J. Qual.
Technol.* 16 (1984) 237.) Vectorised over sliding windows.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from numpy.lib.stride_tricks import sliding_window_view

from camtol.exceptions import RecordError

__all__ = ["RULE_SETS", "run_rules"]

BoolArray = npt.NDArray[np.bool_]
RULE_SETS = ("we", "nelson")


def _count_in(flags: BoolArray, window: int, k: int) -> BoolArray:
    """Point i completes a window of ``window`` points with at least k flags (and is one)."""
    out = np.zeros(flags.size, dtype=bool)
    if flags.size >= window:
        counts = sliding_window_view(flags, window).sum(axis=1)
        out[window - 1 :] = counts >= k
    return out & flags


def _run(flags: BoolArray, length: int) -> BoolArray:
    """Point i ends a run of ``length`` consecutive flags."""
    out = np.zeros(flags.size, dtype=bool)
    if flags.size >= length:
        out[length - 1 :] = sliding_window_view(flags, length).all(axis=1)
    return out


def run_rules(
    points: npt.ArrayLike, center: float, sigma: float, rules: str = "we"
) -> dict[str, BoolArray]:
    """Flag the points that violate each rule of a set.

    Parameters
    ----------
    points : array_like
        The chart's location points, in order.
    center, sigma : float
        Centre line and σ of one point (the limits are center ± 3σ).
    rules : {"we", "nelson"}
        Western Electric (WE1-WE4) or Nelson (N1-N8).

    Returns
    -------
    dict of str to ndarray of bool
        Rule code → which points it flags.
    """
    if rules not in RULE_SETS:
        raise RecordError(f"--rules={rules!r}: allowed {', '.join(RULE_SETS)}")
    x = np.asarray(points, dtype=np.float64)
    z = (x - center) / sigma if sigma > 0 else np.zeros_like(x)
    up, down = z > 0, z < 0
    beyond3 = np.abs(z) > 3
    two = _count_in(z > 2, 3, 2) | _count_in(z < -2, 3, 2)
    four = _count_in(z > 1, 5, 4) | _count_in(z < -1, 5, 4)
    if rules == "we":
        return {
            "WE1": beyond3,
            "WE2": two,
            "WE3": four,
            "WE4": _run(up, 8) | _run(down, 8),
        }
    d = np.diff(x)
    rising = np.concatenate([[False], d > 0])
    falling = np.concatenate([[False], d < 0])
    # six points in a trend are five consecutive rises (or falls)
    trend = _run(rising, 5) | _run(falling, 5)
    sign = np.sign(d)
    alternates = np.concatenate([[False], [False], sign[1:] * sign[:-1] < 0])
    return {
        "N1": beyond3,
        "N2": _run(up, 9) | _run(down, 9),
        "N3": trend,
        "N4": _run(alternates, 12),  # 14 points: 13 differences, 12 sign changes
        "N5": two,
        "N6": four,
        "N7": _run(np.abs(z) < 1, 15),
        "N8": _run(np.abs(z) > 1, 8),
    }
