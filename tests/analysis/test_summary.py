"""Nominal motion peaks and per-cam geometry figures (issue 13 items 1-3)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camtol.config.design_file import load_example

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib
from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.analysis.summary import STANDARD_GRAVITY, cam_geometry, motion_peaks


def _kin(name: str, step: float = 0.1):  # type: ignore[no-untyped-def]
    d = load_example(name)
    theta, left = analysis_grid(step, d.program.boundaries_rad)
    return d, kinematics(d, theta, left_limit=left, check=False)


def test_cycloidal_peaks_match_closed_form() -> None:
    # THEORY §1, cycloidal motion h over β: |V| ≤ 2h/β, |A| ≤ 2πh/β², |J| ≤ 4π²h/β³ (J is
    # largest at the ends, where it jumps: the one-sided limits are on the grid). CW06
    # Example 1: rise over 120°, the faster return over 100° sets |A| and |J|.
    d, kin = _kin("cw06-translating")
    h, rise, ret = 22.0, math.radians(120.0), math.radians(100.0)
    p = motion_peaks(kin, output="translating", omega_rad_s=None)
    assert p.velocity.max == pytest.approx(2 * h / rise, rel=1e-9)
    assert p.velocity.min == pytest.approx(-2 * h / ret, rel=1e-9)
    assert p.acceleration.abs_max == pytest.approx(2 * math.pi * h / ret**2, rel=1e-6)
    assert p.jerk.abs_max == pytest.approx(4 * math.pi**2 * h / ret**3, rel=1e-9)
    assert p.at_speed() is None


def test_peaks_at_speed_in_si_units() -> None:
    d, kin = _kin("roller-translating")
    assert d.omega_rad_s is not None
    p = motion_peaks(kin, output="translating", omega_rad_s=d.omega_rad_s)
    at = p.at_speed()
    assert at is not None
    v, a, j = at
    w = d.omega_rad_s
    assert v.abs_max == pytest.approx(p.velocity.abs_max * w * 1e-3)  # mm/rad -> m/s
    assert a.abs_max == pytest.approx(p.acceleration.abs_max * w**2 * 1e-3)  # m/s²
    assert j.abs_max == pytest.approx(p.jerk.abs_max * w**3 * 1e-3)  # m/s³
    assert a.abs_max / STANDARD_GRAVITY > 0


def test_convex_and_concave_radii_are_reported_apart() -> None:
    # A roller cam with a concave stretch: the old single "min radius of curvature" was a
    # huge negative number near the inflection; the figures now separate the two kinds.
    d, kin = _kin("roller-translating")
    g = cam_geometry("", d.mechanism, kin)
    rho = kin.curvature_radius_mm
    assert g.min_convex_radius_mm == pytest.approx(float(np.min(rho[rho > 0])))
    if np.any(rho < 0):
        assert g.min_concave_radius_mm == pytest.approx(float(np.min(-rho[rho < 0])))
        assert "cutter" in g.concave_limit
    assert "roller radius" in g.convex_limit and not g.undercut


def test_pressure_angle_limit_flag() -> None:
    d, kin = _kin("roller-translating")
    g = cam_geometry("", d.mechanism, kin, pressure_angle_limit_deg=10.0)
    assert g.max_abs_pressure_angle_deg > 10.0 and g.exceeds_pressure_angle_limit
    g = cam_geometry("", d.mechanism, kin, pressure_angle_limit_deg=89.0)
    assert not g.exceeds_pressure_angle_limit
    assert not cam_geometry("", d.mechanism, kin).exceeds_pressure_angle_limit


@pytest.mark.parametrize("face_deg", [6.0, 30.0, 3.0, 15.0])
def test_a_pressure_angle_equal_to_its_limit_meets_it(face_deg: float) -> None:
    """A flat face of obliquity φ = limit has |φ| = limit everywhere: no warning, no flag.

    The obliquity goes through radians (6° comes back as 6.000000000000001°); that
    noise is not "beyond the limit". A thousandth of a degree more is.
    """
    import warnings

    from camtol.analysis.result import analyze
    from camtol.config.design_file import design_from_mapping, dump_design
    from camtol.exceptions import PressureAngleWarning
    from camtol.report.qa import overall_verdict
    from camtol.report.tables import _rows

    data = tomllib.loads(dump_design(load_example("cw06-translating")))
    data["follower"]["face_angle_deg"] = face_deg
    for limit, beyond in ((face_deg, False), (face_deg - 1e-3, True)):
        data.setdefault("operation", {})["pressure_angle_limit_deg"] = limit
        design = design_from_mapping(data)
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            a = analyze(design, step_deg=1.0)
        assert a.pressure_angle_exceeds_limit is beyond
        assert any(issubclass(w.category, PressureAngleWarning) for w in seen) is beyond
        # the report says the same: the extremes table's label and the QA verdict
        (row,) = (r for r in _rows(a) if r[0].startswith("pressure angle"))
        assert ("LIMIT" in row[0]) is beyond
        assert (overall_verdict(a, None).status == "FAIL") is beyond


def test_radii_that_are_not_finite_count_as_neither_side() -> None:
    """NaN and ±inf radii of curvature are no minimum; none at all gives (inf, nan)."""
    d, kin = _kin("roller-translating")
    theta = kin.theta_rad
    rho = np.full(theta.shape, np.nan)
    rho[:3] = (np.inf, -np.inf, np.nan)
    g = cam_geometry("", d.mechanism, dataclasses.replace(kin, curvature_radius_mm=rho))
    assert g.min_convex_radius_mm == math.inf and math.isnan(g.min_convex_radius_at_deg)
    assert g.min_concave_radius_mm == math.inf and math.isnan(g.min_concave_radius_at_deg)
    rho[[10, 20, 30, 40]] = (5.0, 5.0, -7.0, -7.0)  # ties: the first row is taken
    g = cam_geometry("", d.mechanism, dataclasses.replace(kin, curvature_radius_mm=rho))
    assert (g.min_convex_radius_mm, g.min_convex_radius_at_deg) == (5.0, np.degrees(theta[10]))
    assert (g.min_concave_radius_mm, g.min_concave_radius_at_deg) == (7.0, np.degrees(theta[30]))


def test_peaks_are_the_grid_values_in_degrees_bit_for_bit() -> None:
    """Only the peaks are converted to degrees, with numpy's factor: the same numbers."""
    d, kin = _kin("roller-oscillating")
    g = cam_geometry("", d.mechanism, kin)
    deg, phi = np.degrees(kin.theta_rad), np.degrees(kin.pressure_angle_rad)
    i, j = int(np.argmax(phi)), int(np.argmin(phi))
    assert (g.pressure_angle_deg.max, g.pressure_angle_deg.max_at_deg) == (phi[i], deg[i])
    assert (g.pressure_angle_deg.min, g.pressure_angle_deg.min_at_deg) == (phi[j], deg[j])
    p = motion_peaks(kin, output="oscillating", omega_rad_s=None)
    k = int(np.argmax(kin.jerk))
    assert (p.jerk.max, p.jerk.max_at_deg) == (kin.jerk[k], deg[k])
