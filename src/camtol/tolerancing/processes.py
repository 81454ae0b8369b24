"""Random periodic profile errors Δr(ψ) (or Δn(ψ)) sampled by Fourier series.

A machined cam carries a profile error that is a function of the polar angle ψ of the
profile point in the cam frame. Two models:

- a stationary Gaussian process given by its standard deviation σ and correlation length
  L: Δ(ψ) = Σ_{k=1..K} (a_k cos kψ + b_k sin kψ), a_k, b_k ~ N(0, c_k) independent, with
  c_k ∝ exp(−k² L² / 2) (the Fourier coefficients of the periodised Gaussian correlation
  exp(−τ²/(2L²))), normalised so Σ c_k = σ² and truncated where c_k < 1e-8 c_1. The
  order 0 (a constant radial error) is the source ``r`` itself, so the process has zero
  mean;
- chosen harmonics (1 eccentricity, 2 ovality, higher orders waviness) of given amplitude
  A_k and random phase φ_k ~ U(0, 2π): Δ(ψ) = Σ A_k cos(kψ + φ_k).

The follower at cam angle θ touches the profile point A(θ), whose polar angle ψ(θ) =
atan2(A_y, A_x) differs from θ by the mechanism's geometry (THEORY §2): the follower feels
Δ(ψ(θ)), and in the linear model ΔS(θ) = s_r(θ) Δr(ψ(θ)) (THEORY §3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from camtol import jet
from camtol.design.motion import MotionProgram
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, Jet
from camtol.mechanisms.base import Mechanism

__all__ = ["ContactAngleError", "ProcessTarget", "ProfileProcess", "contact_polar_angle"]

ProcessTarget = Literal["r", "n"]
#: Largest Fourier order a process may need.
MAX_ORDER = 720


def _shortest_deg() -> float:
    return math.degrees(math.sqrt(2 * math.log(1e8)) / MAX_ORDER)


@dataclass(frozen=True)
class ProfileProcess:
    """A random periodic profile error (radial ``r`` or normal ``n``).

    Parameters
    ----------
    target : {"r", "n"}
        Radial error along O2A, or normal error along the profile normal (THEORY §0).
    sigma_um : float, optional
        Standard deviation of a stationary Gaussian process. [µm]
    correlation_deg : float, optional
        Its correlation length L (with ``sigma_um``). [deg]
    harmonics : tuple of (int, float)
        (order k ≥ 1, amplitude A_k [µm]) pairs with random phases, instead of σ and L.
    """

    target: str = "r"
    sigma_um: float | None = None
    correlation_deg: float | None = None
    harmonics: tuple[tuple[int, float], ...] = ()

    def __post_init__(self) -> None:
        where = "statistics.profile_process"
        if self.target not in ("r", "n"):
            raise DesignError(f"{where}.target={self.target!r} is unknown; allowed: r, n")
        stationary = self.sigma_um is not None or self.correlation_deg is not None
        if stationary == bool(self.harmonics):
            raise DesignError(
                f"{where}: give either sigma_um and correlation_deg (a stationary Gaussian"
                " process) or harmonics (orders with amplitudes), not both or neither"
            )
        if stationary:
            s, c = self.sigma_um, self.correlation_deg
            if s is None or not (math.isfinite(s) and s > 0):
                raise DesignError(f"{where}.sigma_um={s!r} is not allowed; it must be > 0")
            if c is None or not (math.isfinite(c) and 0 < c <= 180):
                raise DesignError(
                    f"{where}.correlation_deg={c!r} is not allowed; it must be in (0, 180]"
                )
            if self._stationary_orders() > MAX_ORDER:
                raise DesignError(
                    f"{where}.correlation_deg={c:g} needs more than {MAX_ORDER} harmonics;"
                    f" the shortest allowed is {_shortest_deg():.3g}°"
                )
        for k, a in self.harmonics:
            if not (isinstance(k, int) and 1 <= k <= MAX_ORDER):
                raise DesignError(
                    f"{where}.harmonics: order {k!r} is not allowed; use 1..{MAX_ORDER}"
                )
            if not (math.isfinite(a) and a >= 0):
                raise DesignError(f"{where}.harmonics: amplitude {a!r} µm must be ≥ 0")
        if len({k for k, _ in self.harmonics}) != len(self.harmonics):
            raise DesignError(f"{where}.harmonics: an order is given twice")

    def _stationary_orders(self) -> int:
        el = math.radians(float(self.correlation_deg or 1.0))
        return max(1, math.ceil(math.sqrt(2 * math.log(1e8) + el * el) / el))

    @property
    def orders(self) -> FloatArray:
        """Fourier orders k of the process. [-]"""
        if self.harmonics:
            return np.array([k for k, _ in self.harmonics], dtype=float)
        return np.arange(1, self._stationary_orders() + 1, dtype=float)

    @property
    def uniforms(self) -> int:
        """Uniform variates one sample needs (2 per order, or 1 phase per harmonic)."""
        return len(self.harmonics) if self.harmonics else 2 * self.orders.size

    @property
    def columns(self) -> int:
        """Columns of the sample matrix: a_k then b_k for every order."""
        return 2 * self.orders.size

    def coefficient_std_mm(self) -> FloatArray:
        """Return the standard deviation of each a_k (= of b_k), stationary process. [mm]"""
        el = math.radians(float(self.correlation_deg or 1.0))
        k = self.orders
        c = np.exp(-0.5 * (k * k - 1.0) * el * el)
        c *= (float(self.sigma_um or 0.0) * 1e-3) ** 2 / c.sum()
        return np.asarray(np.sqrt(c))

    def coefficient_bounds_mm(self) -> FloatArray:
        """Largest |a_k|, |b_k| of a harmonic process, or 8 σ_k of a Gaussian one. [mm]"""
        if self.harmonics:
            return np.array([a * 1e-3 for _, a in self.harmonics], dtype=float)
        return 8.0 * self.coefficient_std_mm()

    @property
    def gaussian(self) -> bool:
        """True for the stationary Gaussian process (unbounded coefficients)."""
        return not self.harmonics

    def deviation_mm(self) -> float:
        """Return the size of the process as a deviation: 3σ, or its amplitudes summed. [mm]"""
        if self.gaussian:
            return 3.0 * float(self.sigma_um or 0.0) * 1e-3
        return float(np.sum(self.coefficient_bounds_mm()))

    def coefficient_variance_mm2(self) -> FloatArray:
        """Variance of each a_k (= of b_k). [mm²]"""
        if self.harmonics:
            a = np.array([a * 1e-3 for _, a in self.harmonics], dtype=float)
            return np.asarray(0.5 * a * a)
        return np.asarray(self.coefficient_std_mm() ** 2)

    def sample(self, u: FloatArray) -> FloatArray:
        """Coefficients [a_1..a_K, b_1..b_K] from uniforms (rows = samples). [mm]

        Parameters
        ----------
        u : ndarray, shape (samples, uniforms)
            Uniform variates in (0, 1). [-]
        """
        if self.harmonics:
            amp = self.coefficient_bounds_mm()
            phase = 2.0 * math.pi * u
            # A cos(kψ + φ) = A cos φ cos kψ − A sin φ sin kψ
            return np.hstack([amp * np.cos(phase), -amp * np.sin(phase)])
        from scipy.special import ndtri

        s = self.coefficient_std_mm()
        return np.asarray(ndtri(u) * np.concatenate([s, s]))


def contact_polar_angle(
    mechanism: Mechanism,
    program: MotionProgram,
    theta_rad: FloatArray,
    *,
    left_limit: object = None,
) -> Jet:
    """Polar angle ψ(θ) of the contact point A(θ) in the cam frame, with dψ/dθ, d²ψ/dθ².

    Parameters
    ----------
    mechanism : Mechanism
        The nominal mechanism.
    program : MotionProgram
        The nominal motion program.
    theta_rad : ndarray
        Cam angles (profile parameters). [rad]
    left_limit : array_like of bool, optional
        Rows taking left limits at segment boundaries.

    Returns
    -------
    Jet
        ψ, unwrapped along θ when θ is sorted. [rad, rad/rad, rad/rad²]
    """
    t = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    m = program.evaluate(t, left_limit=left_limit)  # type: ignore[arg-type]
    g = mechanism.contact(
        Jet.variable(t),
        Jet(m.lift, m.velocity, m.acceleration),
        Jet(m.velocity, m.acceleration, m.jerk),
    )
    psi = jet.arctan2(g.contact_y, g.contact_x)
    if isinstance(psi, Jet):
        return psi
    z = np.zeros_like(t)
    return Jet(np.asarray(psi, dtype=float), z, z)


@dataclass(frozen=True)
class ContactAngleError:
    """Δ(ψ(t)) = Σ a_k cos kψ(t) + b_k sin kψ(t) as a profile error of parameter t.

    For the exact contact engine (:class:`camtol.contact.AnalyticShape`): the error at the
    profile point A(t) is the process at that point's polar angle ψ(t) (chain rule for the
    derivatives).

    Parameters
    ----------
    mechanism : Mechanism
        The nominal mechanism (defines A(t)).
    program : MotionProgram
        The nominal motion program.
    orders : ndarray
        Fourier orders k. [-]
    cos_mm, sin_mm : ndarray
        a_k and b_k. [mm]
    """

    mechanism: Mechanism
    program: MotionProgram
    orders: FloatArray
    cos_mm: FloatArray
    sin_mm: FloatArray

    def __call__(self, theta_rad: FloatArray) -> Jet:
        """Δ and its t-derivatives. [mm, mm/rad, mm/rad²]"""
        t = np.asarray(theta_rad, dtype=float)
        shape = t.shape
        psi = contact_polar_angle(self.mechanism, self.program, np.mod(t.ravel(), 2 * math.pi))
        k = self.orders[:, None]
        kp = k * psi.v[None, :]
        c, s = np.cos(kp), np.sin(kp)
        a, b = self.cos_mm[:, None], self.sin_mm[:, None]
        f0 = (a * c + b * s).sum(axis=0)
        f1 = (k * (b * c - a * s)).sum(axis=0)
        f2 = (-k * k * (a * c + b * s)).sum(axis=0)
        d1 = f1 * psi.d1
        d2 = f2 * psi.d1 * psi.d1 + f1 * psi.d2
        return Jet(f0.reshape(shape), d1.reshape(shape), d2.reshape(shape))
