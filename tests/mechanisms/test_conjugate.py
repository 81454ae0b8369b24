"""Conjugate pair (THEORY §2.4, §4.1): cam B's contract, the pair, and an exact fixture.

The fixture check re-solves the perturbed conjugate fixture exactly (follower angle ξ and
centre distance f* with both rollers touching their cams, THEORY §5 "conjugate fixture")
and compares the centre-distance change with the closed forms of THEORY §4.1.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from contract import FArr, profile_jets
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from test_roller_oscillating import OscillatingRollerContract

from camtol.analysis.kinematics import kinematics
from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import DesignError, GeometryError
from camtol.mechanisms.conjugate import ConjugateCamB, ConjugatePair
from camtol.mechanisms.roller_oscillating import RollerOscillating
from camtol.pair.fixture import (
    ErrorFunction,
    FixtureErrors,
    conjugate_factors,
    conjugate_variation,
)
from camtol.pair.kinematics import cam_design, conjugate_kinematics

r = math.radians


def cw_program(h_deg: float) -> SegmentProgram:
    return SegmentProgram(
        (
            Segment("rise", 0, r(120), "cycloidal", r(h_deg)),
            Segment("dwell", r(120), r(160)),
            Segment("return", r(160), r(280), "cycloidal", r(h_deg)),
            Segment("dwell", r(280), r(360)),
        )
    )


def pair_design(
    rb: float, rf: float, f: float, la: float, lb: float, eta: float, h: float
) -> CamDesign:
    return CamDesign("pair", ConjugatePair(rb, rf, f, la, lb, r(eta)), cw_program(h))


def _pair_from(
    rb: float, rf: float, f: float, u: float, kb: float, eta: float, h: float
) -> CamDesign:
    la = f - (rb + rf) + 8.0 + 25.0 * u  # arm long enough to reach the prime circle
    return pair_design(rb, rf, f, la, la * kb, eta, h)


pair_designs = st.builds(
    _pair_from,
    rb=st.floats(45, 70),
    rf=st.floats(8, 18),
    f=st.floats(100, 140),
    u=st.floats(0, 1),
    kb=st.floats(0.9, 1.1),
    eta=st.floats(80, 120),
    h=st.floats(10, 30),
)


def cam_b_designs() -> Any:
    return pair_designs.map(lambda d: cam_design(d, "B"))


class TestConjugateCamBContract(OscillatingRollerContract):
    designs = cam_b_designs()
    deltas = {"eta": 1e-6}

    def beta(self, mech: Any, theta: FArr, xi: FArr) -> FArr:
        return theta + mech.arm_angle_rad - xi  # cam B: arm at θ + 180° + η − ξ

    def lambda_special(self, mech: Any, theta: FArr, lift: FArr, vel: FArr, g: Any) -> FArr:
        # CW11 eq. 13 / THEORY §2.5 write sin λ_B = q sin α_B/|O2B| with α_B measured
        # clockwise; the cross-product λ (counterclockwise-positive, as for every other cam)
        # is its negative. Only cos λ_B enters THEORY §4, so the difference is one of sign
        # convention for display; camtol reports the cross-product form for both cams.
        return -super().lambda_special(mech, theta, lift, vel, g)


def test_cam_a_is_the_single_oscillating_roller() -> None:
    pair = ConjugatePair(60, 16, 120, 66, 66, r(100))
    assert pair.cam_a == RollerOscillating(60, 16, 120, 66)
    assert pair.cam_b.initial_angle_rad == pair.cam_a.initial_angle_rad
    assert isinstance(pair.cam_b, ConjugateCamB)


def test_rollers_keep_the_arm_angle_and_cam_b_base_circle() -> None:
    d = pair_design(60, 16, 120, 66, 66, 100, 30)
    theta = np.radians(np.linspace(0, 359, 360))
    k = conjugate_kinematics(d, theta)
    o3x, o3y = 120 * np.cos(theta), 120 * np.sin(theta)
    ca = np.arctan2(k.pitch_a_y_mm - o3y, k.pitch_a_x_mm - o3x)
    cb = np.arctan2(k.pitch_b_y_mm - o3y, k.pitch_b_x_mm - o3x)
    assert np.mod(cb - ca, 2 * math.pi) == pytest.approx(r(100), abs=1e-12)
    # both rollers touch their cams along normals through the same Q
    assert k.a.q_mm == pytest.approx(k.b.q_mm, abs=1e-12)


@pytest.mark.parametrize("eta", [0.0, 180.0, -5.0])
def test_bad_arm_angle(eta: float) -> None:
    with pytest.raises(DesignError, match="arm_angle_deg"):
        ConjugatePair(60, 16, 120, 66, 66, r(eta))


def test_needs_a_conjugate_design() -> None:
    d = CamDesign("x", RollerOscillating(60, 16, 120, 66), cw_program(30))
    with pytest.raises(DesignError, match="conjugate"):
        conjugate_kinematics(d, np.array([0.0]))


# --- exact fixture -------------------------------------------------------------------
Profile = tuple[Callable[[FArr], FArr], Callable[[FArr], FArr]]  # Δr(τ), dΔr/dτ in mm


def _perturbed(design: CamDesign, tau: FArr, dr: Profile | None) -> tuple[FArr, FArr, FArr, FArr]:
    ax, ay = profile_jets(design.mechanism, design, tau)
    x, y, x1, y1 = ax.v, ay.v, ax.d1, ay.d1
    if dr is None:
        return x, y, x1, y1
    d0, d1 = dr[0](tau), dr[1](tau)
    rad = np.hypot(x, y)
    ux, uy = x / rad, y / rad
    rdot = (x * x1 + y * y1) / rad
    dux, duy = (x1 - ux * rdot) / rad, (y1 - uy * rdot) / rad
    return x + d0 * ux, y + d0 * uy, x1 + d1 * ux + d0 * dux, y1 + d1 * uy + d0 * duy


def exact_centre_distance(design: CamDesign, theta: FArr, **p: Any) -> FArr:
    """f* − f of the perturbed fixture at θ (4×4 Newton in ξ, f*, τ_A, τ_B). [mm]"""
    pair = design.mechanism
    assert isinstance(pair, ConjugatePair)
    da, db = cam_design(design, "A"), cam_design(design, "B")
    la = pair.arm_a_mm + p.get("dl_a", 0.0)
    lb = pair.arm_b_mm + p.get("dl_b", 0.0)
    rc = pair.roller_radius_mm + p.get("drr_c", 0.0)
    rd = pair.roller_d_mm + p.get("drr_d", 0.0)
    eta = pair.arm_angle_rad + p.get("deta", 0.0)
    xi = pair.initial_angle_rad + design.program.evaluate(theta).lift
    x = np.stack([xi, np.full_like(theta, pair.pivot_distance_mm), theta.copy(), theta.copy()])

    def residual(x: FArr) -> FArr:
        xi, f, ta, tb = x
        out = []
        for d, tau, arm, beta, rr, dr in (
            (da, ta, la, theta - xi, rc, p.get("dr_a")),
            (db, tb, lb, theta + eta - xi, rd, p.get("dr_b")),
        ):
            cx = f * np.cos(theta) - arm * np.cos(beta)
            cy = f * np.sin(theta) - arm * np.sin(beta)
            px, py, p1x, p1y = _perturbed(d, tau, dr)
            dx, dy = px - cx, py - cy
            dist = np.hypot(dx, dy)
            out += [dist - rr, (dx * p1x + dy * p1y) / dist]
        return np.stack(out)

    h = 1e-7
    for _ in range(40):
        res = residual(x)
        jac = np.empty((theta.size, 4, 4))
        for j in range(4):
            xp = x.copy()
            xp[j] += h
            jac[:, :, j] = ((residual(xp) - res) / h).T
        step = np.linalg.solve(jac, res.T[..., None])[..., 0].T
        x = x - step
        if np.max(np.abs(step)) < 1e-14:
            break
    assert np.max(np.abs(residual(x))) < 1e-10
    return x[1] - pair.pivot_distance_mm


@settings(
    max_examples=5,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)
@given(design=pair_designs)
def test_conjugate_variation_matches_exact_fixture(design: CamDesign) -> None:
    theta = np.radians(np.linspace(1.3, 358.7, 24))
    try:
        fac = conjugate_factors(design, theta)
        kinematics(cam_design(design, "A"), np.radians(np.linspace(0, 360, 721)))
        kinematics(cam_design(design, "B"), np.radians(np.linspace(0, 360, 721)))
    except GeometryError:
        assume(False)
        return
    eps = 1e-4  # mm (1e-6 rad for η)
    # a varying radial error on each cam: Δr(τ) = ε (1 + 0.6 sin 2τ) and ε (0.8 − 0.5 cos τ)
    dra: Profile = (lambda t: eps * (1 + 0.6 * np.sin(2 * t)), lambda t: eps * 1.2 * np.cos(2 * t))
    drb: Profile = (lambda t: eps * (0.8 - 0.5 * np.cos(t)), lambda t: eps * 0.5 * np.sin(t))
    neg = {
        "dr_a": (lambda t: -dra[0](t), lambda t: -dra[1](t)),
        "dr_b": (lambda t: -drb[0](t), lambda t: -drb[1](t)),
    }
    cases = {
        "r": ({"dr_a": dra, "dr_b": drb}, neg),
        "rf": ({"drr_c": eps, "drr_d": 0.7 * eps}, {"drr_c": -eps, "drr_d": -0.7 * eps}),
        "l": ({"dl_a": eps, "dl_b": -0.6 * eps}, {"dl_a": -eps, "dl_b": 0.6 * eps}),
        "eta": ({"deta": 1e-6}, {"deta": -1e-6}),
    }
    closed = conjugate_variation(
        fac,
        dra[0](theta) * 1e3,
        drb[0](theta) * 1e3,
        FixtureErrors(-0.6 * eps, 0.0, 0.0, 0.0, 0.0),
    )
    var = {
        "r": closed.df_r_um,
        "rf": conjugate_variation(fac, 0, 0, FixtureErrors(0, 0, eps, 0.7 * eps, 0)).df_rf_um,
        "l": conjugate_variation(fac, 0, 0, FixtureErrors(eps, -0.6 * eps, 0, 0, 0)).df_l_um,
        "eta": conjugate_variation(fac, 0, 0, FixtureErrors(deta_rad=1e-6)).df_eta_um,
    }
    for name, (plus, minus) in cases.items():
        exact_um = (
            (
                exact_centre_distance(design, theta, **plus)
                - exact_centre_distance(design, theta, **minus)
            )
            / 2
            * 1e3
        )
        np.testing.assert_allclose(exact_um, var[name], rtol=1e-3, atol=1e-7, err_msg=name)
    # Δη > 0 (arms opened wider) shortens the centre distance (THEORY §4.1)
    assert np.all(var["eta"] < 0)


def test_error_function_inputs_to_variation() -> None:
    d = pair_design(60, 16, 120, 66, 66, 100, 30)
    theta = np.radians(np.arange(0, 360, 5.0))
    fac = conjugate_factors(d, theta)
    a = conjugate_variation(
        fac, ErrorFunction.constant(10.0), ErrorFunction.formula("0*theta"), FixtureErrors()
    )
    np.testing.assert_allclose(a.df_r_um, 10.0 * fac.gain_a, rtol=1e-14)
    assert a.df_est_um == pytest.approx(a.df_r_um)


def test_pair_geometry_errors_name_the_cam() -> None:
    from camtol.exceptions import UndercutError

    # a small cam A and a narrow arm angle: cam B is undercut near θ = 142°; the error says
    # which cam and where
    d = CamDesign("bad", ConjugatePair(10, 20, 80, 70, 70, r(60)), cw_program(30))
    theta = np.radians(np.linspace(0, 360, 3601))
    with pytest.raises((UndercutError, GeometryError), match=r"cam [AB]: .*θ=\d+\.\d+°"):
        conjugate_kinematics(d, theta)
