"""Jump speed, residual vibration in time and separations (THEORY §9.2, §9.3).

camtol's own integrator (:func:`camtol.dynamics.jump.simulate`) is checked against the
closed form of the residual vibration after a cycloidal rise from rest, and against an
independent scipy ``solve_ivp`` written here for a damped case and for a separation case.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from dynamics_designs import H_MM, cycloidal_design, cycloidal_lift, residual_from_rest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from camtol.config.design_file import load_example
from camtol.dynamics.jump import jump_speed_rpm, minimum_force, separations, simulate
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.steady import rpm_to_rad_s, steady_state
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError


def _train(**kw: float) -> FollowerTrain:
    base: dict[str, float] = dict(mass=1e-3, spring_rate=1.0, preload=1e5, stiffness=1000.0)
    base.update(kw)
    return FollowerTrain("translating", **base)  # type: ignore[arg-type]


@pytest.mark.parametrize("beta_deg", [20.0, 30.0, 45.0, 60.0, 90.0, 120.0])
def test_undamped_residual_after_a_cycloidal_rise_from_rest(beta_deg: float) -> None:
    # THEORY §9.2: A = κ h |sin πr| / (π r |r² − 1|), r = T/T_n, κ = k_f/(k_f + k_s)
    d = cycloidal_design(beta_deg)
    train = _train()
    lift = nominal_lift(d, 0.01)
    rpm = 600.0
    w = rpm_to_rad_s(rpm)
    wn = train.natural_frequency_rad_s
    assert wn is not None
    x0 = -train.preload / (1000.0 + 1.0)  # at rest on the base circle
    mo = simulate(
        train, lift, rpm, theta_start_rad=0.0, mass_start=x0, mass_rate_start=0.0, revolutions=0.49
    )
    dwell = (mo.theta_rad > math.radians(beta_deg) + 1e-9) & (mo.theta_rad < math.pi)
    k = 1001.0
    wdev = mo.mass[dwell] - mo.lift[dwell] + (mo.lift[dwell] + train.preload) / k
    amp = np.hypot(wdev, mo.mass_rate[dwell] * w / wn)
    r = wn * math.radians(beta_deg) / w / (2 * math.pi)
    expect = residual_from_rest(H_MM, r, 1000.0 / 1001.0)
    np.testing.assert_allclose(amp, expect, rtol=1e-8, atol=1e-12)
    assert mo.in_contact.all() and not mo.separations


def test_damped_transient_matches_an_independent_solve_ivp() -> None:
    beta = math.radians(45.0)
    d = cycloidal_design(45.0)
    train = FollowerTrain(
        "translating",
        mass=1e-3,
        spring_rate=3.0,
        preload=5000.0,
        stiffness=800.0,
        damping_ratio=0.12,
    )
    lift = nominal_lift(d, 0.01)
    rpm = 500.0
    w = rpm_to_rad_s(rpm)
    m, ks, p, kf, c = 1e-3, 3.0, 5000.0, 800.0, train.damping
    x0 = -p / (kf + ks)
    mo = simulate(
        train, lift, rpm, theta_start_rad=0.0, mass_start=x0, mass_rate_start=0.0, revolutions=1.0
    )

    def rhs(th: float, z: np.ndarray) -> list[float]:
        y, v = cycloidal_lift(th, beta)
        f = kf * (y - z[0]) + c * w * (v - z[1])
        return [z[1], (f - ks * z[0] - p) / (m * w * w)]

    sol = solve_ivp(
        rhs,
        (0.0, mo.theta_rad[-1]),
        [x0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        t_eval=mo.theta_rad[::25],
        max_step=1e-2,
    )
    np.testing.assert_allclose(mo.mass[::25], sol.y[0], atol=1e-9)
    np.testing.assert_allclose(mo.mass_rate[::25], sol.y[1], atol=1e-7)


def test_separation_matches_an_independent_solve_ivp() -> None:
    # An undamped elastic train (c = 0) above its jump speed: the contact force is the
    # unilateral spring max(0, k_f (y − x)); the reference integrates it with its own
    # events at y − x = 0 and compares where the follower leaves and lands, and how fast
    # cam and follower meet.
    beta = math.radians(60.0)
    d = cycloidal_design(60.0)
    m, ks, p, kf = 1e-3, 5.0, 200.0, 3000.0
    train = FollowerTrain("translating", mass=m, spring_rate=ks, preload=p, stiffness=kf)
    lift = nominal_lift(d, 0.01)
    rigid = jump_speed_rpm(FollowerTrain("translating", mass=m, spring_rate=ks, preload=p), lift)
    assert rigid is not None
    rpm = 1.3 * rigid  # it leaves the cam within the first revolution from rest
    w = rpm_to_rad_s(rpm)
    th0 = math.radians(300.0)  # on the base circle, at rest, contact kept
    x0 = -p / (kf + ks)
    mo = simulate(
        train, lift, rpm, theta_start_rad=th0, mass_start=x0, mass_rate_start=0.0, revolutions=1.0
    )
    assert mo.separations

    def contact(th: float, z: np.ndarray) -> list[float]:
        y, _ = cycloidal_lift(th, beta)
        return [z[1], (kf * (y - z[0]) - ks * z[0] - p) / (m * w * w)]

    def flight(th: float, z: np.ndarray) -> list[float]:
        return [z[1], (-ks * z[0] - p) / (m * w * w)]

    def gap(th: float, z: np.ndarray) -> float:
        return cycloidal_lift(th, beta)[0] - z[0]

    gap.terminal = True  # type: ignore[attr-defined]
    t, z = th0, np.array([x0, 0.0])
    found = []
    for sep in mo.separations:
        gap.direction = -1  # type: ignore[attr-defined]
        a = solve_ivp(
            contact,
            (t, t + 2 * math.pi),
            z,
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            events=gap,
            max_step=2e-3,
        )
        t_leave = float(a.t_events[0][0])
        z = a.y_events[0][0]
        gap.direction = 1  # type: ignore[attr-defined]
        b = solve_ivp(
            flight,
            (t_leave + 1e-9, t_leave + 2 * math.pi),
            z,
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            events=gap,
            max_step=2e-3,
        )
        t_land = float(b.t_events[0][0])
        z = b.y_events[0][0]
        closing = (cycloidal_lift(t_land, beta)[1] - z[1]) * w
        found.append((t_leave, t_land, closing))
        assert sep.start_rad == pytest.approx(t_leave, abs=1e-7)
        assert sep.end_rad == pytest.approx(t_land, abs=1e-7)
        assert sep.impact_velocity == pytest.approx(closing, rel=1e-6)
        t = t_land
    assert len(found) == len(mo.separations)


def test_rigid_popa_separation_is_the_closed_form() -> None:
    # Rigid train on Popa's eccentric cam above ω_j: it leaves where
    # F0 + k_s e (1 − cos θ) + m ω² e cos θ = 0 and flies on its spring in closed form.
    e, m, ks, f0 = 5.0, 1e-3, 10.0, 100.0
    train = FollowerTrain("translating", mass=m, spring_rate=ks, preload=f0)
    lift = nominal_lift(load_example("popa-eccentric"), 0.01)
    rpm = 2300.0
    w = rpm_to_rad_s(rpm)
    steady = steady_state(train, lift, rpm)
    (sep,) = separations(train, lift, steady)
    cos_s = -(f0 + ks * e) / ((m * w * w - ks) * e)
    t_leave = math.acos(cos_s)  # the first root, θ < 180°
    assert sep.start_deg == pytest.approx(math.degrees(t_leave), abs=1e-7)
    x0, u0 = e * (1 - cos_s), e * math.sin(t_leave)
    nu = math.sqrt(ks / m) / w
    x_eq = -f0 / ks

    def gap(phi: float) -> float:
        x = x_eq + (x0 - x_eq) * math.cos(nu * phi) + u0 / nu * math.sin(nu * phi)
        return e * (1 - math.cos(t_leave + phi)) - x

    phis = np.linspace(1e-4, 2 * math.pi, 20001)
    g = np.array([gap(f) for f in phis])
    j = int(np.flatnonzero(g >= 0)[0])
    land = brentq(gap, phis[j - 1], phis[j], xtol=1e-15)
    assert sep.end_deg == pytest.approx(math.degrees(t_leave + land) % 360, abs=1e-7)
    xd = -(x0 - x_eq) * nu * math.sin(nu * land) + u0 * math.cos(nu * land)
    closing = (e * math.sin(t_leave + land) - xd) * w
    assert sep.impact_velocity == pytest.approx(closing, rel=1e-7)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.3])
def test_jump_speed_is_where_the_minimum_force_first_reaches_zero(zeta: float) -> None:
    d = load_example("roller-translating")
    train = FollowerTrain(
        "translating", mass=1e-3, spring_rate=10.0, preload=100.0, stiffness=1e4, damping_ratio=zeta
    )
    lift = nominal_lift(d, 0.05)
    jump = jump_speed_rpm(train, lift)
    assert jump is not None
    assert minimum_force(train, lift, jump * (1 - 1e-3))[0] > 0
    assert abs(minimum_force(train, lift, jump)[0]) < 1e-6 * 100.0
    assert minimum_force(train, lift, jump * (1 + 1e-3))[0] < 0
    assert separations(train, lift, steady_state(train, lift, 0.9 * jump)) == ()


def test_a_form_closed_pair_never_jumps() -> None:
    d = load_example("cw11-conjugate")
    train = FollowerTrain("oscillating", mass=2e-3, spring_rate=0.0, preload=0.0, form_closed=True)
    assert jump_speed_rpm(train, nominal_lift(d, 1.0)) is None
    with pytest.raises(DesignError, match="form-closed"):
        simulate(
            train,
            nominal_lift(d, 1.0),
            100.0,
            theta_start_rad=0.0,
            mass_start=0.0,
            mass_rate_start=0.0,
        )
