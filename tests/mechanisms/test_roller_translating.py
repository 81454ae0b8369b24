"""Translating roller follower (THEORY §2.3, §3.3): contract and specific checks."""

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
from camtol.exceptions import DesignError, PressureAngleWarning, UndercutError
from camtol.mechanisms import MECHANISMS, RollerTranslating


def program(h: float, rise: float = 120.0, dwell: float = 60.0) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0, r(rise), "cycloidal", h),
            Segment("dwell", r(rise), r(rise + dwell)),
            Segment("return", r(rise + dwell), r(360), "cycloidal", h),
        )
    )


designs = st.builds(
    lambda rb, rf, e, h: CamDesign("rt", RollerTranslating(rb, rf, e), program(h)),
    rb=st.floats(30, 70),
    rf=st.floats(4, 20),
    e=st.floats(-15, 15),
    h=st.floats(2, 15),
)


class TestRollerTranslatingContract(MechanismContract):
    designs = designs
    pressure_sign = -1.0

    def element(self, mech: Any, nominal: Any, theta: FArr, s: FArr) -> Element:
        e, r = mech.offset_mm, mech.roller_radius_mm
        c, sn = np.cos(theta), np.sin(theta)
        axial = nominal.s0_mm + s  # the nominal s0 is the follower's fixed datum
        return Element("roller", -e * sn + axial * c, e * c + axial * sn, r)

    def follower_velocity(self, mech: Any, theta: FArr, g: Any) -> tuple[FArr, FArr]:
        return np.cos(theta), np.sin(theta)

    def lambda_special(self, mech: Any, theta: FArr, lift: FArr, vel: FArr, g: Any) -> FArr:
        # (A − Q) × A = −Q × A = q (A·t) and |QA| = (s0+S)/cos φ − r_f give
        # sin λ = V cos φ / |O2A|, the same form as the translating flat face (THEORY §2.5).
        rad = np.hypot(g.contact_x, g.contact_y)
        return np.arcsin(vel * np.cos(g.pressure_angle) / rad)


def test_registered() -> None:
    assert MECHANISMS["roller_translating"] is RollerTranslating


def test_base_circle_dwell_is_a_circle_and_sensitivities_there() -> None:
    mech = RollerTranslating(40.0, 10.0, 8.0)
    design = CamDesign("d", mech, program(10.0))
    theta = np.radians(np.linspace(125, 175, 11))  # dwell at S = h
    k = kinematics(design, theta)
    # pitch radius r_p on the base circle would be 50; at the top dwell |C| = sqrt(e²+(s0+h)²)
    s0 = math.sqrt(50.0**2 - 64.0)
    rho = k.curvature_radius_mm
    assert rho == pytest.approx(math.hypot(8.0, s0 + 10.0) - 10.0, rel=1e-12)
    assert k.radius_mm == pytest.approx(math.hypot(8.0, s0 + 10.0) - 10.0, rel=1e-12)
    # φ = atan(−e/(s0+h)) in a dwell; ΔS_e = +tan φ (dS/de on a circle = −e/(s0+S))
    phi = math.atan2(-8.0, s0 + 10.0)
    assert k.pressure_angle_rad == pytest.approx(phi, abs=1e-12)
    g = mech.contact(theta, k.lift, k.velocity)
    sens = mech.sensitivities(g, theta)
    assert np.asarray(sens["e"]) == pytest.approx(math.tan(phi), abs=1e-12)
    assert np.asarray(sens["rf"]) == pytest.approx(1 / math.cos(phi), abs=1e-12)


def test_undercut_reported_with_cam_angle() -> None:
    # A fast rise with a small base circle and a big roller: the convex pitch curve near
    # the top of the rise is sharper than the roller.
    design = CamDesign("u", RollerTranslating(10.0, 25.0, 0.0), program(30.0, rise=60, dwell=10))
    with pytest.raises(
        UndercutError, match=r"roller undercuts the profile: .* θ=\d+\.\d+°.* roller radius 25"
    ):
        kinematics(design, np.radians(np.linspace(0, 360, 3601)))


def test_concave_profile_is_not_undercut() -> None:
    # A concave flank (negative ρ, |ρ_pitch| any size) is fine for a roller.
    mech = RollerTranslating(40.0, 5.0, 0.0)
    design = CamDesign("c", mech, program(20.0, rise=60, dwell=60))
    k = kinematics(design, np.radians(np.linspace(0, 360, 3601)))
    assert k.curvature_radius_mm.min() < -mech.roller_radius_mm  # has a concave part
    assert not np.any(mech.undercut_mask(k.curvature_radius_mm))


def test_pressure_angle_beyond_limit_warns_with_cam_angle() -> None:
    # tan φ = (V − e)/(s0 + S) stays below 90° for a translating roller (s0 + S > 0), so
    # only the design limit can be exceeded here; it is warned about with the cam angle.
    design = CamDesign(
        "p", RollerTranslating(30.0, 10.0, 0.0), program(20.0), pressure_angle_limit_deg=10.0
    )
    with pytest.warns(PressureAngleWarning, match=r"θ=\d+\.\d+°"):
        kinematics(design, np.radians(np.linspace(0, 360, 721)))


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"base_radius_mm": -1.0, "roller_radius_mm": 5.0}, "base_radius_mm"),
        ({"base_radius_mm": 30.0, "roller_radius_mm": 0.0}, "roller_radius_mm"),
        ({"base_radius_mm": 30.0, "roller_radius_mm": 5.0, "offset_mm": 40.0}, "offset_mm"),
    ],
)
def test_bad_dimensions_name_the_field(kwargs: dict[str, float], field: str) -> None:
    with pytest.raises(DesignError, match=field):
        RollerTranslating(**kwargs)


def test_design_file_schema_and_analysis() -> None:
    from camtol.analysis.result import analyse
    from camtol.config.design_file import design_from_mapping

    d = design_from_mapping(
        {
            "name": "rt",
            "follower": {
                "type": "roller_translating",
                "base_radius_mm": 40,
                "roller_radius_mm": 10,
                "offset_mm": 8,
            },
            "motion": {
                "segments": [
                    {
                        "kind": "rise",
                        "law": "cycloidal",
                        "start_deg": 0,
                        "end_deg": 120,
                        "lift_mm": 20,
                    },
                    {"kind": "dwell", "end_deg": 190},
                    {"kind": "return", "law": "cycloidal", "end_deg": 290, "lift_mm": 20},
                    {"kind": "dwell", "end_deg": 360},
                ]
            },
            "tolerances": {"r": "IT6", "rf_um": 9, "e_um": 9},
        }
    )
    assert d.mechanism == RollerTranslating(40, 10, 8)
    a = analyse(d, step_deg=1.0)
    assert set(a.errors.sources) == {"r", "rf", "e"}
    # ΔS_rf = Δr_f / cos φ ≥ Δr_f
    assert a.errors.sources["rf"].delta_lift.min() >= 0.009 - 1e-15
