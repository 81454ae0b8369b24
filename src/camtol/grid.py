"""The cam-angle grids camtol evaluates on, and the one rule that validates them.

Every command that takes an angular step (``--step``, ``--table-step``, ``--read-step``,
``--cut-step``) and every reader of a tabulated function of the cam angle goes through
here, so the same step is accepted or refused everywhere with the same message.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.exceptions import DesignError, InputFileError

__all__ = [
    "MAX_GRID_POINTS",
    "check_step",
    "ordered_segment_runs",
    "run_bounds",
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
    theta_deg: ArrayLike, *, source: str, name: str = "theta_deg", max_points: int = MAX_GRID_POINTS
) -> tuple[float, int]:
    """Check that tabulated cam angles are one revolution on a uniform grid.

    The angles must start at 0°, increase by one constant step that divides 360°, and end
    one step before 360° (a closing row at 360° repeats 0° and is dropped by the caller).

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

    Returns
    -------
    step_deg, n : float, int
        The step [deg] and the number of rows (360 / step).

    Raises
    ------
    InputFileError
        Naming the first row where the table has a gap, a repeat or an unequal step.
    """
    t = np.asarray(theta_deg, dtype=float)
    if t.size < 3:
        raise InputFileError(f"{source}: column {name} has {t.size} rows; at least 3 are needed")
    if abs(t[0]) > 1e-9:
        raise InputFileError(f"{source}: column {name} must start at 0°, found {t[0]:g}°")
    step = 360.0 / t.size
    d = np.diff(t)
    bad = np.abs(d - step) > 1e-6 * max(step, 1e-3)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise InputFileError(
            f"{source}: column {name} must be one revolution in equal steps of {step:g}°"
            f" ({t.size} rows from 0° to {360.0 - step:g}°); rows {i + 1}-{i + 2} go from"
            f" {t[i]:g}° to {t[i + 1]:g}° (a gap, repeat or unequal step)"
        )
    try:
        check_step(step, name=f"{source}: step of {name}", max_points=max_points)
    except DesignError as exc:
        raise InputFileError(str(exc)) from None
    return step, t.size


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
