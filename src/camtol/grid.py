"""The cam-angle grids camtol evaluates on, and the one rule that validates them.

Every command that takes an angular step (``--step``, ``--table-step``, ``--read-step``,
``--cut-step``) and every reader of a tabulated function of the cam angle goes through
here, so the same step is accepted or refused everywhere with the same message.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.exceptions import DesignError, InputFileError

__all__ = [
    "MAX_GRID_POINTS",
    "check_step",
    "drop_closing_row",
    "ordered_segment_runs",
    "run_bounds",
    "sorted_unique",
    "uniform_table_step",
]

#: Most points of a grid over one revolution (0.0001° steps); beyond, memory and time
#: grow without any gain in the numbers camtol reports.
MAX_GRID_POINTS = 3_600_000


def check_step(
    step_deg: float,
    *,
    name: str = "--step",
    max_points: int = MAX_GRID_POINTS,
    min_points: int = 1,
) -> int:
    """Validate an angular step that must divide 360° and return the number of steps.

    Parameters
    ----------
    step_deg : float
        The step as the user gave it. [deg]
    name : str
        How the user wrote the field or flag (``--step``, ``motion.table_step_deg``).
    max_points : int
        Largest number of steps allowed (bounds memory and time).
    min_points : int
        Smallest number of steps allowed.

    Returns
    -------
    int
        n = 360 / step, a whole number.

    Raises
    ------
    DesignError
        If the step is not a finite positive number, does not divide 360° into a whole
        number of steps (to 1e-6), or gives a grid outside ``min_points..max_points``.

    Examples
    --------
    >>> check_step(0.1)
    3600
    """
    if isinstance(step_deg, bool) or not isinstance(step_deg, int | float):
        raise DesignError(
            f"{name}={step_deg!r} is not allowed; give a number of degrees that can divide 360°"
        )
    coarsest = 360.0 / min_points
    finest = 360.0 / max_points
    allowed = (
        f"it must divide 360° into a whole number of steps, between {finest:g}° and"
        f" {coarsest:g}° (e.g. 1, 0.5, 0.1, 0.01)"
    )
    if not (math.isfinite(step_deg) and step_deg > 0):
        raise DesignError(f"{name}={step_deg!r} is not allowed; {allowed}")
    n = 360.0 / step_deg
    if not math.isfinite(n) or n > max_points * (1 + 1e-9) or n < min_points * (1 - 1e-9):
        raise DesignError(f"{name}={step_deg:g} is not allowed; {allowed}")
    if abs(n - round(n)) > 1e-6 * max(1.0, n):
        raise DesignError(f"{name}={step_deg:g} is not allowed; {allowed}")
    return int(round(n))


def uniform_table_step(
    theta_deg: ArrayLike,
    *,
    source: str,
    name: str = "theta_deg",
    max_points: int = MAX_GRID_POINTS,
    line_of: Callable[[int], int] | None = None,
) -> tuple[float, int]:
    """Check that tabulated cam angles are one revolution on a uniform grid.

    The angles must start at 0°, increase by one constant step that divides 360°, and end
    one step before 360° (a closing row at 360° repeats 0°: see :func:`drop_closing_row`).
    A refusal names the first offending row and says what it is: rows missing (a gap of
    whole steps), a repeat, a decrease, an unequal step, a table beyond 360°, or one that
    stops short of a revolution (half a revolution, say).

    Parameters
    ----------
    theta_deg : array_like
        Tabulated angles in file order. [deg]
    source : str
        File name (or field) for messages.
    name : str
        Column name for messages.
    max_points : int
        Largest number of rows allowed.
    line_of : callable, optional
        Maps a row index to its line in the file (:meth:`camtol.tables.Table.line_of`);
        without it, messages name 1-based rows.

    Returns
    -------
    step_deg, n : float, int
        The step [deg] and the number of rows (360 / step).

    Raises
    ------
    InputFileError
        Naming the first row where the table departs from one revolution in equal steps.
    """
    t = np.asarray(theta_deg, dtype=float)

    def row(i: int) -> str:
        line = line_of(i) if line_of is not None else 0
        return f"line {line}" if line > 0 else f"row {i + 1}"

    if t.size < 3:
        raise InputFileError(f"{source}: column {name} has {t.size} rows; at least 3 are needed")
    if not np.all(np.isfinite(t)):
        i = int(np.argmax(~np.isfinite(t)))
        raise InputFileError(f"{source}, {row(i)}: {name}={t[i]:g} is not a finite angle")
    if abs(t[0]) > 1e-9:
        raise InputFileError(f"{source}, {row(0)}: {name}={t[0]:g}°; the table must start at 0°")
    allowed = "one revolution from 0° in equal increasing steps (360° row optional)"
    d = np.diff(t)
    # The step the table means: the most common difference, the earliest on a tie (a few
    # bad rows cannot move it, and a short table is read from its start).
    rounded = np.round(d, 9)
    order = np.argsort(rounded, kind="stable")  # equal steps together, each in file order
    starts = np.flatnonzero(np.r_[True, rounded[order][1:] != rounded[order][:-1]])
    counts = np.diff(np.r_[starts, d.size])
    best = starts[counts == counts.max()]
    step = float(d[int(np.min(order[best]))])
    tol = 1e-6 * max(abs(step), 1e-3)
    i = int(np.argmax(d <= tol)) if np.any(d <= tol) else -1
    if i >= 0:
        what = (
            "repeats the angle of the row before"
            if abs(d[i]) <= tol
            else (f"comes after {t[i]:g}°: angles must increase")
        )
        raise InputFileError(f"{source}, {row(i + 1)}: {name}={t[i + 1]:g}° {what}; give {allowed}")
    beyond = np.flatnonzero(t >= 360.0 - 1e-9)
    if beyond.size:
        j = int(beyond[0])
        raise InputFileError(
            f"{source}, {row(j)}: {name}={t[j]:g}° is beyond one revolution (0° to"
            f" {t[j - 1]:g}° before it); give {allowed}, not more"
        )
    bad = np.abs(d - step) > tol
    if np.any(bad):
        i = int(np.argmax(bad))
        k = d[i] / step
        if k > 1.5 and abs(k - round(k)) < 1e-6 * k:
            m = int(round(k)) - 1
            first, last = t[i] + step, t[i + 1] - step
            gap = f"{first:g}°" if m == 1 else f"{first:g}° to {last:g}°"
            raise InputFileError(
                f"{source}, {row(i + 1)}: {name} jumps from {t[i]:g}° to {t[i + 1]:g}°;"
                f" {m} row{'s' if m > 1 else ''} missing ({gap} in steps of {step:g}°); give"
                f" {allowed}"
            )
        raise InputFileError(
            f"{source}, {row(i + 1)}: {name} steps from {t[i]:g}° to {t[i + 1]:g}°"
            f" ({d[i]:g}°) where the table steps by {step:g}°; give {allowed}"
        )
    covered = t[-1] + step
    if abs(covered - 360.0) > 1e-6 * max(step, 1e-3) * t.size:
        whole = abs(360.0 / step - round(360.0 / step)) < 1e-6
        raise InputFileError(
            f"{source}, {row(t.size - 1)}: {name} ends at {t[-1]:g}°, so the table covers"
            f" {covered:g}°, not one revolution; give "
            + (
                f"{360.0 / step:g} rows from 0° to {360.0 - step:g}° (360° row optional)"
                if whole
                else f"{allowed} (a step of {step:g}° does not divide 360°)"
            )
        )
    step = 360.0 / t.size
    try:
        check_step(step, name=f"{source}: step of {name}", max_points=max_points)
    except DesignError as exc:
        raise InputFileError(str(exc)) from None
    return step, t.size


def drop_closing_row(
    theta_deg: ArrayLike,
    values: ArrayLike,
    *,
    source: str,
    name: str,
    line_of: Callable[[int], int] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Drop a closing 360° row after checking that it repeats the 0° row.

    A periodic table may close the revolution with a row at 360°; it carries no new
    information only when it equals the 0° row (to 1e-9 of the largest value, the
    rounding of a number written out and read back). Any other value is a second,
    conflicting lift at the same cam angle, refused rather than dropped silently.

    Parameters
    ----------
    theta_deg, values : array_like
        Angles [deg] and the tabulated values [unit of the column], in file order.
    source : str
        File name for messages.
    name : str
        Column name of ``values``, for messages.
    line_of : callable, optional
        Maps a row index to its line in the file.

    Returns
    -------
    theta_deg, values : ndarray
        Without the closing row when there was one (copies otherwise unchanged).

    Raises
    ------
    InputFileError
        The 360° row's value differs from the 0° row's.
    """
    t = np.asarray(theta_deg, dtype=float)
    v = np.asarray(values, dtype=float)
    if t.size < 2 or abs(t[-1] - 360.0) >= 1e-9:
        return t, v
    if abs(t[0]) < 1e-9 and np.isfinite(v[-1]) and np.isfinite(v[0]):
        scale = float(np.max(np.abs(v[np.isfinite(v)]), initial=0.0))
        if abs(v[-1] - v[0]) > 1e-9 * max(scale, 1e-300) + 1e-12:
            line = line_of(t.size - 1) if line_of is not None else 0
            where = f"line {line}" if line > 0 else f"row {t.size}"
            raise InputFileError(
                f"{source}, {where}: the closing 360° row has {name}={v[-1]:.10g} but the 0°"
                f" row has {v[0]:.10g}; a 360° row must repeat the 0° row, or be left out"
            )
    return t[:-1], v[:-1]


