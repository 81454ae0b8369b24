"""Roller followers' lean sensitivities equal the general form through the contact point.

:meth:`Mechanism.error_sensitivities` is the analytic engine's hot path; for the rollers it
is written without the contact point (tan φ, cos φ and cos λ from the motion alone,
THEORY §2.3-2.5). These tests hold it to :meth:`sensitivities` of :meth:`contact` (values
and both θ-derivatives) for every roller example and for random roller geometries.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from camtol import jet
from camtol.config.design_file import example_names, load_example
from camtol.design.motion import MotionProgram, Segment, SegmentProgram
from camtol.jet import Jet
from camtol.mechanisms.base import Mechanism
from camtol.mechanisms.roller_oscillating import RollerOscillating
from camtol.mechanisms.roller_translating import RollerTranslating

THETA = np.radians(np.linspace(0.0, 359.5, 720))


def _assert_lean_equals_general(mech: Mechanism, program: MotionProgram) -> None:
    m = program.evaluate(THETA)
    args = (
        Jet.variable(THETA),
        Jet(m.lift, m.velocity, m.acceleration),
        Jet(m.velocity, m.acceleration, m.jerk),
    )
    lean = mech.error_sensitivities(*args)
    general = mech.sensitivities(mech.contact(*args), args[0])
    assert lean.keys() == general.keys()
    for key in general:
        a, b = lean[key], general[key]
        for part in ("v", "d1", "d2"):
            x = getattr(a, part) if isinstance(a, Jet) else (jet.value(a) if part == "v" else 0.0)
            y = getattr(b, part) if isinstance(b, Jet) else (jet.value(b) if part == "v" else 0.0)
            scale = float(np.max(np.abs(y))) if np.ndim(y) else abs(float(y))
            # the same quantities by other formulas: equal to rounding (relative to the curve)
            np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-10 * max(scale, 1.0))


ROLLER_EXAMPLES = [
    n for n in example_names() if load_example(n).mechanism.kind.startswith(("roller", "conj"))
]


@pytest.mark.parametrize("name", ROLLER_EXAMPLES)
def test_examples(name: str) -> None:
    design = load_example(name)
    for cam in design.cams():  # cam A and cam B (mirrored) of a conjugate pair
        _assert_lean_equals_general(cam.mechanism, design.program)


def _program(height: float, rise_deg: float) -> SegmentProgram:
    return SegmentProgram(
        (
            Segment("rise", 0.0, math.radians(rise_deg), "cycloidal", height),
            Segment("dwell", math.radians(rise_deg), math.radians(180.0)),
            Segment(
                "return", math.radians(180.0), math.radians(180.0 + rise_deg), "cycloidal", height
            ),
            Segment("dwell", math.radians(180.0 + rise_deg), 2 * math.pi),
        )
    )


@given(
    rb=st.floats(30.0, 80.0),
    rf=st.floats(3.0, 20.0),
    e=st.floats(-15.0, 15.0),
    h=st.floats(2.0, 20.0),
    rise=st.floats(90.0, 170.0),
)
def test_random_translating_rollers(rb: float, rf: float, e: float, h: float, rise: float) -> None:
    _assert_lean_equals_general(RollerTranslating(rb, rf, e), _program(h, rise))


@given(
    rb=st.floats(30.0, 60.0),
    rf=st.floats(3.0, 15.0),
    f=st.floats(90.0, 140.0),
    arm=st.floats(60.0, 100.0),
    swing=st.floats(5.0, 20.0),
    rise=st.floats(100.0, 170.0),
)
def test_random_oscillating_rollers(
    rb: float, rf: float, f: float, arm: float, swing: float, rise: float
) -> None:
    if not abs(f - arm) < rb + rf < f + arm:
        return
    _assert_lean_equals_general(
        RollerOscillating(rb, rf, f, arm), _program(math.radians(swing), rise)
    )


@pytest.mark.parametrize("side", [-1, 1])
def test_oscillating_lean_cos_shift_is_nonnegative_where_the_normal_faces_in(side: int) -> None:
    """cos λ = n·A/|A| is taken ≥ 0 (as §2.5's arcsin gives it) where n·A < 0 too.

    Random arm angles and ratios, far outside a working cam, put the contact normal
    facing the cam's centre (n·A < 0) in about one case of seven; there the lean ΔS_r
    must still equal the general form, cos(arcsin(sin λ)) ≥ 0.
    """
    from camtol.mechanisms.roller_oscillating import (
        oscillating_roller_contact,
        oscillating_roller_lean_sensitivities,
        oscillating_roller_sensitivities,
    )

    rng = np.random.default_rng(0)
    gamma, v = rng.uniform(0.05, 3.0, 20_000), rng.uniform(-3.0, 0.9, 20_000)
    f, arm, rf = 100.0, 70.0, 30.0
    geometry = oscillating_roller_contact(0.0, gamma, v, f, arm, rf, side)
    nx, ny = jet.value(geometry.extras["normal_x"]), jet.value(geometry.extras["normal_y"])
    n_dot_a = nx * jet.value(geometry.contact_x) + ny * jet.value(geometry.contact_y)
    faces_in = n_dot_a < 0.0
    assert np.count_nonzero(faces_in) > 1000  # the case is exercised
    lean = jet.value(oscillating_roller_lean_sensitivities(gamma, v, f, arm, rf, side)["r"])
    general = jet.value(oscillating_roller_sensitivities(geometry, arm, side)["r"])
    # √(1 − sin²λ) of the general form loses digits as λ nears 90°: 1e-6 relative.
    np.testing.assert_allclose(lean[faces_in], general[faces_in], rtol=1e-6)
