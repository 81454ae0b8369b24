"""Statistics of a production lot from its inspection records (pure numpy, scipy for the CI).

A lot is a set of parts of one design inspected on the same cam (A, B or a single cam).
Each part contributes its radial deviation curve Δr(θ) on a uniform grid over [0°, 360°)
(THEORY §4.2 for the fixture's Δr_est; the CMM's Δr(θ) likewise). From them:

- per cam angle: mean, sample standard deviation σ (ddof = 1), max and min envelopes;
- process capability of the per-part extreme deviations against the radial tolerance
  [lower, upper] (see :class:`LotStatistics` for the exact definitions);
- the fraction of failing parts with an exact (Clopper-Pearson) binomial confidence interval;
- a trend: the least-squares slope of each part's maximum deviation against its position in
  the production sequence (tool wear shows as a steady positive slope).

The storage of records is an I/O edge (:mod:`camtol.records.store`); this module only
computes on arrays.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from camtol.exceptions import RecordError
from camtol.jet import FloatArray
from camtol.spc.binomial import clopper_pearson

__all__ = [
    "MAX_GAP_STEPS",
    "LotStatistics",
    "deviation_on_grid",
    "largest_polar_gap",
    "lot_statistics",
    "resample_periodic",
    "scan_on_grid",
]

#: A scan is resampled onto a grid of step h only when no two neighbouring points (by
#: polar angle, across 0°/360° too) are more than this many grid steps apart: linear
#: interpolation then fills at most 4 grid values between two measured points.
MAX_GAP_STEPS = 5.0


@dataclass(frozen=True)
class LotStatistics:
    """Statistics of the deviation curves of the parts of a lot.

    Attributes
    ----------
    n_parts : int
        Number of parts (records).
    theta_deg : ndarray
        Uniform cam-angle grid over [0, 360), shape (n,). [deg]
    mean_um, std_um : ndarray
        Per-angle mean and sample standard deviation (ddof = 1; NaN for one part) of Δr. [µm]
    max_um, min_um : ndarray
        Per-angle envelopes of Δr over the parts. [µm]
    part_max_um, part_min_um : ndarray
        Each part's maximum and minimum deviation over θ, in the order given. [µm]
    tolerance_um : tuple of float
        Radial tolerance (lower LSL, upper USL). [µm]
    pp : float
        (USL − LSL) / (6 s_max), s_max the sample σ of ``part_max_um`` (NaN if undefined).
        Performance indices (overall σ, ISO 22514-2), not Cp/Cpk: the within-σ indices,
        their intervals and the control chart are :mod:`camtol.spc`'s
        (:func:`camtol.records.lot_summary.summarise_lot`).
    ppu : float
        (USL − mean(part_max)) / (3 s_max): the upper side, decided by the largest deviation.
    ppl : float
        (mean(part_min) − LSL) / (3 s_min): the lower side, decided by the smallest deviation.
    ppk : float
        min(ppu, ppl).
    n_failing : int
        Parts whose verdict is a failure.
    fraction_failing : float
        n_failing / n_parts.
    fraction_failing_ci : tuple of float
        Exact (Clopper-Pearson) two-sided confidence interval of the failing fraction.
    confidence : float
        Confidence level of that interval (e.g. 0.95).
    trend_um_per_part : float
        Least-squares slope of ``part_max_um`` against ``sequence`` (NaN for < 2 distinct
        positions). [µm per part]
    trend_stderr_um_per_part : float
        Its standard error (NaN for < 3 parts). [µm per part]
    sequence : ndarray
        Position of each part in the production sequence used for the trend.
    """

    n_parts: int
    theta_deg: FloatArray
    mean_um: FloatArray
    std_um: FloatArray
    max_um: FloatArray
    min_um: FloatArray
    part_max_um: FloatArray
    part_min_um: FloatArray
    tolerance_um: tuple[float, float]
    pp: float
    ppu: float
    ppl: float
    ppk: float
    n_failing: int
    fraction_failing: float
    fraction_failing_ci: tuple[float, float]
    confidence: float
    trend_um_per_part: float
    trend_stderr_um_per_part: float
    sequence: FloatArray


def resample_periodic(values: npt.NDArray[np.floating[Any]], n: int) -> FloatArray:
    """Resample a periodic curve on a uniform grid of ``len(values)`` points onto ``n`` points.

    Linear interpolation with wrap-around at 360°; both grids start at 0°.

    Parameters
    ----------
    values : ndarray
        Curve on θ_i = 360° i / m, i = 0 … m − 1.
    n : int
        Number of points of the target grid.

    Returns
    -------
    ndarray
        The curve at θ_j = 360° j / n, shape (n,).
    """
    v = np.asarray(values, dtype=np.float64)
    m = v.size
    if m == n:
        return v.copy()
    src = np.arange(m + 1) * (360.0 / m)
    dst = np.arange(n) * (360.0 / n)
    return np.asarray(np.interp(dst, src, np.append(v, v[0])))


def deviation_on_grid(theta_deg: npt.ArrayLike, dr_um: npt.ArrayLike, n_points: int) -> FloatArray:
    """Scattered deviations (e.g. CMM points) on the uniform grid θ_j = 360° j / n.

    Periodic linear interpolation between the points sorted by angle, so that a scan can be
    stored as a record and compared across parts.

    Parameters
    ----------
    theta_deg : array_like
        Polar angles of the points, any order, any range (taken modulo 360°). [deg]
    dr_um : array_like
        Deviations at those angles. [µm]
    n_points : int
        Points of the target grid (≥ 1).

    Returns
    -------
    ndarray
        Deviation at θ_j, shape (n_points,). [µm]
    """
    t = np.asarray(theta_deg, dtype=np.float64)
    v = np.asarray(dr_um, dtype=np.float64)
    if t.shape != v.shape or t.ndim != 1 or t.size < 2 or n_points < 1:
        raise RecordError(
            f"deviation_on_grid: need matching 1-D angles and deviations (≥ 2 points) and"
            f" n_points ≥ 1; got {t.shape}, {v.shape}, n_points={n_points}"
        )
    grid = np.arange(n_points) * (360.0 / n_points)
    return np.asarray(np.interp(grid, np.mod(t, 360.0), v, period=360.0))


def largest_polar_gap(theta_deg: npt.ArrayLike) -> tuple[float, float]:
    """Largest angular gap between neighbouring polar angles, across 0°/360° too.

    Parameters
    ----------
    theta_deg : array_like
        Polar angles, any order, any range (taken modulo 360°); at least one. [deg]

    Returns
    -------
    (float, float)
        The gap and the angle where it starts, in [0, 360). [deg, deg]
    """
    phi = np.sort(np.mod(np.asarray(theta_deg, dtype=np.float64).ravel(), 360.0))
    if phi.size == 0:
        return 360.0, 0.0
    gaps = np.diff(np.append(phi, phi[0] + 360.0))
    k = int(np.argmax(gaps))
    return float(gaps[k]), float(phi[k])


def scan_on_grid(
    theta_deg: npt.ArrayLike,
    dr_um: npt.ArrayLike,
    n_points: int,
    *,
    source: str = "scan",
    max_gap_steps: float = MAX_GAP_STEPS,
) -> FloatArray:
    """Put a CMM scan's radial deviations on the record grid θ_j = 360° j / n, or refuse.

    The honest-resampling rule: the largest gap between neighbouring measured polar angles
    (periodic) must not exceed ``max_gap_steps`` grid steps 360°/n; the deviations are then
    interpolated linearly and periodically (:func:`deviation_on_grid`), so that every grid
    value lies within that many steps of a measured point on either side.

    Parameters
    ----------
    theta_deg : array_like
        Polar angles of the measured points in the cam frame (outliers removed). [deg]
    dr_um : array_like
        Their radial deviations Δr. [µm]
    n_points : int
        Points n of the grid.
    source : str, optional
        The scan's name, for the message.
    max_gap_steps : float, optional
        Largest gap allowed, in grid steps.

    Returns
    -------
    ndarray
        Δr at θ_j, shape (n_points,). [µm]

    Raises
    ------
    RecordError
        A gap wider than ``max_gap_steps`` grid steps (naming its angles and the step that
        would allow it).
    """
    step = 360.0 / n_points if n_points >= 1 else math.inf
    gap, start = largest_polar_gap(theta_deg)
    if not gap <= max_gap_steps * step:
        raise RecordError(
            f"{source}: cannot record the scan on a {step:g}° grid: no point between polar"
            f" angles {start:.2f}° and {math.fmod(start + gap, 360.0):.2f}° (a gap of"
            f" {gap:.3g}°, at most {max_gap_steps:g} grid steps = {max_gap_steps * step:.3g}°"
            f" allowed); give a coarser --step (≥ {gap / max_gap_steps:.3g}°, dividing 360)"
            " or a denser scan"
        )
    return deviation_on_grid(theta_deg, dr_um, n_points)


def _sample_std(x: FloatArray) -> float:
    return float(np.std(x, ddof=1)) if x.size > 1 else math.nan


def _ratio(num: float, den: float) -> float:
    return num / den if den > 0.0 and math.isfinite(den) else math.nan


def lot_statistics(
    curves_um: Sequence[npt.NDArray[np.floating[Any]]],
    tolerance_um: tuple[float, float],
    failed: Sequence[bool],
    *,
    sequence: Sequence[float] | None = None,
    confidence: float = 0.95,
) -> LotStatistics:
    """Per-angle statistics, capability, failing fraction and trend of a lot.

    Parameters
    ----------
    curves_um : sequence of ndarray
        One deviation curve Δr(θ) per part, each on a uniform grid over [0°, 360°) starting
        at 0°; grids of different sizes are resampled (periodic linear interpolation) onto
        the finest. [µm]
    tolerance_um : tuple of float
        Radial tolerance (lower, upper) with lower < upper. [µm]
    failed : sequence of bool
        Per part: True when its inspection verdict was a failure.
    sequence : sequence of float, optional
        Position of each part in production (e.g. its serial number); by default the order
        given, 0, 1, 2, ...
    confidence : float, optional
        Confidence level of the failing fraction's interval, in (0, 1).

    Returns
    -------
    LotStatistics

    Raises
    ------
    RecordError
        No parts, lengths that disagree, a bad tolerance or confidence level.
    """
    n_parts = len(curves_um)
    if n_parts == 0:
        raise RecordError("lot statistics need at least one record; none matched")
    if len(failed) != n_parts:
        raise RecordError(f"failed has {len(failed)} entries for {n_parts} parts")
    lo, hi = (float(tolerance_um[0]), float(tolerance_um[1]))
    if not lo < hi:
        raise RecordError(f"tolerance_um={tolerance_um!r}: need lower < upper")
    if not 0.0 < confidence < 1.0:
        raise RecordError(f"confidence={confidence!r}: allowed 0 < confidence < 1")
    n = max(np.asarray(c).size for c in curves_um)
    if n < 1:
        raise RecordError("lot statistics need curves with at least one point")
    part_max, part_min, max_um, min_um, mean, std = _pooled_curves(curves_um, n)
    seq = (
        np.arange(n_parts, dtype=np.float64)
        if sequence is None
        else np.asarray(sequence, dtype=np.float64)
    )
    if seq.shape != (n_parts,):
        raise RecordError(f"sequence has {seq.size} entries for {n_parts} parts")

    s_max, s_min = _sample_std(part_max), _sample_std(part_min)
    pp = _ratio(hi - lo, 6.0 * s_max)
    ppu = _ratio(hi - float(part_max.mean()), 3.0 * s_max)
    ppl = _ratio(float(part_min.mean()) - lo, 3.0 * s_min)
    ppk = min(ppu, ppl) if not (math.isnan(ppu) or math.isnan(ppl)) else math.nan

    k = int(np.count_nonzero(np.asarray(failed, dtype=bool)))
    slope, stderr = _trend(seq, part_max)
    return LotStatistics(
        n_parts=n_parts,
        theta_deg=np.asarray(np.arange(n) * (360.0 / n), dtype=np.float64),
        mean_um=mean,
        std_um=std,
        max_um=max_um,
        min_um=min_um,
        part_max_um=part_max,
        part_min_um=part_min,
        tolerance_um=(lo, hi),
        pp=pp,
        ppu=ppu,
        ppl=ppl,
        ppk=ppk,
        n_failing=k,
        fraction_failing=k / n_parts,
        fraction_failing_ci=clopper_pearson(k, n_parts, confidence),
        confidence=confidence,
        trend_um_per_part=slope,
        trend_stderr_um_per_part=stderr,
        sequence=seq,
    )


def _pooled_curves(
    curves_um: Sequence[npt.NDArray[np.floating[Any]]], n: int, block: int = 32
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Each part's max and min, and each angle's max, min, mean and sample σ (ddof 1).

    One pass over the parts in blocks small enough to stay in cache (no parts × angles
    table: 10,000 curves of 3,600 points would be 288 MB to allocate and read six times),
    each block's mean and sum of squares merged into the running ones by Chan, Golub and
    LeVeque's pairwise update, as stable as the two-pass formula. σ is NaN for one part.
    [µm]
    """
    n_parts = len(curves_um)
    buf = np.empty((min(block, n_parts), n))
    part_max, part_min = np.empty(n_parts), np.empty(n_parts)
    max_um, min_um = np.full(n, -np.inf), np.full(n, np.inf)
    mean, m2 = np.zeros(n), np.zeros(n)
    for k in range(0, n_parts, block):
        chunk = curves_um[k : k + block]
        b = buf[: len(chunk)]
        for i, c in enumerate(chunk):
            c = np.asarray(c)
            b[i] = c if c.size == n else resample_periodic(c.astype(np.float64), n)
        b.max(axis=1, out=part_max[k : k + b.shape[0]])
        b.min(axis=1, out=part_min[k : k + b.shape[0]])
        np.maximum(max_um, b.max(axis=0), out=max_um)
        np.minimum(min_um, b.min(axis=0), out=min_um)
        b_mean = b.mean(axis=0)
        d = b - b_mean
        delta = b_mean - mean
        seen, total = k, k + b.shape[0]
        mean += delta * (b.shape[0] / total)
        m2 += np.einsum("ij,ij->j", d, d) + delta * delta * (seen * b.shape[0] / total)
    std = np.sqrt(m2 / (n_parts - 1)) if n_parts > 1 else np.full(n, math.nan)
    return part_max, part_min, max_um, min_um, mean, np.asarray(std)


def _trend(x: FloatArray, y: FloatArray) -> tuple[float, float]:
    """Least-squares slope of y on x and its standard error (NaN where undefined)."""
    dx = x - x.mean()
    sxx = float(dx @ dx)
    if sxx <= 0.0:
        return math.nan, math.nan
    slope = float(dx @ (y - y.mean())) / sxx
    if x.size < 3:
        return slope, math.nan
    resid = y - y.mean() - slope * dx
    return slope, math.sqrt(float(resid @ resid) / (x.size - 2) / sxx)
