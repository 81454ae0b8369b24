"""Reproduce Chang & Wu (2006), Examples 1 and 2 (THEORY §8.1, §8.2).

[CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006.
Expected values are typed as printed in THEORY §8.1 (labels corrected there where the
paper misprints them). Tolerance: one unit of the last printed digit (the paper rounds),
and 0.01° in angle, as the issue and THEORY §8.1 state.
"""

from __future__ import annotations

import math

import pytest

from camtol.analysis.extremes import Extreme
from camtol.analysis.result import Analysis, analyse
from camtol.config.design_file import load_example
from camtol.report.display import display_analysis, display_curves, display_extremes


@pytest.fixture(scope="module")
def ex1() -> Analysis:
    return analyse(load_example("cw06-translating"))


@pytest.fixture(scope="module")
def ex2() -> Analysis:
    return analyse(load_example("cw06-oscillating"))


@pytest.fixture(scope="module")
def shown1(ex1: Analysis) -> dict[str, tuple[Extreme, Extreme]]:
    """Example 1's extremes in the paper's units (µm, degrees), as camtol reports them."""
    return display_extremes(ex1)


def _unit_of_last_digit(printed: str) -> float:
    """One unit of the last printed digit: '22.21' -> 0.01."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return 10.0**-decimals


# (quantity, max|min, θ printed (deg) or None for a plateau, value as printed)
TABLE_8_1 = [
    ("shift_angle", "max", "54.84", "22.21"),  # λ max
    ("face_contact", "max", "63.41", "23.67"),  # u max [mm]
    ("dS_phi", "max", "63.41", "4.704"),  # ΔS_φ max [µm]
    ("dS_worst", "max", "71.5", "25.57"),
    ("dS_rms", "max", "103.89", "19.87"),
    ("dS_worst", "min", "206.39", "21.99"),
    ("face_contact", "min", "242.37", "-21.27"),  # paper prints "µm"; it is mm
    ("dS_phi", "min", "242.37", "-4.23"),  # paper prints "max"
    ("radial_factor", "min", "244.31", "0.9297"),  # cos λ / cos φ
    ("shift_angle", "min", "244.31", "-26.1"),
    ("dS_r", "min", "244.31", "17.66"),
    ("dS_rms", "min", "245.23", "18.32"),  # paper prints "max"
]


@pytest.mark.parametrize(("quantity", "kind", "theta", "value"), TABLE_8_1)
def test_cw06_example1_table_extremes(
    shown1: dict[str, tuple[Extreme, Extreme]], quantity: str, kind: str, theta: str, value: str
) -> None:
    ext = shown1[quantity][0 if kind == "max" else 1]
    assert ext.ranges_deg == ()
    # one unit of the last printed digit (values) and 0.01° (angles): THEORY §8.1
    assert ext.value == pytest.approx(float(value), abs=_unit_of_last_digit(value))
    assert ext.theta_deg == pytest.approx(float(theta), abs=0.01 + 1e-9)


@pytest.mark.parametrize(("quantity", "value"), [("radial_factor", "1.0353"), ("dS_r", "19.67")])
def test_cw06_example1_dwell_plateaus(
    shown1: dict[str, tuple[Extreme, Extreme]], quantity: str, value: str
) -> None:
    # Table rows "120-190" and "290-360": the maximum is held over both dwells.
    ext = shown1[quantity][0]
    assert ext.value == pytest.approx(float(value), abs=_unit_of_last_digit(value))
    flat = [x for r in ext.ranges_deg for x in r]
    assert flat == pytest.approx([120.0, 190.0, 290.0, 360.0], abs=1e-6)


def test_cw06_example1_constant_offset_error(
    ex1: Analysis, shown1: dict[str, tuple[Extreme, Extreme]]
) -> None:
    # ΔS_e = −2.41 µm everywhere (printed to 0.01 µm); internally in mm.
    mx, mn = shown1["dS_e"]
    assert mx.value == pytest.approx(-2.41, abs=0.01)
    assert mn.value == mx.value
    assert mx.ranges_deg == ((0.0, 360.0),)
    assert ex1.extremes["dS_e"][0].value == pytest.approx(mx.value * 1e-3, rel=1e-15)


def test_cw06_example1_max_radius_and_grade(ex1: Analysis) -> None:
    assert ex1.max_radius_mm == pytest.approx(61.25, abs=0.01)  # printed 61.25 mm
    assert {t.key: round(t.deviation * 1e3, 6) for t in ex1.tolerances if t.unit == "mm"} == {
        "r": 19.0,
        "e": 9.0,
    }
    phi = next(t for t in ex1.tolerances if t.key == "phi")
    assert math.degrees(phi.deviation) == pytest.approx(0.011, abs=1e-12)
    assert (ex1.accuracy.lower, ex1.accuracy.upper) == ("IT7", "IT8")
    assert ex1.accuracy.describe() == "between IT7 (21 µm) and IT8 (33 µm)"


def test_cw06_example1_velocity_acceleration_errors(ex1: Analysis) -> None:
    """ΔA_φ jumps at every start and end of a motion; ΔA_r is smooth; ΔV_e = ΔA_e = 0."""
    theta = ex1.kinematics.theta_rad
    left = ex1.kinematics.left_limit
    curves = display_curves(ex1)  # µm/rad: the tolerances below are in display units
    assert curves["dV_e"] == pytest.approx(0.0, abs=1e-12)
    assert curves["dA_e"] == pytest.approx(0.0, abs=1e-12)
    for b_deg in (0.0, 120.0, 190.0, 290.0):
        b = math.radians(b_deg) if b_deg else 2 * math.pi
        i_left = int(((abs(theta - b) < 1e-12) & left).nonzero()[0][0])
        if b_deg == 0.0:
            i_right = 0
        else:
            i_right = int(((abs(theta - b) < 1e-12) & ~left).nonzero()[0][0])
        jump_phi = abs(curves["dA_phi"][i_right] - curves["dA_phi"][i_left])
        jump_r = abs(curves["dA_r"][i_right] - curves["dA_r"][i_left])
        scale = max(abs(curves["dA_phi"]).max(), 1e-12)
        assert jump_phi > 0.2 * scale, b_deg  # a real jump, not smeared
        assert jump_r < 1e-9 * max(abs(curves["dA_r"]).max(), 1.0), b_deg


def test_cw06_example2_hand_checkable_invariants(ex2: Analysis) -> None:
    # THEORY §8.2: max radial dimension 58.934 mm (printed to 0.001 mm).
    assert ex2.max_radius_mm == pytest.approx(58.934, abs=0.001)
    # ξ0 = asin((r_b − e)/f) = asin(24/80)
    xi = ex2.kinematics.follower_angle_rad
    assert xi is not None
    assert math.degrees(xi[0]) == pytest.approx(math.degrees(math.asin(24 / 80)), abs=1e-12)
    # IT6 deviations of the paper: Δr = Δf = 19 µm, Δe = 11 µm.
    assert {t.key: round(t.deviation * 1e3, 6) for t in ex2.tolerances} == {
        "r": 19.0,
        "f": 19.0,
        "e": 11.0,
    }
    # Reported in degrees; every acceleration error jumps at each start and end of a motion.
    assert display_analysis(ex2).error_unit == "deg"
    assert {q.unit for q in ex2.quantities if q.key.startswith("dS_")} == {"rad"}  # internal
    for key in ("dA_r", "dA_f", "dA_e"):
        theta, left = ex2.kinematics.theta_rad, ex2.kinematics.left_limit
        for b_deg in (120.0, 160.0, 280.0):
            b = math.radians(b_deg)
            il = int(((abs(theta - b) < 1e-12) & left).nonzero()[0][0])
            ir = int(((abs(theta - b) < 1e-12) & ~left).nonzero()[0][0])
            assert (
                abs(ex2.curves[key][ir] - ex2.curves[key][il]) > 1e-3 * abs(ex2.curves[key]).max()
            ), (key, b_deg)


def test_cw06_example2_sign_of_face_offset_error(ex2: Analysis) -> None:
    # THEORY §3.2: moving the face away from the cam centre makes the follower swing back,
    # so ΔS_e < 0 and ΔS_f has the sign of −sin ξ (ξ in (0, 90°) here). Internal rad and
    # displayed degrees have the same sign.
    assert ex2.extremes["dS_e"][0].value < 0
    assert ex2.extremes["dS_f"][0].value < 0
