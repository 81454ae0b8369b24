"""Monte Carlo samples of the tolerances at speed: the distribution of the forces (THEORY §9.7).

The steady state (THEORY §9.2) is linear in the lift, and to first order so is every
sample of the tolerances: its lift is S + Σ_j g_j(θ) x_j with the sensitivities g_j of
THEORY §3 (ΔS and ΔA per unit deviation of column j) and the sample's deviations x_j. So
the train force of a sample is Q_nom + Σ_j x_j Q_j, with Q_j the response to column j
alone, and a whole study is one matrix product per chunk of samples. The normal force is
taken with the nominal ∂S/∂n (first order too).

:func:`column_responses` prepares the responses of the columns (from any sensitivity
matrices on the dynamics grid: the tolerancing's, with its profile process, or
:func:`tolerance_columns` for the design's own tolerances), :func:`sample_dynamics` runs
the rows of a sample matrix through them: peak and minimum contact force, residual
vibration, and the yield against a force or jump-margin spec.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from camtol.design.cam_design import CamDesign
from camtol.dynamics.lift import CamLift, nominal_lift
from camtol.dynamics.steady import check_rpm, rpm_to_rad_s, steady_state, transfer
from camtol.dynamics.stress import cam_contacts
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = [
    "ColumnResponses",
    "DynamicsSamples",
    "column_responses",
    "sample_dynamics",
    "tolerance_columns",
]

#: Samples per chunk of :func:`sample_dynamics` (bounds the memory of one product).
CHUNK_SAMPLES = 256


@dataclass(frozen=True)
class ColumnResponses:
    """Nominal contact force and the force per unit deviation of each sampled column.

    Attributes
    ----------
    labels : tuple of str
        Column labels (tolerance keys, process columns).
    rpm : float
        Cam speed. [rpm]
    nominal_force_n : ndarray (N,)
        Normal contact force of the nominal cam. [N]
    force_n : ndarray (C, N)
        Normal force per unit deviation of each column. [N per mm, or per rad]
    dwell_index : tuple of ndarray
        Grid indices of each dwell.
    nominal_w, nominal_w_rate : tuple of ndarray
        Nominal deviation from the static deflection w and its time rate per dwell.
        [mm or rad, per s]
    w, w_rate : tuple of ndarray (C, n_dwell)
        The same per unit deviation of each column.
    natural_frequency_rad_s : float or None
        ω_n (None: rigid train, no vibration). [rad/s]
    damping_ratio : float
        ζ. [-]
    margin_rpm : float or None
        The speed of a jump-margin check. [rpm]
    margin_nominal_force_n, margin_force_n : ndarray or None
        Nominal force and column forces at that speed. [N]
    """

    labels: tuple[str, ...]
    rpm: float
    nominal_force_n: FloatArray
    force_n: FloatArray
    dwell_index: tuple[np.ndarray, ...]
    nominal_w: tuple[FloatArray, ...]
    nominal_w_rate: tuple[FloatArray, ...]
    w: tuple[FloatArray, ...]
    w_rate: tuple[FloatArray, ...]
    natural_frequency_rad_s: float | None
    damping_ratio: float
    margin_rpm: float | None = None
    margin_nominal_force_n: FloatArray | None = None
    margin_force_n: FloatArray | None = None


@dataclass(frozen=True)
class DynamicsSamples:
    """Per-sample dynamics of a Monte Carlo study (THEORY §9.7).

    Attributes
    ----------
    peak_force_n, min_force_n : ndarray (samples,)
        Largest and smallest normal contact force of each sample. [N]
    residual_vibration : ndarray (samples,) or None
        Largest residual vibration over the dwells (None: no dwell). [mm, or rad]
    margin_min_force_n : ndarray or None
        Smallest contact force at the jump-margin speed. [N]
    passed : ndarray of bool
        Whether each sample meets every spec given.
    """

    peak_force_n: FloatArray
    min_force_n: FloatArray
    residual_vibration: FloatArray | None
    margin_min_force_n: FloatArray | None
    passed: np.ndarray

    @property
    def yield_fraction(self) -> float:
        """Fraction of samples meeting the specs. [-]"""
        return float(np.mean(self.passed)) if self.passed.size else math.nan


def tolerance_columns(
    design: CamDesign, step_deg: float
) -> tuple[tuple[str, ...], FloatArray, FloatArray, tuple[float, ...]]:
    """Sensitivities of ΔS and ΔA to each toleranced source on the dynamics grid (THEORY §3).

    Parameters
    ----------
    design : CamDesign
        A single-cam design with tolerances.
    step_deg : float
        Grid step. [deg]

    Returns
    -------
    labels : tuple of str
        Tolerance keys.
    lift, acceleration : ndarray (N, C)
        ΔS and ΔA per unit deviation. [per mm or per rad]
    deviations : tuple of float
        Each source's resolved deviation Δ (THEORY §3.6). [mm, or rad]
    """
    from camtol.analysis.errors import error_analysis
    from camtol.analysis.result import max_radius_mm
    from camtol.design.cam_design import ResolvedTolerance

    tols = design.resolve_tolerances(max_radius_mm(design))
    if not tols:
        raise DesignError(f"design {design.name!r} has no [tolerances]: nothing to sample")
    unit = tuple(ResolvedTolerance(t.key, 1.0, t.unit, "unit") for t in tols)
    theta = nominal_lift(design, step_deg).theta_rad
    err = error_analysis(design, unit, theta)
    labels = tuple(t.key for t in tols)
    lift = np.column_stack([err.sources[k].delta_lift for k in labels])
    acc = np.column_stack([err.sources[k].delta_acceleration for k in labels])
    return labels, lift, acc, tuple(abs(t.deviation) for t in tols)


def _responses(
    train: FollowerTrain, lift: CamLift, omega: float, ds: FloatArray, da: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Q, e, de/dθ per unit column (columns along axis 0), the nominal excluded."""
    f = train.spring_rate * ds.T + (train.mass * omega * omega) * da.T  # (C, N)
    if train.rigid:
        zero = np.zeros_like(f)
        return f, zero, zero
    n = lift.angles
    half = n // 2
    g, d = transfer(train, omega, half + 1)
    fh = sfft.rfft(f, axis=1)
    if n % 2 == 0:
        fh[:, half] = 0.0
    q = sfft.irfft(g * fh, n, axis=1)
    eh = -fh / d
    e = sfft.irfft(eh, n, axis=1)
    de = sfft.irfft(1j * np.arange(half + 1) * eh, n, axis=1)
    return q, e, de