def sorted_unique(values: ArrayLike) -> NDArray[np.float64]:
    """Return the distinct values, sorted: ``np.unique`` of a float array, without numpy.ma.

    ``np.unique`` imports :mod:`numpy.ma` on first use (about 15 ms, a twentieth of
    ``camtol analyze``'s start-up) only to ask whether its input is masked; grids and
    boundary lists never are.

    Parameters
    ----------
    values : array_like
        Real numbers (no NaN). [any unit]

    Returns
    -------
    ndarray
        Sorted, without repeats (bit-for-bit equality), one-dimensional. [same unit]
    """
    s = np.sort(np.asarray(values, dtype=float).ravel())
    if s.size < 2:
        return s
    keep = np.empty(s.size, dtype=bool)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def run_bounds(values: NDArray[Any]) -> list[int]:
    """Return where the runs of equal values along a grid start, and the grid's length.

    Parameters
    ----------
    values : ndarray
        One value per grid row (a mask, a segment index...), one-dimensional.

    Returns
    -------
    list of int
        ``[0, s1, s2, ..., n]``: run ``k`` is rows ``bounds[k]`` to ``bounds[k + 1]``
        (excluded), all of one value; ``[0]`` for an empty array.
    """
    if values.size == 0:
        return [0]
    return [0, *(np.flatnonzero(values[1:] != values[:-1]) + 1).tolist(), values.size]


