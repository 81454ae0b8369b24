"""Shewhart control charts of a lot's per-part values: I-MR, X̄-R and X̄-S.

* ``imr``: individuals x_i with CL = x̄, limits x̄ ± 3 MR̄/d2(2) (= x̄ ± 2.660 MR̄), and the
  moving range MR_i = |x_i − x_{i−1}| with CL = MR̄, UCL = D4(2) MR̄, LCL = D3(2) MR̄ = 0;
* ``xbar-r``: means of consecutive subgroups of N parts, X̿ ± A2(N) R̄; ranges D3 R̄ … D4 R̄;
* ``xbar-s``: X̿ ± A3(N) S̄; standard deviations B3 S̄ … B4 S̄.

Subgroups are consecutive parts in production order; the parts after the last complete
subgroup are left out of the chart (said in :attr:`ControlChart.left_out`). Limits come
from the data or are frozen from a reference lot (:func:`chart_limits` on it, then
:func:`control_chart` with ``limits=``). Constants: :mod:`camtol.spc.constants`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from camtol.exceptions import RecordError
from camtol.spc.constants import A2, A3, B3, B4, D3, D4, d2

__all__ = ["CHARTS", "ChartLimits", "ControlChart", "chart_limits", "control_chart"]

FloatArray = npt.NDArray[np.float64]
CHARTS = ("imr", "xbar-r", "xbar-s")


@dataclass(frozen=True)
class ChartLimits:
    """Centre lines and 3σ limits of a chart pair (location and dispersion).

    Attributes
    ----------
    kind : {"imr", "xbar-r", "xbar-s"}
    subgroup : int
        Subgroup size (1 for individuals).
    center, lcl, ucl : float
        Location chart (individuals or subgroup means).
    dispersion_center, dispersion_lcl, dispersion_ucl : float
        Moving range, range or standard deviation chart.
    sigma : float
        σ of one plotted location point (the zones of the run rules are ±1σ, ±2σ of it).
    """

    kind: str
    subgroup: int
    center: float
    lcl: float
    ucl: float
    dispersion_center: float
    dispersion_lcl: float
    dispersion_ucl: float
    sigma: float


@dataclass(frozen=True)
class ControlChart:
    """A chart pair over a lot: its points, the limits and which parts each point is.

    Attributes
    ----------
    limits : ChartLimits
    frozen : bool
        Limits from a reference lot, not from these data.
    points, dispersion : ndarray
        Plotted location and dispersion points (the first moving range is NaN).
    members : tuple of tuple of int
        Indices into the lot's values of the parts each point stands for.
    left_out : int
        Parts after the last complete subgroup, not charted.
    """

    limits: ChartLimits
    frozen: bool
    points: FloatArray
    dispersion: FloatArray
    members: tuple[tuple[int, ...], ...]
    left_out: int


def _check(n_values: int, kind: str, subgroup: int) -> None:
    if kind not in CHARTS:
        raise RecordError(f"--chart={kind!r}: allowed {', '.join(CHARTS)}")
    if kind == "imr" and subgroup != 1:
        raise RecordError(f"--chart=imr charts individuals: leave out --subgroup={subgroup}")
    if kind != "imr" and subgroup < 2:
        raise RecordError(f"--chart={kind} needs --subgroup N with N ≥ 2; got {subgroup}")
    need = 2 if kind == "imr" else subgroup
    if n_values < need:
        what = "individuals" if kind == "imr" else f"a subgroup of {subgroup}"
        raise RecordError(
            f"--subgroup={subgroup}: larger than the lot ({n_values} parts)"
            if kind != "imr"
            else f"a control chart of {what} needs at least 2 parts; the lot has {n_values}"
        )


def _groups(x: FloatArray, subgroup: int) -> FloatArray:
    k = x.size // subgroup
    return x[: k * subgroup].reshape(k, subgroup)


def _dispersion(x: FloatArray, kind: str, subgroup: int) -> FloatArray:
    if kind == "imr":
        return np.concatenate([[math.nan], np.abs(np.diff(x))])
    g = _groups(x, subgroup)
    out = np.ptp(g, axis=1) if kind == "xbar-r" else g.std(axis=1, ddof=1)
    return np.asarray(out, dtype=np.float64)


def chart_limits(values: npt.ArrayLike, kind: str = "imr", subgroup: int = 1) -> ChartLimits:
    """Limits of a chart pair computed from values in production order.

    Parameters
    ----------
    values : array_like
        One value per part.
    kind : {"imr", "xbar-r", "xbar-s"}
    subgroup : int
        Subgroup size N (1 for ``imr``).

    Returns
    -------
    ChartLimits

    Raises
    ------
    RecordError
        An unknown chart, a subgroup size that does not fit it or is larger than the lot.
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    _check(x.size, kind, subgroup)
    disp = _dispersion(x, kind, subgroup)
    if kind == "imr":
        mr = float(np.nanmean(disp))
        sigma = mr / d2(2)
        c = float(x.mean())
        return ChartLimits(
            kind, 1, c, c - 3 * sigma, c + 3 * sigma, mr, D3(2) * mr, D4(2) * mr, sigma
        )
    g = _groups(x, subgroup)
    c = float(g.mean())
    bar = float(disp.mean())
    a, lo, hi = (
        (A2(subgroup), D3(subgroup), D4(subgroup))
        if kind == "xbar-r"
        else (A3(subgroup), B3(subgroup), B4(subgroup))
    )
    return ChartLimits(
        kind, subgroup, c, c - a * bar, c + a * bar, bar, lo * bar, hi * bar, a * bar / 3.0
    )


