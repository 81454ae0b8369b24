"""Oscillating roller follower (THEORY §2.4, §3.3): contract and specific checks."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from contract import Element, FArr, MechanismContract
from hypothesis import strategies as st

from camtol.analysis.kinematics import kinematics
from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import DesignError, GeometryError, UndercutError
from camtol.mechanisms import MECHANISMS, RollerOscillating


def program(h_deg: float, rise: float = 120.0, dwell: float = 40.0) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0, r(rise), "cycloidal", r(h_deg)),
            Segment("dwell", r(rise), r(rise + dwell)),
            Segment("return", r(rise + dwell), r(360), "cycloidal", r(h_deg)),
        )
    )


def _design(rb: float, rf: float, f: float, lr: float, h: float) -> CamDesign:
    # arm length as a fraction of the admissible range |f − l| < r_p < f + l
    rp = rb + rf
    lo, hi = abs(f - rp) + 1.0, f + rp - 1.0
    return CamDesign("ro", RollerOscillating(rb, rf, f, lo + lr * (hi - lo)), program(h))


designs = st.builds(
    _design,
    rb=st.floats(30, 60),
    rf=st.floats(4, 18),
    f=st.floats(80, 140),
    lr=st.floats(0.2, 0.8),
    h=st.floats(5, 30),
)


class OscillatingRollerContract(MechanismContract):
    """Shared by cam A (this file) and cam B (test_conjugate.py)."""

    pressure_sign = -1.0

    def position(self, mech: Any, lift: FArr) -> FArr:
        return mech.initial_angle_rad + lift

    def beta(self, mech: Any, theta: FArr, xi: FArr) -> FArr:
        return theta - xi  # cam A: arm at θ + 180° − ξ

    def element(self, mech: Any, nominal: Any, theta: FArr, s: FArr) -> Element:
        # s is the absolute follower angle ξ: no datum from the nominal mechanism needed
        f, r, arm = mech.pivot_distance_mm, mech.roller_radius_mm, mech.arm_length_mm
        beta = self.beta(mech, theta, s)
        return Element(
            "roller",
            f * np.cos(theta) - arm * np.cos(beta),
            f * np.sin(theta) - arm * np.sin(beta),
            r,
        )

    def follower_velocity(self, mech: Any, theta: FArr, g: Any) -> tuple[FArr, FArr]:
        # roller centre C turning about O3, clockwise as ξ grows
        f = mech.pivot_distance_mm
        dx = np.asarray(g.extras["pitch_x"]) - f * np.cos(theta)
        dy = np.asarray(g.extras["pitch_y"]) - f * np.sin(theta)
        return dy, -dx

    def lambda_special(self, mech: Any, theta: FArr, lift: FArr, vel: FArr, g: Any) -> FArr:
        # THEORY §2.5: sin λ = q sin α / |O2A| (CW11 eqs. 12-13)
        rad = np.hypot(g.contact_x, g.contact_y)
        return np.arcsin(g.q * np.sin(g.extras["centre_line_angle"]) / rad)


class TestRollerOscillatingContract(OscillatingRollerContract):
    designs = designs


def test_registered() -> None:
    assert MECHANISMS["roller_oscillating"] is RollerOscillating


def test_dwell_geometry_and_signs_by_hand() -> None:
    # CW11 dimensions (THEORY §8.3), cam A alone: on the base circle q = 0, Q = O2.
    mech = RollerOscillating(60.0, 16.0, 120.0, 66.0)
    xi0 = math.acos((66**2 + 120**2 - 76**2) / (2 * 66 * 120))
    assert mech.initial_angle_rad == pytest.approx(xi0, abs=1e-15)
    r = math.radians
    cw11 = SegmentProgram(
        (
            Segment("rise", 0, r(120), "cycloidal", r(30)),
            Segment("dwell", r(120), r(160)),
            Segment("return", r(160), r(280), "cycloidal", r(30)),
            Segment("dwell", r(280), r(360)),
        )
    )
    design = CamDesign("d", mech, cw11)
    theta = np.radians([300.0, 330.0])
    k = kinematics(design, theta)
    assert k.radius_mm == pytest.approx(60.0, abs=1e-12)
    # angle at C of triangle O2 O3 C is 90° + φ (φ = 90° − α − ξ with α + ξ + C = 180°)
    cos_c = (66**2 + 76**2 - 120**2) / (2 * 66 * 76)
    phi = math.acos(cos_c) - math.pi / 2
    assert k.pressure_angle_rad == pytest.approx(phi, abs=1e-12)
    g = mech.contact(theta, k.lift, k.velocity)
    sens = mech.sensitivities(g, theta)
    # dξ/dl on the base circle, from l² + f² − 2lf cos ξ = r_p²: (f cos ξ − l)/(l f sin ξ)
    dxi_dl = (120 * math.cos(xi0) - 66) / (66 * 120 * math.sin(xi0))
    assert np.asarray(sens["l"]) == pytest.approx(dxi_dl, rel=1e-12)
    assert dxi_dl > 0  # THEORY §3.3's "−Δl tan φ / l" has the wrong sign for φ > 0
    dxi_df = (66 * math.cos(xi0) - 120) / (66 * 120 * math.sin(xi0))
    assert np.asarray(sens["f"]) == pytest.approx(dxi_df, rel=1e-12)


def test_velocity_ratio_one_is_an_error_with_angle() -> None:
    design = CamDesign("v", RollerOscillating(40.0, 10.0, 100.0, 70.0), program(80.0, rise=60))
    with pytest.raises(GeometryError, match=r"θ=\d+\.\d+°"):
        kinematics(design, np.radians(np.linspace(0, 360, 721)))


def test_undercut_reported_with_cam_angle() -> None:
    design = CamDesign("u", RollerOscillating(10.0, 30.0, 100.0, 70.0), program(15.0, rise=40))
    with pytest.raises(UndercutError, match=r"θ=\d+\.\d+°"):
        kinematics(design, np.radians(np.linspace(0, 360, 3601)))


def test_arm_that_cannot_reach_the_prime_circle() -> None:
    with pytest.raises(DesignError, match="arm_length_mm"):
        RollerOscillating(40.0, 10.0, 200.0, 60.0)


def test_design_file_schema_and_analysis() -> None:
    from camtol.analysis.result import analyse
    from camtol.config.design_file import design_from_mapping
    from camtol.exceptions import ConfigError

    base = {
        "name": "ro",
        "follower": {
            "type": "roller_oscillating",
            "base_radius_mm": 60,
            "roller_radius_mm": 16,
            "pivot_distance_mm": 120,
            "arm_length_mm": 66,
        },
        "motion": {
            "segments": [
                {
                    "kind": "rise",
                    "law": "cycloidal",
                    "start_deg": 0,
                    "end_deg": 120,
                    "lift_deg": 30,
                },
                {"kind": "dwell", "end_deg": 160},
                {"kind": "return", "law": "cycloidal", "end_deg": 280, "lift_deg": 30},
                {"kind": "dwell", "end_deg": 360},
            ]
        },
        "tolerances": {"r": "IT6", "l": "IT6", "f": "IT6", "rf": "IT6"},
    }
    d = design_from_mapping(base)
    assert d.mechanism == RollerOscillating(60, 16, 120, 66)
    a = analyse(d, step_deg=1.0)
    assert a.max_radius_mm == pytest.approx(93.793, abs=1e-3)  # cam A of THEORY §8.3
    bad = {**base, "follower": {**base["follower"], "arm_length_mm": 10}}
    with pytest.raises(ConfigError, match="arm_length_mm"):
        design_from_mapping(bad)


@pytest.mark.parametrize("side", [-1, 1])
def test_frame_contact_is_the_general_formula_at_zero_bit_for_bit(side: int) -> None:
    """θ = 0.0 (the engine's frame of the line of centres) takes a shorter path: same bits."""
    from camtol.mechanisms.roller_oscillating import oscillating_roller_contact

    rng = np.random.default_rng(3)
    gamma, v = rng.uniform(0.2, 1.3, 500), rng.uniform(-0.6, 0.6, 500)
    frame = oscillating_roller_contact(0.0, gamma, v, 120.0, 80.0, 15.0, side)
    general = oscillating_roller_contact(np.zeros(500), gamma, v, 120.0, 80.0, 15.0, side)
    fields = ("contact_x", "contact_y", "centre_x", "centre_y", "q", "pressure_angle")
    for name in (*fields, "shift_angle"):
        np.testing.assert_array_equal(
            np.broadcast_to(getattr(frame, name), (500,)), getattr(general, name), err_msg=name
        )
    for key in ("pitch_x", "pitch_y", "normal_x", "normal_y", "centre_line_angle"):
        np.testing.assert_array_equal(frame.extras[key], general.extras[key], err_msg=key)
    assert np.all(np.isfinite(frame.pressure_angle))
