"""Second-order jets against finite differences."""

from __future__ import annotations

import numpy as np
import pytest

from camtol import jet
from camtol.jet import Jet


def _fd(f, t: np.ndarray, h: float = 1e-4) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    return (f(t + h) - f(t - h)) / (2 * h), (f(t + h) - 2 * f(t) + f(t - h)) / h**2


@pytest.mark.parametrize(
    "expr",
    [
        lambda m, t: m.sin(t) * m.cos(2 * t) + t * t / 3,
        lambda m, t: m.sqrt(2 + m.sin(t)) / (1.5 + m.cos(t)),
        lambda m, t: m.arcsin(0.5 * m.sin(t)) - m.arccos(0.3 * m.cos(t)),
        lambda m, t: m.arctan2(1 + m.sin(t), 2 + 0.5 * m.cos(3 * t)) + m.arctan(t),
        lambda m, t: m.hypot(m.cos(t), 2 * m.sin(t)) ** 1.5 - 1 / (3 - t),
        lambda m, t: m.tan(0.3 * t) - (2 - t) + 4.0 * t,
    ],
)
def test_jet_derivatives_match_finite_differences(expr) -> None:  # type: ignore[no-untyped-def]
    t = np.linspace(-1.0, 1.0, 41)
    j = expr(jet, Jet.variable(t))
    d1, d2 = _fd(lambda x: expr(np, x), t)
    assert j.v == pytest.approx(expr(np, t), rel=1e-14, abs=1e-14)
    # central differences with h=1e-4: error ≲ 1e-7 (d1) and ≲ 1e-5 (d2, roundoff ε/h²)
    assert j.d1 == pytest.approx(d1, abs=1e-6)
    assert j.d2 == pytest.approx(d2, abs=1e-4)


def test_ndarray_times_jet_stays_a_jet() -> None:
    t = np.linspace(0, 1, 5)
    out = np.full(5, 2.0) * Jet.variable(t)
    assert isinstance(out, Jet)
    assert out.d1 == pytest.approx(2.0)


def test_quotient_and_root_rules_match_the_chain_rule() -> None:
    """f/g, c/g and √f (own rules, fewer operations) equal f·g⁻¹, c·g⁻¹ and f^½ via pow."""
    rng = np.random.default_rng(7)
    f = Jet(rng.uniform(1, 2, 50), rng.normal(size=50), rng.normal(size=50))
    g = Jet(rng.uniform(1, 2, 50), rng.normal(size=50), rng.normal(size=50))
    pairs = [(f / g, f * g**-1.0), (3.0 / g, 3.0 * g**-1.0), (jet.sqrt(f), f**0.5)]
    for got, want in pairs:
        assert isinstance(got, Jet)
        for part in ("v", "d1", "d2"):
            # different operation orders in double precision: a few ulps
            np.testing.assert_allclose(getattr(got, part), getattr(want, part), rtol=1e-13)


def test_hypot_of_arrays_is_within_two_ulp_of_the_exact_norm() -> None:
    """The in-place √(x² + y²) (not ``np.hypot``) against the norm in exact arithmetic."""
    from fractions import Fraction
    from math import isqrt

    rng = np.random.default_rng(11)
    x = rng.uniform(-500.0, 500.0, 400) * 10.0 ** rng.integers(-6, 4, 400)
    y = rng.uniform(-500.0, 500.0, 400) * 10.0 ** rng.integers(-6, 4, 400)
    got = jet.hypot(x, y)
    scale = 2**200  # √ of an exact rational, to far more digits than a double holds
    exact = np.array(
        [
            isqrt(int((Fraction(a) ** 2 + Fraction(b) ** 2) * scale**2)) / scale
            for a, b in zip(x.tolist(), y.tolist(), strict=True)
        ]
    )
    assert np.all(np.abs(got - exact) <= 2 * np.spacing(exact))


@pytest.mark.parametrize(
    ("x", "y", "shape"),
    [
        (3.0, 4.0, ()),
        (np.full(3, 3.0), 4.0, (3,)),
        (3.0, np.full(3, 4.0), (3,)),
        (np.full((2, 1), 3.0), np.full(3, 4.0), (2, 3)),
    ],
)
def test_hypot_broadcasts_scalars_and_arrays(x: object, y: object, shape: tuple[int, ...]) -> None:
    out = jet.hypot(x, y)  # type: ignore[arg-type]
    assert np.shape(out) == shape
    np.testing.assert_array_equal(out, np.full(shape, 5.0))


def test_sincos_is_sin_and_cos_for_arrays_scalars_and_jets() -> None:
    t = np.linspace(-4.0, 4.0, 101)
    s, c = jet.sincos(t)
    np.testing.assert_array_equal(s, np.sin(t))
    np.testing.assert_array_equal(c, np.cos(t))
    assert jet.sincos(0.25) == (np.sin(0.25), np.cos(0.25))
    x = Jet(0.5 * t, np.cos(t), -np.sin(t))
    js, jc = jet.sincos(x)
    for got, want in ((js, jet.sin(x)), (jc, jet.cos(x))):
        assert isinstance(got, Jet) and isinstance(want, Jet)
        for part in ("v", "d1", "d2"):
            np.testing.assert_array_equal(getattr(got, part), getattr(want, part))


def test_reused_sincos_reuses_equal_angles_in_its_block_only() -> None:
    """The engine's per-chunk memo: equal angles (another array) give the same results."""
    t = np.linspace(0.0, 1.0, 50)
    with jet.reused_sincos():
        s1, c1 = jet.sincos(t)
        s2, c2 = jet.sincos(t.copy())  # equal values, another array: reused
        assert s2 is s1 and c2 is c1
        with pytest.raises(ValueError, match="read-only"):
            s1 += 1.0  # no formula can change what the next caller gets
        js, _ = jet.sincos(Jet(t.copy(), np.ones(50), np.zeros(50)))
        assert isinstance(js, Jet) and js.v is s1  # a jet of the same angles too
        other = t.copy()
        other[0] = -0.0  # bitwise different: sin(-0.0) is -0.0
        s3, _ = jet.sincos(other)
        assert s3 is not s1 and np.signbit(s3[0]) and not np.signbit(s1[0])
    s4, _ = jet.sincos(t)  # outside the block: computed afresh, writable
    assert s4 is not s1 and s4.flags.writeable
    np.testing.assert_array_equal(s4, s1)
