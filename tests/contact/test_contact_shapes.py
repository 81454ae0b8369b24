"""Shapes of the contact engine: support functions, arcs, analytic profiles (THEORY §5)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from contact_designs import cw06_translating, star_polygon
from hypothesis import given, settings
from hypothesis import strategies as st

from camtol.contact.errors_profile import FourierError, TabulatedError
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.exceptions import InputFileError


def test_fast_support_equals_bruteforce_on_nonconvex_polygon(rng: np.random.Generator) -> None:
    poly = PolygonShape(star_polygon(rng, 500, 50.0, 8.0))
    assert not poly.is_convex
    psi = rng.uniform(-10, 10, 2000)
    fast, brute = poly.support(psi), poly.support_bruteforce(psi)
    np.testing.assert_allclose(fast.h_mm, brute.h_mm, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(fast.feature, brute.feature)


@settings(max_examples=30, deadline=None)
@given(st.integers(3, 200), st.integers(0, 2**32 - 1))
def test_support_matches_bruteforce_random_clouds(m: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(m, 2)) * rng.uniform(1, 100)
    poly = PolygonShape(pts)
    psi = rng.uniform(0, 2 * math.pi, 300)
    fast, brute = poly.support(psi), poly.support_bruteforce(psi)
    scale = float(np.max(np.abs(poly.vertices_mm)))
    np.testing.assert_allclose(fast.h_mm, brute.h_mm, rtol=0, atol=1e-12 * scale)
    # The supporting point attains the support value.
    dot = fast.contact_x_mm * np.cos(psi) + fast.contact_y_mm * np.sin(psi)
    np.testing.assert_allclose(dot, fast.h_mm, rtol=0, atol=1e-12 * scale)


def test_clockwise_input_is_reversed_with_bulges() -> None:
    sq = np.array([[1.0, 1.0], [1.0, -1.0], [-1.0, -1.0], [-1.0, 1.0]])  # clockwise
    b = np.array([-0.2, 0.0, 0.0, 0.0])  # arc on the right edge, bulging outward
    poly = PolygonShape(sq, b)
    area2 = np.sum(poly.vertices_mm[:, 0] * np.roll(poly.vertices_mm[:, 1], -1)) - np.sum(
        np.roll(poly.vertices_mm[:, 0], -1) * poly.vertices_mm[:, 1]
    )
    assert area2 > 0
    # The outward bulge became a positive bulge on the counterclockwise polygon.
    assert np.count_nonzero(poly.bulges > 0) == 1
    # Support in +x reaches beyond the square's edge by the arc's sagitta.
    sweep = 4 * math.atan(0.2)
    radius = 1.0 / math.sin(sweep / 2)
    sag = radius * (1 - math.cos(sweep / 2))
    assert poly.support(np.array([0.0])).h_mm[0] == pytest.approx(1.0 + sag, abs=1e-12)


def test_circle_from_four_arcs_has_constant_support() -> None:
    radius, c = 30.0, np.array([-5.0, 2.0])
    ang = np.array([0, 0.5, 1.0, 1.5]) * math.pi
    verts = c + radius * np.column_stack([np.cos(ang), np.sin(ang)])
    poly = PolygonShape(verts, np.full(4, math.tan(math.pi / 8)))
    psi = np.linspace(-3, 9, 1001)
    sup = poly.support(psi)
    expected = c[0] * np.cos(psi) + c[1] * np.sin(psi) + radius
    np.testing.assert_allclose(sup.h_mm, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(sup.radius_mm, radius, rtol=1e-12)
    brute = poly.support_bruteforce(psi)
    np.testing.assert_allclose(brute.h_mm, expected, rtol=0, atol=1e-12)


def test_concave_arcs_never_support_the_hull() -> None:
    # A square whose edges are all concave arcs: the hull is the square's corners.
    sq = np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    poly = PolygonShape(sq, np.full(4, -0.3))
    psi = np.linspace(0, 2 * math.pi, 721)
    sup = poly.support(psi)
    np.testing.assert_allclose(sup.h_mm, np.abs(np.cos(psi)) + np.abs(np.sin(psi)), atol=1e-12)
    assert np.all(sup.radius_mm == 0.0)


@pytest.mark.parametrize(
    ("verts", "message"),
    [
        (np.zeros((2, 2)), "at least 3"),
        (np.array([[0, 0], [1, 0], [np.nan, 1]]), "finite"),
        (np.zeros((4, 3)), r"\(M, 2\)"),
    ],
)
def test_bad_polygons_are_rejected(verts: np.ndarray, message: str) -> None:
    with pytest.raises(InputFileError, match=message):
        PolygonShape(verts)


def test_bulges_of_wrong_length_are_rejected() -> None:
    with pytest.raises(InputFileError, match="one per edge"):
        PolygonShape(np.eye(3)[:, :2] + [[0, 0], [0, 0], [1, 1]], np.zeros(2))


def test_fourier_error_derivatives() -> None:
    err = FourierError(0.01, cos_mm=(0.002, 0.001), sin_mm=(0.003,))
    t = np.linspace(0, 2 * math.pi, 50)
    j = err(t)
    h = 1e-5
    np.testing.assert_allclose(j.d1, (err(t + h).v - err(t - h).v) / (2 * h), atol=1e-9)
    np.testing.assert_allclose(j.d2, (err(t + h).d1 - err(t - h).d1) / (2 * h), atol=1e-8)
    assert err.scaled(0.5)(t).v == pytest.approx(0.5 * j.v)


def _fourier_one_harmonic_at_a_time(err: FourierError, t: np.ndarray) -> tuple[np.ndarray, ...]:
    """The former per-harmonic loop of FourierError.__call__, the reference."""
    v, d1, d2 = np.full_like(t, err.mean_mm), np.zeros_like(t), np.zeros_like(t)
    for k, a in enumerate(err.cos_mm, start=1):
        v, d1, d2 = (
            v + a * np.cos(k * t),
            d1 - a * k * np.sin(k * t),
            d2 - a * k * k * np.cos(k * t),
        )
    for k, b in enumerate(err.sin_mm, start=1):
        v, d1, d2 = (
            v + b * np.sin(k * t),
            d1 + b * k * np.cos(k * t),
            d2 - b * k * k * np.sin(k * t),
        )
    return v, d1, d2


@pytest.mark.parametrize("harmonics", [0, 1, 7, 100, 700])
@pytest.mark.parametrize("shape", [(3600,), (7, 13), ()])  # 3,600: several chunks
def test_vectorised_fourier_error_equals_the_loop(harmonics: int, shape: tuple[int, ...]) -> None:
    # One matrix product over the harmonics (chunked over angles) gives the values of the
    # per-harmonic loop: the same terms summed in another order, so equal to rounding
    # (1e-13 of the largest value; K·eps·max|a|k² for Δ'' at K = 700 is about 1e-13).
    rng = np.random.default_rng(harmonics)
    coef = rng.normal(size=(2, harmonics)) * 1e-3
    coef[0, ::3] = 0.0  # zero harmonics are skipped
    err = FourierError(0.02, tuple(coef[0]), tuple(coef[1][: max(0, harmonics - 2)]))
    t = rng.uniform(-7.0, 14.0, size=shape)
    got = err(t)
    for new, ref in zip(
        (got.v, got.d1, got.d2), _fourier_one_harmonic_at_a_time(err, t), strict=True
    ):
        assert np.shape(new) == np.shape(ref)
        np.testing.assert_allclose(
            new, ref, rtol=0, atol=1e-13 * max(1.0, float(np.max(np.abs(ref))))
        )


def test_tabulated_error_interpolates_and_validates() -> None:
    t = np.linspace(0, 2 * math.pi, 360, endpoint=False)
    tab = TabulatedError(t, 0.01 * np.sin(t))
    tt = np.array([0.123, 4.0])
    np.testing.assert_allclose(tab(tt).v, 0.01 * np.sin(tt), atol=1e-9)
    np.testing.assert_allclose(tab(tt).d1, 0.01 * np.cos(tt), atol=1e-7)
    with pytest.raises(InputFileError, match="equally spaced"):
        TabulatedError(t**1.01, np.zeros(360))
    with pytest.raises(InputFileError, match="at least 8"):
        TabulatedError(t[:5], np.zeros(5))


def test_radial_error_moves_profile_along_the_radius() -> None:
    d = cw06_translating()
    nominal = AnalyticShape(d.mechanism, d.program)
    err = FourierError(0.02, sin_mm=(0.005,))
    shape = nominal.with_errors(radial_error=err)
    t = np.linspace(0, 2 * math.pi, 37)
    ax, ay = nominal.jets(t)
    px, py = shape.jets(t)
    r0, r1 = np.hypot(ax.v, ay.v), np.hypot(px.v, py.v)
    np.testing.assert_allclose(r1 - r0, err(t).v, atol=1e-12)
    np.testing.assert_allclose(np.arctan2(py.v, px.v), np.arctan2(ay.v, ax.v), atol=1e-14)


def test_normal_error_moves_profile_along_the_outward_normal() -> None:
    d = cw06_translating()
    nominal = AnalyticShape(d.mechanism, d.program)
    shape = nominal.with_errors(normal_error=FourierError(0.02))
    t = np.linspace(0, 2 * math.pi, 37)
    ax, ay = nominal.jets(t)
    px, py = shape.jets(t)
    # For a translating flat face the outward normal at θ is (cos(θ+φ), sin(θ+φ)).
    psi = t + d.mechanism.face_angle_rad  # type: ignore[attr-defined]
    np.testing.assert_allclose(px.v - ax.v, 0.02 * np.cos(psi), atol=1e-12)
    np.testing.assert_allclose(py.v - ay.v, 0.02 * np.sin(psi), atol=1e-12)


def test_analytic_support_is_at_least_the_sampled_polygon() -> None:
    d = cw06_translating()
    shape = AnalyticShape(d.mechanism, d.program, samples=720)
    psi = np.linspace(0, 2 * math.pi, 1001)
    exact = shape.support(psi)
    poly = shape.polygon.support(psi)
    assert np.all(exact.h_mm >= poly.h_mm - 1e-12)
    # Chord sag of 0.5° sampling on radii ≥ 40 mm is below 2e-3 mm.
    assert np.max(exact.h_mm - poly.h_mm) < 2e-3


def test_sweep_rank_equals_searchsorted(rng: np.random.Generator) -> None:
    from camtol.contact.shapes import sweep_rank

    a = np.sort(rng.uniform(0, 10, 500))
    a[100:110] = a[100]  # ties
    for q in (rng.uniform(-1, 11, 999), np.roll(np.linspace(0, 10, 999), 300), a.copy()):
        np.testing.assert_array_equal(sweep_rank(a, q), np.searchsorted(a, q, side="right"))


def test_point_cloud_in_any_order(rng: np.random.Generator) -> None:
    pts = star_polygon(rng, 300, 40.0, 5.0)
    shuffled = pts[rng.permutation(300)]
    cloud = PolygonShape.from_point_cloud(shuffled)
    np.testing.assert_allclose(np.sort(cloud.vertices_mm, axis=0), np.sort(pts, axis=0))
    ordered = PolygonShape(pts)
    # Same cyclic sequence of vertices.
    start = int(np.argmin(np.hypot(*(cloud.vertices_mm - ordered.vertices_mm[0]).T)))
    np.testing.assert_allclose(np.roll(cloud.vertices_mm, -start, axis=0), ordered.vertices_mm)


@settings(max_examples=40, deadline=None)
@given(st.integers(3, 400), st.floats(-math.pi, math.pi), st.integers(0, 2**32 - 1))
def test_convex_hull_normals_are_numpys_unwrap(m: int, start: float, seed: int) -> None:
    # A convex counterclockwise polygon takes the O(M) branch, whose normals come from
    # the edge angles and their wrapped turns; they must be numpy's unwrap exactly.
    rng = np.random.default_rng(seed)
    t = start + np.sort(rng.uniform(0, 2 * math.pi, m))
    verts = np.column_stack([40 * np.cos(t), 25 * np.sin(t)])
    poly = PolygonShape(verts)
    if not poly.is_convex:  # nearly coincident draws can leave a collinear triple
        return
    v = poly.vertices_mm
    e = np.roll(v, -1, axis=0) - v
    expected = np.unwrap(np.arctan2(e[:, 1], e[:, 0])) - 0.5 * math.pi
    np.testing.assert_array_equal(poly._hull[1], expected)


def test_unwrap_from_turns_equals_numpy(rng: np.random.Generator) -> None:
    from camtol.contact.polygon import _edges, _unwrap

    for n in (2, 3, 50, 1000):
        ang = rng.uniform(-math.pi, math.pi, n)
        ang[::5] = rng.choice([-math.pi, math.pi], ang[::5].size)  # numpy's ±π rule
        turn = np.mod(_edges(ang) + math.pi, 2 * math.pi) - math.pi
        np.testing.assert_array_equal(_unwrap(ang, turn), np.unwrap(ang))


def test_support_carries_its_directions_and_polygon_constants(rng: np.random.Generator) -> None:
    psi = rng.uniform(-7, 7, 500)
    poly = PolygonShape(star_polygon(rng, 300, 40.0, 5.0))
    d = cw06_translating()
    analytic = AnalyticShape(d.mechanism, d.program)
    for sup in (poly.support(psi), poly.support_bruteforce(psi), analytic.support(psi)):
        np.testing.assert_array_equal(sup.normal_x, np.cos(psi))
        np.testing.assert_array_equal(sup.normal_y, np.sin(psi))
    sup = poly.support(psi)
    # Straight edges: the contact is the vertex (its own centre, ρ = 0), shared read-only.
    np.testing.assert_array_equal(sup.contact_x_mm, poly.vertices_mm[sup.feature, 0])
    np.testing.assert_array_equal(sup.contact_y_mm, sup.centre_y_mm)
    assert np.all(sup.radius_mm == 0.0) and np.all(np.isnan(sup.param_rad))
    assert not sup.contact_x_mm.flags.writeable


def test_polygon_keeps_its_own_copy_of_the_vertices() -> None:
    verts = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    poly = PolygonShape(verts)
    verts[0] = [50.0, 50.0]
    assert poly.vertices_mm[0].tolist() == [0.0, 0.0]
    with pytest.raises(InputFileError, match="at least 3"):
        PolygonShape(np.zeros((0, 2)))


@pytest.mark.parametrize("name", ["cw06-translating", "cw06-oscillating", "roller-translating"])
def test_snap_finds_the_nearest_boundary_by_search(name: str) -> None:
    """snap() searches the sorted boundaries; the same as comparing t with every one."""
    from camtol.config import load_example
    from camtol.contact.shapes import TWO_PI

    d = load_example(name)
    shape = AnalyticShape(d.mechanism, d.program)
    b = shape.boundaries_rad
    rng = np.random.default_rng(1)
    t = np.concatenate(
        [
            rng.uniform(-1.0, 7.0, 5000),
            b + rng.uniform(-2e-9, 2e-9, b.size),
            b,
            [0.0, TWO_PI, -1e-10, TWO_PI - 1e-10, 5e-10],
        ]
    )
    wrapped = np.mod(t, TWO_PI)
    every = np.append(b, TWO_PI)
    j = np.argmin(np.abs(wrapped[:, None] - every[None, :]), axis=1)
    near = np.abs(wrapped - every[j]) < 1e-9
    np.testing.assert_array_equal(shape.snap(t), np.where(near, np.mod(every[j], TWO_PI), wrapped))
