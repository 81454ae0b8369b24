"""The modified constant-velocity law (issue 32 item 6; docs/theory.md §1)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camtol.design.laws import MCV_RAMP_FRACTION, MOTION_LAWS, normalized_law
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import DesignError

LAW = "modified_constant_velocity"
R = MCV_RAMP_FRACTION


def test_it_is_listed_and_pure_constant_velocity_is_not() -> None:
    assert LAW in MOTION_LAWS
    assert "constant_velocity" not in MOTION_LAWS
    with pytest.raises(DesignError, match="'constant_velocity' is not allowed.*modified_constant"):
        normalized_law("constant_velocity")


def test_constant_velocity_over_the_middle_half() -> None:
    # Between the ramps A and J vanish and V is the constant 1/(1 − r) exactly (to rounding).
    x = np.linspace(R, 1 - R, 1001)[1:-1]
    s, v, a, j = normalized_law(LAW)(x)
    assert v == pytest.approx(1.0 / (1.0 - R), rel=1e-13)
    assert np.max(np.abs(a)) < 1e-12 and np.max(np.abs(j)) < 1e-12
    # S is the straight line through the middle: S(1/2) = 1/2 by symmetry.
    assert float(normalized_law(LAW)(np.array([0.5]))[0][0]) == pytest.approx(0.5, abs=1e-14)
    assert np.allclose(np.diff(s) / np.diff(x), 1.0 / (1.0 - R), rtol=1e-9)


def test_peak_factors_are_the_closed_forms() -> None:
    # V_max = 1/(1 − r), A_max = π/(2 r (1 − r)) (derived in docs/theory.md §1); the grid of
    # 200,001 points hits the peak of A at x = r/2 exactly.
    x = np.linspace(0.0, 1.0, 200_001)
    _, v, a, j = normalized_law(LAW)(x)
    assert v.max() == pytest.approx(1.0 / (1.0 - R), rel=1e-12)
    assert a.max() == pytest.approx(math.pi / (2.0 * R * (1.0 - R)), rel=1e-9)
    assert a.min() == pytest.approx(-math.pi / (2.0 * R * (1.0 - R)), rel=1e-9)
    assert np.abs(j).max() == pytest.approx(math.pi**2 / (2.0 * R**2 * (1.0 - R)), rel=1e-9)


@pytest.mark.parametrize("knot", [R, 1.0 - R])
def test_velocity_and_acceleration_are_continuous_at_the_ramp_ends(knot: float) -> None:
    # The law claims C²: S, V, A continuous; J jumps (by A_max·π/r) as the cycloidal's does.
    law = normalized_law(LAW)
    eps = 1e-9
    left = law(np.array([knot - eps]))
    right = law(np.array([knot + eps]))
    a_max = math.pi / (2.0 * R * (1.0 - R))
    assert abs(float(left[0][0] - right[0][0])) < 1e-8
    assert abs(float(left[1][0] - right[1][0])) < 1e-7
    assert abs(float(left[2][0] - right[2][0])) < 1e-6 * a_max
    assert abs(float(left[3][0] - right[3][0])) == pytest.approx(a_max * math.pi / R, rel=1e-6)


def test_program_with_dwells_is_continuous_in_v_and_a() -> None:
    r = math.radians
    p = SegmentProgram(
        (
            Segment("rise", 0, r(120), LAW, 22.0),
            Segment("dwell", r(120), r(190)),
            Segment("return", r(190), r(290), LAW, 22.0),
            Segment("dwell", r(290), r(360)),
        )
    )
    b = p.boundaries_rad
    left = p.evaluate(b, left_limit=np.ones(b.size, bool))
    right = p.evaluate(b)
    assert left.velocity == pytest.approx(right.velocity, abs=1e-12)
    assert left.acceleration == pytest.approx(right.acceleration, abs=1e-10)


def test_analytic_derivatives_match_numerical_ones_across_the_segment() -> None:
    # Central differences of order h² (h = 1e-6 rad): away from the 4 ramp ends the error is
    # below 1e-6 of each derivative's scale.
    r = math.radians
    p = SegmentProgram(
        (Segment("rise", 0, r(180), LAW, 10.0), Segment("return", r(180), r(360), LAW, 10.0))
    )
    theta = np.linspace(0.001, 2 * math.pi - 0.001, 4001)
    knots = np.radians([45.0, 135.0, 180.0, 225.0, 315.0])
    theta = theta[np.min(np.abs(theta[:, None] - knots[None, :]), axis=1) > 1e-4]
    h = 1e-6
    m, plus, minus = p.evaluate(theta), p.evaluate(theta + h), p.evaluate(theta - h)
    for got, hi, lo in (
        (m.velocity, plus.lift, minus.lift),
        (m.acceleration, plus.velocity, minus.velocity),
        (m.jerk, plus.acceleration, minus.acceleration),
    ):
        fd = (hi - lo) / (2 * h)
        assert np.max(np.abs(fd - got)) <= 1e-6 * max(1.0, float(np.max(np.abs(got))))
