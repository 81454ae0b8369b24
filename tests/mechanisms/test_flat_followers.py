"""Flat-faced followers: geometry and sensitivities against exact re-solution.

THEORY §2.1, §2.2, §3.1, §3.2. The exact checks use the profile's support function: a
flat face touching the cam has p(ψ) = max over the cam of X·n(ψ), and for the nominal cam
p is known in closed form along the contact parameter (translating: p = r_b + S cos φ at
ψ = θ + φ; oscillating: p = f sin ξ + e at ψ = θ + 90° − ξ).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from camtol import jet
from camtol.analysis.errors import error_analysis
from camtol.analysis.kinematics import kinematics, to_jet
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import DesignError, GeometryError, UndercutError
from camtol.jet import Jet
from camtol.mechanisms import FlatOscillating, FlatTranslating


def _program(
    h: float, rise: float = 120, dwell: float = 60, law: str = "cycloidal"
) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0, r(rise), law, h),
            Segment("dwell", r(rise), r(rise + dwell)),
            Segment("return", r(rise + dwell), r(360), law, h),
        )
    )


THETA = np.radians(np.linspace(0.05, 359.95, 1440))


def _parametric_rho(design: CamDesign) -> np.ndarray:
    """ρ from the parametric contact curve A(θ), differentiated exactly with jets."""
    m = design.program.evaluate(THETA)
    g = design.mechanism.contact(
        Jet.variable(THETA),
        to_jet(m.lift, m.velocity, m.acceleration),
        to_jet(m.velocity, m.acceleration, m.jerk),
    )
    x, y = g.contact_x, g.contact_y
    assert isinstance(x, Jet) and isinstance(y, Jet)
    return (x.d1**2 + y.d1**2) ** 1.5 / (x.d1 * y.d2 - y.d1 * x.d2)


translating_designs = st.builds(
    lambda rb, e, phi, h: CamDesign("t", FlatTranslating(rb, e, math.radians(phi)), _program(h)),
    rb=st.floats(30, 80),
    e=st.floats(-20, 20),
    phi=st.floats(-30, 30),
    h=st.floats(1, 15),
)
oscillating_designs = st.builds(
    lambda rb, f, e, h: CamDesign("o", FlatOscillating(rb, f, e), _program(math.radians(h))),
    rb=st.floats(30, 60),
    f=st.floats(70, 120),
    e=st.floats(-10, 20),
    h=st.floats(2, 15),
)


@given(translating_designs)
def test_translating_closed_form_curvature_matches_parametric(design: CamDesign) -> None:
    m = design.program.evaluate(THETA)
    rho = design.mechanism.curvature_radius(THETA, m.lift, m.velocity, m.acceleration)
    if rho.min() <= 0.5:
        return  # near a cusp the parametric form is ill-conditioned
    assert rho == pytest.approx(_parametric_rho(design), rel=1e-8)


@given(oscillating_designs)
def test_oscillating_closed_form_curvature_matches_parametric(design: CamDesign) -> None:
    m = design.program.evaluate(THETA)
    rho = design.mechanism.curvature_radius(THETA, m.lift, m.velocity, m.acceleration)
    if rho.min() <= 0.5 or m.velocity.max() > 0.9:
        return
    assert rho == pytest.approx(_parametric_rho(design), rel=1e-7)


@given(translating_designs)
def test_translating_special_forms(design: CamDesign) -> None:
    mech = design.mechanism
    assert isinstance(mech, FlatTranslating)
    k = kinematics(design, THETA, check=False)
    phi = mech.face_angle_rad
    # sin λ = V cos φ / |O2A| (THEORY §2.5) and the profile does not depend on e
    assert np.sin(k.shift_angle_rad) == pytest.approx(
        k.velocity * math.cos(phi) / k.radius_mm, abs=1e-12
    )
    other = kinematics(
        CamDesign(
            "t", FlatTranslating(mech.base_radius_mm, mech.offset_mm + 3.0, phi), design.program
        ),
        THETA,
        check=False,
    )
    assert other.contact_x_mm == pytest.approx(k.contact_x_mm, abs=1e-9)
    # the common normal passes through Q: (A − Q) ∥ n
    n = np.stack([np.cos(THETA + phi), np.sin(THETA + phi)])
    qa = np.stack([k.contact_x_mm - k.centre_x_mm, k.contact_y_mm - k.centre_y_mm])
    assert np.abs(qa[0] * n[1] - qa[1] * n[0]) == pytest.approx(0.0, abs=1e-9)


def _translating_exact_lift(design: CamDesign, e: float, phi: float) -> np.ndarray:
    """Exact S of a follower with offset e and face angle phi on the *nominal* cam."""
    mech = design.mechanism
    assert isinstance(mech, FlatTranslating)
    phi0 = mech.face_angle_rad
    # Face normal at θ + phi touches the nominal cam where ψ = θ' + phi0, i.e. θ' = θ + phi − phi0
    tp = THETA + (phi - phi0)
    p = mech.base_radius_mm + design.program.evaluate(tp).lift * math.cos(phi0)
    big_l = (p - e * math.sin(phi)) / math.cos(phi)
    # S measured as the nominal mechanism measures it: L − (r_b sec φ0 − e0 tan φ0)
    return big_l - (mech.base_radius_mm / math.cos(phi0) - mech.offset_mm * math.tan(phi0))


@given(translating_designs)
def test_translating_sensitivities_match_exact_resolution(design: CamDesign) -> None:
    mech = design.mechanism
    assert isinstance(mech, FlatTranslating)
    nominal = design.program.evaluate(THETA).lift
    for key, dev in (("e", 0.009), ("phi", math.radians(0.011))):
        e = mech.offset_mm + (dev if key == "e" else 0.0)
        phi = mech.face_angle_rad + (dev if key == "phi" else 0.0)
        exact = _translating_exact_lift(design, e, phi) - nominal
        lin = error_analysis(design, [ResolvedTolerance(key, dev, "mm", "")], THETA)
        linear = lin.sources[key].delta_lift
        # second-order remainder: |exact − linear| ≲ C·dev², far below 1% of the value
        assert np.max(np.abs(exact - linear)) <= 0.01 * np.max(np.abs(linear)) + 1e-9


def _oscillating_exact_angle(design: CamDesign, f: float, e: float) -> np.ndarray:
    """Exact ξ of a face at distance e from a pivot at distance f on the nominal cam."""
    mech = design.mechanism
    assert isinstance(mech, FlatOscillating)

    def xi_nom(t: np.ndarray) -> np.ndarray:
        return mech.initial_angle_rad + design.program.evaluate(t).lift

    # Tangency: the same face-normal direction ψ = θ + 90° − ξ' = t + 90° − ξ(t) and the
    # same support value f' sin ξ' + e' = f sin ξ(t) + e0. Solve for t by Newton.
    t = THETA.copy()
    for _ in range(30):

        def g(tt: np.ndarray) -> np.ndarray:
            xi_p = xi_nom(tt) + THETA - tt
            return (
                mech.pivot_distance_mm * np.sin(xi_nom(tt))
                + mech.face_offset_mm
                - (f * np.sin(xi_p) + e)
            )

        h = 1e-7
        step = g(t) / ((g(t + h) - g(t - h)) / (2 * h))
        t = t - step
        if np.max(np.abs(step)) < 1e-14:
            break
    return xi_nom(t) + THETA - t


@given(oscillating_designs)
def test_oscillating_sensitivities_match_exact_resolution(design: CamDesign) -> None:
    """Proves the signs of THEORY §3.2 (CW06 eqs. 34-35 misprint them)."""
    mech = design.mechanism
    assert isinstance(mech, FlatOscillating)
    if design.program.evaluate(THETA).velocity.max() > 0.8:
        return
    xi0 = mech.initial_angle_rad + design.program.evaluate(THETA).lift
    for key, dev in (("f", 0.019), ("e", 0.011)):
        f = mech.pivot_distance_mm + (dev if key == "f" else 0.0)
        e = mech.face_offset_mm + (dev if key == "e" else 0.0)
        exact = _oscillating_exact_angle(design, f, e) - xi0
        linear = error_analysis(design, [ResolvedTolerance(key, dev, "mm", "")], THETA)
        lin = linear.sources[key].delta_lift
        assert np.max(np.abs(exact - lin)) <= 0.01 * np.max(np.abs(lin)) + 1e-9


@given(translating_designs)
def test_translating_shift_angle_zero_on_dwell_and_offset_error_constant(
    design: CamDesign,
) -> None:
    dwell = np.radians(np.linspace(121, 179, 30))
    k = kinematics(design, dwell, check=False)
    assert k.shift_angle_rad == pytest.approx(0.0, abs=1e-15)
    err = error_analysis(
        design,
        [
            ResolvedTolerance("r", 0.019, "mm", ""),
            ResolvedTolerance("e", 0.009, "mm", ""),
            ResolvedTolerance("phi", 1.9e-4, "rad", ""),
        ],
        THETA,
    )
    de = err.sources["e"].delta_lift
    assert de == pytest.approx(np.full_like(de, de[0]), abs=1e-15)
    parts = np.abs(np.stack([s.delta_lift for s in err.sources.values()]))
    assert np.all(err.worst_lift >= err.rms_lift - 1e-15)
    assert np.all(err.rms_lift >= parts.max(axis=0) - 1e-15)


def test_translating_validation_messages() -> None:
    with pytest.raises(DesignError, match=r"follower.base_radius_mm=-40 .* positive length"):
        FlatTranslating(-40.0)
    with pytest.raises(DesignError, match=r"follower.face_angle_deg=95 .* between -90 and 90"):
        FlatTranslating(40.0, 0.0, math.radians(95))


def test_oscillating_validation_messages() -> None:
    with pytest.raises(DesignError, match=r"pivot_distance_mm=20 is too short"):
        FlatOscillating(40.0, 20.0, 0.0)


def test_cusp_is_reported_with_angle() -> None:
    # r_b = 5 mm with a 22 mm rise over 40°: ρ = r_b + S + A < 0 during the rise.
    d = CamDesign("cusp", FlatTranslating(5.0), _program(22.0, rise=40, dwell=10))
    with pytest.raises(UndercutError, match=r"radius of curvature -\d.* at θ=\d+\.\d\d°"):
        kinematics(d, THETA)


def test_oscillating_velocity_ratio_at_least_one_is_reported() -> None:
    # a 60° swing in 30°: V peaks at 2·60/30 = 4 > 1
    d = CamDesign("fast", FlatOscillating(40, 80, 16), _program(math.radians(60), rise=30))
    with pytest.raises(GeometryError, match=r"V reaches 4 at θ=15.0\d°.*V < 1"):
        kinematics(d, THETA)


def test_jet_and_plain_contact_agree() -> None:
    d = CamDesign("t", FlatOscillating(40, 80, 16), _program(math.radians(15)))
    m = d.program.evaluate(THETA)
    plain = d.mechanism.contact(THETA, m.lift, m.velocity)
    jets = d.mechanism.contact(
        Jet.variable(THETA),
        to_jet(m.lift, m.velocity, m.acceleration),
        to_jet(m.velocity, m.acceleration, m.jerk),
    )
    assert jet.value(jets.contact_x) == pytest.approx(plain.contact_x, rel=1e-13, abs=1e-13)
    assert jet.value(jets.shift_angle) == pytest.approx(plain.shift_angle, rel=1e-13, abs=1e-13)


@given(translating_designs)
def test_translating_closed_form_shift_angle_and_radius_equal_the_points(
    design: CamDesign,
) -> None:
    """λ = asin(p'/|O2A|) and |O2A| = √(p² + p'²) (the support function) as jets: those of
    the cross product of §2.5 and of the contact point's norm, derivatives included."""
    from camtol.mechanisms.base import shift_angle

    m = design.program.evaluate(THETA)
    g = design.mechanism.contact(
        Jet.variable(THETA),
        to_jet(m.lift, m.velocity, m.acceleration),
        to_jet(m.velocity, m.acceleration, m.jerk),
    )
    general = shift_angle(g.contact_x, g.contact_y, g.centre_x, g.centre_y)
    norm = jet.hypot(g.contact_x, g.contact_y)
    for closed, points, atol in ((g.shift_angle, general, 1e-12), (g.extras["radius"], norm, 1e-9)):
        assert isinstance(closed, Jet) and isinstance(points, Jet)
        for part in ("v", "d1", "d2"):
            np.testing.assert_allclose(getattr(closed, part), getattr(points, part), atol=atol)
    # Plain arrays (the engine's path): the same values.
    plain = design.mechanism.contact(THETA, m.lift, m.velocity)
    np.testing.assert_allclose(plain.shift_angle, general.v, atol=1e-14)
    np.testing.assert_allclose(plain.extras["radius"], norm.v, rtol=1e-15)


