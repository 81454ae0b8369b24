"""The pitch curve's radius of curvature from the follower's frame (roller_common).

``pitch_curvature_radius`` works on the roller centre in the frame of the line of centres
(no sine or cosine of θ). It must equal the radius of curvature of the pitch curve traced
in the cam frame, |P'|³ / (P' × P''), with P and its θ-derivatives from the contact jets.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from camtol.analysis.kinematics import analysis_grid, contact_jets
from camtol.config.design_file import example_names, load_example

ROLLER_CAMS = [
    (name, cam.label)
    for name in example_names()
    for cam in load_example(name).cams()
    if hasattr(cam.mechanism, "roller_radius_mm")
]


@pytest.mark.parametrize(("name", "label"), ROLLER_CAMS)
def test_follower_frame_equals_cam_frame_curvature(name: str, label: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        design = load_example(name)
    cam = next(c for c in design.cams() if c.label == label).design
    theta, left = analysis_grid(0.25, cam.program.boundaries_rad)
    motion = cam.program.evaluate(theta, left_limit=left)
    g = contact_jets(cam, theta, motion)
    px, py = g.extras["pitch_x"], g.extras["pitch_y"]
    speed = np.hypot(px.d1, py.d1)
    cam_frame = speed**3 / (px.d1 * py.d2 - py.d1 * px.d2)
    roller = cam.mechanism.roller_radius_mm  # type: ignore[attr-defined]
    follower_frame = cam.mechanism.curvature_radius(
        theta, motion.lift, motion.velocity, motion.acceleration
    )
    # Two algebraically equal forms in double precision: 1e-12 relative leaves room for
    # the cancellation in the cross product, far below any physical meaning.
    np.testing.assert_allclose(follower_frame + roller, cam_frame, rtol=1e-12)


def test_translating_roller_closed_form() -> None:
    """c = (s0 + S, e): the denominator is (V − e)(2V − e) − (s0 + S)(A − s0 − S)."""
    design = load_example("roller-translating")
    mech = design.mechanism
    theta, left = analysis_grid(1.0, design.program.boundaries_rad)
    m = design.program.evaluate(theta, left_limit=left)
    e, p = mech.offset_mm, mech.s0_mm + m.lift  # type: ignore[attr-defined]
    v, a = m.velocity, m.acceleration
    expected = ((v - e) ** 2 + p**2) ** 1.5 / ((v - e) * (2 * v - e) - p * (a - p))
    rho = mech.curvature_radius(theta, m.lift, v, a) + mech.roller_radius_mm  # type: ignore[attr-defined]
    np.testing.assert_allclose(rho, expected, rtol=1e-13)


@pytest.mark.parametrize("side", [-1, 1])
def test_oscillating_roller_closed_form_equals_the_general_form(side: int) -> None:
    """ρ of the arm's roller from m = γ' + side alone equals pitch_curvature_radius on c."""
    from camtol import jet
    from camtol.jet import Jet
    from camtol.mechanisms.roller_common import pitch_curvature_radius
    from camtol.mechanisms.roller_oscillating import oscillating_roller_pitch_curvature_radius

    rng = np.random.default_rng(5)
    n = 2000
    gamma = Jet(rng.uniform(0.1, 1.4, n), rng.uniform(-0.8, 0.8, n), rng.uniform(-4, 4, n))
    f, arm = 100.0, 70.0
    general = pitch_curvature_radius(f - arm * jet.cos(gamma), (-side * arm) * jet.sin(gamma))
    closed = oscillating_roller_pitch_curvature_radius(gamma, f, arm, side)
    # Algebraically equal; the cross product cancels near an inflection, where both
    # forms lose the same digits: 1e-11 relative, or 1e-9 of the radius scale there.
    np.testing.assert_allclose(closed, general, rtol=1e-11, atol=1e-9 * f)
