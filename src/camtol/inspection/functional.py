"""Functional inspection: the follower motion a measured cam actually gives (THEORY §3, §5).

A profile deviation matters through the follower's motion. From a registered scan
(:class:`~camtol.inspection.deviations.CmmInspection`) the normal deviation Δn(t) along the
profile (t the profile parameter: the cam angle at which that point touches the nominal
follower) is smoothed by a stated Fourier low-pass: the least-squares Fourier series of
the points' Δn up to ``harmonics`` (default 100: wavelengths down to 3.6°; shorter
features and the probe noise are removed). The measured cam is then the nominal analytic
profile with that normal error (:class:`~camtol.contact.AnalyticShape`), and the contact
engine (THEORY §5) gives its follower motion exactly, with exact V and A of the smoothed
shape:

    ΔS(θ) = S_measured(θ) − S_design(θ),  ΔV, ΔA likewise,

beside the linear prediction of THEORY §3, ΔS_lin(θ) = (∂S/∂n)(θ) · Δn(θ), with the
mechanism's closed-form sensitivity to a normal profile error. Their difference is of
second order in Δn (tested).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol import jet
from camtol.contact import AnalyticShape, FourierError, follow
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.inspection.deviations import CamProfile, CmmInspection
from camtol.jet import FloatArray, Jet

__all__ = [
    "DEFAULT_HARMONICS",
    "FunctionalDeviation",
    "SampledFourier",
    "fourier_fit",
    "functional_deviation",
]

#: Default Fourier cut-off of the smoothing (harmonics per revolution).
DEFAULT_HARMONICS = 100

#: Largest point count fitted directly by least squares; larger scans are first
#: interpolated onto a uniform grid of the profile parameter.
_DIRECT_FIT = 20_000


def fourier_fit(t_rad: ArrayLike, values_mm: ArrayLike, harmonics: int) -> FourierError:
    """Least-squares Fourier series up to ``harmonics`` through scattered (t, value).

    Parameters
    ----------
    t_rad : array_like
        Profile parameters (any order, covering the revolution). [rad]
    values_mm : array_like
        Values at those parameters. [mm]
    harmonics : int
        Highest harmonic K (the fit has 2K + 1 coefficients).

    Returns
    -------
    FourierError
        The fitted series. [mm]

    Raises
    ------
    DesignError
        If ``harmonics`` is not a positive integer below half the number of points.
    """
    t = np.mod(np.asarray(t_rad, dtype=float), 2 * math.pi)
    v = np.asarray(values_mm, dtype=float)
    if isinstance(harmonics, bool) or not isinstance(harmonics, int) or not 0 < harmonics:
        raise DesignError(f"harmonics={harmonics!r} is not allowed; give an integer ≥ 1")
    if 2 * harmonics + 1 > t.size // 2:
        raise DesignError(
            f"harmonics={harmonics} is not allowed for {t.size} points; give at most"
            f" {max(1, (t.size // 2 - 1) // 2)}"
        )
    if t.size > _DIRECT_FIT:
        order = np.argsort(t)
        grid = np.linspace(0.0, 2 * math.pi, 8 * harmonics + 8, endpoint=False)
        ts, vs = t[order], v[order]
        v = np.interp(
            grid,
            np.concatenate([ts - 2 * math.pi, ts, ts + 2 * math.pi]),
            np.concatenate([vs, vs, vs]),
        )
        t = grid
    coef = np.linalg.solve(*_normal_equations(t, v, harmonics))
    return FourierError(
        float(coef[0]),
        tuple(coef[1 : harmonics + 1].tolist()),
        tuple(coef[harmonics + 1 :].tolist()),
    )


def _powers(e: NDArray[np.complex128], out: NDArray[np.complex128]) -> None:
    """Fill ``out[:, k−1]`` with e^k, k = 1..K, by doubling: e^{j+n} = e^j · e^n.

    log₂K vectorised products over blocks of columns instead of K − 1 single ones; the
    rounding grows like k·ε, as for the plain recurrence (both are dominated by the
    rounding of e itself raised to the k-th power).
    """
    out[:, 0] = e
    n = 1
    while n < out.shape[1]:
        m = min(n, out.shape[1] - n)
        np.multiply(out[:, :m], out[:, n - 1 : n], out=out[:, n : n + m])
        n += m


def harmonic_table(t: FloatArray, harmonics: int) -> tuple[FloatArray, FloatArray]:
    """Return cos kt and sin kt, k = 1..K, as two (N, K) tables.

    From the powers of e^{it} (:func:`_powers`): about 10x faster than a sine and a
    cosine per entry; the rounding grows like k·ε (below 1e-13 at K = 100, far below any
    measured deviation).

    Parameters
    ----------
    t : ndarray
        Angles, shape (N,). [rad]
    harmonics : int
        K ≥ 1.

    Returns
    -------
    (ndarray, ndarray)
        cos kt and sin kt, shape (N, K). [1]
    """
    e = np.exp(1j * np.asarray(t, dtype=float))
    z = np.empty((e.size, harmonics), dtype=complex)
    _powers(e, z)
    return np.ascontiguousarray(z.real), np.ascontiguousarray(z.imag)


#: Rows of the table e^{ikt} held at once by :func:`_normal_equations` (1.6 MB at 100
#: harmonics): fewer rows pay a matrix product's call overhead too often (256 rows cost
#: 1.7x as much), the whole table of a large scan costs fresh pages.
_MOMENT_ROWS = 1024


def _normal_equations(
    t: FloatArray, v: FloatArray, harmonics: int
) -> tuple[FloatArray, FloatArray]:
    """Return the normal equations AᵀA c = Aᵀv of the Fourier least squares, in O(N·K).

    A has the columns 1, cos kt, sin kt (k = 1..K). Its Gram matrix is made of the
    trigonometric moments C_m + i S_m = Σ exp(i m t_n), m = 0..2K, by the product
    formulas (cos jt cos kt = ½[cos (j−k)t + cos (j+k)t], etc.): the moments up to K are
    column sums of the table exp(i k t), those from K+1 to 2K the products
    exp(i K t) · exp(i j t) summed, and Aᵀv is v times the same table; all three come
    from one product [1, v, Re e^{iKt}, Im e^{iKt}] · table per block of
    :data:`_MOMENT_ROWS` points, so that AᵀA costs O(N·K) instead of the O(N·K²) of
    forming it from A. The system is well conditioned for points spread round the
    revolution (AᵀA is nearly N/2 times the identity).

    Parameters
    ----------
    t : ndarray
        Profile parameters. [rad]
    v : ndarray
        Values. [mm]
    harmonics : int
        K.

    Returns
    -------
    (ndarray, ndarray)
        AᵀA, (2K+1, 2K+1), and Aᵀv, (2K+1,). [1, mm]
    """
    n_k = harmonics
    e = np.exp(1j * np.asarray(t, dtype=float))
    v = np.asarray(v, dtype=float)
    table = np.empty((min(e.size, _MOMENT_ROWS), n_k), dtype=complex)
    weights = np.empty((4, table.shape[0]))
    weights[0] = 1.0
    sums = np.zeros((4, 2 * n_k))  # rows: 1, v, Re e^{iKt}, Im e^{iKt}; Re, Im interleaved
    for a in range(0, e.size, _MOMENT_ROWS):
        rows = min(_MOMENT_ROWS, e.size - a)
        z = table[:rows]
        _powers(e[a : a + rows], z)
        w = weights[:, :rows]
        w[1] = v[a : a + rows]
        w[2] = z[:, -1].real
        w[3] = z[:, -1].imag
        sums += w @ z.view(np.float64)
    k = np.arange(1, n_k + 1)
    re_k, im_k = sums[0, 0::2], sums[0, 1::2]  # Σ e^{ikt}, k = 1..K
    # Σ e^{iKt} e^{ijt} = Σ (w_r z_r − w_i z_i) + i Σ (w_r z_i + w_i z_r), j = 1..K
    re_high = sums[2, 0::2] - sums[3, 1::2]
    im_high = sums[2, 1::2] + sums[3, 0::2]
    big_c = np.concatenate([[t.size], re_k, re_high])  # C_m, m = 0..2K
    big_s = np.concatenate([[0.0], im_k, im_high])  # S_m
    j = k[:, None]
    diff, tot = np.abs(j - k), j + k
    gram = np.empty((2 * n_k + 1, 2 * n_k + 1))
    gram[0, 0] = t.size
    gram[0, 1 : n_k + 1] = gram[1 : n_k + 1, 0] = big_c[k]
    gram[0, n_k + 1 :] = gram[n_k + 1 :, 0] = big_s[k]
    gram[1 : n_k + 1, 1 : n_k + 1] = 0.5 * (big_c[diff] + big_c[tot])
    gram[n_k + 1 :, n_k + 1 :] = 0.5 * (big_c[diff] - big_c[tot])
    cs = 0.5 * (big_s[tot] + np.sign(k - j) * big_s[diff])  # Σ cos jt sin kt
    gram[1 : n_k + 1, n_k + 1 :] = cs
    gram[n_k + 1 :, 1 : n_k + 1] = cs.T
    rhs = np.concatenate([[v.sum()], sums[1, 0::2], sums[1, 1::2]])
    return gram, rhs


class SampledFourier:
    """A Fourier series Δ(t) evaluated fast (a :class:`~camtol.contact.ProfileError`).

    Exact values and derivatives on a fine grid (inverse FFT, at least 128 nodes per
    highest harmonic), quintic Hermite between nodes
    (errors O(h⁶) in Δ, O(h⁴) in Δ''; about 1e-13 mm and 1e-9 relative for 100 harmonics).
    The contact engine evaluates the error several times per angle grid; the series
    itself (:class:`~camtol.contact.FourierError`, one matrix product over the harmonics)
    costs O(N·K) trigonometric evaluations per call, this O(N) after an O(M log M)
    set-up: for 3,600 angles and 100 harmonics about 0.1 ms against 8 ms a call.

    Parameters
    ----------
    series : FourierError
        The series. [mm]
    nodes : int
        Grid nodes per revolution.
    """

    def __init__(self, series: FourierError, nodes: int = 8192) -> None:
        from camtol.inspection.profile_table import _quintic

        k_max = max(len(series.cos_mm), len(series.sin_mm))
        m = max(nodes, 128 * (k_max + 1))
        spec = np.zeros(m // 2 + 1, dtype=complex)
        spec[0] = series.mean_mm * m
        for k, a in enumerate(series.cos_mm, start=1):
            spec[k] += 0.5 * m * a
        for k, b in enumerate(series.sin_mm, start=1):
            spec[k] -= 0.5j * m * b
        ik = 1j * np.arange(spec.size)
        v, d1, d2 = (np.fft.irfft(spec * ik**p, m) for p in (0, 1, 2))
        self.h = 2 * math.pi / m
        self.coef = _quintic(
            v, d1, d2, np.roll(v, -1), np.roll(d1, -1), np.roll(d2, -1), np.full(m, self.h)
        )
        self.series = series

    def __call__(self, theta_rad: FloatArray) -> Jet:
        """Δ and its first two derivatives. [mm, mm/rad, mm/rad²]"""
        from camtol.inspection.profile_table import _horner

        t = np.mod(np.asarray(theta_rad, dtype=float), 2 * math.pi) / self.h
        j = np.minimum(t.astype(np.intp), self.coef.shape[0] - 1)
        v, d, dd = _horner(self.coef[j].T, t - j)
        return Jet(v, d / self.h, dd / (self.h * self.h))


@dataclass(frozen=True)
class FunctionalDeviation:
    """The follower-motion error of a measured cam (see the module notes).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    unit : str
        Unit of S: ``"mm"`` (translating) or ``"rad"`` (oscillating).
    ds_measured, dv_measured, da_measured : ndarray
        ΔS, ΔV, ΔA of the measured (smoothed) cam, exact. [unit, unit/rad, unit/rad²]
    ds_linear : ndarray
        ΔS_lin = (∂S/∂n) Δn. [unit]
    normal_error : FourierError
        The smoothed Δn(t) the motion was computed from. [mm]
    harmonics : int
        Its Fourier cut-off.
    spec : float or None
        Motion spec: the largest allowed max |ΔS_measured| (None: not judged). [unit]
    """

    theta_rad: FloatArray
    unit: str
    ds_measured: FloatArray
    dv_measured: FloatArray
    da_measured: FloatArray
    ds_linear: FloatArray
    normal_error: FourierError
    harmonics: int
    spec: float | None = None

    @property
    def max_abs_measured(self) -> float:
        """Max |ΔS_measured|. [unit]"""
        return float(np.max(np.abs(self.ds_measured)))

    @property
    def max_abs_linear(self) -> float:
        """Max |ΔS_linear|. [unit]"""
        return float(np.max(np.abs(self.ds_linear)))

    @property
    def passed(self) -> bool | None:
        """Whether max |ΔS_measured| ≤ :attr:`spec` (None when no spec was given)."""
        return None if self.spec is None else self.max_abs_measured <= self.spec


def functional_deviation(
    profile: CamProfile,
    source: CmmInspection | FourierError,
    *,
    step_deg: float = 0.1,
    harmonics: int = DEFAULT_HARMONICS,
    spec: float | None = None,
) -> FunctionalDeviation:
    """Exact follower-motion error of a measured cam and its linear prediction.

    Parameters
    ----------
    profile : CamProfile
        The inspected cam (:func:`~camtol.inspection.deviations.cam_profile`).
    source : CmmInspection or FourierError
        A registered scan (its Δn of the points kept is smoothed with ``harmonics``), or
        the normal error Δn(t) itself. [mm]
    step_deg : float
        Cam-angle grid; 360 must be a multiple of it. [deg]
    harmonics : int
        Fourier cut-off of the smoothing.
    spec : float, optional
        Motion spec, the largest allowed max |ΔS_measured| in the unit of S (mm for a
        translating follower, rad for an oscillating one); the result's
        :attr:`~FunctionalDeviation.passed` judges against it. [mm or rad]

    Returns
    -------
    FunctionalDeviation

    Raises
    ------
    DesignError
        If ``spec`` is not a finite number > 0.
    """
    if spec is not None and not (
        isinstance(spec, (int, float)) and not isinstance(spec, bool) and 0 < spec < math.inf
    ):
        raise DesignError(f"spec={spec!r} is not allowed; give a finite number > 0 (mm or rad)")
    n = check_step(step_deg, name="step_deg", min_points=4)
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    if isinstance(source, CmmInspection):
        kept = source.kept
        err = fourier_fit(source.param_rad[kept], source.dn_um[kept] * 1e-3, harmonics)
    else:
        err = source
    mech, program = profile.mechanism, profile.design.program
    sampled = SampledFourier(err)
    shape = AnalyticShape(mech, program, normal_error=sampled)
    motion = follow(shape, mech, theta)
    nominal = program.evaluate(theta)
    sens = mech.error_sensitivities(theta, nominal.lift, nominal.velocity)["n"]
    ds_lin = np.asarray(jet.value(sens), dtype=float) * sampled(theta).v
    return FunctionalDeviation(
        theta_rad=theta,
        unit="mm" if mech.output == "translating" else "rad",
        ds_measured=np.asarray(motion.lift - nominal.lift),
        dv_measured=np.asarray(motion.velocity - nominal.velocity),
        da_measured=np.asarray(motion.acceleration - nominal.acceleration),
        ds_linear=np.broadcast_to(ds_lin, theta.shape).astype(float),
        normal_error=err,
        harmonics=harmonics if isinstance(source, CmmInspection) else len(err.cos_mm),
        spec=None if spec is None else float(spec),
    )
