"""Fewer points per curve where a figure cannot show them (issue 32: report start-up).

A report's curves come from the analysis grid (3,601 angles at the default 0.1°), but a
panel of the report's figure is some 5.5 in wide: a 96-dpi screen shows it on about 530
pixel columns. Writing every grid point into the page's SVG costs time in
``camtol report`` for nothing that can be seen.

:func:`thin_lines` keeps, in each column of :data:`COLUMNS_PER_INCH` per inch of the
axes' width, the first and last point and the smallest and largest value, in their order
along the curve (the "M4" min-max decimation of Jugel et al., VLDB 2014, which draws the
same pixels as the full curve at that resolution): every column's extremes are kept
exactly, so a peak is never lost and a jump (of A at a segment boundary) is drawn across
its column as before; only points lying between a column's extremes are dropped. Curves
whose x is not in increasing order (a cam profile), that hold non-finite values (gaps),
or that are already short are left as they are.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["COLUMNS_PER_INCH", "thin_lines"]

#: Columns per inch of axes width in which the extremes are kept: one per pixel of a
#: 96-dpi screen showing the figure at its size (the report's page shows it smaller). [1/in]
COLUMNS_PER_INCH = 96


def thinned_indices(x: np.ndarray, y: np.ndarray, columns: int) -> np.ndarray | None:
    """Return the indices of the points kept by min-max decimation into ``columns`` of x.

    Parameters
    ----------
    x, y : ndarray
        The curve, x non-decreasing and both finite. [data units]
    columns : int
        Number of equal columns across x's range.

    Returns
    -------
    ndarray of intp or None
        Sorted indices of the kept points (first, last, argmin, argmax of each column), or
        None when thinning would keep more than 80 % of the points.
    """
    n = x.size
    if n < 5 * columns // 4 or columns < 1:
        return None
    span = float(x[-1] - x[0])
    if not span > 0:
        return None
    col = np.minimum(((x - x[0]) * (columns / span)).astype(np.intp), columns - 1)
    starts = np.flatnonzero(np.r_[True, col[1:] != col[:-1]])
    ends = np.r_[starts[1:], n]
    # The minimum and maximum of y in each column: sorted by column, then by value.
    order = np.lexsort((y, col))  # by column, then by value: first/last of a run = min/max
    first = order[starts]
    last = order[ends - 1]
    keep = np.unique(np.concatenate([starts, ends - 1, first, last]))
    return keep if keep.size <= 0.8 * n else None


def thin_lines(fig: Figure) -> int:
    """Thin every long line of ``fig`` in place (module docstring); return the points dropped.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure laid out in inches (its axes' widths give the columns).

    Returns
    -------
    int
        How many points were dropped in all.
    """
    dropped = 0
    width_in = fig.get_figwidth()
    for ax in fig.axes:
        columns = max(1, math.ceil(ax.get_position().width * width_in * COLUMNS_PER_INCH))
        for line in ax.get_lines():
            x = np.asarray(line.get_xdata(), dtype=float)
            y = np.asarray(line.get_ydata(), dtype=float)
            if x.ndim != 1 or x.shape != y.shape or x.size < 5 * columns // 4:
                continue
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
                continue
            if np.any(np.diff(x) < 0):  # not a function of x (a profile): leave it
                continue
            keep = thinned_indices(x, y, columns)
            if keep is None:
                continue
            data: Any = (x[keep], y[keep])
            line.set_data(*data)
            dropped += x.size - keep.size
    return dropped
