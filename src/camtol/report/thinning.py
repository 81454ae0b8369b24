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

A band filled between two curves (``fill_between``: the worst-case envelopes of ΔV and
ΔA) is thinned the same way, each of its two edges on its own: matplotlib simplifies the
path of a line it writes but never that of a filled area, so the two envelopes were two
thirds of the report's figure (370 of 543 kB) before.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["COLUMNS_PER_INCH", "thin_lines", "thinned_band"]

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


def thinned_band(vertices: np.ndarray, columns: int) -> np.ndarray | None:
    """Thin a band's polygon: an edge forward in x, then the other edge back.

    Parameters
    ----------
    vertices : ndarray, shape (n, 2)
        The closed polygon as ``fill_between`` makes it (its last vertex may repeat the
        first). [data units]
    columns : int
        Number of equal columns across x's range.

    Returns
    -------
    ndarray, shape (m, 2), or None
        The polygon (not repeating its first vertex) with each edge decimated as
        :func:`thinned_indices` decimates a curve; None when it is not such a band (an
        edge not monotonic in x, a non-finite vertex) or too short to gain.
    """
    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 2 or not np.all(np.isfinite(v)):
        return None
    if len(v) > 1 and np.array_equal(v[0], v[-1]):
        v = v[:-1]
    dx = np.diff(v[:, 0])
    turn = int(np.argmax(dx < 0)) if np.any(dx < 0) else len(dx)
    # Both edges share the turning vertex, so that both span the same x range and are
    # cut into the same columns; each keeps its ends, so the shared vertex is kept once.
    forward, back = v[: turn + 1], v[turn:]
    if len(back) < 2 or np.any(np.diff(back[:, 0]) > 0):
        return None  # not one forward and one backward edge
    kept_f = thinned_indices(forward[:, 0], forward[:, 1], columns)
    rev = back[::-1]
    kept_b = thinned_indices(rev[:, 0], rev[:, 1], columns)
    if kept_f is None or kept_b is None:
        return None
    return np.concatenate([forward[kept_f], rev[kept_b][::-1][1:]])


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
    from matplotlib.collections import PolyCollection

    dropped = 0
    width_in = fig.get_figwidth()
    for ax in fig.axes:
        columns = max(1, math.ceil(ax.get_position().width * width_in * COLUMNS_PER_INCH))
        for coll in ax.collections:  # fill_between's bands (a PolyCollection each)
            if not isinstance(coll, PolyCollection):
                continue
            polygons = [np.asarray(p.vertices, dtype=float) for p in coll.get_paths()]
            bands = [thinned_band(v, columns) for v in polygons]
            thinned = [b for b in bands if b is not None]
            if polygons and len(thinned) == len(polygons):
                dropped += sum(len(v) for v in polygons) - sum(len(b) for b in thinned)
                coll.set_verts(thinned, closed=True)
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
