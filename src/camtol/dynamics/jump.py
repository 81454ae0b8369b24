r"""Jump: the speed at which the follower first leaves the cam, and what it does then.

THEORY §9.3. A force-closed follower stays on the cam while the train force Q ≥ 0. The
**jump speed** is the lowest cam speed at which min_θ Q < 0, found by a root search on
the minimum of Q over the revolution (:func:`jump_speed_rpm`): for a rigid train Q is
P + k_s S + M ω² A, whose minimum falls monotonically with ω², so the root is bracketed
by ω = 0 and the grid estimate; for an elastic train the minimum is not monotone
(resonances), so the speeds are scanned upward in small steps for the first negative
minimum, which is then bracketed and refined.

Above it the follower flies: :func:`simulate` integrates the train in the cam angle.
With contact it is scipy's event-driven ``solve_ivp`` (DOP853, rtol 1e-10) stopped where
Q crosses zero downwards; in flight the motion is in closed form (the mass on its return
spring; the train's spring unloaded, its damper relaxing with time constant c/k_f), and
the landing is the first root of y − z (lift minus the train's contact end). An elastic
train lands without a velocity jump of its mass; a rigid one by a plastic impact (the
follower takes the cam's velocity). The impact velocity is the closing speed ẏ − ż > 0
at which cam and follower meet.

Why one module: the jump speed and the separations are one question, where Q < 0, asked
across speeds and then in time; both need the same minimum of Q and the same lift.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from camtol.dynamics.lift import CamLift
from camtol.dynamics.steady import (
    RESOLUTION_MARGIN,
    SteadyState,
    check_rpm,
    rpm_to_rad_s,
    steady_state,
    transfer,
)
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = [
    "Motion",
    "Separation",
    "jump_speed_rpm",
    "minimum_force",
    "separations",
    "simulate",
]

TWO_PI = 2.0 * math.pi
#: Lowest speed the jump search starts from, as a fraction of the rigid train's. [-]
SCAN_START = 0.05
#: Highest speed searched, as a multiple of the rigid train's jump speed. [-]
SCAN_END = 16.0
#: Most flights and contacts :func:`simulate` follows before giving up.
MAX_PHASES = 5000


# ---------------------------------------------------------------------------------------
# The minimum of Q over a revolution, and the jump speed
# ---------------------------------------------------------------------------------------
def _parabola_min(q: FloatArray, i: int, h: float) -> tuple[float, float]:
    """Vertex of the parabola through q[i−1], q[i], q[i+1] (periodic): (value, angle)."""
    n = q.size
    a, b, c = q[(i - 1) % n], q[i], q[(i + 1) % n]
    d = a - 2.0 * b + c
    if d <= 0.0:
        return float(b), i * h
    off = float(np.clip(0.5 * (a - c) / d, -0.5, 0.5))
    return float(b - 0.125 * (a - c) ** 2 / d), (i + off) * h


def _rigid_exact_min(
    train: FollowerTrain, lift: CamLift, omega: float, q: FloatArray
) -> tuple[float, float]:
    """Min of P + k_s S + M ω² A from the program itself, one-sided limits included."""
    program = lift.program
    m_w2 = train.mass * omega * omega
    h = TWO_PI / q.size

    def load(t: float, left: bool = False) -> float:
        st = program.evaluate(np.array([t]), left_limit=np.array([left]))
        return float(train.preload + train.spring_rate * st.lift[0] + m_w2 * st.acceleration[0])

    i = int(np.argmin(q))
    t0 = i * h
    best = minimize_scalar(
        load, bounds=(t0 - h, t0 + h), method="bounded", options={"xatol": 1e-13}
    )
    value, where = float(best.fun), float(best.x)
    if q[i] < value:
        value, where = float(q[i]), t0
    for b in np.asarray(program.boundaries_rad, dtype=float):  # where A may jump
        v = load(float(b), left=True)
        if v < value:
            value, where = v, float(b)
    return value, where % TWO_PI


def minimum_force(train: FollowerTrain, lift: CamLift, rpm: float) -> tuple[float, float]:
    """Return the smallest train force over the revolution and where it is (THEORY §9.3).

    The grid minimum is refined between the grid angles: exactly from the program for a
    rigid train on the nominal cam (one-sided limits at segment boundaries included), by
    the parabola through the three grid values around it otherwise.

    Parameters
    ----------
    train : FollowerTrain
        The train.
    lift : CamLift
        The cam's lift.
    rpm : float
        Cam speed. [rpm]

    Returns
    -------
    (float, float)
        min Q [N, or N·m] and the cam angle where it is reached [rad].
    """
    steady = steady_state(train, lift, rpm)
    q = steady.train_force
    if train.rigid and lift.exact:
        return _rigid_exact_min(train, lift, steady.omega_rad_s, q)
    return _parabola_min(q, int(np.argmin(q)), TWO_PI / q.size)


@dataclass(frozen=True)
class _Loads:
    """The spectra the speed search reuses: Q(ω) = irfft(G(kω)·(â + ω² b̂ + r̂(ω)))."""

    a_hat: np.ndarray
    b_hat: np.ndarray
    rough_hat: np.ndarray | None
    n: int


def _loads(train: FollowerTrain, lift: CamLift) -> _Loads:
    a = train.preload + train.spring_rate * lift.smooth_lift
    b = train.mass * lift.smooth_acceleration
    rough = None if lift.rough_lift is None else sfft.rfft(lift.rough_lift)
    return _Loads(sfft.rfft(a), sfft.rfft(b), rough, lift.angles)


def _elastic_min(
    train: FollowerTrain, loads: _Loads, omega: float, *, coarse: bool = False
) -> tuple[float, float]:
    """Min of Q at ω (refined); ``coarse``: from the harmonics below N/4 on N/2 angles."""
    n = loads.n // 2 if coarse else loads.n
    half = n // 2
    g, _ = transfer(train, omega, half + 1)
    fh = loads.a_hat[: half + 1] + (omega * omega) * loads.b_hat[: half + 1]
    if loads.rough_hat is not None:
        w = np.arange(half + 1) * omega
        fh = fh + (train.spring_rate - train.mass * w * w) * loads.rough_hat[: half + 1]
    qh = g * fh
    qh[half] = 0.0  # Nyquist (and, coarse, everything above N/4) dropped
    q = sfft.irfft(qh, n) * (n / loads.n)
    return _parabola_min(q, int(np.argmin(q)), TWO_PI / n)


def _rigid_estimate(train: FollowerTrain, lift: CamLift) -> float | None:
    """Grid estimate of the rigid train's jump speed ω² = min over b < 0 of a/(−b). [rad/s]"""
    a = train.preload + train.spring_rate * lift.smooth_lift
    b = train.mass * lift.smooth_acceleration
    neg = b < 0
    if not np.any(neg):
        return None
    return float(math.sqrt(max(float(np.min(a[neg] / -b[neg])), 0.0)))


