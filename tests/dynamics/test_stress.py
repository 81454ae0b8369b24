"""Normal contact force, camshaft torque and Hertz stress (THEORY §9.4, §9.5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.steady import steady_state
from camtol.dynamics.stress import cam_contacts, camshaft_torque_nm, hertz_stress_mpa
from camtol.dynamics.train import ContactMaterials, FollowerTrain


def test_hertz_line_contact_closed_form() -> None:
    # p = √(F E*/(π L R)), 1/E* = 2 (1 − ν²)/E for steel on steel, 1/R = 1/ρ + 1/r_f
    m = ContactMaterials(face_width_mm=12.0)
    e_star = 210e3 / (2 * (1 - 0.3**2))
    assert m.effective_modulus_mpa == pytest.approx(e_star, rel=1e-14)
    rho, rf, f = np.array([40.0, -80.0, np.inf]), 10.0, np.array([900.0, 900.0, 900.0])
    r = 1 / (1 / rho + 1 / rf)
    got = hertz_stress_mpa(f, rho, rf, m)
    assert got is not None
    np.testing.assert_allclose(got, np.sqrt(f * e_star / (math.pi * 12.0 * r)), rtol=1e-14)
    flat = hertz_stress_mpa(np.array([-5.0, 900.0]), np.array([40.0, 40.0]), None, m)
    assert flat is not None and flat[0] == 0.0  # no contact, no stress
    assert flat[1] == pytest.approx(math.sqrt(900 * e_star / (math.pi * 12 * 40)), rel=1e-14)
    assert hertz_stress_mpa(f, rho, rf, ContactMaterials()) is None  # no face width


def test_normal_force_of_a_translating_roller_is_q_over_cos_phi() -> None:
    # virtual work: F_n = Q ∂S/∂n = Q / cos φ, tan φ = (V − e)/(s0 + S) (THEORY §2.3, §3.3)
    d = load_example("roller-translating")
    lift = nominal_lift(d, 0.5)
    train = FollowerTrain("translating", mass=1e-3, spring_rate=10.0, preload=100.0)
    q = steady_state(train, lift, 500.0).train_force
    (contact,) = cam_contacts(d, lift, train, q)
    e, rp = 6.0, 45.0 + 10.0
    phi = np.arctan((lift.velocity - e) / (math.sqrt(rp * rp - e * e) + lift.lift))
    np.testing.assert_allclose(contact.normal_force_n, q / np.cos(phi), rtol=1e-12)
    assert contact.roller_radius_mm == 10.0


@pytest.mark.parametrize("name", ["cw06-translating", "cw06-oscillating", "roller-oscillating"])
def test_a_conservative_train_does_no_net_work_per_revolution(name: str) -> None:
    # τ = Q V (power balance): ∮ τ dθ = ∮ Q dS = 0 when nothing dissipates (rigid, or
    # elastic and undamped in its periodic state)
    d = load_example(name)
    lift = nominal_lift(d, 0.05)
    output = d.mechanism.output
    for stiffness in (None, 1e4):
        train = FollowerTrain(
            output, mass=2e-3, spring_rate=20.0, preload=50.0, stiffness=stiffness
        )
        q = steady_state(train, lift, 200.0).train_force
        tau = camshaft_torque_nm(train, q, lift.velocity)
        assert abs(float(np.mean(tau))) < 1e-9 * float(np.max(np.abs(tau)))


def test_a_conjugate_pair_loads_one_roller_at_a_time() -> None:
    d = load_example("cw11-conjugate")
    lift = nominal_lift(d, 0.5)
    train = FollowerTrain("oscillating", mass=2e-3, spring_rate=0.0, preload=0.0, form_closed=True)
    q = steady_state(train, lift, 300.0).train_force
    a, b = cam_contacts(d, lift, train, q)
    assert (a.label, b.label) == ("A", "B")
    assert np.all(a.normal_force_n >= 0) and np.all(b.normal_force_n >= 0)
    assert not np.any((a.normal_force_n > 0) & (b.normal_force_n > 0))
    np.testing.assert_array_equal(a.normal_force_n > 0, q > 0)  # A drives the rise
