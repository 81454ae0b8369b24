"""Motion laws and programs (THEORY §1)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from camtol.design.motion import MOTION_LAWS, LiftTable, Segment, SegmentProgram, normalized_law
from camtol.exceptions import DesignError

RISE_LAWS = [n for n in MOTION_LAWS if n != "constant_velocity"]


@pytest.mark.parametrize("name", MOTION_LAWS)
def test_law_derivatives_match_finite_differences(name: str) -> None:
    # Central differences with h = 1e-5: truncation ~h² · s'''' ≲ 1e-7, so 1e-5 relative
    # to the derivative's scale is a safe bound away from interior knots.
    law = normalized_law(name)
    h = 1e-5
    x = np.linspace(0.01, 0.99, 397)
    x = x[np.min(np.abs(x[:, None] - np.arange(1, 8)[None, :] / 8), axis=1) > 2 * h]
    s, v, a, j = law(x)
    sp, vp, ap, _ = law(x + h)
    sm, vm, am, _ = law(x - h)
    for got, plus, minus in ((v, sp, sm), (a, vp, vm), (j, ap, am)):
        fd = (plus - minus) / (2 * h)
        assert np.max(np.abs(fd - got)) <= 1e-5 * max(1.0, np.max(np.abs(got)))


@pytest.mark.parametrize("name", RISE_LAWS)
def test_law_boundary_values(name: str) -> None:
    s, v, a, _ = normalized_law(name)(np.array([0.0, 1.0]))
    assert s == pytest.approx([0.0, 1.0], abs=1e-14)
    assert v == pytest.approx([0.0, 0.0], abs=1e-12)
    if name != "simple_harmonic":  # SHM's acceleration jumps at the ends (THEORY §1)
        assert a == pytest.approx([0.0, 0.0], abs=1e-12)


@pytest.mark.parametrize(
    ("name", "cv", "ca"),
    # Norton, Cam Design and Manufacturing Handbook, peak factors (printed to 4 decimals)
    [
        ("cycloidal", 2.0, 6.2832),
        ("modified_trapezoid", 2.0, 4.8881),
        ("modified_sine", 1.7596, 5.5280),
        ("polynomial_345", 1.875, 5.7735),
    ],
)
def test_law_peak_factors_match_norton(name: str, cv: float, ca: float) -> None:
    x = np.linspace(0, 1, 200001)
    _, v, a, _ = normalized_law(name)(x)
    assert v.max() == pytest.approx(cv, abs=1e-4)
    assert a.max() == pytest.approx(ca, abs=1e-4)


def test_unknown_law_message_lists_allowed() -> None:
    with pytest.raises(DesignError, match="'spline9' is unknown; allowed: cycloidal"):
        normalized_law("spline9")


def _cw06() -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0, r(120), "cycloidal", 22.0),
            Segment("dwell", r(120), r(190)),
            Segment("return", r(190), r(290), "cycloidal", 22.0),
            Segment("dwell", r(290), r(360)),
        )
    )


def test_program_values_and_periodicity() -> None:
    p = _cw06()
    m = p.evaluate(np.radians([0, 60, 150, 240, 300, 360, 420]))
    assert m.lift == pytest.approx([0, 11, 22, 11, 0, 0, 11], abs=1e-12)
    assert p.total_travel == pytest.approx(22.0)
    assert np.degrees(p.boundaries_rad) == pytest.approx([0, 120, 190, 290])


def test_program_left_and_right_limits_at_boundaries() -> None:
    p = _cw06()
    t = np.radians([120.0, 120.0, 360.0, 0.0])
    m = p.evaluate(t, left_limit=[True, False, True, False])
    beta = math.radians(120)
    # cycloidal A = 2π h/β² sin(2πx): 0 at both ends; J = 4π² h/β³ cos(2πx) jumps.
    assert m.jerk[0] == pytest.approx(4 * math.pi**2 * 22 / beta**3)
    assert m.jerk[1] == 0.0
    beta_r = math.radians(100)
    assert m.jerk[2] == 0.0
    assert m.jerk[3] == pytest.approx(4 * math.pi**2 * 22 / beta**3)
    m2 = p.evaluate(np.radians([290.0]), left_limit=[True])
    assert m2.jerk[0] == pytest.approx(-4 * math.pi**2 * 22 / beta_r**3)


def test_segment_index_by_comparisons_is_the_binary_search(monkeypatch: pytest.MonkeyPatch) -> None:
    """A few segments' index by one comparison per start: searchsorted's, row for row.

    Angles on every boundary with either limit, a NaN and random angles (issue 8).
    """
    import camtol.design.motion as motion_module

    p = _cw06()
    rng = np.random.default_rng(5)
    bounds = np.radians([0.0, 120.0, 190.0, 290.0, 360.0])
    t = np.concatenate([bounds, bounds, rng.uniform(0.0, 2 * math.pi, 9000), [math.nan]])
    left = np.zeros(t.size, bool)
    left[bounds.size : 2 * bounds.size] = True
    t = p._wrap(t)
    ours = p.segment_index(t, left_limit=left, wrapped=True)
    monkeypatch.setattr(motion_module, "_COMPARED_STARTS", 0)
    np.testing.assert_array_equal(ours, p.segment_index(t, left_limit=left, wrapped=True))


def test_a_grid_in_order_and_shuffled_give_the_same_motion() -> None:
    """Segments evaluated run by run (a grid in order) or row set by row set: bit for bit."""
    p = _cw06()
    theta = np.linspace(0.0, 2 * math.pi, 3601)
    left = np.zeros(theta.size, bool)
    left[-1] = True  # 360° as the last segment's end
    order = np.random.default_rng(7).permutation(theta.size)
    in_order = p.evaluate(theta, left_limit=left)
    shuffled = p.evaluate(theta[order], left_limit=left[order])
    for field in ("lift", "velocity", "acceleration", "jerk"):
        np.testing.assert_array_equal(getattr(in_order, field)[order], getattr(shuffled, field))
    runs = list(p._segment_rows(p._wrap(theta), left))
    assert all(isinstance(rows, slice) for _, rows in runs)
    assert [i for i, _ in runs] == [0, 1, 2, 3]


@pytest.mark.parametrize("step_deg", [0.01, 0.0375, 0.3])
def test_segment_runs_of_a_grid_in_order_are_the_segment_index(step_deg: float) -> None:
    """Runs by binary search (a grid in order): the rows segment_index gives, row for row.

    Analysis grids (each boundary twice, left limit first) and every slice of them the
    engine evaluates, with 360° wrapped to 0 (not in order: compared instead).
    """
    from camtol.analysis.kinematics import analysis_grid
    from camtol.grid import ordered_segment_runs

    r = math.radians
    programs = [
        _cw06(),
        SegmentProgram(  # starting off 0°: the grid wraps around the first start
            (
                Segment("rise", r(30), r(150), "polynomial_345", 5.0),
                Segment("return", r(150), r(390), "cycloidal", 5.0),
            )
        ),
    ]
    for p in programs:
        theta, left = analysis_grid(step_deg, p.boundaries_rad)
        for a, b in ((0, theta.size), (0, theta.size - 1), (theta.size // 3, theta.size - 5)):
            t, lft = p._wrap(theta[a:b]), left[a:b]
            index = p.segment_index(t, left_limit=lft, wrapped=True)
            runs = ordered_segment_runs(t, p._starts, lft)
            if not np.all(np.diff(t) >= 0):
                assert runs is None
                continue
            assert runs is not None
            got = np.full(t.size, -1)
            for i, lo, hi in runs:
                assert (got[lo:hi] == -1).all()
                got[lo:hi] = i
            np.testing.assert_array_equal(got, index)
            m = p.evaluate(theta[a:b], left_limit=lft)  # the numbers: as row by row
            for row in np.random.default_rng(3).integers(0, t.size, 40):
                one = p.evaluate(theta[a:b][row : row + 1], left_limit=lft[row : row + 1])
                assert m.lift[row] == one.lift[0] and m.jerk[row] == one.jerk[0]


def test_segment_runs_refuse_a_left_limit_after_its_right_limit() -> None:
    from camtol.grid import ordered_segment_runs

    t = np.array([0.0, 1.0, 1.0, 2.0])
    starts = np.array([0.0, 1.0])
    assert ordered_segment_runs(t, starts, np.array([False, True, False, False])) == [
        (0, 0, 2),
        (1, 2, 4),
    ]
    assert ordered_segment_runs(t, starts, np.array([False, False, True, False])) is None
    assert ordered_segment_runs(t[::-1].copy(), starts) is None
    # A left limit at the first start: the last segment (segment 0 is then empty).
    assert ordered_segment_runs(t, starts, np.array([True, False, False, False])) == [
        (1, 0, 1),
        (1, 1, 4),
    ]


@pytest.mark.parametrize(
    ("segments", "message"),
    [
        ((), "empty"),
        (((("rise", 0, 100, "cycloidal", 5.0)),), "cover 100°; they must cover exactly 360°"),
        (
            (("rise", 0, 180, "cycloidal", 5.0), ("return", 190, 360, "cycloidal", 5.0)),
            "does not continue the previous segment's end 180°",
        ),
        (
            (("rise", 0, 180, "cycloidal", 5.0), ("return", 180, 360, "cycloidal", 4.0)),
            "rises and returns must balance",
        ),
        (
            (("rise", 0, 180, "cubic", 5.0), ("return", 180, 360, "cycloidal", 5.0)),
            "'cubic' is unknown",
        ),
        (
            (("rise", 0, 180, "cycloidal", -5.0), ("return", 180, 360, "cycloidal", -5.0)),
            "height=-5 must be > 0",
        ),
        (
            (("rise", 0, 0, "cycloidal", 5.0), ("return", 0, 360, "cycloidal", 5.0)),
            "the end must be after the start",
        ),
    ],
)
def test_program_validation_messages(segments: tuple, message: str) -> None:  # type: ignore[type-arg]
    r = math.radians
    segs = tuple(Segment(k, r(a), r(b), law, h) for k, a, b, law, h in segments)
    with pytest.raises(DesignError, match=message.replace("(", r"\(").replace(")", r"\)")):
        SegmentProgram(segs)


def test_lift_table_reproduces_smooth_program() -> None:
    # A 1° table of the cycloidal program: the periodic spline reproduces S to ~1e-5 mm and
    # V to ~1e-3 mm/rad (cubic spline error ~ h⁴ S''''/384 with h = 1° ≈ 0.0175 rad).
    p = _cw06()
    t = np.radians(np.arange(360.0))
    table = LiftTable(t, p.evaluate(t).lift)
    fine = np.radians(np.linspace(0, 360, 7201))
    ref, got = p.evaluate(fine), table.evaluate(fine)
    assert np.max(np.abs(got.lift - ref.lift)) < 1e-4
    assert np.max(np.abs(got.velocity - ref.velocity)) < 5e-3
    assert table.total_travel == pytest.approx(22.0)


def test_lift_table_validation() -> None:
    with pytest.raises(DesignError, match="equally spaced"):
        LiftTable(np.radians(np.array([0, 1, 3, 4, 5, 6, 7, 8.0])), np.zeros(8))
    with pytest.raises(DesignError, match="at least 8"):
        LiftTable(np.radians(np.array([0, 90, 180, 270.0])), np.zeros(4))


@given(
    law=st.sampled_from(RISE_LAWS),
    rise=st.floats(30, 200),
    dwell=st.floats(5, 60),
    h=st.floats(0.1, 50),
)
def test_random_program_is_continuous_in_lift_and_velocity(
    law: str, rise: float, dwell: float, h: float
) -> None:
    r = math.radians
    p = SegmentProgram(
        (
            Segment("rise", 0, r(rise), law, h),
            Segment("dwell", r(rise), r(rise + dwell)),
            Segment("return", r(rise + dwell), r(360), law, h),
        )
    )
    b = p.boundaries_rad
    left = p.evaluate(b, left_limit=np.ones(b.size, bool))
    right = p.evaluate(b)
    assert left.lift == pytest.approx(right.lift, abs=1e-9 * h)
    assert left.velocity == pytest.approx(right.velocity, abs=1e-9 * h)


def test_table_resolution_detects_the_rounding_quantum() -> None:
    from camtol.design.table_noise import table_resolution

    x = np.linspace(0, 22, 360)
    assert table_resolution(np.round(x, 3)) == pytest.approx(1e-3)
    assert table_resolution(np.round(x, 6)) == pytest.approx(1e-6)
    assert table_resolution(np.round(x)) == pytest.approx(1.0)
    assert table_resolution(x + math.pi * 1e-7) is None  # full precision


def test_lift_table_jerk_takes_left_limits_at_knots() -> None:
    p = _cw06()
    t = np.radians(np.arange(360.0))
    table = LiftTable(t, p.evaluate(t).lift)
    knots = np.radians([30.0, 200.0])
    left = table.evaluate(knots, left_limit=[True, True]).jerk
    right = table.evaluate(knots).jerk
    inside_before = table.evaluate(knots - np.radians(0.5)).jerk
    assert left == pytest.approx(inside_before, rel=1e-12)  # J constant on each interval
    assert not np.allclose(left, right)  # and it jumps at the knot


@pytest.mark.parametrize(
    "coefficients",
    [(0, 0, 0, 10, -15, 6), (0, 0, 0, 0, 35, -84, 70, -20), (1.5, -2.0, 0.0, 3.0)],
)
def test_polynomial_laws_equal_numpy_polyval_bit_for_bit(coefficients: tuple[float, ...]) -> None:
    """The in-place Horner rule gives numpy's Polynomial values, signed zeros included."""
    from camtol.design.laws import _polynomial

    x = np.concatenate([np.linspace(0.0, 1.0, 10_001), [-0.0, 0.0, 1.0]])
    p = np.polynomial.Polynomial(coefficients)
    expected = [p(x), p.deriv(1)(x), p.deriv(2)(x), p.deriv(3)(x)]
    for got, want in zip(_polynomial(coefficients)(x), expected, strict=True):
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(np.signbit(got), np.signbit(want))


def test_evaluate_into_a_block_gives_the_same_numbers() -> None:
    # The engine has the program write S, V, A, J straight into its result block.
    p = _cw06()
    table = LiftTable(np.radians(np.arange(360.0)), p.evaluate(np.radians(np.arange(360.0))).lift)
    theta = np.radians(np.linspace(-30, 400, 1001))
    left = np.zeros(theta.shape, bool)
    left[::7] = True
    for program in (p, table):
        ref = program.evaluate(theta, left_limit=left)
        block = np.full((6, theta.size), np.nan)
        got = program.evaluate(theta, left_limit=left, out=block[1:5])
        for a, b, row in zip(
            (got.lift, got.velocity, got.acceleration, got.jerk),
            (ref.lift, ref.velocity, ref.acceleration, ref.jerk),
            block[1:5],
            strict=True,
        ):
            np.testing.assert_array_equal(a, b)
            np.testing.assert_array_equal(row, b)  # written in place
        assert np.all(np.isnan(block[[0, 5]]))  # and nowhere else
        with pytest.raises(ValueError, match=r"out has shape \(3, 1001\)"):
            program.evaluate(theta, out=block[:3])
