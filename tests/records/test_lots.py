"""Lot statistics against numpy and scipy computed by hand."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from camtol.exceptions import RecordError
from camtol.records.lots import deviation_on_grid, lot_statistics, resample_periodic


def _lot(rng: np.random.Generator, n_parts: int = 12, n: int = 360) -> np.ndarray:
    theta = np.arange(n) * (2 * np.pi / n)
    wear = 0.8 * np.arange(n_parts)[:, None]  # a steady drift: tool wear
    return (
        6.0 * np.sin(theta)[None, :]
        + wear
        + rng.normal(0.0, 1.5, size=(n_parts, 1))
        + rng.normal(0.0, 0.3, size=(n_parts, n))
    )


def test_per_angle_statistics_and_capability_by_hand(rng: np.random.Generator) -> None:
    table = _lot(rng)
    failed = [False] * 9 + [True] * 3
    st = lot_statistics(list(table), (-15.0, 20.0), failed)
    np.testing.assert_allclose(st.mean_um, table.mean(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(st.std_um, table.std(axis=0, ddof=1), rtol=1e-12)
    np.testing.assert_array_equal(st.max_um, table.max(axis=0))
    np.testing.assert_array_equal(st.min_um, table.min(axis=0))
    np.testing.assert_allclose(st.theta_deg, np.arange(360.0))

    pmax, pmin = table.max(axis=1), table.min(axis=1)
    s_max, s_min = pmax.std(ddof=1), pmin.std(ddof=1)
    assert st.pp == pytest.approx(35.0 / (6 * s_max), rel=1e-12)
    assert st.ppu == pytest.approx((20.0 - pmax.mean()) / (3 * s_max), rel=1e-12)
    assert st.ppl == pytest.approx((pmin.mean() + 15.0) / (3 * s_min), rel=1e-12)
    assert st.ppk == min(st.ppu, st.ppl)

    ci = stats.binomtest(3, 12).proportion_ci(confidence_level=0.95, method="exact")
    assert st.n_failing == 3 and st.fraction_failing == 0.25
    assert st.fraction_failing_ci == pytest.approx((ci.low, ci.high), rel=1e-9)

    fit = stats.linregress(np.arange(12.0), pmax)
    assert st.trend_um_per_part == pytest.approx(fit.slope, rel=1e-10)
    assert st.trend_stderr_um_per_part == pytest.approx(fit.stderr, rel=1e-9)
    assert st.trend_um_per_part > 0.3  # the simulated wear (0.8 µm/part) shows


def test_pooling_in_blocks_matches_the_whole_table(rng: np.random.Generator) -> None:
    # 101 parts: blocks of 32 and a partial one, merged by the pairwise update; a large
    # common offset (1 mm) against a 0.3 µm spread checks it is as stable as two passes.
    table = 1000.0 + rng.normal(0.0, 0.3, size=(101, 50))
    st = lot_statistics(list(table), (990.0, 1010.0), [False] * 101)
    np.testing.assert_allclose(st.mean_um, table.mean(axis=0), rtol=1e-15, atol=0)
    np.testing.assert_allclose(st.std_um, table.std(axis=0, ddof=1), rtol=1e-10)
    np.testing.assert_array_equal(st.part_max_um, table.max(axis=1))
    np.testing.assert_array_equal(st.min_um, table.min(axis=0))


def test_trend_uses_the_given_sequence(rng: np.random.Generator) -> None:
    table = _lot(rng, n_parts=5)
    serials = [101.0, 103.0, 104.0, 110.0, 111.0]
    st = lot_statistics(list(table), (-30.0, 30.0), [False] * 5, sequence=serials)
    slope = np.polyfit(serials, table.max(axis=1), 1)[0]
    assert st.trend_um_per_part == pytest.approx(slope, rel=1e-10)


def test_edge_cases_one_part_and_no_failures() -> None:
    st = lot_statistics([np.array([1.0, 2.0, 3.0])], (-5.0, 5.0), [False])
    assert st.n_parts == 1
    assert np.all(np.isnan(st.std_um)) and np.isnan(st.pp) and np.isnan(st.ppk)
    assert np.isnan(st.trend_um_per_part)
    lo, hi = st.fraction_failing_ci
    assert lo == 0.0 and hi == pytest.approx(1 - 0.025 ** (1 / 1))  # exact for k = 0, n = 1


def test_curves_on_different_grids_are_resampled() -> None:
    theta_a = np.arange(360) * (2 * np.pi / 360)
    theta_b = np.arange(720) * (2 * np.pi / 720)
    st = lot_statistics([np.cos(theta_a), np.cos(theta_b)], (-2.0, 2.0), [False, False])
    assert st.theta_deg.size == 720
    np.testing.assert_allclose(st.mean_um, np.cos(theta_b), atol=4e-5)  # linear interp error
    v = np.array([0.0, 1.0, 2.0, 3.0])
    np.testing.assert_allclose(resample_periodic(v, 8), [0, 0.5, 1, 1.5, 2, 2.5, 3, 1.5])


@pytest.mark.parametrize(
    ("args", "kw", "match"),
    [
        (([], (-1.0, 1.0), []), {}, "at least one record"),
        (([np.zeros(3)], (1.0, -1.0), [False]), {}, "need lower < upper"),
        (([np.zeros(3)], (-1.0, 1.0), [False, True]), {}, "failed has 2 entries"),
        (([np.zeros(3)], (-1.0, 1.0), [False]), {"confidence": 1.0}, "confidence=1.0"),
        (([np.zeros(3)], (-1.0, 1.0), [False]), {"sequence": [1, 2]}, "sequence has 2"),
    ],
)
def test_bad_input_is_named(args: tuple, kw: dict, match: str) -> None:  # type: ignore[type-arg]
    with pytest.raises(RecordError, match=match):
        lot_statistics(*args, **kw)


def test_scattered_points_onto_the_grid(rng: np.random.Generator) -> None:
    theta = rng.uniform(-180.0, 540.0, 3600)  # any order, any range
    dr = 4.0 * np.cos(np.radians(theta)) + 1.0
    got = deviation_on_grid(theta, dr, 720)
    want = 4.0 * np.cos(np.radians(np.arange(720) * 0.5)) + 1.0
    # linear interpolation over gaps of at most ~2° on a 4 µm cosine: error < 4·(2°)²/8 rad²
    np.testing.assert_allclose(got, want, atol=4.0 * np.radians(2.0) ** 2 / 8)
    with pytest.raises(RecordError, match="n_points=0"):
        deviation_on_grid(theta, dr, 0)
