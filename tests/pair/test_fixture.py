"""Conjugate fixture (THEORY §4): error functions, inverse analysis, bands, verdicts."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camtol.config.inspection_table import fixture_spec_from_mapping
from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import DesignError, InputFileError
from camtol.inspection import ErrorFunction
from camtol.inspection.error_functions import parse_error_function
from camtol.inspection.units import parse_length_um
from camtol.mechanisms.conjugate import ConjugatePair
from camtol.pair.acceptance import acceptance_bands, failing_intervals
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec
from camtol.pair.variation import conjugate_factors, conjugate_variation, inverse_estimate

r = math.radians
PROGRAM = SegmentProgram(
    (
        Segment("rise", 0, r(120), "cycloidal", r(30)),
        Segment("dwell", r(120), r(160)),
        Segment("return", r(160), r(280), "cycloidal", r(30)),
        Segment("dwell", r(280), r(360)),
    )
)
DESIGN = CamDesign("cw11", ConjugatePair(60, 16, 120, 66, 66, r(100)), PROGRAM)
THETA = np.radians(np.arange(0.0, 360.0, 0.5))
FACTORS = conjugate_factors(DESIGN, THETA)


# --- error functions ---------------------------------------------------------------------
def test_constant_formula_and_degrees() -> None:
    t = np.radians([0.0, 90.0, 180.0])
    assert ErrorFunction.constant(5.0)(t) == pytest.approx([5, 5, 5])
    f = ErrorFunction.formula("18.5 + 3.5*sin(theta)")
    assert f(t) == pytest.approx([18.5, 22.0, 18.5])
    g = ErrorFunction.formula("-theta_deg/90 + 2**2 + cos(pi) + sqrt(4) + exp(0) + abs(-1)")
    assert g(t) == pytest.approx([7.0, 6.0, 5.0])


@pytest.mark.parametrize(
    "text",
    [
        "__import__('os').system('true')",
        "theta.real",
        "open('x')",
        "lambda: 1",
        "sin(theta, 2)",
        "x + 1",
        "[1, 2]",
        "theta if 1 else 2",
        "True",
        "'a'",
    ],
)
def test_formula_rejects_anything_else(text: str) -> None:
    with pytest.raises(DesignError, match="not allowed|not a valid formula"):
        ErrorFunction.formula(text)


def test_formula_syntax_error_and_non_finite() -> None:
    with pytest.raises(DesignError, match="not a valid formula"):
        ErrorFunction.formula("1 +")
    with pytest.raises(DesignError, match="not finite at θ="):
        ErrorFunction.formula("1/theta")(np.array([0.0, 1.0]))


def test_table_interpolates_periodically() -> None:
    f = ErrorFunction.table([10.0, 350.0, 180.0], [2.0, 0.0, 5.0])
    # across 0°: 350° → 0, 370° (10°) → 2, so 0° is midway = 1
    assert f(np.radians([0.0, 360.0, 720.0, 95.0])) == pytest.approx([1.0, 1.0, 1.0, 3.5])
    with pytest.raises(InputFileError, match="appears twice"):
        ErrorFunction.table([0.0, 360.0], [1.0, 2.0])


def test_csv_table(tmp_path: Path) -> None:
    p = tmp_path / "e.csv"
    p.write_text("theta_deg,um\n0,1\n# comment\n180,3\n")
    assert ErrorFunction.from_csv(p)(np.radians([90.0, 270.0])) == pytest.approx([2.0, 2.0])
    assert parse_error_function(str(p))(np.array([0.0])) == pytest.approx([1.0])
    bad = tmp_path / "bad.csv"
    bad.write_text("theta_deg,um\n0,1\n10,x\n")
    with pytest.raises(InputFileError, match="line 3"):
        ErrorFunction.from_csv(bad)
    with pytest.raises(InputFileError, match="cannot be read"):  # the shared reader's words
        ErrorFunction.from_csv(tmp_path / "missing.csv")


@pytest.mark.parametrize(
    ("text", "um"), [("22 um", 22.0), ("22µm", 22.0), ("0.022 mm", 22.0), ("-3", -3.0), (7, 7.0)]
)
def test_length_units(text: str | float, um: float) -> None:
    assert parse_length_um(text) == pytest.approx(um)


def test_length_bad_unit() -> None:
    with pytest.raises(DesignError, match="um or mm"):
        parse_length_um("22 inch", field="--df-mea")


# --- forward / inverse -------------------------------------------------------------------
errors_st = st.builds(
    FixtureErrors,
    dl_a_mm=st.floats(-0.05, 0.05),
    dl_b_mm=st.floats(-0.05, 0.05),
    drr_c_mm=st.floats(-0.02, 0.02),
    drr_d_mm=st.floats(-0.02, 0.02),
    deta_rad=st.floats(-0.005, 0.005),
)


@settings(max_examples=25, deadline=None)
@given(
    errors=errors_st,
    c=st.lists(st.floats(-50, 50), min_size=4, max_size=4),
)
def test_inverse_put_back_into_forward_returns_measurement(
    errors: FixtureErrors, c: list[float]
) -> None:
    mea = ErrorFunction.formula(f"{c[0]} + {c[1]}*sin(theta) + {c[2]}*cos(3*theta)")
    ma = ErrorFunction.formula(f"{c[3]} + 2*cos(theta)")
    mb = ErrorFunction.formula(f"{c[1] / 3} - sin(2*theta)")
    est = inverse_estimate(FACTORS, mea, ma, mb, errors)
    back_a = conjugate_variation(FACTORS, est.dr_a_est_um, mb, errors).df_est_um
    back_b = conjugate_variation(FACTORS, ma, est.dr_b_est_um, errors).df_est_um
    np.testing.assert_allclose(back_a, mea(THETA), rtol=0, atol=1e-9)
    np.testing.assert_allclose(back_b, mea(THETA), rtol=0, atol=1e-9)


def test_bands_equivalent_to_estimate_within_tolerance() -> None:
    errors = FixtureErrors(0.019, 0.019, 0.011, 0.011, r(0.022))
    ma = ErrorFunction.formula("18.5 + 3.5*sin(theta)")
    mb = ErrorFunction.formula("17.5 + 4.5*cos(2*theta)")
    mea = ErrorFunction.formula("22 + 6*sin(2*theta)")
    b = acceptance_bands(FACTORS, (-22, 22), (-15, 20), ma, mb, errors)
    est = inverse_estimate(FACTORS, mea, ma, mb, errors)
    m = mea(THETA)
    in_a = (b.df_a_lower_um <= m) & (m <= b.df_a_upper_um)
    in_b = (b.df_b_lower_um <= m) & (m <= b.df_b_upper_um)
    # Δf grows with Δr_A (gain > 0), so the band test is Δr_A,est within the tolerance
    assert np.all(FACTORS.gain_a > 0) and np.all(FACTORS.gain_b > 0)
    np.testing.assert_array_equal(in_a, (-22 <= est.dr_a_est_um) & (est.dr_a_est_um <= 22))
    np.testing.assert_array_equal(in_b, (-15 <= est.dr_b_est_um) & (est.dr_b_est_um <= 20))


def test_constant_parts_signs() -> None:
    v = conjugate_variation(FACTORS, 0, 0, FixtureErrors(deta_rad=r(0.022)))
    assert np.all(v.df_eta_um < 0)  # arms opened wider: shorter centre distance
    v = conjugate_variation(FACTORS, 0, 0, FixtureErrors(drr_c_mm=0.011, drr_d_mm=0.011))
    assert np.all(v.df_rf_um > 0)  # bigger rollers push the pivot out


# --- failing intervals -------------------------------------------------------------------
GRID = np.radians(np.arange(0.0, 360.0, 0.1))


def test_failing_intervals_located_to_hundredth_degree() -> None:
    def margin(t: np.ndarray) -> np.ndarray:
        return np.cos(t) - 0.5  # fails in (60°, 300°)

    ((a, b),) = failing_intervals(GRID, margin)
    assert a == pytest.approx(60.0, abs=0.005) and b == pytest.approx(300.0, abs=0.005)


def test_failing_interval_wrapping_through_zero_and_several() -> None:
    ((a, b),) = failing_intervals(GRID, lambda t: 0.5 - np.cos(t))
    assert a == pytest.approx(300.0, abs=0.005) and b == pytest.approx(60.0, abs=0.005)
    got = failing_intervals(GRID, lambda t: np.sin(3 * t) + 0.2)
    # sin 3θ < −0.2 on three intervals
    x = math.degrees(math.asin(0.2)) / 3
    want = [(60 + x + 120 * k, 120 - x + 120 * k) for k in range(3)]
    assert len(got) == 3
    for (ga, gb), (wa, wb) in zip(got, want, strict=True):
        assert ga == pytest.approx(wa, abs=0.005) and gb == pytest.approx(wb, abs=0.005)


def test_failing_everywhere_or_nowhere() -> None:
    assert failing_intervals(GRID, lambda t: -1 + 0 * t) == [(0.0, 360.0)]
    assert failing_intervals(GRID, lambda t: 1 + 0 * t) == []


# --- whole analysis ----------------------------------------------------------------------
def _spec(df_mea: ErrorFunction | None) -> FixtureSpec:
    return FixtureSpec(
        FixtureErrors(0.019, 0.019, 0.011, 0.011, r(0.022)),
        (-22, 22),
        (-22, 22),
        ErrorFunction.formula("18.5 + 3.5*sin(theta)"),
        ErrorFunction.formula("17.5 + 4.5*cos(2*theta)"),
        df_mea,
    )


def test_inspection_passes_inside_both_bands() -> None:
    res = inspect_conjugate(DESIGN, _spec(ErrorFunction.constant(15.0)), step_deg=1.0)
    assert res.passed is True
    assert all(v.failing_intervals_deg == [] and v.min_margin_um > 0 for v in res.verdicts.values())


def test_inspection_interval_ends_are_where_estimate_crosses_tolerance() -> None:
    res = inspect_conjugate(DESIGN, _spec(ErrorFunction.constant(22.0)), step_deg=0.5)
    assert res.passed is False
    for cam, tol in (("A", 22.0), ("B", 22.0)):
        for end in np.array(res.verdicts[cam].failing_intervals_deg).ravel():
            t = np.radians([end])
            est = inverse_estimate(
                conjugate_factors(DESIGN, t),
                22.0,
                _spec(None).master_a,
                _spec(None).master_b,
                _spec(None).errors,
            )
            value = est.dr_a_est_um if cam == "A" else est.dr_b_est_um
            # |dΔr_est/dθ| < 0.2 µm/deg here, so 0.01° is < 0.002 µm
            assert value[0] == pytest.approx(tol, abs=2e-3)


def test_no_record_gives_forward_variation_and_no_verdict() -> None:
    res = inspect_conjugate(DESIGN, _spec(None), step_deg=1.0)
    assert res.passed is None and res.estimate is None
    want = conjugate_variation(
        res.factors, _spec(None).master_a, _spec(None).master_b, _spec(None).errors
    )
    np.testing.assert_allclose(res.variation.df_est_um, want.df_est_um)


def test_spec_mapping_errors() -> None:
    with pytest.raises(DesignError, match="inspection.foo is not a known field"):
        fixture_spec_from_mapping({"tolerance_a_um": [-1, 1], "foo": 1})
    with pytest.raises(DesignError, match=r"inspection.tolerance_a_um=.*\[lower, upper\]"):
        fixture_spec_from_mapping({"tolerance_a_um": 22})
    with pytest.raises(DesignError, match="lower < upper"):
        fixture_spec_from_mapping({"tolerance_a_um": [5, -5]})
    with pytest.raises(DesignError, match="inspection.master_a_um"):
        fixture_spec_from_mapping({"tolerance_a_um": [-1, 1], "master_a_um": "import os"})


def test_needs_conjugate_design_and_valid_step() -> None:
    from camtol.mechanisms import RollerOscillating

    with pytest.raises(DesignError, match="conjugate"):
        conjugate_factors(CamDesign("x", RollerOscillating(60, 16, 120, 66), PROGRAM), THETA)
    with pytest.raises(DesignError, match="step_deg"):
        inspect_conjugate(DESIGN, _spec(None), step_deg=0.7)


def test_fixture_extremes_are_refined_and_plateaus_are_ranges() -> None:
    """Extremes use the shared finder: located to step/1000, constants as 0-360°."""
    from camtol.config.design_file import load_example

    design = load_example("cw11-conjugate")
    spec = design.inspection
    assert spec is not None
    coarse = inspect_conjugate(design, spec, step_deg=1.0)
    fine = inspect_conjugate(design, spec, step_deg=0.1)
    mx_c, _ = coarse.extremes["dr_A_est"]
    mx_f, _ = fine.extremes["dr_A_est"]
    # refined on a 1° grid to 0.001°, the location agrees with the 0.1° grid's refinement
    assert mx_c.theta_deg == pytest.approx(mx_f.theta_deg, abs=2e-3)
    assert mx_c.value == pytest.approx(mx_f.value, abs=1e-6)  # quadratic in the location error
    assert fine.extremes["df_mea"][0].ranges_deg == ((0.0, 360.0),)


def test_merge_intervals_joins_short_gaps_only() -> None:
    from camtol.pair.acceptance import merge_intervals

    slivers = [(80.5, 80.51), (80.62, 80.72), (81.0, 133.9), (134.2, 135.0), (221.95, 248.5)]
    assert merge_intervals(slivers, 1.0) == [(80.5, 135.0), (221.95, 248.5)]
    assert merge_intervals(slivers, 0.0) == slivers  # no gap is shorter than 0°
    assert merge_intervals([], 1.0) == []


def test_json_has_exact_intervals_and_stretches(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from camtol.cli.app import main

    assert main(["conjugate", "-e", "cw11-conjugate", "--json", "--step", "0.5"]) == 1
    verdict = json.loads(capsys.readouterr().out)["verdicts"]["A"]
    assert verdict["stretch_merge_gap_deg"] == 1.0
    # a clean record: the stretches are the exact intervals
    assert verdict["failing_stretches_deg"] == verdict["failing_intervals_deg"]