def jump_speed_rpm(train: FollowerTrain, lift: CamLift) -> float | None:
    """Return the lowest cam speed at which the follower leaves the cam (THEORY §9.3).

    Parameters
    ----------
    train : FollowerTrain
        The train; a form-closed pair never jumps (None).
    lift : CamLift
        The cam's lift.

    Returns
    -------
    float or None
        The jump speed [rpm]: 0 when the contact force is negative at rest; None for a
        form-closed pair, a motion without deceleration, or an elastic train that keeps
        contact up to 16 times the rigid train's jump speed.

    Raises
    ------
    DesignError
        The train leaves the cam already below the lowest speed searched (5% of a rigid
        train's jump speed, or the lowest speed whose resonance the grid resolves: the
        message says which step would go lower).

    Examples
    --------
    >>> from camtol.config.design_file import load_example
    >>> from camtol.dynamics.lift import nominal_lift
    >>> train = FollowerTrain("translating", mass=1e-3, spring_rate=10.0, preload=100.0)
    >>> w = math.sqrt((100.0 + 2 * 10.0 * 5.0) / (1e-3 * 5.0))  # Popa: √((F0+2k e)/(m e))
    >>> rpm = jump_speed_rpm(train, nominal_lift(load_example("popa-eccentric"), 1.0))
    >>> abs(rpm / (w * 60 / (2 * math.pi)) - 1) < 1e-9
    True
    """
    if train.form_closed:
        return None
    at_rest = float(np.min(train.preload + train.spring_rate * lift.smooth_lift))
    if at_rest < 0.0:
        return 0.0
    estimate = _rigid_estimate(train, lift)
    if estimate is None:
        return None
    if train.rigid:
        if lift.rough_lift is not None:
            steady_state(train, lift, 1.0)  # refuses the rough lift, naming the remedy

        def fmin(omega: float) -> float:
            return minimum_force(train, lift, omega * 60.0 / TWO_PI)[0]

        hi = estimate * 1.000001
        while fmin(hi) > 0.0:  # the grid missed the true minimum by a little: step out
            hi *= 1.001
        root = brentq(fmin, 0.5 * estimate, hi, xtol=1e-13 * estimate, rtol=1e-15)
        return float(root) * 60.0 / TWO_PI
    loads = _loads(train, lift)
    wn = float(train.natural_frequency_rad_s or 0.0)
    resolved = wn * 2.0 * RESOLUTION_MARGIN / lift.angles
    lo = max(SCAN_START * estimate, resolved * (1.0 + 1e-9))
    if _elastic_min(train, loads, lo)[0] <= 0.0:
        what = (
            "the lowest speed whose resonance the grid resolves: use a finer --step"
            if lo > SCAN_START * estimate
            else f"{SCAN_START:.0%} of the rigid train's jump speed (a resonance of a"
            " lightly damped train: check dynamics.damping_ratio)"
        )
        raise DesignError(
            f"the follower leaves the cam already at {lo * 60 / TWO_PI:.4g} rpm, {what}"
        )
    factor = 1.0 + float(np.clip(0.5 * train.damping_ratio, 0.005, 0.025))

    def full(w: float) -> float:
        return _elastic_min(train, loads, w)[0]

    prev, omega = lo, lo * factor
    while omega <= SCAN_END * estimate:
        # the scan looks at the harmonics below N/4 (half the cost); a negative minimum
        # there is confirmed on the whole series, and the bracket's low end too
        if _elastic_min(train, loads, omega, coarse=True)[0] < 0.0 and full(omega) < 0.0:
            while prev > lo and full(prev) <= 0.0:
                prev /= factor
            root = brentq(full, max(prev, lo), omega, xtol=1e-10 * omega, rtol=1e-14)
            return float(root) * 60.0 / TWO_PI
        prev, omega = omega, omega * factor
    return None


