r"""Periodic steady state of the follower train, through the frequency domain (THEORY §9.2).

With contact kept the train (:mod:`camtol.dynamics.train`) is linear and the cam's lift is
periodic, so the periodic response is exact harmonic by harmonic: harmonic k of the cam
speed ω, Ω = kω, of the rigid-body load f = P + k_s S + M ω² A (the force a rigid train
would carry) passes to the contact force Q through

.. math:: G(Ω) = \frac{k_f + i c Ω}{k_f + k_s - M Ω^2 + i c Ω},

and the dynamic error e = x − y (mass against lift) is E = −F/(k_f + k_s − MΩ² + icΩ);
a rough lift error ΔS (THEORY §9.6) adds (k_s − MΩ²) ΔŜ to F. The series is evaluated by
one real FFT of the N grid values (harmonics 0 .. N/2 − 1; the Nyquist term is dropped).
A rigid train (k_f infinite) needs no series: Q = f exactly, e = 0.

Truncation: the result is exact for the trigonometric interpolant of f at the N angles.
The harmonics beyond N/2 are missing and alias onto the lower ones; when the harmonics of
f decay at least as 1/k² (the lift's acceleration continuous: every law of THEORY §1 but
the simple harmonic rise between dwells) the missing tail is at most the sum of the last
octave, and :func:`truncation_bound` states the error of Q that follows
(:attr:`SteadyState.truncation_bound`).

Why one module: the steady state and what is read from it, the residual vibration in the
dwells, the truncation bound and the bound of an as-made lift's effect, are one transfer
function G applied to one spectrum; they change together.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from camtol.dynamics.lift import CamLift
from camtol.dynamics.train import FollowerTrain, train_fields
from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = [
    "RESOLUTION_MARGIN",
    "as_made_bound",
    "DwellVibration",
    "SteadyState",
    "check_resolution",
    "check_rpm",
    "residual_vibration",
    "rigid_load",
    "rpm_to_rad_s",
    "steady_state",
    "transfer",
    "truncation_bound",
]

TWO_PI = 2.0 * math.pi
#: The train's resonance must lie at or below (N/2)/RESOLUTION_MARGIN harmonics. [-]
RESOLUTION_MARGIN = 4.0
#: Grid steps :func:`check_resolution` proposes, coarsest first. [deg]
_STEPS_DEG = (0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 0.0005, 0.0002, 0.0001)


def rpm_to_rad_s(rpm: float) -> float:
    """Return the cam speed ω for a speed in rev/min. [rad/s]

    Parameters
    ----------
    rpm : float
        Cam speed. [rpm]
    """
    return rpm * TWO_PI / 60.0


def check_rpm(rpm: float, name: str = "--rpm") -> float:
    """Return ``rpm`` as a float, or refuse a speed that is not finite and > 0.

    Parameters
    ----------
    rpm : float
        Cam speed. [rpm]
    name : str
        How the user gave it, for the message.

    Returns
    -------
    float
        The speed. [rpm]

    Raises
    ------
    DesignError
        One line naming the field, the value and what is allowed.
    """
    if (
        isinstance(rpm, bool)
        or not isinstance(rpm, int | float)
        or not (math.isfinite(rpm) and rpm > 0)
    ):
        raise DesignError(f"{name}={rpm!r} is not allowed; give a cam speed > 0 rpm")
    return float(rpm)


def check_resolution(train: FollowerTrain, angles: int, rpm: float) -> None:
    """Refuse a speed whose train resonance lies beyond the harmonics the grid resolves.

    The grid of N angles carries harmonics up to N/2; the train's natural frequency ω_n
    is harmonic ω_n/ω of the cam speed, and it must lie within (N/2)/4 so that the
    resonance and the octave above it are represented (THEORY §9.2).

    Parameters
    ----------
    train : FollowerTrain
        The train (a rigid train has no resonance: always accepted).
    angles : int
        N. [-]
    rpm : float
        Cam speed. [rpm]

    Raises
    ------
    DesignError
        Naming the speed, the resonance's harmonic, what the grid resolves and the step
        that would.
    """
    wn = train.natural_frequency_rad_s
    if wn is None:
        return
    harmonic = wn / rpm_to_rad_s(rpm)
    most = angles / 2.0 / RESOLUTION_MARGIN
    if harmonic <= most:
        return
    need = 360.0 / (2.0 * RESOLUTION_MARGIN * harmonic)
    step = next((s for s in _STEPS_DEG if s <= need), None)
    hint = (
        f"use --step {step:g} or finer"
        if step is not None
        else "no grid camtol takes resolves it (the finest step is 0.0001°)"
    )
    raise DesignError(
        f"--rpm={rpm:g}: the follower train's natural frequency ({wn / TWO_PI:.4g} Hz) is"
        f" harmonic {harmonic:.0f} of the cam speed, beyond the {most:.0f} that a"
        f" {360.0 / angles:g}° grid resolves (harmonics up to {angles // 2}, margin"
        f" {RESOLUTION_MARGIN:g}); {hint}, or a higher speed"
    )


@dataclass(frozen=True)
class SteadyState:
    """The periodic response of a train to a cam's lift at one speed (THEORY §9.2).

    Attributes
    ----------
    theta_rad : ndarray
        Grid angles θ_j = 2πj/N. [rad]
    rpm : float
        Cam speed. [rpm]
    lift : ndarray
        The cam's lift y = S. [mm, or rad]
    mass : ndarray
        The mass's position x. [mm, or rad]
    dynamic_error : ndarray
        x − y: the train's compression under load and its vibration. [mm, or rad]
    dynamic_error_rate : ndarray
        d(x − y)/dθ. [mm/rad, or rad/rad]
    train_force : ndarray
        Contact force of the train Q (generalised). [N, or N·m]
    truncation_bound : float
        Bound on the error of Q from the truncated series (0 when exact). [N, or N·m]
    force_spectrum : ndarray or None
        Q̂_k (rfft normalisation, Nyquist dropped), for values between the grid angles;
        None for a rigid train.
    """

    theta_rad: FloatArray
    rpm: float
    lift: FloatArray
    mass: FloatArray
    dynamic_error: FloatArray
    dynamic_error_rate: FloatArray
    train_force: FloatArray
    truncation_bound: float
    force_spectrum: np.ndarray | None = None

    @property
    def omega_rad_s(self) -> float:
        """Cam speed ω. [rad/s]"""
        return rpm_to_rad_s(self.rpm)

    def force_at(self, theta_rad: FloatArray) -> FloatArray:
        """Evaluate Q between the grid angles through its series (elastic trains).

        Parameters
        ----------
        theta_rad : ndarray
            Cam angles. [rad]

        Returns
        -------
        ndarray
            Q there (rigid train: linear interpolation of the exact grid values). [N, N·m]
        """
        t = np.asarray(theta_rad, dtype=float)
        if self.force_spectrum is None:
            period = np.append(self.theta_rad, TWO_PI)
            vals = np.append(self.train_force, self.train_force[0])
            return np.asarray(np.interp(np.mod(t, TWO_PI), period, vals))
        n = self.theta_rad.size
        k = np.arange(self.force_spectrum.size)
        e = np.exp(1j * np.multiply.outer(t, k))
        c = self.force_spectrum
        vals = (c[0].real + 2.0 * np.real(e[..., 1:] @ c[1:])) / n
        return np.asarray(vals, dtype=float)


def rigid_load(train: FollowerTrain, lift: CamLift, omega_rad_s: float) -> FloatArray:
    """Return the rigid-body load f = P + k_s S + M ω² A of the smooth lift (THEORY §9.1).

    Parameters
    ----------
    train : FollowerTrain
        The train.
    lift : CamLift
        The lift (its smooth part).
    omega_rad_s : float
        Cam speed ω. [rad/s]

    Returns
    -------
    ndarray
        The contact force a rigid train carries. [N, or N·m]
    """
    f = train.spring_rate * lift.smooth_lift
    f += train.preload
    f += (train.mass * omega_rad_s**2) * lift.smooth_acceleration
    return f


def transfer(
    train: FollowerTrain, omega_rad_s: float, harmonics: int
) -> tuple[np.ndarray, np.ndarray]:
    """Return G(kω) and D(kω) = k_f + k_s − M(kω)² + ickω for k = 0 .. harmonics − 1.

    Parameters
    ----------
    train : FollowerTrain
        An elastic train.
    omega_rad_s : float
        Cam speed ω. [rad/s]
    harmonics : int
        Number of harmonics.

    Returns
    -------
    G, D : ndarray (complex)
        G [-] and D [N/mm, or N·m/rad].

    Raises
    ------
    DesignError
        At an undamped resonance (D = 0 for some harmonic).
    """
    kf = float(train.stiffness) if train.stiffness is not None else math.inf
    w = np.arange(harmonics) * omega_rad_s
    icw = 1j * train.damping * w
    d = (kf + train.spring_rate) - train.mass * w * w + icw
    small = np.abs(d) <= 1e-12 * (kf + train.spring_rate)
    if np.any(small):
        k = int(np.argmax(small))
        raise DesignError(
            f"the undamped follower train resonates with harmonic {k} of the cam speed"
            f" ({omega_rad_s * 60.0 / TWO_PI:g} rpm): give dynamics.damping_ratio > 0 or"
            " another speed"
        )
    return (kf + icw) / d, d


def truncation_bound(
    load_spectrum: np.ndarray,
    gain: np.ndarray,
    angles: int,
    *,
    rough_spectrum: np.ndarray | None = None,
    rough_gain: np.ndarray | None = None,
) -> float:
    """Bound the error of Q from the truncated, aliased series (THEORY §9.2).

    The harmonics of an input beyond K = N/2 are missing from Q and alias onto the kept
    ones: harmonic N − k folds onto k. Under a 1/m² decay of the input's amplitudes
    |f_m|, |f_{N−k}| ≤ |f_k| (k/(N−k))² (further folds add at most a factor π²/6), so the
    aliasing moves Q by at most Σ_k |G_k| |f_k| (π²/6)(k/(N−k))²; the missing tail is at
    most |G_K| times the amplitudes of the last octave (K/2, K), which bound those beyond
    K under the same decay. The bound is twice the sum, over the load f (gain G) and a
    rough lift ΔS (the stiffness's share of its gain, k_f (k_s − MΩ²)/D). It holds when
    the input's harmonics decay at least as 1/k² (the lift's acceleration continuous;
    the lift itself, for a rough lift). The damper's share of a rough lift is a force
    that jumps by c ω ΔV at each vertex, where no series converges uniformly: the caller
    adds the Gibbs bound of those steps, 0.6 × the largest jump.

    Parameters
    ----------
    load_spectrum : ndarray (complex)
        rfft of the load f over the N angles. [N, or N·m]
    gain : ndarray (complex)
        G at the harmonics 0 .. K. [-]
    angles : int
        N.
    rough_spectrum : ndarray (complex), optional
        rfft of a rough lift ΔS. [mm, or rad]
    rough_gain : ndarray (complex), optional
        Its gain at the same harmonics. [N/mm, or N·m/rad]

    Returns
    -------
    float
        The bound. [N, or N·m]
    """
    n = angles
    half = n // 2
    k = np.arange(1, half, dtype=float)
    # harmonic N − k mirrors harmonic k under a 1/m² decay: |f_{N−k}| ≤ |f_k| (k/(N−k))²
    mirror = (math.pi**2 / 6.0) * (k / (n - k)) ** 2
    total = 0.0
    pairs = [(load_spectrum, gain)]
    if rough_spectrum is not None and rough_gain is not None:
        pairs.append((rough_spectrum, rough_gain))
    for spectrum, g in pairs:
        amp = 2.0 * np.abs(spectrum[1:half]) / n
        alias = float(np.sum(np.abs(g[1:half]) * amp * mirror))
        tail = float(np.abs(g[half - 1])) * float(np.sum(amp[half // 2 - 1 :]))
        total += alias + tail
    return 2.0 * total


def steady_state(train: FollowerTrain, lift: CamLift, rpm: float) -> SteadyState:
    """Periodic response of the train to the lift at ``rpm``, contact kept (THEORY §9.2).

    Parameters
    ----------
    train : FollowerTrain
        The follower train.
    lift : CamLift
        The cam's lift over a revolution.
    rpm : float
        Cam speed. [rpm]

    Returns
    -------
    SteadyState
        Where the train force Q is negative the follower would leave the cam: the result
        is then the contact-kept motion (THEORY §9.3 simulates the separation).

    Raises
    ------
    DesignError
        A speed that is not > 0, a resonance beyond the harmonics the grid resolves
        (:func:`check_resolution`), an undamped resonance, or a rough lift (a cut cam) on
        a rigid train (THEORY §9.6).

    Examples
    --------
    >>> from camtol.config.design_file import load_example
    >>> from camtol.dynamics.lift import nominal_lift
    >>> train = FollowerTrain("translating", mass=1e-3, spring_rate=10.0, preload=100.0)
    >>> s = steady_state(train, nominal_lift(load_example("popa-eccentric"), 1.0), 2000.0)
    >>> round(float(s.train_force.min()), 3)  # F0 + 2 k_s e − m ω² e at θ = 180°
    -19.325
    """
    rpm = check_rpm(rpm)
    omega = rpm_to_rad_s(rpm)
    n = lift.angles
    f = rigid_load(train, lift, omega)
    if train.rigid:
        if lift.rough_lift is not None:
            field = train_fields(train.output)[3]
            raise DesignError(
                f"dynamics.{field} is missing: the lift of a cam {lift.description} has"
                " kinks whose acceleration is unbounded, and a rigid follower train would"
                " feel an infinite force there (THEORY §9.6); give the train's stiffness"
                f" (dynamics.{field} or --{field.replace('_', '-')})"
            )
        zeros = np.zeros(n)
        return SteadyState(
            theta_rad=lift.theta_rad,
            rpm=rpm,
            lift=lift.lift,
            mass=lift.lift.copy(),
            dynamic_error=zeros,
            dynamic_error_rate=zeros.copy(),
            train_force=f,
            truncation_bound=0.0,
        )
    check_resolution(train, n, rpm)
    half = n // 2
    g, d = transfer(train, omega, half + 1)
    fh = sfft.rfft(f)
    smooth_hat = fh.copy()
    rough_hat = rough_gain = None
    if lift.rough_lift is not None:
        w = np.arange(half + 1) * omega
        rough_hat = sfft.rfft(lift.rough_lift)
        fh += (train.spring_rate - train.mass * w * w) * rough_hat
        # the stiffness's share: the damper's share of a kinked lift is a step (below)
        kf = float(train.stiffness or 0.0)
        rough_gain = kf * (train.spring_rate - train.mass * w * w) / d
    if n % 2 == 0:
        fh[half] = 0.0  # the Nyquist harmonic is ambiguous on the grid: dropped
    qh = g * fh
    eh = -fh / d
    q = sfft.irfft(qh, n)
    e = sfft.irfft(eh, n)
    de = sfft.irfft(1j * np.arange(half + 1) * eh, n)
    bound = truncation_bound(smooth_hat, g, n, rough_spectrum=rough_hat, rough_gain=rough_gain)
    if rough_hat is not None:  # the damper's force jumps by c ω ΔV at a vertex: Gibbs
        bound += 0.6 * train.damping * omega * 2.0 * lift.velocity_error_max
    return SteadyState(
        theta_rad=lift.theta_rad,
        rpm=rpm,
        lift=lift.lift,
        mass=lift.lift + e,
        dynamic_error=e,
        dynamic_error_rate=de,
        train_force=q,
        truncation_bound=bound,
        force_spectrum=qh[:half],
    )


@dataclass(frozen=True)
class DwellVibration:
    """The train's free vibration in one dwell of the program (THEORY §9.2).

    Attributes
    ----------
    start_rad, end_rad : float
        The dwell. [rad]
    amplitude : float
        Largest amplitude over the dwell of the vibration about the static deflection,
        √(w² + ((ẇ + ζω_n w)/ω_d)²) with w = e + (k_s S + P)/(k_f + k_s). [mm, or rad]
    at_rad : float
        Where it is largest (the dwell's start for a damped train). [rad]
    """

    start_rad: float
    end_rad: float
    amplitude: float
    at_rad: float


def residual_vibration(
    train: FollowerTrain, lift: CamLift, steady: SteadyState
) -> tuple[DwellVibration, ...]:
    """Return the residual vibration of the train in each dwell (THEORY §9.2).

    In a dwell the lift is constant and the train vibrates freely about its static
    deflection e_s = −(k_s S + P)/(k_f + k_s); the deviation w = e − e_s has the
    amplitude √(w² + ((ẇ + ζω_n w)/ω_d)²) (ω_d = ω_n √(1 − ζ²); √(w² + (ẇ/ω_n)²) for
    ζ ≥ 1), constant for an undamped train and largest at the dwell's start otherwise.

    Parameters
    ----------
    train : FollowerTrain
        The train (a rigid train does not vibrate: amplitudes 0).
    lift : CamLift
        The lift (its dwells).
    steady : SteadyState
        The steady state.

    Returns
    -------
    tuple of DwellVibration
        One per dwell of the design's program (none for a lift table).
    """
    out = []
    theta = steady.theta_rad
    n = theta.size
    h = TWO_PI / n
    wn = train.natural_frequency_rad_s
    for a, b in lift.dwells_rad:
        i0 = int(math.ceil(a / h - 1e-9))
        i1 = int(math.floor(b / h + 1e-9))
        idx = np.arange(i0, i1 + 1) % n
        if wn is None or idx.size == 0:
            out.append(DwellVibration(a, b, 0.0, a))
            continue
        kf = float(train.stiffness or 0.0)
        k = kf + train.spring_rate
        w = steady.dynamic_error[idx] + (train.spring_rate * lift.lift[idx] + train.preload) / k
        w_rate = steady.omega_rad_s * (
            steady.dynamic_error_rate[idx] + train.spring_rate * lift.velocity[idx] / k
        )
        z = train.damping_ratio
        if z < 1.0:
            amp = np.hypot(w, (w_rate + z * wn * w) / (wn * math.sqrt(1.0 - z * z)))
        else:
            amp = np.hypot(w, w_rate / wn)
        j = int(np.argmax(amp))
        out.append(DwellVibration(a, b, float(amp[j]), float(theta[idx[j]])))
    return tuple(out)


def as_made_bound(train: FollowerTrain, lift: CamLift, rpm: float) -> float | None:
    """Bound the change of the train force that the as-made lift error can cause (THEORY §9.6).

    With a lift error ΔS of at most E and a velocity error of at most ΔV (one-sided at a
    polygon's vertices), the force changes by ΔQ = k_f (ΔS − Δx) + c ω (ΔS' − Δx'), the
    mass's response Δx = h ∗ ΔS with h the periodic impulse response of
    H = (k_f + icΩ)/D, so

        |ΔQ| ≤ (1 + ‖h‖₁) (k_f E + c ω ΔV),

    ‖h‖₁ evaluated on the grid. It needs an elastic train and a lift error.

    Parameters
    ----------
    train : FollowerTrain
        The train.
    lift : CamLift
        The as-made lift (its error bounds).
    rpm : float
        Cam speed. [rpm]

    Returns
    -------
    float or None
        The bound [N, or N·m]; None for the nominal lift or a rigid train.
    """
    if train.rigid or lift.source == "nominal":
        return None
    omega = rpm_to_rad_s(check_rpm(rpm))
    n = lift.angles
    g, _ = transfer(train, omega, n // 2 + 1)
    h = sfft.irfft(g, n)  # the periodic kernel of H (G = H: the same transfer)
    norm = float(np.sum(np.abs(h)))
    kf = float(train.stiffness or 0.0)
    return (1.0 + norm) * (
        kf * lift.lift_error_max + train.damping * omega * lift.velocity_error_max
    )
