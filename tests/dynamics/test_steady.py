"""The periodic steady state (THEORY §9.2): closed forms, and a long time integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from dynamics_designs import H_MM, cycloidal_design, cycloidal_lift, residual_periodic
from scipy.integrate import solve_ivp

from camtol.config.design_file import load_example
from camtol.dynamics.jump import jump_speed_rpm
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.steady import (
    residual_vibration,
    rpm_to_rad_s,
    steady_state,
)
from camtol.dynamics.stress import cam_contacts
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError

# Popa's eccentric cam (THEORY §6.2, §8.5): s = e (1 − cos θ), e = 5 mm.
E_MM = 5.0
M_KG, K_N_PER_MM, F0_N = 0.8, 12.0, 150.0


def _popa_train(**kw: float | None) -> FollowerTrain:
    return FollowerTrain(
        "translating", mass=M_KG * 1e-3, spring_rate=K_N_PER_MM, preload=F0_N, **kw
    )  # type: ignore[arg-type]


@pytest.mark.parametrize("rpm", [300.0, 1200.0, 2500.0])
def test_popa_rigid_contact_force_is_the_closed_form(rpm: float) -> None:
    # F = F0 + k_s s + m s̈, s̈ = ω² e cos θ (flat face, φ = 0: the normal force is F)
    d = load_example("popa-eccentric")
    lift = nominal_lift(d, 0.5)
    train = _popa_train()
    steady = steady_state(train, lift, rpm)
    (contact,) = cam_contacts(d, lift, train, steady.train_force)
    th = lift.theta_rad
    w = rpm_to_rad_s(rpm)
    s = E_MM * (1 - np.cos(th))
    expect = F0_N + K_N_PER_MM * s + (M_KG * 1e-3) * w * w * E_MM * np.cos(th)
    np.testing.assert_allclose(contact.normal_force_n, expect, rtol=1e-6)
    np.testing.assert_allclose(steady.train_force, expect, rtol=1e-12)


def test_popa_rigid_jump_speed_is_the_closed_form() -> None:
    # ω = √((F0 + 2 k_s e)/(m e)), valid when m ω² > k_s (the minimum is then at θ = 180°)
    train = _popa_train()
    w = math.sqrt((F0_N + 2 * K_N_PER_MM * E_MM) / (M_KG * 1e-3 * E_MM))
    assert M_KG * 1e-3 * w * w > K_N_PER_MM
    got = jump_speed_rpm(train, nominal_lift(load_example("popa-eccentric"), 1.0))
    assert got is not None
    assert got == pytest.approx(w * 60 / (2 * math.pi), rel=1e-6)


@pytest.mark.parametrize("beta_deg", [30.0, 45.0, 60.0, 75.0, 90.0, 120.0])
def test_undamped_residual_vibration_is_the_periodic_closed_form(beta_deg: float) -> None:
    # THEORY §9.2: the periodic amplitude in the dwell after the rise, over rise durations
    d = cycloidal_design(beta_deg)
    train = FollowerTrain(
        "translating", mass=1e-3, spring_rate=1.0, preload=5000.0, stiffness=1000.0
    )
    train = FollowerTrain(**{**train.__dict__, "damping_ratio": 0.0})
    lift = nominal_lift(d, 0.01)
    rpm = 600.0
    steady = steady_state(train, lift, rpm)
    (after_rise, _) = residual_vibration(train, lift, steady)
    wn = train.natural_frequency_rad_s
    assert wn is not None
    kappa = 1000.0 / 1001.0
    expect = residual_periodic(H_MM, math.radians(beta_deg), rpm_to_rad_s(rpm), wn, kappa)
    assert after_rise.amplitude == pytest.approx(expect, rel=1e-5)


def test_frequency_domain_equals_a_long_time_integration() -> None:
    # A damped elastic train driven by the cycloidal cam, integrated by scipy from rest
    # for 12 revolutions (the transient decays by e^-30): the last revolution is periodic
    # and equals the steady state of the frequency domain.
    beta = math.radians(60.0)
    d = cycloidal_design(60.0)
    m, ks, p, kf, zeta = 1e-3, 5.0, 400.0, 2000.0, 0.08
    train = FollowerTrain(
        "translating", mass=m, spring_rate=ks, preload=p, stiffness=kf, damping_ratio=zeta
    )
    c = train.damping
    rpm = 450.0
    w = rpm_to_rad_s(rpm)
    steady = steady_state(train, nominal_lift(d, 0.01), rpm)

    def rhs(t: float, z: np.ndarray) -> list[float]:
        y, v = cycloidal_lift(w * t, beta)
        f = kf * (y - z[0]) + c * (w * v - z[1])
        return [z[1], (f - ks * z[0] - p) / m]

    period = 2 * math.pi / w
    t_end = 12 * period
    sample = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    sol = solve_ivp(
        rhs,
        (0.0, t_end + period),
        [-p / (kf + ks), 0.0],
        method="DOP853",
        rtol=1e-11,
        atol=1e-13,
        t_eval=t_end + sample / w,
        max_step=period / 2000,
    )
    x_ref = sol.y[0]
    x_fd = steady.mass[::50]
    np.testing.assert_allclose(x_fd, x_ref, atol=1e-8 * H_MM + 1e-9)
    y = np.array([cycloidal_lift(t, beta)[0] for t in sample])
    yd = np.array([cycloidal_lift(t, beta)[1] for t in sample]) * w
    q_ref = kf * (y - x_ref) + c * (yd - sol.y[1])
    np.testing.assert_allclose(steady.train_force[::50], q_ref, atol=1e-6 * np.max(q_ref))


def test_truncation_bound_covers_the_error_against_a_finer_grid() -> None:
    d = cycloidal_design(45.0)
    train = FollowerTrain(
        "translating", mass=1e-3, spring_rate=1.0, preload=5000.0, stiffness=1000.0
    )
    coarse = steady_state(train, nominal_lift(d, 0.05), 600.0)
    fine = steady_state(train, nominal_lift(d, 0.005), 600.0)
    err = np.max(np.abs(coarse.train_force - fine.train_force[::10]))
    assert 0 < err <= coarse.truncation_bound
    assert fine.truncation_bound < coarse.truncation_bound


def test_rigid_train_is_exact_and_does_not_vibrate() -> None:
    d = cycloidal_design(60.0)
    train = FollowerTrain("translating", mass=1e-3, spring_rate=5.0, preload=400.0)
    lift = nominal_lift(d, 0.1)
    s = steady_state(train, lift, 300.0)
    assert s.truncation_bound == 0.0 and not np.any(s.dynamic_error)
    assert all(r.amplitude == 0.0 for r in residual_vibration(train, lift, s))


def test_a_resonance_beyond_the_grid_names_the_step_that_resolves_it() -> None:
    d = cycloidal_design(60.0)
    train = FollowerTrain(
        "translating", mass=1e-3, spring_rate=5.0, preload=400.0, stiffness=1e5
    )  # f_n ≈ 1.6 kHz: harmonic ~970 at 100 rpm
    with pytest.raises(
        DesignError, match=r"--rpm=100: .*harmonic 955 .*1° grid.*use --step 0\.02 or finer"
    ):
        steady_state(train, nominal_lift(d, 1.0), 100.0)


def test_an_undamped_exact_resonance_is_refused() -> None:
    d = cycloidal_design(60.0)
    train = FollowerTrain("translating", mass=1e-3, spring_rate=1.0, preload=400.0, stiffness=999.0)
    wn = train.natural_frequency_rad_s
    assert wn is not None
    rpm = wn / 20 * 60 / (2 * math.pi)  # harmonic 20 at ω_n exactly
    with pytest.raises(DesignError, match="resonates with harmonic 20"):
        steady_state(train, nominal_lift(d, 0.1), rpm)


@pytest.mark.parametrize("rpm", [0.0, -5.0, math.inf, math.nan])
def test_a_speed_must_be_positive(rpm: float) -> None:
    train = _popa_train()
    with pytest.raises(DesignError, match="give a cam speed > 0 rpm"):
        steady_state(train, nominal_lift(load_example("popa-eccentric"), 1.0), rpm)