# ---------------------------------------------------------------------------------------
# Separation and impact, in time
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Separation:
    """One flight of the follower: where it leaves the cam and where it lands.

    Attributes
    ----------
    start_rad : float
        Cam angle (unwrapped: may exceed 2π) where the contact force reaches zero. [rad]
    end_rad : float or None
        Where the follower lands (None: not within the simulated span). [rad]
    impact_velocity : float or None
        Closing speed ẏ − ż of cam and follower at the landing. [mm/s, or rad/s]
    """

    start_rad: float
    end_rad: float | None
    impact_velocity: float | None

    @property
    def start_deg(self) -> float:
        """Start, in [0, 360). [deg]"""
        return math.degrees(self.start_rad) % 360.0

    @property
    def end_deg(self) -> float | None:
        """Landing, in [0, 360). [deg]"""
        return None if self.end_rad is None else math.degrees(self.end_rad) % 360.0


@dataclass(frozen=True)
class Motion:
    """The train's motion in time over some revolutions (THEORY §9.3).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles of the samples (the grid's, unwrapped, from the start angle). [rad]
    lift : ndarray
        The cam's lift y there. [mm, or rad]
    mass, mass_rate : ndarray
        The mass's position x and dx/dθ. [mm or rad, per rad]
    in_contact : ndarray of bool
        Whether the follower touches the cam.
    train_force : ndarray
        Q (0 in flight). [N, or N·m]
    separations : tuple of Separation
        Every flight that starts within the span.
    """

    theta_rad: FloatArray
    lift: FloatArray
    mass: FloatArray
    mass_rate: FloatArray
    in_contact: np.ndarray
    train_force: FloatArray
    separations: tuple[Separation, ...]