def column_responses(
    design: CamDesign,
    train: FollowerTrain,
    rpm: float,
    labels: Sequence[str],
    lift_sensitivity: FloatArray,
    acceleration_sensitivity: FloatArray,
    *,
    step_deg: float,
    jump_margin: float | None = None,
) -> ColumnResponses:
    """Prepare the nominal force and the force per unit deviation of each column.

    Parameters
    ----------
    design : CamDesign
        A single-cam, force-closed design.
    train : FollowerTrain
        Its train.
    rpm : float
        Cam speed. [rpm]
    labels : sequence of str
        Column labels.
    lift_sensitivity, acceleration_sensitivity : ndarray (N, C)
        ΔS and ΔA per unit deviation of each column on the grid θ_j = 2πj/N of
        ``step_deg`` (e.g. :func:`tolerance_columns`, or the tolerancing's
        ``sensitivity_matrices`` on that grid). [per mm or rad]
    step_deg : float
        Grid step. [deg]
    jump_margin : float, optional
        Also prepare the forces at ``jump_margin`` × ``rpm`` (> 1). [-]

    Returns
    -------
    ColumnResponses

    Raises
    ------
    DesignError
        A pair (form-closed: its forces need both cams), matrices of the wrong shape, a
        margin ≤ 1, or what :func:`~camtol.dynamics.steady.steady_state` refuses.
    """
    if train.form_closed or len(design.cams()) > 1:
        raise DesignError("Monte Carlo dynamics take a single force-closed cam, not a pair")
    rpm = check_rpm(rpm)
    lift = nominal_lift(design, step_deg)
    ds = np.asarray(lift_sensitivity, dtype=float)
    da = np.asarray(acceleration_sensitivity, dtype=float)
    n = lift.angles
    if ds.ndim != 2 or ds.shape != da.shape or ds.shape[0] != n or ds.shape[1] != len(labels):
        raise DesignError(
            f"sensitivity matrices of shape {ds.shape} and {da.shape}: need ({n},"
            f" {len(labels)}) on the {step_deg:g}° grid, one column per label"
        )
    if jump_margin is not None and not (math.isfinite(jump_margin) and jump_margin > 1.0):
        raise DesignError(f"--jump-margin={jump_margin!r} is not allowed; give a number > 1")

    def forces(speed: float) -> tuple[FloatArray, ...]:
        steady = steady_state(train, lift, speed)
        (contact,) = cam_contacts(design, lift, train, steady.train_force)
        scale = np.abs(contact.normal_factor) * train.force_to_newton
        q, e, de = _responses(train, lift, rpm_to_rad_s(speed), ds, da)
        nominal = (contact.normal_force_n, q * scale)
        return (*nominal, steady.dynamic_error, e, de, steady.dynamic_error_rate)

    nom, cols, e0, e, de, de0 = forces(rpm)
    omega = rpm_to_rad_s(rpm)
    k = (train.stiffness or 0.0) + train.spring_rate
    idx, w0, wr0, w, wr = [], [], [], [], []
    h = 2.0 * math.pi / n
    for a, b in lift.dwells_rad:
        i = np.arange(int(math.ceil(a / h - 1e-9)), int(math.floor(b / h + 1e-9)) + 1) % n
        idx.append(i)
        if train.rigid:
            w0.append(np.zeros(i.size))
            wr0.append(np.zeros(i.size))
            w.append(np.zeros((ds.shape[1], i.size)))
            wr.append(np.zeros((ds.shape[1], i.size)))
            continue
        s, v = lift.lift[i], lift.velocity[i]
        w0.append(e0[i] + (train.spring_rate * s + train.preload) / k)
        wr0.append(omega * (de0[i] + train.spring_rate * v / k))
        w.append(e[:, i] + train.spring_rate * ds[i].T / k)
        wr.append(omega * de[:, i])
    margin_nom = margin_cols = None
    margin_rpm = None
    if jump_margin is not None:
        margin_rpm = rpm * jump_margin
        margin_nom, margin_cols, *_ = forces(margin_rpm)
    return ColumnResponses(
        labels=tuple(labels),
        rpm=rpm,
        nominal_force_n=nom,
        force_n=cols,
        dwell_index=tuple(idx),
        nominal_w=tuple(w0),
        nominal_w_rate=tuple(wr0),
        w=tuple(w),
        w_rate=tuple(wr),
        natural_frequency_rad_s=train.natural_frequency_rad_s,
        damping_ratio=train.damping_ratio,
        margin_rpm=margin_rpm,
        margin_nominal_force_n=margin_nom,
        margin_force_n=margin_cols,
    )