@given(st.one_of(translating_designs, oscillating_designs))
def test_lean_sensitivities_equal_general_form(design: CamDesign) -> None:
    """The hot path (support-function forms) agrees with the cross-product λ of §2.5."""
    m = design.program.evaluate(THETA)
    if design.mechanism.output == "oscillating" and m.velocity.max() > 0.9:
        return
    args = (
        Jet.variable(THETA),
        to_jet(m.lift, m.velocity, m.acceleration),
        to_jet(m.velocity, m.acceleration, m.jerk),
    )
    mech = design.mechanism
    lean = mech.error_sensitivities(*args)
    general = mech.sensitivities(mech.contact(*args), args[0])
    for key in general:
        a, b = lean[key], general[key]
        for part in ("v", "d1", "d2"):
            x = getattr(a, part) if isinstance(a, Jet) else (jet.value(a) if part == "v" else 0.0)
            y = getattr(b, part) if isinstance(b, Jet) else (jet.value(b) if part == "v" else 0.0)
            assert np.allclose(x, y, rtol=1e-9, atol=1e-12), (key, part)


def test_cam_reaching_the_pivot_is_reported() -> None:
    # r_b = 59.75 mm, f = 70 mm, 18° swing: the profile reaches beyond the pivot (found by
    # hypothesis in the contact engine's round-trip test; the analytic engine must say so).
    d = CamDesign(
        "hits-pivot", FlatOscillating(59.75, 70.0, 4.0), _program(math.radians(18), rise=93)
    )
    with pytest.raises(GeometryError, match=r"reaches 7\d\.\d+ mm .* beyond the follower pivot"):
        kinematics(d, THETA)
