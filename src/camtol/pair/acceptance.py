"""Acceptance of inspected conjugate cams: bands, verdicts, failing intervals (THEORY §4.3).

Inspecting cam A with the master cam B (and B with master A) on the fixture, Δf must lie
between the bands Δf_A(l),est and Δf_A(u),est obtained by putting cam A's tolerance limits
into the forward variation with the master's known error ([CW11] eqs. 22-31). A cam
passes when the measured Δf_mea stays inside its band at every θ: a necessary condition.
The intervals where it leaves the band are located by bisection on the continuous
functions, to better than 0.01° regardless of the grid.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.inspection.error_functions import ErrorFunction
from camtol.jet import FloatArray
from camtol.pair.variation import ConjugateFactors, FixtureErrors, conjugate_variation

__all__ = [
    "AcceptanceBands",
    "CamVerdict",
    "acceptance_bands",
    "failing_intervals",
    "merge_intervals",
]


@dataclass(frozen=True)
class AcceptanceBands:
    """The four acceptance bands of THEORY §4.3 (CW11 eqs. 22-31). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_a_upper_um, df_a_lower_um : ndarray
        Δf_A(u),est, Δf_A(l),est: inspecting cam A with master B. [µm]
    df_b_upper_um, df_b_lower_um : ndarray
        Δf_B(u),est, Δf_B(l),est: inspecting cam B with master A. [µm]
    """

    theta_rad: FloatArray
    df_a_upper_um: FloatArray
    df_a_lower_um: FloatArray
    df_b_upper_um: FloatArray
    df_b_lower_um: FloatArray

    def band_um(self, cam: str) -> tuple[FloatArray, FloatArray]:
        """Return (upper, lower) of the band of inspected cam ``"A"`` or ``"B"``. [µm]

        Parameters
        ----------
        cam : {"A", "B"}
            The inspected cam (the other one is its master).

        Returns
        -------
        (ndarray, ndarray)
            Δf_cam(u),est and Δf_cam(l),est. [µm]

        Raises
        ------
        ValueError
            If ``cam`` is not "A" or "B".
        """
        if cam == "A":
            return self.df_a_upper_um, self.df_a_lower_um
        if cam == "B":
            return self.df_b_upper_um, self.df_b_lower_um
        raise ValueError(f"cam={cam!r} is not allowed; give 'A' or 'B'")

    def margin_um(
        self, cam: str, df_mea_um: ArrayLike, *, at: NDArray[np.intp] | None = None
    ) -> FloatArray:
        """Margin of a reading against the band of cam ``cam``: min(Δf − lower, upper − Δf).

        The one rule by which the fixture judges a cam (THEORY §4.3): it passes at θ where
        the margin is ≥ 0. ``df_mea_um`` may hold several readings (samples × angles).

        Parameters
        ----------
        cam : {"A", "B"}
            The inspected cam.
        df_mea_um : array_like
            Δf read on the fixture over the bands' grid (last axis), or at the grid
            indices ``at``. [µm]
        at : ndarray of int, optional
            Indices of the grid angles the reading is given at (default: every angle).

        Returns
        -------
        ndarray
            The margin, shaped as ``df_mea_um``. [µm]
        """
        up, lo = self.band_um(cam)
        if at is not None:
            up, lo = up[at], lo[at]
        mea = np.asarray(df_mea_um, dtype=float)
        return np.asarray(np.minimum(mea - lo, up - mea))

    @staticmethod
    def master_of(cam: str) -> str:
        """Return the master cam that inspects ``cam`` on the fixture (A's is B, B's is A).

        Parameters
        ----------
        cam : {"A", "B"}
            The inspected cam.

        Returns
        -------
        str
        """
        return "B" if cam == "A" else "A"


def acceptance_bands(
    factors: ConjugateFactors,
    tolerance_a_um: tuple[float, float],
    tolerance_b_um: tuple[float, float],
    master_a: ErrorFunction | ArrayLike,
    master_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> AcceptanceBands:
    """Compute the acceptance bands of Δf for each inspected cam (THEORY §4.3).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    tolerance_a_um, tolerance_b_um : tuple of float
        Radial tolerances (lower, upper) of cams A and B, e.g. (−22, 22). [µm]
    master_a, master_b : ErrorFunction or array_like
        Known errors of the master cams. [µm]
    errors : FixtureErrors
        Constant errors.

    Notes
    -----
    Δf_A(u),est = Δf_r(Δr_A = Δr_A(u), Δr_B = Δr_B(m),mea) + Δf_rf + Δf_l + Δf_η and
    likewise for the lower limit and for cam B with master A.
    """

    def est(ra: ErrorFunction | ArrayLike, rb: ErrorFunction | ArrayLike) -> FloatArray:
        return conjugate_variation(factors, ra, rb, errors).df_est_um

    n = factors.theta_rad.shape
    lo_a, hi_a = (np.full(n, float(v)) for v in tolerance_a_um)
    lo_b, hi_b = (np.full(n, float(v)) for v in tolerance_b_um)
    return AcceptanceBands(
        factors.theta_rad,
        est(hi_a, master_b),
        est(lo_a, master_b),
        est(master_a, hi_b),
        est(master_a, lo_b),
    )


@dataclass(frozen=True)
class CamVerdict:
    """Acceptance of one inspected cam (THEORY §4.3).

    Attributes
    ----------
    cam : str
        ``"A"`` or ``"B"``.
    passed : bool
        True when Δf_lower ≤ Δf_mea ≤ Δf_upper at every θ (a necessary condition).
    failing_intervals_deg : list of (float, float)
        Cam-angle intervals (start, end) where it fails, ends located to < 0.01°; an
        interval that wraps through 0° has end < start. [deg]
    min_margin_um : float
        Smallest margin min(Δf_mea − lower, upper − Δf_mea) over θ (< 0: fails). [µm]
    """

    cam: str
    passed: bool
    failing_intervals_deg: list[tuple[float, float]]
    min_margin_um: float


def merge_intervals(
    intervals: Sequence[tuple[float, float]], gap_deg: float
) -> list[tuple[float, float]]:
    """Join failing intervals separated by less than ``gap_deg``.

    A noisy measured record crosses a band edge many times; the exact intervals are then
    many slivers. Joining them across short gaps gives the stretches an inspector acts on.

    Parameters
    ----------
    intervals : sequence of (float, float)
        Sorted, non-overlapping cam-angle intervals. [deg]
    gap_deg : float
        Gaps shorter than this are closed. [deg]

    Returns
    -------
    list of (float, float)
        The joined intervals. [deg]
    """
    out: list[tuple[float, float]] = []
    for a, b in intervals:
        if out and a - out[-1][1] < gap_deg:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def failing_intervals(
    theta_rad: FloatArray,
    margin: Callable[[FloatArray], FloatArray],
    *,
    tol_deg: float = 1e-4,
) -> list[tuple[float, float]]:
    """Intervals of θ over a revolution where ``margin(θ) < 0``, ends refined by bisection.

    Parameters
    ----------
    theta_rad : ndarray
        Uniform grid over [0, 2π) (without the end point). [rad]
    margin : callable
        Continuous function of θ (rad) evaluated vectorised; < 0 means failing.
    tol_deg : float
        Bisection tolerance of the interval ends. [deg]

    Returns
    -------
    list of (float, float)
        (start, end) in degrees in [0, 360); a wrapping interval has end < start; the whole
        revolution is (0.0, 360.0).
    """
    theta = np.asarray(theta_rad, dtype=float)
    fail = margin(theta) < 0
    if not np.any(fail):
        return []
    if np.all(fail):
        return [(0.0, 360.0)]
    n = theta.size
    nxt = np.roll(np.arange(n), -1)
    t_next = np.where(nxt == 0, theta[0] + 2 * math.pi, theta[nxt])
    starts_i = np.flatnonzero(~fail & fail[nxt])  # pass → fail between i and i+1
    ends_i = np.flatnonzero(fail & ~fail[nxt])  # fail → pass between i and i+1

    def refine(idx: np.ndarray, fail_on_left: bool) -> FloatArray:
        lo, hi = theta[idx].copy(), t_next[idx].copy()
        tol = math.radians(tol_deg)
        while np.any(hi - lo > tol):
            mid = 0.5 * (lo + hi)
            f_mid = margin(np.mod(mid, 2 * math.pi)) < 0
            left_side = f_mid if fail_on_left else ~f_mid
            lo = np.where(left_side, mid, lo)
            hi = np.where(left_side, hi, mid)
        return np.asarray(np.mod(np.degrees(0.5 * (lo + hi)), 360.0))

    starts = refine(starts_i, fail_on_left=False)
    ends = refine(ends_i, fail_on_left=True)
    s_order, e_order = np.argsort(starts_i), np.argsort(ends_i)
    starts, ends = starts[s_order], ends[e_order]
    if ends_i.min() < starts_i.min():  # the first end belongs to an interval wrapping 0°
        ends = np.roll(ends, -1)
    return [(float(s), float(e)) for s, e in zip(starts, ends, strict=True)]