def sample_dynamics(
    responses: ColumnResponses,
    rows: FloatArray,
    *,
    force_min_spec_n: float | None = None,
    force_max_spec_n: float | None = None,
) -> DynamicsSamples:
    """Run the rows of a sample matrix through the column responses (THEORY §9.7).

    Parameters
    ----------
    responses : ColumnResponses
        From :func:`column_responses`.
    rows : ndarray (samples, C)
        Each sample's deviations, one column per label. [mm, or rad]
    force_min_spec_n : float, optional
        A sample passes only if its contact force never falls below this. [N]
    force_max_spec_n : float, optional
        A sample passes only if its contact force never exceeds this. [N]

    Returns
    -------
    DynamicsSamples
        With a jump margin prepared, a sample also passes only if its contact force stays
        positive at the margin speed.
    """
    x = np.asarray(rows, dtype=float)
    if x.ndim != 2 or x.shape[1] != len(responses.labels):
        raise DesignError(
            f"rows of shape {x.shape}: need (samples, {len(responses.labels)}), one column"
            f" per label {', '.join(responses.labels)}"
        )
    samples = x.shape[0]
    peak = np.empty(samples)
    low = np.empty(samples)
    margin = np.empty(samples) if responses.margin_force_n is not None else None
    resid = np.zeros(samples) if responses.dwell_index else None
    wn, z = responses.natural_frequency_rad_s, responses.damping_ratio
    for c0 in range(0, samples, CHUNK_SAMPLES):
        xc = x[c0 : c0 + CHUNK_SAMPLES]
        f = xc @ responses.force_n
        f += responses.nominal_force_n
        peak[c0 : c0 + xc.shape[0]] = f.max(axis=1)
        low[c0 : c0 + xc.shape[0]] = f.min(axis=1)
        if margin is not None:
            assert responses.margin_force_n is not None
            assert responses.margin_nominal_force_n is not None
            fm = xc @ responses.margin_force_n
            fm += responses.margin_nominal_force_n
            margin[c0 : c0 + xc.shape[0]] = fm.min(axis=1)
        if resid is not None and wn is not None:
            best = np.zeros(xc.shape[0])
            for w0, wr0, w, wr in zip(
                responses.nominal_w,
                responses.nominal_w_rate,
                responses.w,
                responses.w_rate,
                strict=True,
            ):
                ww = xc @ w + w0
                rate = xc @ wr + wr0
                if z < 1.0:
                    amp = np.hypot(ww, (rate + z * wn * ww) / (wn * math.sqrt(1.0 - z * z)))
                else:
                    amp = np.hypot(ww, rate / wn)
                best = np.maximum(best, amp.max(axis=1))
            resid[c0 : c0 + xc.shape[0]] = best
    passed = np.ones(samples, dtype=bool)
    if force_min_spec_n is not None:
        passed &= low >= force_min_spec_n
    if force_max_spec_n is not None:
        passed &= peak <= force_max_spec_n
    if margin is not None:
        passed &= margin > 0.0
    return DynamicsSamples(peak, low, resid, margin, passed)
