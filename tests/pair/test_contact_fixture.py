"""Exact simulation of the conjugate measuring fixture (THEORY §4, §5, §8.3; [CW11])."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camtol.analysis.kinematics import analysis_grid
from camtol.config.design_file import load_example
from camtol.contact.engine import follow
from camtol.contact.errors_profile import CallableError, FourierError
from camtol.contact.shapes import AnalyticShape
from camtol.exceptions import GeometryError
from camtol.mechanisms.conjugate import ConjugatePair
from camtol.pair.contact_fixture import Fixture, simulate_fixture
from camtol.pair.fixture_spec import FixtureErrors
from camtol.pair.variation import conjugate_factors, conjugate_variation


@pytest.fixture(scope="module")
def cw11() -> tuple[object, ConjugatePair, AnalyticShape, AnalyticShape]:
    d = load_example("cw11-conjugate")
    pair = d.mechanism
    assert isinstance(pair, ConjugatePair)
    return d, pair, AnalyticShape(pair.cam_a, d.program), AnalyticShape(pair.cam_b, d.program)


def test_nominal_fixture_reproduces_motion_and_zero_variation(cw11: tuple) -> None:
    d, pair, a, b = cw11
    theta, left = analysis_grid(0.25, d.program.boundaries_rad)
    res = simulate_fixture(
        theta, a, b, Fixture.of(pair), initial_angle_rad=pair.initial_angle_rad, left_limit=left
    )
    m = d.program.evaluate(theta, left_limit=left)
    assert np.max(np.abs(res.lift - m.lift)) <= 1e-9  # acceptance: round trip 1e-9 rad
    assert np.max(np.abs(res.extras["delta_f_mm"])) <= 1e-9  # and Δf = 0 to 1e-9 mm
    np.testing.assert_allclose(res.velocity, m.velocity, atol=1e-9)


def test_master_cams_and_constant_errors_match_forward_analysis_to_second_order(
    cw11: tuple,
) -> None:
    # Acceptance (issue 4): the master-cam error functions of THEORY §8.3 and the constant
    # errors applied to the shapes and the fixture give a Δf that agrees with CW11 eqs.
    # 14-18 (THEORY §4.1) to second order: the difference is < 1 % of Δf and falls by 4
    # when every error is halved.
    d, pair, a, b = cw11
    spec = d.inspection
    assert spec is not None
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    fac = conjugate_factors(d, theta)
    diffs = []
    for k in (1.0, 0.5):
        ea = FourierError(18.5e-3 * k, sin_mm=(3.5e-3 * k,))
        eb = FourierError(17.5e-3 * k, cos_mm=(0.0, 4.5e-3 * k))
        e = spec.errors
        errs = FixtureErrors(
            e.dl_a_mm * k, e.dl_b_mm * k, e.drr_c_mm * k, e.drr_d_mm * k, e.deta_rad * k
        )
        res = simulate_fixture(
            theta,
            a.with_errors(radial_error=ea),
            b.with_errors(radial_error=eb),
            Fixture.of(pair, errs),
            initial_angle_rad=pair.initial_angle_rad,
        )
        var = conjugate_variation(fac, ea(theta).v * 1e3, eb(theta).v * 1e3, errs)
        exact_um = res.extras["delta_f_mm"] * 1e3
        diffs.append(np.max(np.abs(exact_um - var.df_est_um)))
        if k == 1.0:
            assert diffs[0] < 0.01 * np.max(np.abs(var.df_est_um))
    assert diffs[0] / diffs[1] == pytest.approx(4.0, rel=0.05)


def test_formula_master_errors_via_callable(cw11: tuple) -> None:
    # The fixture spec's formula errors (values only) give the same Δf as the Fourier form.
    d, pair, a, b = cw11
    spec = d.inspection
    assert spec is not None
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    ma = CallableError(lambda t: np.asarray(spec.master_a(t)) * 1e-3)
    fa = FourierError(18.5e-3, sin_mm=(3.5e-3,))
    r1 = simulate_fixture(
        theta,
        a.with_errors(radial_error=ma),
        b,
        Fixture.of(pair),
        initial_angle_rad=pair.initial_angle_rad,
    )
    r2 = simulate_fixture(
        theta,
        a.with_errors(radial_error=fa),
        b,
        Fixture.of(pair),
        initial_angle_rad=pair.initial_angle_rad,
    )
    np.testing.assert_allclose(r1.extras["delta_f_mm"], r2.extras["delta_f_mm"], atol=1e-11)


def test_fixed_pivot_agrees_with_single_roller_solvers(cw11: tuple) -> None:
    # Consistency of two solvers: with cam A enlarged the fixture settles at some f*; a
    # single oscillating roller on cam A with its pivot fixed at that f* sits at the same ξ.
    d, pair, a, b = cw11
    theta = np.radians(np.arange(0.0, 360.0, 10.0))
    ea = FourierError(0.03)
    res = simulate_fixture(
        theta,
        a.with_errors(radial_error=ea),
        b,
        Fixture.of(pair),
        initial_angle_rad=pair.initial_angle_rad,
    )
    fstar = res.extras["centre_distance_mm"]
    for i in (0, 7, 20):
        mech = ConjugatePair(60.0, 16.0, float(fstar[i]), 66.0, 66.0, math.radians(100.0))
        single = follow(a.with_errors(radial_error=ea), mech.cam_a, theta[i : i + 1])
        assert single.extras["follower_angle_rad"][0] == pytest.approx(
            res.extras["follower_angle_rad"][i], abs=1e-11
        )


def test_rollers_too_large_are_reported(cw11: tuple) -> None:
    d, pair, a, b = cw11
    fx = Fixture(120.0, 66.0, 66.0, 16.0, 16.0, math.radians(100.0))
    bad = Fixture(fx.pivot_mm, fx.arm_a_mm, fx.arm_b_mm, 200.0, 200.0, fx.arm_angle_rad)
    with pytest.raises(GeometryError):
        simulate_fixture(np.array([0.3]), a, b, bad, initial_angle_rad=pair.initial_angle_rad)


def _segment_distance(px: np.ndarray, py: np.ndarray, verts: np.ndarray) -> np.ndarray:
    a = verts
    ab = np.roll(a, -1, axis=0) - a
    t = ((px[:, None] - a[:, 0]) * ab[:, 0] + (py[:, None] - a[:, 1]) * ab[:, 1]) / np.sum(
        ab * ab, axis=1
    )
    t = np.clip(t, 0.0, 1.0)
    d = np.hypot(px[:, None] - a[:, 0] - t * ab[:, 0], py[:, None] - a[:, 1] - t * ab[:, 1])
    return np.asarray(np.min(d, axis=1))


def test_fixture_on_polygons_touches_both_cams(cw11: tuple) -> None:
    # Measured or cut cams are polygons: both rollers must touch (distance = radius, from
    # an independent point-to-segment evaluation), and Δf must approach the analytic
    # fixture's within the polygons' chordal sag (1440 samples: sag below 1 µm).
    d, pair, a, b = cw11
    err = FourierError(0.02, sin_mm=(0.01,))
    sa = AnalyticShape(pair.cam_a, d.program, radial_error=err, samples=1440)
    sb = AnalyticShape(pair.cam_b, d.program, samples=1440)
    theta = np.radians(np.arange(0.0, 360.0, 3.0))
    fx = Fixture.of(pair)
    xi0 = pair.initial_angle_rad
    poly = simulate_fixture(theta, sa.polygon, sb.polygon, fx, initial_angle_rad=xi0)
    exact = simulate_fixture(theta, sa, sb, fx, initial_angle_rad=xi0)
    np.testing.assert_allclose(poly.lift, exact.lift, atol=1e-4)
    dc = _segment_distance(
        poly.extras["roller_c_x_mm"], poly.extras["roller_c_y_mm"], sa.polygon.vertices_mm
    )
    dd = _segment_distance(
        poly.extras["roller_d_x_mm"], poly.extras["roller_d_y_mm"], sb.polygon.vertices_mm
    )
    np.testing.assert_allclose(dc, fx.roller_c_mm, atol=1e-9)
    np.testing.assert_allclose(dd, fx.roller_d_mm, atol=1e-9)
    diff = np.abs(poly.extras["delta_f_mm"] - exact.extras["delta_f_mm"])
    assert np.max(diff) < 1e-3
    assert np.max(diff) > 0  # the polygon is not the curve


def test_mixed_shapes_are_rejected(cw11: tuple) -> None:
    d, pair, a, b = cw11
    with pytest.raises(TypeError, match="two analytic shapes or two polygons"):
        simulate_fixture(np.array([0.0]), a, b.polygon, Fixture.of(pair), initial_angle_rad=0.0)


@pytest.mark.parametrize(
    "law", ["simple_harmonic", "polynomial_345", "polynomial_4567", "modified_trapezoid"]
)
def test_fixture_roundtrip_every_law(law: str) -> None:
    from camtol.design.motion import Segment, SegmentProgram

    r = math.radians
    prog = SegmentProgram(
        (
            Segment("rise", 0.0, r(130), law, r(25.0)),
            Segment("dwell", r(130), r(170)),
            Segment("return", r(170), r(300), law, r(25.0)),
            Segment("dwell", r(300), 2 * math.pi),
        )
    )
    pair = ConjugatePair(60.0, 16.0, 120.0, 66.0, 66.0, r(100.0))
    theta, left = analysis_grid(0.5, prog.boundaries_rad)
    res = simulate_fixture(
        theta,
        AnalyticShape(pair.cam_a, prog),
        AnalyticShape(pair.cam_b, prog),
        Fixture.of(pair),
        initial_angle_rad=pair.initial_angle_rad,
        left_limit=left,
    )
    assert np.max(np.abs(res.lift - prog.evaluate(theta, left_limit=left).lift)) <= 1e-9
    assert np.max(np.abs(res.extras["delta_f_mm"])) <= 1e-9
