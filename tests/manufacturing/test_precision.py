"""Table precision (THEORY §6.1, §6.2): truncation, handbook bounds, the spline's bound."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from camtol.analysis.result import analyse
from camtol.config.design_file import design_from_mapping, load_example
from camtol.design.motion import LiftTable
from camtol.design.table_noise import spline_acceleration_gain, spline_acceleration_response
from camtol.exceptions import DesignError
from camtol.manufacturing.precision import table_precision
from camtol.report.display import analysis_notes

E_MM = 5.0


def _central_a(y: np.ndarray, h: float) -> np.ndarray:
    return (np.roll(y, 1) + np.roll(y, -1) - 2.0 * y) / h**2


@pytest.mark.parametrize("step_deg", [0.5, 1.0, 2.0, 5.0])
def test_truncation_of_second_difference_is_e_dtheta2_over_12(step_deg: float) -> None:
    # s = e(1 − cos φ): the second difference is exactly A·2(1 − cos h)/h², so its error
    # is −e cos φ (h²/12 − h⁴/360 + ...): |error| ≤ e h²/12, with equality to O(h⁴).
    h = math.radians(step_deg)
    phi = np.arange(round(360 / step_deg)) * h
    s = E_MM * (1 - np.cos(phi))
    err = _central_a(s, h) - E_MM * np.cos(phi)
    assert_allclose(err, -E_MM * np.cos(phi) * (1 - 2 * (1 - math.cos(h)) / h**2), atol=1e-9)
    bound = E_MM * h**2 / 12
    assert np.max(np.abs(err)) <= bound
    assert np.max(np.abs(err)) == pytest.approx(bound, rel=h**2 / 30 + 1e-6)
    st = table_precision(load_example("popa-eccentric"), table_step_deg=step_deg, decimals=[9])
    assert st.truncation_dA_central == pytest.approx(np.max(np.abs(err)), rel=1e-6)
    assert st.truncation_estimate_dA == pytest.approx(bound, rel=1e-3)


@pytest.mark.parametrize("name", ["cw06-translating", "cw06-oscillating", "roller-translating"])
def test_truncation_estimate_includes_jerk_jumps(name: str) -> None:
    # Cycloidal and modified-sine laws have J jumps at their ends: a second difference on a
    # jump errs by ΔJ·Δθ/6, far more than Δθ²/12·S''''. The estimate must cover it.
    st = table_precision(load_example(name), decimals=[9])
    assert st.truncation_dA_central == pytest.approx(st.truncation_estimate_dA, rel=0.01)


def test_rounded_tables_stay_within_the_handbook_bounds() -> None:
    d = load_example("popa-eccentric")
    h = math.radians(1.0)
    phi = np.arange(360) * h
    s = E_MM * (1 - np.cos(phi))
    st = table_precision(d, decimals=[2, 3, 4, 5, 6])
    for row in st.rows:
        rounded = np.round(s, row.decimals)
        change = np.abs(_central_a(rounded, h) - _central_a(s, h))
        # Rounding alone moves a second difference by at most 4 s/Δθ², s = Q/2 ([CDH]).
        assert np.max(change) <= row.bound_alternating * (1 + 1e-9)
        assert row.bound_alternating == pytest.approx(2 * row.quantum / h**2)
        assert row.bound_dip == pytest.approx(row.quantum / h**2)
        # Total error = rounding + truncation.
        assert row.max_abs_dA_central <= row.bound_alternating + st.truncation_dA_central + 1e-12
        assert row.max_abs_dA_spline <= row.bound_spline + 1e-3


def test_popas_verdict_with_numbers() -> None:
    # Popa (THEORY §6.2): 1e-3 mm badly distorted, 1e-4 marginal, 1e-6 like theory.
    st = table_precision(load_example("popa-eccentric"), decimals=[3, 4, 5, 6])
    signal = st.max_abs_acceleration
    assert signal == pytest.approx(E_MM)
    ratio = {r.decimals: r.max_abs_dA_central / signal for r in st.rows}
    assert ratio[3] > 1.0  # the error exceeds the signal
    assert 0.05 < ratio[4] < 0.2  # marginal: 5-20 %
    assert ratio[6] < 0.002  # indistinguishable: below 0.2 %
    st = table_precision(load_example("popa-eccentric"), accel_budget_pct=1.0)
    assert st.recommended_decimals == 6


def test_spline_gain_is_exactly_twelve_and_attained_by_alternation() -> None:
    n = 360
    h = 2 * math.pi / n
    assert spline_acceleration_gain(n) == pytest.approx(12.0, rel=1e-12)
    theta = np.arange(n) * h
    q = 1e-3
    alternating = 0.5 * q * (-1.0) ** np.arange(n)
    a = LiftTable(theta, alternating).evaluate(theta).acceleration
    assert np.max(np.abs(a)) == pytest.approx(6 * q / h**2, rel=1e-9)
    # The worst sequence for knot 0 follows the signs of the spline's response.
    worst = 0.5 * q * np.sign(spline_acceleration_response(n))
    a0 = LiftTable(theta, np.roll(worst[::-1], 1)).evaluate(np.array([0.0])).acceleration
    assert abs(float(a0[0])) == pytest.approx(spline_acceleration_gain(n) * 0.5 * q / h**2)


def test_spline_bound_holds_for_random_roundings(rng: np.random.Generator) -> None:
    n, q = 360, 1e-3
    h = 2 * math.pi / n
    theta = np.arange(n) * h
    bound = spline_acceleration_gain(n) * 0.5 * q / h**2
    fine = np.linspace(0, 2 * math.pi, 7200, endpoint=False)
    for _ in range(20):
        dev = rng.uniform(-0.5 * q, 0.5 * q, n)
        a = LiftTable(theta, dev).evaluate(fine).acceleration
        assert np.max(np.abs(a)) <= bound


def test_lift_table_note_states_a_bound_that_holds() -> None:
    # The case: Popa's lift every 1° rounded to 1e-3 mm; the spline's A error is
    # 14.82 mm/rad², above the old note's 2Q/Δθ² = 6.566 mm/rad².
    phi = np.arange(360.0)
    lift = np.round(E_MM * (1 - np.cos(np.radians(phi))), 3)
    data = {
        "name": "popa-table",
        "follower": {"type": "flat_translating", "base_radius_mm": 25.0},
        "motion": {"table_step_deg": 1.0, "table_lift_mm": lift.tolist()},
    }
    d = design_from_mapping(data)
    assert isinstance(d.program, LiftTable)
    bound = d.program.acceleration_noise_bound
    assert bound == pytest.approx(6e-3 / math.radians(1.0) ** 2)
    theta = np.linspace(0, 2 * math.pi, 7200, endpoint=False)
    actual = np.max(np.abs(d.program.evaluate(theta).acceleration - E_MM * np.cos(theta)))
    assert actual == pytest.approx(14.82, abs=0.01)
    assert actual <= bound + E_MM * math.radians(1.0) ** 2  # rounding bound + truncation
    a = analyse(d, step_deg=1.0)
    note = " ".join(analysis_notes(a))
    assert a.lift_table is not None and a.lift_table.acceleration_noise_bound == bound
    assert "6Q/Δθ²" in note and f"{bound:.4g}" in note


def test_bad_inputs_name_the_field() -> None:
    d = load_example("popa-eccentric")
    with pytest.raises(DesignError, match="table_step_deg=7"):
        table_precision(d, table_step_deg=7.0)
    with pytest.raises(DesignError, match="decimals"):
        table_precision(d, decimals=[3, 13])
    for bad in (math.nan, math.inf, 3.5, "3", True):  # nan and inf raised ValueError, OverflowError
        with pytest.raises(DesignError, match="decimals=.* is not allowed"):
            table_precision(d, decimals=[bad])  # type: ignore[list-item]
    assert [r.decimals for r in table_precision(d, decimals=[np.int64(3), 6.0]).rows] == [3, 6]
    with pytest.raises(DesignError, match="accel_budget_pct"):
        table_precision(d, accel_budget_pct=-1.0)