def ordered_segment_runs(
    theta_rad: NDArray[np.float64],
    starts_rad: NDArray[np.float64],
    left_limit: NDArray[np.bool_] | None = None,
) -> list[tuple[int, int, int]] | None:
    """Return the rows of each segment of a grid in order, by binary search; else None.

    The rows of segment ``k`` are those with ``starts[k] <= θ < starts[k + 1]``, except
    that a left-limit row lying on a start belongs to the segment that ends there (the
    last one for the first start), as :meth:`camtol.design.motion.SegmentProgram.segment_index`
    assigns them. On a non-decreasing grid whose left-limit rows at a start come before
    its other rows there (as :func:`camtol.analysis.kinematics.analysis_grid` builds them), each
    segment is one run, found by a search per start instead of a comparison per row
    and start.

    Parameters
    ----------
    theta_rad : ndarray
        One-dimensional grid, already in the revolution that starts at ``starts[0]``.
        [rad]
    starts_rad : ndarray
        Start of each segment, increasing. [rad]
    left_limit : ndarray of bool, optional
        The grid's left-limit rows.

    Returns
    -------
    list of (int, int, int) or None
        ``(segment, first row, end row)`` of every non-empty run; None when the grid is
        not in that order (the caller compares instead).
    """
    t = theta_rad
    if t.ndim != 1 or t.size < 2 or not bool(np.all(t[1:] >= t[:-1])):
        return None
    bounds = np.searchsorted(t, starts_rad, side="left").tolist()
    if left_limit is not None:
        rows = np.flatnonzero(left_limit)
        at_start = rows[np.isin(t[rows], starts_rad)].tolist()
        for k, start in enumerate(starts_rad.tolist()):
            while at_start and bounds[k] < t.size and bounds[k] == at_start[0]:
                if t[bounds[k]] != start:
                    break
                at_start.pop(0)
                bounds[k] += 1  # the left limit belongs to the segment before
        if at_start:  # a left limit after a right one: not this order
            return None
    last = len(bounds) - 1
    runs = [(last, 0, bounds[0])]  # left limits at the first start: the last segment
    runs += [(k, bounds[k], bounds[k + 1]) for k in range(last)]
    runs.append((last, bounds[last], t.size))
    return [r for r in runs if r[2] > r[1]]
