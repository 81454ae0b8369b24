"""Exact flat-faced follower motion on any shape (THEORY §5, §2.1, §2.2, §6.2, §6.3)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from contact_designs import cw06_oscillating, cw06_translating, program, r
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.contact.engine import follow
from camtol.contact.errors_profile import FourierError
from camtol.contact.flat import follow_flat_oscillating, follow_flat_translating
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design.cam_design import CamDesign
from camtol.exceptions import GeometryError
from camtol.mechanisms import FlatOscillating, FlatTranslating

LAWS = ["cycloidal", "simple_harmonic", "polynomial_345", "polynomial_4567", "modified_sine",
        "modified_trapezoid"]  # fmt: skip


def roundtrip(design: CamDesign, step_deg: float = 0.25) -> tuple[float, float, float]:
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    res = follow(AnalyticShape(design.mechanism, design.program), design.mechanism, theta,
                 left_limit=left)  # fmt: skip
    m = design.program.evaluate(theta, left_limit=left)
    return (
        float(np.max(np.abs(res.lift - m.lift))),
        float(np.max(np.abs(res.velocity - m.velocity))),
        float(np.max(np.abs(res.acceleration - m.acceleration))),
    )


@pytest.mark.parametrize("design", [cw06_translating(), cw06_oscillating()], ids=lambda d: d.name)
def test_roundtrip_published_examples(design: CamDesign) -> None:
    # Acceptance: lift within 1e-9 (mm or rad); V and A are exact as well (one-sided at
    # the segment boundaries, where A of the simple laws jumps).
    s, v, a = roundtrip(design, 0.1)
    assert s <= 1e-9
    assert v <= 1e-9
    assert a <= 1e-8


@pytest.mark.parametrize("law", LAWS)
def test_roundtrip_every_law_both_flat_followers(law: str) -> None:
    t = CamDesign("t", FlatTranslating(45.0, -7.0, r(-20.0)), program(15.0, law=law))
    o = CamDesign("o", FlatOscillating(45.0, 90.0, -10.0), program(r(12.0), 150, 30, 140, law))
    for d in (t, o):
        kinematics(d, np.linspace(0, 2 * math.pi, 721))  # valid design
        assert roundtrip(d)[0] <= 1e-9


@settings(max_examples=25, deadline=None)
@given(
    rb=st.floats(25.0, 80.0),
    e=st.floats(-20.0, 20.0),
    phi=st.floats(-30.0, 30.0),
    h=st.floats(1.0, 25.0),
    rise=st.floats(60.0, 170.0),
    dwell=st.floats(5.0, 60.0),
    law=st.sampled_from(LAWS),
    law_ret=st.sampled_from(LAWS),
)
def test_roundtrip_random_translating(
    rb: float, e: float, phi: float, h: float, rise: float, dwell: float, law: str, law_ret: str
) -> None:
    ret = min(340.0 - rise - dwell, 150.0)
    d = CamDesign("x", FlatTranslating(rb, e, r(phi)), program(h, rise, dwell, ret, law, law_ret))
    rho = kinematics(d, np.linspace(0, 2 * math.pi, 1441), check=False).curvature_radius_mm
    assume(np.min(rho) > 1.0)
    assert roundtrip(d, 0.5)[0] <= 1e-9


@settings(max_examples=25, deadline=None)
@given(
    rb=st.floats(25.0, 60.0),
    f=st.floats(70.0, 140.0),
    e=st.floats(-15.0, 20.0),
    swing=st.floats(3.0, 25.0),
    rise=st.floats(80.0, 170.0),
    law=st.sampled_from(LAWS),
)
def test_roundtrip_random_oscillating(
    rb: float, f: float, e: float, swing: float, rise: float, law: str
) -> None:
    assume(abs(rb - e) < 0.8 * f)
    d = CamDesign("x", FlatOscillating(rb, f, e), program(r(swing), rise, 20, 150, law))
    kin = kinematics(d, np.linspace(0, 2 * math.pi, 1441), check=False)
    assume(np.max(kin.velocity) < 0.9 and np.min(kin.curvature_radius_mm) > 1.0)
    assume(np.max(kin.radius_mm) < 0.95 * f)  # the cam must clear the follower pivot
    assert roundtrip(d, 0.5)[0] <= 1e-9


def test_eccentric_circle_popa() -> None:
    # THEORY §6.2 (Pop eqs. 1-7): circle r = 30, base r0 = 25, flat translating face:
    # s = e(1 − cos θ), ds/dθ = e sin θ, d²s/dθ² = e cos θ with e = 5 mm. The circle is
    # given as four circular arcs, so the contact engine's answer is exact.
    rad, r0 = 30.0, 25.0
    ecc = rad - r0
    c = np.array([-ecc, 0.0])
    ang = np.array([0.3, 1.9, 3.4, 5.0])
    verts = c + rad * np.column_stack([np.cos(ang), np.sin(ang)])
    sweeps = np.diff(np.append(ang, ang[0] + 2 * math.pi))
    poly = PolygonShape(verts, np.tan(sweeps / 4))
    theta = np.linspace(0, 2 * math.pi, 3601)
    res = follow_flat_translating(poly, FlatTranslating(r0), theta)
    np.testing.assert_allclose(res.lift, ecc * (1 - np.cos(theta)), atol=1e-12)
    np.testing.assert_allclose(res.velocity, ecc * np.sin(theta), atol=1e-12)
    np.testing.assert_allclose(res.acceleration, ecc * np.cos(theta), atol=1e-12)


def test_flat_cut_polygon_lift_error_is_rho_delta2_over_8() -> None:
    # THEORY §6.3: a cam cut by a flat tool at angles kδ is the polygon of the half-planes
    # X·n(kδ) ≤ h(kδ). At the cut angles the lift is exact; midway it exceeds S by about
    # ρ δ²/8 (ρ: local radius of curvature; the face is normal to the translation, φ = 0).
    d = CamDesign("c", FlatTranslating(40.0), program(20.0, 120, 60, 120))
    delta = r(2.0)
    k = np.arange(180) * delta
    nominal = d.program.evaluate(k).lift
    level = 40.0 + nominal  # h(ψ) of the nominal profile, φ = 0
    n0 = np.column_stack([np.cos(k), np.sin(k)])
    n1 = np.roll(n0, -1, axis=0)
    l0, l1 = level, np.roll(level, -1)
    det = n0[:, 0] * n1[:, 1] - n0[:, 1] * n1[:, 0]
    vx = (l0 * n1[:, 1] - l1 * n0[:, 1]) / det
    vy = (n0[:, 0] * l1 - n1[:, 0] * l0) / det
    poly = PolygonShape(np.column_stack([vx, vy]))
    at_cuts = follow_flat_translating(poly, d.mechanism, k)  # type: ignore[arg-type]
    np.testing.assert_allclose(at_cuts.lift, nominal, atol=1e-11)
    mid = k + delta / 2
    res = follow_flat_translating(poly, d.mechanism, mid)  # type: ignore[arg-type]
    m = d.program.evaluate(mid)
    excess = res.lift - m.lift
    rho = 40.0 + m.lift + m.acceleration
    assert np.all(excess > 0)
    np.testing.assert_allclose(excess, rho * delta**2 / 8, rtol=2e-3)
    # Segment-aware velocity: on a vertex V = X·n', and it jumps at each cut angle where
    # the contact passes to the next vertex; the jump is the length of the face's edge
    # (about ρ δ).
    eps = 1e-9
    mech = d.mechanism
    left = follow_flat_translating(poly, mech, k[1:] - eps).velocity  # type: ignore[arg-type]
    right = follow_flat_translating(poly, mech, k[1:] + eps).velocity  # type: ignore[arg-type]
    edge = np.hypot(vx - np.roll(vx, 1), vy - np.roll(vy, 1))[1:]
    np.testing.assert_allclose(right - left, edge, atol=1e-6)
    mk = d.program.evaluate(k[1:])
    np.testing.assert_allclose(edge, (40.0 + mk.lift + mk.acceleration) * delta, rtol=2e-2)


def test_oscillating_flat_on_polygon_matches_independent_root_finding(
    rng: np.random.Generator,
) -> None:
    # Non-convex polygon: the face touches the hull; ξ from brentq on the brute-force
    # support function agrees with the feature iteration.
    ang = np.sort(rng.uniform(0, 2 * math.pi, 60))
    rad = 40 + 5 * rng.uniform(-1, 1, 60)
    poly = PolygonShape(np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]))
    mech = FlatOscillating(40.0, 85.0, 12.0)
    theta = np.linspace(0, 2 * math.pi, 97)
    res = follow_flat_oscillating(poly, mech, theta)
    xi = res.extras["follower_angle_rad"]

    def g(x: float, th: float) -> float:
        h = poly.support_bruteforce(np.array([th + math.pi / 2 - x])).h_mm[0]
        return float(h - 85.0 * math.sin(x) - 12.0)

    ref = np.array([brentq(g, 0.0, 1.2, args=(th,), xtol=1e-15) for th in theta])
    np.testing.assert_allclose(xi, ref, atol=1e-12)


def test_oscillating_velocity_and_acceleration_match_finite_differences() -> None:
    d = cw06_oscillating()
    shape = AnalyticShape(d.mechanism, d.program, radial_error=FourierError(0.05, sin_mm=(0.03,)))
    theta = np.linspace(0.3, 1.8, 7)  # inside the rise
    h = 1e-4
    f = [follow(shape, d.mechanism, theta + s * h).lift for s in (-1, 0, 1)]
    res = follow(shape, d.mechanism, theta)
    np.testing.assert_allclose(res.velocity, (f[2] - f[0]) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(res.acceleration, (f[2] - 2 * f[1] + f[0]) / h**2, atol=1e-5)


def test_perturbed_translating_follower_signs() -> None:
    # THEORY §3.1: ΔS_e = −Δe tan φ exactly (a shift of the translation line).
    d = cw06_translating()
    mech = d.mechanism
    shape = AnalyticShape(mech, d.program)
    theta = np.linspace(0, 2 * math.pi, 361)
    moved = FlatTranslating(40.0, 10.0 + 0.009, r(15.0))
    res = follow(shape, moved, theta, reference=mech)
    ds = res.lift - d.program.evaluate(theta).lift
    np.testing.assert_allclose(ds, -0.009 * math.tan(r(15.0)), atol=1e-12)


def test_face_that_cannot_reach_is_reported() -> None:
    poly = PolygonShape(np.array([[100.0, 0], [0, 100.0], [-100.0, 0], [0, -100.0]]))
    with pytest.raises(GeometryError, match="towards the follower pivot"):
        follow_flat_oscillating(poly, FlatOscillating(40.0, 80.0, 16.0), np.array([0.0]))


def test_no_warnings_on_the_grid() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        roundtrip(cw06_oscillating(), 1.0)


def test_roundtrip_lift_table_program() -> None:
    # A lift table (THEORY §1: every 2°, periodic spline): the contact engine follows the
    # spline's profile exactly.
    from camtol.design.motion import LiftTable

    t = np.radians(np.arange(0.0, 360.0, 2.0))
    lift = 6.0 * (1 - np.cos(t)) / 2 + 0.8 * np.sin(2 * t) ** 2
    d = CamDesign("table", FlatTranslating(40.0, 3.0, r(10.0)), LiftTable(t, lift))
    s, v, a = roundtrip(d, 0.25)
    assert s <= 1e-9 and v <= 1e-9
