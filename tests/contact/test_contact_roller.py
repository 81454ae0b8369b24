"""Exact roller follower motion on any shape (THEORY §5, §2.3, §2.4)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from contact_designs import (
    conjugate_pair,
    program,
    r,
    roller_oscillating,
    roller_translating,
    star_polygon,
)
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.contact.engine import follow
from camtol.contact.errors_profile import FourierError
from camtol.contact.roller_path import roller_path
from camtol.contact.roller_polygon import _features, solve_polygon
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design.cam_design import CamDesign
from camtol.design.motion import SegmentProgram
from camtol.exceptions import DesignError, GeometryError
from camtol.mechanisms import FlatTranslating, RollerOscillating, RollerTranslating
from camtol.mechanisms.base import Mechanism


def roundtrip(mech: Mechanism, prog: SegmentProgram, step: float = 0.25) -> np.ndarray:
    theta, left = analysis_grid(step, prog.boundaries_rad)
    res = follow(AnalyticShape(mech, prog), mech, theta, left_limit=left)
    m = prog.evaluate(theta, left_limit=left)
    return np.array(
        [
            np.max(np.abs(res.lift - m.lift)),
            np.max(np.abs(res.velocity - m.velocity)),
            np.max(np.abs(res.acceleration - m.acceleration)),
        ]
    )


@pytest.mark.parametrize(
    ("mech", "prog"),
    [
        (roller_translating().mechanism, roller_translating().program),
        (roller_oscillating().mechanism, roller_oscillating().program),
        (conjugate_pair().cam_a, program(r(30.0))),
        (conjugate_pair().cam_b, program(r(30.0))),
    ],
    ids=["translating", "oscillating", "conjugate-A", "conjugate-B"],
)
def test_roundtrip_rollers(mech: Mechanism, prog: SegmentProgram) -> None:
    # Acceptance: the synthesised profile (THEORY §2.3/§2.4, written by the mechanism
    # modules) gives back S within 1e-9; V and A exactly too (one-sided at boundaries).
    err = roundtrip(mech, prog, 0.1)
    assert err[0] <= 1e-9
    assert err[1] <= 1e-9
    assert err[2] <= 1e-8


@settings(max_examples=20, deadline=None)
@given(
    rb=st.floats(25.0, 70.0),
    rf=st.floats(3.0, 20.0),
    e=st.floats(-15.0, 15.0),
    h=st.floats(2.0, 25.0),
    rise=st.floats(90.0, 170.0),
    law=st.sampled_from(["cycloidal", "polynomial_345", "polynomial_4567", "modified_sine"]),
)
def test_roundtrip_random_translating_rollers(
    rb: float, rf: float, e: float, h: float, rise: float, law: str
) -> None:
    d = CamDesign("x", RollerTranslating(rb, rf, e), program(h, rise, 20, 150, law))
    kin = kinematics(d, np.linspace(0, 2 * math.pi, 1441), check=False)
    rho = kin.curvature_radius_mm
    # Valid: no undercut (concave parts allowed), pressure angle below 60°.
    assume(np.all((rho > 0.5) | (rho < -rf - 0.5)))
    assume(np.max(np.abs(kin.pressure_angle_rad)) < r(60))
    assert roundtrip(d.mechanism, d.program, 0.5)[0] <= 1e-9


@settings(max_examples=20, deadline=None)
@given(
    rb=st.floats(30.0, 60.0),
    rf=st.floats(5.0, 20.0),
    f=st.floats(90.0, 140.0),
    arm=st.floats(50.0, 90.0),
    swing=st.floats(5.0, 30.0),
    rise=st.floats(90.0, 170.0),
)
def test_roundtrip_random_oscillating_rollers(
    rb: float, rf: float, f: float, arm: float, swing: float, rise: float
) -> None:
    assume(abs(f - arm) < rb + rf < f + arm)
    d = CamDesign("x", RollerOscillating(rb, rf, f, arm), program(r(swing), rise, 20, 150))
    kin = kinematics(d, np.linspace(0, 2 * math.pi, 1441), check=False)
    rho = kin.curvature_radius_mm
    assume(np.max(kin.velocity) < 0.8 and np.all(np.isfinite(rho)))
    assume(np.all((rho > 0.5) | (rho < -rf - 0.5)))
    assume(np.max(np.abs(kin.pressure_angle_rad)) < r(60))
    assert roundtrip(d.mechanism, d.program, 0.5)[0] <= 1e-9


@pytest.mark.parametrize("kind", ["translating", "oscillating", "cam_b"])
def test_prefilter_equals_bruteforce_on_nonconvex_polygons(
    kind: str, rng: np.random.Generator
) -> None:
    mech: Mechanism = {
        "translating": RollerTranslating(45.0, 8.0, 4.0),
        "oscillating": RollerOscillating(45.0, 8.0, 110.0, 70.0),
        "cam_b": conjugate_pair().cam_b,
    }[kind]
    path = roller_path(mech)[0]
    pts = star_polygon(rng, 400, 50.0 if kind != "cam_b" else 62.0, 6.0)
    bulges = np.where(rng.uniform(size=400) < 0.3, rng.uniform(-0.2, 0.2, 400), 0.0)
    poly = PolygonShape(pts, bulges)
    theta = np.linspace(0, 2 * math.pi, 181)
    fast = solve_polygon(theta, poly, path)
    brute = solve_polygon(theta, poly, path, bruteforce=True)
    np.testing.assert_allclose(fast[0], brute[0], rtol=0, atol=1e-11)
    np.testing.assert_array_equal(fast[5], brute[5])


def test_roller_on_polygon_touches_and_is_clear(rng: np.random.Generator) -> None:
    # Independent check: the roller centre is exactly r_f from the polygon (distance to
    # every segment, evaluated directly) — touching, not overlapping.
    pts = star_polygon(rng, 150, 50.0, 7.0)
    poly = PolygonShape(pts)
    mech = RollerTranslating(45.0, 6.0, 3.0)
    theta = np.linspace(0, 2 * math.pi, 241)
    res = follow(poly, mech, theta)
    cx, cy = res.extras["roller_x_mm"], res.extras["roller_y_mm"]
    a = poly.vertices_mm
    b = np.roll(a, -1, axis=0)
    ab = b - a
    t = ((cx[:, None] - a[:, 0]) * ab[:, 0] + (cy[:, None] - a[:, 1]) * ab[:, 1]) / np.sum(
        ab * ab, axis=1
    )
    t = np.clip(t, 0, 1)
    dist = np.hypot(cx[:, None] - a[:, 0] - t * ab[:, 0], cy[:, None] - a[:, 1] - t * ab[:, 1])
    np.testing.assert_allclose(np.min(dist, axis=1), 6.0, atol=1e-10)
    # The contact point is on the polygon boundary at r_f from the centre.
    np.testing.assert_allclose(
        np.hypot(cx - res.contact_x_mm, cy - res.contact_y_mm), 6.0, atol=1e-10
    )


def test_translating_roller_on_eccentric_circle_is_exact() -> None:
    # A circle of radius R centred at c, given as arcs: the roller centre lies on the circle
    # R + r_f about c, y = c·t + sqrt((R + r_f)² − (e − c·w)²).
    rad, c, rf, e = 30.0, np.array([-5.0, 3.0]), 8.0, 4.0
    ang = np.array([0.2, 1.8, 3.3, 4.9])
    verts = c + rad * np.column_stack([np.cos(ang), np.sin(ang)])
    sweeps = np.diff(np.append(ang, ang[0] + 2 * math.pi))
    poly = PolygonShape(verts, np.tan(sweeps / 4))
    mech = RollerTranslating(25.0, rf, e)
    theta = np.linspace(0, 2 * math.pi, 721)
    res = follow(poly, mech, theta)
    ct, st_ = np.cos(theta), np.sin(theta)
    ct_, cw = c[0] * ct + c[1] * st_, -c[0] * st_ + c[1] * ct
    y = ct_ + np.sqrt((rad + rf) ** 2 - (e - cw) ** 2)
    np.testing.assert_allclose(res.lift, y - mech.s0_mm, atol=1e-11)
    h = 1e-5

    def y_of(t: np.ndarray) -> np.ndarray:
        a1 = c[0] * np.cos(t) + c[1] * np.sin(t)
        a2 = -c[0] * np.sin(t) + c[1] * np.cos(t)
        return a1 + np.sqrt((rad + rf) ** 2 - (e - a2) ** 2)

    np.testing.assert_allclose(res.velocity, (y_of(theta + h) - y_of(theta - h)) / (2 * h),
                               atol=1e-8)  # fmt: skip
    h2 = 1e-3  # second differences need a larger step; truncation about 1e-6
    np.testing.assert_allclose(
        res.acceleration,
        (y_of(theta + h2) - 2 * y_of(theta) + y_of(theta - h2)) / h2**2,
        atol=1e-5,
    )


def test_notch_narrower_than_roller_is_bridged() -> None:
    # A square with a narrow deep notch on its right side: the roller (r_f = 5) cannot
    # enter a 2 mm notch; it rests on the notch's corners.
    sq = np.array(
        [[40, -40], [40, -1], [20, -1], [20, 1], [40, 1], [40, 40], [-40, 40], [-40, -40]],
        dtype=float,
    )
    poly = PolygonShape(sq)
    assert not poly.is_convex
    mech = RollerTranslating(35.0, 5.0, 0.0)
    res = follow(poly, mech, np.array([0.0]))
    # Centre on the x axis touching the corners (40, ±1): y = 40 + sqrt(25 − 1).
    assert res.lift[0] + mech.s0_mm == pytest.approx(40 + math.sqrt(24), abs=1e-12)
    # A flat face only sees the hull: the notch is invisible.
    flat = follow(poly, FlatTranslating(35.0), np.array([0.0]))
    assert flat.lift[0] == pytest.approx(40 - 35, abs=1e-12)


def test_perturbed_roller_radius_shifts_lift_by_rf_over_cos_phi() -> None:
    # THEORY §3.3: ΔS_rf = Δr_f / cos φ to first order; exact re-simulation agrees to
    # second order (difference falls by 4 when Δr_f is halved).
    d = roller_translating()
    mech = d.mechanism
    shape = AnalyticShape(mech, d.program)
    theta, left = analysis_grid(1.0, d.program.boundaries_rad)
    kin = kinematics(d, theta, left_limit=left)
    base = d.program.evaluate(theta, left_limit=left).lift
    diffs = []
    for drf in (0.02, 0.01):
        big = RollerTranslating(40.0, 10.0 + drf, 6.0)
        ds = follow(shape, big, theta, reference=mech, left_limit=left).lift - base
        diffs.append(np.max(np.abs(ds - drf / np.cos(kin.pressure_angle_rad))))
    assert diffs[0] < 0.01 * 0.02
    assert diffs[0] / diffs[1] == pytest.approx(4.0, rel=0.05)


def test_radial_error_on_roller_profile_moves_follower() -> None:
    d = roller_oscillating()
    shape = AnalyticShape(d.mechanism, d.program, radial_error=FourierError(0.03))
    theta = np.linspace(0, 2 * math.pi, 181)
    res = follow(shape, d.mechanism, theta)
    assert np.all(res.lift - d.program.evaluate(theta).lift > 0)  # material added: pushes ξ up


def test_non_roller_mechanism_is_rejected() -> None:
    with pytest.raises(DesignError, match="not a roller"):
        roller_path(FlatTranslating(40.0))


def test_unreachable_cam_is_reported() -> None:
    poly = PolygonShape(np.array([[1.0, 0], [0, 1.0], [-1.0, 0]]) + [200.0, 0])
    with pytest.raises(GeometryError, match="cannot reach"):
        follow(poly, RollerTranslating(40.0, 5.0, 30.0), np.array([math.pi]))


def test_features_face_outward() -> None:
    poly = PolygonShape(np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]]))
    feat = _features(poly, 0.5)
    # Offsets of the right edge (x = 1, outward normal +x) sit at x = 1.5.
    i = int(np.argmax(feat.nx))
    assert feat.k[i] == pytest.approx(1.5)


@pytest.mark.parametrize(
    "mech",
    [RollerTranslating(30.0, 6.0, 4.0), RollerOscillating(30.0, 6.0, 90.0, 60.0)],
    ids=["translating", "oscillating"],
)
def test_polygon_velocity_and_acceleration_are_one_sided_derivatives(mech: Mechanism) -> None:
    # On a polygon the contact moves between vertices (circles) and edges (lines); V and
    # A are the exact derivatives of the contact in place, checked against differences of
    # the lift wherever the same feature holds on both sides.
    ang = np.radians([10.0, 80.0, 150.0, 200.0, 260.0, 320.0])
    rad = np.array([30.0, 34.0, 31.0, 36.0, 30.0, 33.0])
    poly = PolygonShape(np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]))
    theta = np.linspace(0.05, 2 * math.pi - 0.05, 400)
    # Truncation of the differences is about h²/6 times the next derivative (checked to
    # scale with h²): h = 1e-5 for V, 1e-4 for A.
    mid = follow(poly, mech, theta)
    fd: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
    for h in (1e-5, 1e-4):
        lo, hi = follow(poly, mech, theta - h), follow(poly, mech, theta + h)
        same = (lo.feature == mid.feature) & (hi.feature == mid.feature)
        fd[h] = (
            same,
            (hi.lift - lo.lift) / (2 * h),
            (hi.lift - 2 * mid.lift + lo.lift) / h**2,
        )
    same, fd_v, _ = fd[1e-5]
    assert np.count_nonzero(same) > 300
    is_edge = mid.feature >= poly.size
    assert np.any(is_edge[same]) and np.any(~is_edge[same])  # both kinds are exercised
    np.testing.assert_allclose(mid.velocity[same], fd_v[same], rtol=1e-6, atol=1e-7)
    same, _, fd_a = fd[1e-4]
    np.testing.assert_allclose(mid.acceleration[same], fd_a[same], rtol=1e-4, atol=1e-3)
    # Where the feature changes, V is continuous but A jumps (a real jump on a polygon).
    assert np.max(np.abs(np.diff(mid.acceleration))) > 1.0


def test_contact_point_inside_a_concave_arc() -> None:
    # A cam whose right side is a concave arc of radius 50 centred at (90, 0): the roller
    # (r_f = 5) on the axis touches the arc's inside at x = 90 − 50 = 40, centre at 45.
    b = -math.tan(math.asin(20 / 50) / 2)  # sweep of the arc through (40 ± ..., ±20)
    xv = 90 - math.sqrt(50**2 - 20**2)
    verts = np.array([[xv, -20.0], [xv, 20.0], [-30.0, 20.0], [-30.0, -20.0]])
    poly = PolygonShape(verts, np.array([b, 0.0, 0.0, 0.0]))
    res = follow(poly, RollerTranslating(30.0, 5.0, 0.0), np.array([0.0]))
    assert res.extras["roller_x_mm"][0] == pytest.approx(45.0, abs=1e-12)
    assert res.contact_x_mm[0] == pytest.approx(40.0, abs=1e-12)
    assert res.contact_y_mm[0] == pytest.approx(0.0, abs=1e-12)


LAWS = ["cycloidal", "simple_harmonic", "polynomial_345", "polynomial_4567", "modified_sine",
        "modified_trapezoid"]  # fmt: skip


@pytest.mark.parametrize("law", LAWS)
def test_roundtrip_every_law_every_roller(law: str) -> None:
    cases: list[tuple[Mechanism, SegmentProgram]] = [
        (RollerTranslating(45.0, 10.0, -5.0), program(15.0, 150, 30, 150, law)),
        (RollerOscillating(55.0, 14.0, 120.0, 70.0), program(r(20.0), 150, 30, 150, law)),
        (conjugate_pair().cam_b, program(r(25.0), 150, 30, 150, law)),
    ]
    for mech, prog in cases:
        assert roundtrip(mech, prog, 0.5)[0] <= 1e-9


def test_analytic_shape_without_own_seed_uses_the_polygon() -> None:
    # A roller on a flat-follower design's profile: no nominal roller seed exists, so the
    # solver seeds from the sampled polygon and refines on the curve; it agrees with the
    # polygon solution to the chordal sag and touches the curve exactly.
    from contact_designs import cw06_translating

    d = cw06_translating()
    shape = AnalyticShape(d.mechanism, d.program, samples=3600)
    mech = RollerTranslating(40.0, 8.0, 2.0)
    theta = np.linspace(0, 2 * math.pi, 181)
    exact = follow(shape, mech, theta)
    poly = follow(shape.polygon, mech, theta)
    assert np.all(exact.lift >= poly.lift - 1e-12)  # the polygon is inscribed
    assert np.max(exact.lift - poly.lift) < 1e-4
    t = exact.param_rad
    px, py = shape.jets(t)
    dist = np.hypot(exact.extras["roller_x_mm"] - px.v, exact.extras["roller_y_mm"] - py.v)
    np.testing.assert_allclose(dist, 8.0, atol=1e-10)


def test_cam_cut_by_cylindrical_tool_roller_of_tool_radius() -> None:
    # THEORY §6.3 "by cutting": a cylindrical tool of radius R set at the pitch points
    # C(kδ) leaves the blank minus the tool disks, a polygon of concave arcs (radius R)
    # meeting at cusps. A roller of the tool's radius sits exactly in the tool's circle at
    # every cut angle (lift = S(kδ) exactly) and rides on the cusps in between (lift > S).
    rf = 10.0
    mech = RollerTranslating(40.0, rf, 4.0)
    prog = program(15.0, 140, 40, 140)
    delta = r(2.0)
    k = np.arange(180) * delta
    cx, cy = mech.pitch_point(k, prog.evaluate(k).lift)
    c = np.column_stack([cx, cy])
    c1 = np.roll(c, -1, axis=0)
    mid, dv = 0.5 * (c + c1), c1 - c
    dist = np.hypot(dv[:, 0], dv[:, 1])
    perp = np.column_stack([-dv[:, 1], dv[:, 0]]) / dist[:, None]
    a = np.sqrt(rf**2 - (dist / 2) ** 2)
    cand = np.stack([mid + a[:, None] * perp, mid - a[:, None] * perp])
    inner = np.argmin(np.hypot(cand[..., 0], cand[..., 1]), axis=0)
    verts = cand[inner, np.arange(180)]  # cusp between tool circles k and k+1
    # Edge i joins cusp i to cusp i+1 along tool circle i+1 (concave: negative bulge).
    ctr = np.roll(c, -1, axis=0)
    u0 = verts - ctr
    u1 = np.roll(verts, -1, axis=0) - ctr
    sweep = np.abs(np.arctan2(u0[:, 0] * u1[:, 1] - u0[:, 1] * u1[:, 0], np.sum(u0 * u1, axis=1)))
    poly = PolygonShape(verts, -np.tan(sweep / 4))
    res = follow(poly, mech, k)
    np.testing.assert_allclose(res.lift, prog.evaluate(k).lift, atol=1e-9)
    between = k + delta / 2
    res_mid = follow(poly, mech, between)
    assert np.all(res_mid.lift > prog.evaluate(between).lift)
    # The fast prefilter agrees with brute force on this all-arc shape.
    path = roller_path(mech)[0]
    th = np.linspace(0, 2 * math.pi, 361)
    np.testing.assert_allclose(
        solve_polygon(th, poly, path)[0],
        solve_polygon(th, poly, path, bruteforce=True)[0],
        atol=1e-11,
    )