def control_chart(
    values: npt.ArrayLike,
    kind: str = "imr",
    subgroup: int = 1,
    *,
    limits: ChartLimits | None = None,
) -> ControlChart:
    """Chart the values, with their own limits or frozen ones.

    Parameters
    ----------
    values : array_like
        One value per part, in production order.
    kind, subgroup :
        As :func:`chart_limits`.
    limits : ChartLimits, optional
        Frozen limits (from a reference lot); they must be of the same chart and subgroup.

    Returns
    -------
    ControlChart
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    _check(x.size, kind, subgroup)
    if limits is not None and (limits.kind, limits.subgroup) != (kind, subgroup):
        raise RecordError(
            f"--limits-from: the reference limits are of a {limits.kind} chart with subgroup"
            f" {limits.subgroup}, not {kind} with subgroup {subgroup}"
        )
    lim = limits if limits is not None else chart_limits(x, kind, subgroup)
    members: tuple[tuple[int, ...], ...]
    if kind == "imr":
        points = x.copy()
        members = tuple((i,) for i in range(x.size))
        left = 0
    else:
        g = _groups(x, subgroup)
        points = g.mean(axis=1)
        members = tuple(tuple(range(i * subgroup, (i + 1) * subgroup)) for i in range(len(g)))
        left = x.size - g.size
    return ControlChart(
        lim, limits is not None, points, _dispersion(x, kind, subgroup), members, left
    )


def within_sigma(values: npt.ArrayLike, subgroup: int = 1) -> tuple[float, float, str]:
    """σ_within for the capability indices, its (effective) degrees of freedom, the method.

    Individuals: MR̄ / d2(2) with :func:`camtol.spc.capability.moving_range_dof`; subgroups
    of N: the pooled σ of the complete subgroups (:func:`camtol.spc.capability.pooled_sigma`).
    """
    from camtol.spc.capability import moving_range_dof, pooled_sigma

    x = np.asarray(values, dtype=np.float64).ravel()
    if subgroup <= 1:
        if x.size < 2:
            return math.nan, 0.0, "moving range"
        return float(np.abs(np.diff(x)).mean()) / d2(2), moving_range_dof(x.size), "moving range"
    g = _groups(x, subgroup)
    sigma, dof = pooled_sigma(list(g))
    return sigma, dof, "pooled subgroups"