class _Curve:
    """The lift y(θ) between grid angles: a periodic quintic (or cubic) Hermite.

    Quintic through S, V, A at the grid angles for a smooth lift (A the left limit at the
    end of each interval, so that the jumps of A at segment boundaries are kept); cubic
    through S, V for a lift with a rough part.
    """

    def __init__(self, lift: CamLift) -> None:
        n = lift.angles
        h = TWO_PI / n
        s0, v0 = lift.lift, lift.velocity
        s1, v1 = np.roll(s0, -1), np.roll(v0, -1)
        ds = s1 - s0
        c = np.zeros((n, 6))
        c[:, 0], c[:, 1] = s0, v0 * h
        if lift.rough_lift is None:
            a0 = lift.smooth_acceleration
            a1 = np.roll(a0, -1)
            if lift.exact:  # the left limit of A at the interval's end
                nxt = np.append(lift.theta_rad[1:], TWO_PI)
                a1 = lift.program.evaluate(nxt, left_limit=np.ones(n, bool)).acceleration
            c[:, 2] = 0.5 * a0 * h * h
            c[:, 3] = 10 * ds - (6 * v0 + 4 * v1) * h - (1.5 * a0 - 0.5 * a1) * h * h
            c[:, 4] = -15 * ds + (8 * v0 + 7 * v1) * h + (1.5 * a0 - a1) * h * h
            c[:, 5] = 6 * ds - 3 * (v0 + v1) * h - 0.5 * (a0 - a1) * h * h
        else:
            c[:, 2] = 3 * ds - (2 * v0 + v1) * h
            c[:, 3] = -2 * ds + (v0 + v1) * h
        self.coef, self.h, self.n = c, h, n

    def __call__(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """y, dy/dθ, d²y/dθ² at any angles. [mm or rad, per rad^k]"""
        u = np.mod(np.asarray(theta, dtype=float), TWO_PI) / self.h
        i = np.minimum(u.astype(np.intp), self.n - 1)
        t = u - i
        c = self.coef[i]
        y = c[..., 5]
        d1 = 5.0 * c[..., 5]
        d2 = 20.0 * c[..., 5]
        for k in (4, 3, 2):
            y = y * t + c[..., k]
            d1 = d1 * t + k * c[..., k]
            if k >= 2:
                d2 = d2 * t + k * (k - 1) * c[..., k]
        y = (y * t + c[..., 1]) * t + c[..., 0]
        d1 = d1 * t + c[..., 1]
        return y, d1 / self.h, d2 / (self.h * self.h)

    def value_rate(self, theta: float) -> tuple[float, float]:
        """Y and dy/dθ at one angle, without array overhead."""
        u = (theta % TWO_PI) / self.h
        i = min(int(u), self.n - 1)
        t = u - i
        c0, c1, c2, c3, c4, c5 = self.coef[i].tolist()
        y = ((((c5 * t + c4) * t + c3) * t + c2) * t + c1) * t + c0
        d = (((5 * c5 * t + 4 * c4) * t + 3 * c3) * t + 2 * c2) * t + c1
        return y, d / self.h


@dataclass
class _Phase:
    theta: list[FloatArray]
    mass: list[FloatArray]
    rate: list[FloatArray]
    contact: list[np.ndarray]
    force: list[FloatArray]


def _grid_between(a: float, b: float, h: float, include_end: bool = False) -> FloatArray:
    """Grid angles k·h in [a, b) (or [a, b])."""
    k0 = math.ceil(a / h - 1e-9)
    k1 = math.floor(b / h + 1e-9) if include_end else math.ceil(b / h - 1e-9) - 1
    return np.arange(k0, k1 + 1, dtype=float) * h


def simulate(
    train: FollowerTrain,
    lift: CamLift,
    rpm: float,
    *,
    theta_start_rad: float,
    mass_start: float,
    mass_rate_start: float,
    revolutions: float = 1.0,
) -> Motion:
    """Integrate the train in time from a state in contact, separations included.

    Parameters
    ----------
    train : FollowerTrain
        The train (force-closed).
    lift : CamLift
        The cam's lift.
    rpm : float
        Cam speed. [rpm]
    theta_start_rad : float
        Cam angle of the start. [rad]
    mass_start, mass_rate_start : float
        The mass's position x and dx/dθ there (a rigid train: ignored, the follower
        starts on the cam). [mm or rad, per rad]
    revolutions : float
        How far to integrate. [rev]

    Returns
    -------
    Motion
        Samples at the grid angles of the span; a flight that starts within the span is
        followed to its landing (up to one more revolution).

    Raises
    ------
    DesignError
        A form-closed pair (it cannot leave its cams) or a rough lift on a rigid train.
    """
    if train.form_closed:
        raise DesignError("a conjugate pair is form-closed: its follower cannot leave the cams")
    rpm = check_rpm(rpm)
    omega = rpm_to_rad_s(rpm)
    if train.rigid and lift.rough_lift is not None:
        steady_state(train, lift, rpm)  # refuses, naming the remedy
    curve = _Curve(lift)
    h = TWO_PI / lift.angles
    end = theta_start_rad + TWO_PI * revolutions
    horizon = end + TWO_PI
    m_w2 = train.mass * omega * omega
    kf = train.stiffness
    c_w = train.damping * omega
    out = _Phase([], [], [], [], [])
    seps: list[Separation] = []
    theta, x, u = theta_start_rad, mass_start, mass_rate_start
    if kf is None:
        y0, v0, _ = curve(np.array(theta_start_rad))
        x, u = float(y0), float(v0)
    for _ in range(MAX_PHASES):
        if theta >= end:
            break
        if kf is None:
            t_sep = _rigid_contact(train, lift, curve, omega, theta, end, out)
        else:
            t_sep, x, u = _elastic_contact(
                train, curve, m_w2, float(kf), c_w, theta, end, x, u, out
            )
        if t_sep is None:
            break
        if kf is None:
            x, u = curve.value_rate(t_sep)
            delta0 = 0.0
        else:
            delta0 = curve.value_rate(t_sep)[0] - x if c_w > 0 else 0.0
        landing = _flight(train, curve, omega, t_sep, x, u, delta0, horizon, h, out)
        if landing is None:
            seps.append(Separation(t_sep, None, None))
            break
        theta, x, u, closing = landing
        seps.append(Separation(t_sep, theta, closing * omega))
    th = np.concatenate(out.theta) if out.theta else np.empty(0)
    order = np.argsort(th, kind="stable")
    keep = order[th[order] < end - 1e-12]

    def cat(parts: list[FloatArray] | list[np.ndarray]) -> FloatArray:
        return np.concatenate(parts)[keep] if parts else np.empty(0)

    th = th[keep]
    return Motion(
        theta_rad=th,
        lift=curve(th)[0] if th.size else th,
        mass=cat(out.mass),
        mass_rate=cat(out.rate),
        in_contact=cat(out.contact).astype(bool),
        train_force=cat(out.force),
        separations=tuple(s for s in seps if s.start_rad < end),
    )


def _elastic_contact(
    train: FollowerTrain,
    curve: _Curve,
    m_w2: float,
    kf: float,
    c_w: float,
    theta: float,
    end: float,
    x: float,
    u: float,
    out: _Phase,
) -> tuple[float | None, float, float]:
    """Integrate with contact from θ until Q = 0 (returned) or ``end`` (None)."""
    ks, p = train.spring_rate, train.preload

    def force(t: float, z: FloatArray) -> float:
        y, dy = curve.value_rate(t)
        return float(kf * (y - z[0]) + c_w * (dy - z[1]))

    def rhs(t: float, z: FloatArray) -> list[float]:
        q = force(t, z)
        return [z[1], (q - ks * z[0] - p) / m_w2]

    q0 = force(theta, np.array([x, u]))
    if q0 <= 0.0:  # at a landing Q starts at zero: contact holds if Q grows from there
        _, dy, d2y = curve(np.array(theta))
        x2 = (q0 - ks * x - p) / m_w2
        rate = kf * (float(dy) - u) + c_w * (float(d2y) - x2)
        if q0 < -1e-9 * max(abs(p), 1.0) or rate < 0.0:
            return theta, x, u  # already pulling: it leaves at once

    def event(t: float, z: FloatArray) -> float:
        return force(t, z)

    event.terminal = True  # type: ignore[attr-defined]
    event.direction = -1.0  # type: ignore[attr-defined]
    h = curve.h
    t_eval = _grid_between(theta, end, h)
    t_eval = t_eval[(t_eval >= theta) & (t_eval <= end)]
    sol = solve_ivp(
        rhs,
        (theta, end),
        [x, u],
        method="DOP853",
        t_eval=t_eval,
        events=event,
        rtol=1e-10,
        atol=1e-13 * max(1.0, abs(x)),
        max_step=8 * h,
    )
    if sol.t.size:
        y, dy, _ = curve(sol.t)
        out.theta.append(sol.t)
        out.mass.append(sol.y[0])
        out.rate.append(sol.y[1])
        out.contact.append(np.ones(sol.t.size, bool))
        out.force.append(kf * (y - sol.y[0]) + c_w * (dy - sol.y[1]))
    if sol.t_events[0].size:
        t_sep = float(sol.t_events[0][0])
        z = sol.y_events[0][0]
        return t_sep, float(z[0]), float(z[1])
    return None, float(sol.y[0][-1]) if sol.y.size else x, float(sol.y[1][-1]) if sol.y.size else u


def _rigid_contact(
    train: FollowerTrain,
    lift: CamLift,
    curve: _Curve,
    omega: float,
    theta: float,
    end: float,
    out: _Phase,
) -> float | None:
    """Follow the cam from θ until P + k_s y + Mω²y'' crosses zero downwards, or ``end``."""
    m_w2 = train.mass * omega * omega
    h = curve.h

    def load(t: FloatArray) -> FloatArray:
        y, _, a = curve(np.atleast_1d(t))
        return np.asarray(train.preload + train.spring_rate * y + m_w2 * a)

    grid = _grid_between(theta, end, h, include_end=True)
    pts = np.concatenate([[theta], grid[grid > theta + 1e-12]])
    q = load(pts)
    neg = np.flatnonzero(q < 0.0)
    t_sep: float | None = None
    exact = load
    if lift.exact:  # the program itself between the grid angles

        def exact(t: FloatArray) -> FloatArray:
            st = lift.program.evaluate(np.atleast_1d(t))
            return np.asarray(train.preload + train.spring_rate * st.lift + m_w2 * st.acceleration)

    if neg.size:
        j = int(neg[0])
        if j == 0:
            t_sep = theta
        else:
            a, b = float(pts[j - 1]), float(pts[j])
            if float(exact(np.array(a))[0]) * float(exact(np.array(b))[0]) > 0:
                exact = load  # a jump of A at a boundary: the grid's own values decide
            t_sep = float(brentq(lambda t: float(exact(np.array(t))[0]), a, b, xtol=1e-14))
    stop = end if t_sep is None else t_sep
    samples = _grid_between(theta, stop, h)
    if samples.size:
        y, dy, _ = curve(samples)
        out.theta.append(samples)
        out.mass.append(y)
        out.rate.append(dy)
        out.contact.append(np.ones(samples.size, bool))
        out.force.append(load(samples))
    return t_sep


def _flight(
    train: FollowerTrain,
    curve: _Curve,
    omega: float,
    t_sep: float,
    x0: float,
    u0: float,
    delta0: float,
    horizon: float,
    h: float,
    out: _Phase,
) -> tuple[float, float, float, float] | None:
    """Closed-form flight from t_sep; the landing (θ, x, dx/dθ, closing rate) or None."""
    ks, p, m = train.spring_rate, train.preload, train.mass
    nu = math.sqrt(ks / m) / omega  # the mass on its spring, per radian of cam angle
    x_eq = -p / ks
    lam = (
        float(train.stiffness) / (train.damping * omega)
        if train.stiffness is not None and train.damping > 0
        else math.inf
    )

    def state(phi: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        cs, sn = np.cos(nu * phi), np.sin(nu * phi)
        x = x_eq + (x0 - x_eq) * cs + (u0 / nu) * sn
        dx = -(x0 - x_eq) * nu * sn + u0 * cs
        if math.isinf(lam):
            d = np.zeros_like(phi)
            dd = np.zeros_like(phi)
        else:
            d = delta0 * np.exp(-lam * phi)
            dd = -lam * d
        return x, dx, d, dd

    def gap(phi: FloatArray) -> FloatArray:
        x, _, d, _ = state(phi)
        return np.asarray(curve(t_sep + phi)[0] - x - d)

    scale = max(1.0, abs(x0)) * 1e-13
    step = min(h, 0.05 / max(nu, 1e-9))
    span = horizon - t_sep
    landed: float | None = None
    opened = False  # the gap has opened (the touching start is behind)
    phi0 = 0.0
    while phi0 < span and landed is None:
        phis = np.asarray(phi0 + step * np.arange(1, 4097), dtype=np.float64)
        phis = phis[phis <= span]
        if phis.size == 0:
            break
        g = gap(phis)
        first = 0
        if not opened:
            away = np.flatnonzero(g < -scale)
            if away.size == 0:  # the gap never opens: a grazing touch, no flight
                landed = float(phis[0])
                break
            first, opened = int(away[0]), True
        ok = np.flatnonzero(g[first:] >= 0.0)
        if ok.size:
            j = first + int(ok[0])
            a = float(phis[j - 1]) if j > 0 else phi0
            landed = float(
                brentq(
                    lambda f: float(gap(np.array(f, dtype=float))), a, float(phis[j]), xtol=1e-15
                )
            )
        phi0 = float(phis[-1])
    stop = span if landed is None else landed
    samples = _grid_between(t_sep, t_sep + stop, h)
    samples = samples[samples > t_sep]
    if samples.size:
        xs, dxs, _, _ = state(samples - t_sep)
        out.theta.append(samples)
        out.mass.append(xs)
        out.rate.append(dxs)
        out.contact.append(np.zeros(samples.size, bool))
        out.force.append(np.zeros(samples.size))
    if landed is None:
        return None
    xl, dxl, _, ddl = (float(v) for v in state(np.array(landed)))
    y, dy = curve.value_rate(t_sep + landed)
    closing = dy - dxl - ddl
    if train.stiffness is None:  # plastic impact: the follower takes the cam's motion
        return t_sep + landed, y, dy, closing
    return t_sep + landed, xl, dxl, closing


def separations(
    train: FollowerTrain,
    lift: CamLift,
    steady: SteadyState,
    *,
    revolutions: int = 3,
) -> tuple[Separation, ...]:
    """Flights of the follower at the steady state's speed, where Q would go negative.

    The train is integrated from its contact-kept periodic motion at the angle of the
    largest contact force, for ``revolutions`` revolutions (one for a rigid train, which
    keeps no memory of a flight); the flights that start in the last one are returned.

    Parameters
    ----------
    train : FollowerTrain
        The train.
    lift : CamLift
        The cam's lift.
    steady : SteadyState
        The contact-kept steady state at the speed (its force says whether any flight).
    revolutions : int
        Revolutions to integrate (≥ 1).

    Returns
    -------
    tuple of Separation
        Empty when the steady contact force never goes negative, or for a pair.
    """
    if train.form_closed or float(np.min(steady.train_force)) >= 0.0:
        return ()
    if revolutions < 1:
        raise DesignError(f"revolutions={revolutions!r} is not allowed; give a whole number ≥ 1")
    revs = 1 if train.rigid else int(revolutions)
    j = int(np.argmax(steady.train_force))
    start = float(steady.theta_rad[j])
    motion = simulate(
        train,
        lift,
        steady.rpm,
        theta_start_rad=start,
        mass_start=float(steady.mass[j]),
        mass_rate_start=float(lift.velocity[j] + steady.dynamic_error_rate[j]),
        revolutions=revs,
    )
    first = start + TWO_PI * (revs - 1)
    return tuple(s for s in motion.separations if s.start_rad >= first - 1e-12)
