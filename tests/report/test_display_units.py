"""Internal units in :mod:`camtol.analysis.result`, display units in :mod:`camtol.report.display`.

Issue 8 ("results in internal units with unit-suffixed names; display conversion in
report"): the analysis knows mm, rad and per-radian derivatives only (THEORY §0); the
report layer turns them into µm or degrees, per second at a cam speed.
"""

from __future__ import annotations

import ast
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import camtol.analysis.result
from camtol.analysis.result import Analysis, analyse
from camtol.config.design_file import load_example
from camtol.design.cam_design import ToleranceSpec
from camtol.report.display import (
    DisplayUnit,
    DisplayUnits,
    display_analysis,
    display_curves,
    display_extremes,
    display_unit,
)

DEG = 180.0 / math.pi


def _variant(name: str, *, speed_rpm: float | None, negative: bool) -> Analysis:
    design = load_example(name)
    if negative:  # explicit signed deviations, one of them negative
        first = design.tolerances[0]
        neg = ToleranceSpec(first.key, deviation=-abs(design.resolve_tolerances(60.0)[0].deviation))
        design = dataclasses.replace(design, tolerances=(neg, *design.tolerances[1:]))
    return analyse(dataclasses.replace(design, speed_rpm=speed_rpm), step_deg=1.0)


CASES = [
    (name, speed, negative)
    for name in ("cw06-translating", "cw06-oscillating", "roller-oscillating")
    for speed in (None, 300.0)
    for negative in (False, True)
]


@pytest.mark.parametrize(("name", "speed_rpm", "negative"), CASES)
def test_internal_extremes_are_the_display_ones_over_the_factor(
    name: str, speed_rpm: float | None, negative: bool
) -> None:
    a = _variant(name, speed_rpm=speed_rpm, negative=negative)
    shown = display_extremes(a)
    assert set(shown) == set(a.extremes) == {q.key for q in a.quantities}
    for q in a.quantities:
        f = display_unit(q, a.design).factor
        assert f > 0.0
        for internal, disp in zip(a.extremes[q.key], shown[q.key], strict=True):
            assert internal.kind == disp.kind  # a positive factor keeps max and min
            assert internal.theta_deg == disp.theta_deg
            assert internal.ranges_deg == disp.ranges_deg
            # the display value is the internal one times the factor (rounding only)
            assert internal.value == pytest.approx(disp.value / f, rel=1e-14, abs=1e-300)
        mx, mn = a.extremes[q.key]
        assert mx.value >= mn.value, q.key  # max and min right, whatever the deviation's sign
        curve = a.curves[q.key]  # the extremes bound the internal curve on the grid
        assert float(np.max(curve)) <= mx.value + 1e-12 * max(1.0, abs(mx.value))
        assert float(np.min(curve)) >= mn.value - 1e-12 * max(1.0, abs(mn.value))
    if negative:
        key = f"dS_{a.tolerances[0].key}"
        src = a.errors.sources[a.tolerances[0].key]
        assert src.deviation < 0
        mx, mn = a.extremes[key]  # the sensitivity's min times a negative deviation
        sens = np.broadcast_to(src.sensitivity, a.kinematics.theta_rad.shape)
        low = float(np.min(sens))
        assert mx.value == pytest.approx(low * src.deviation, rel=1e-4)  # refined off-grid
        assert mx.value >= low * src.deviation
        if not mx.ranges_deg:  # where the sensitivity is smallest (within a grid step)
            at = math.degrees(float(a.kinematics.theta_rad[int(np.argmin(sens))]))
            assert abs((mx.theta_deg - at + 180.0) % 360.0 - 180.0) <= 1.0 + 1e-9


@pytest.mark.parametrize(("name", "speed_rpm", "negative"), CASES)
def test_units_internal_in_the_analysis_display_in_the_report(
    name: str, speed_rpm: float | None, negative: bool
) -> None:
    a = _variant(name, speed_rpm=speed_rpm, negative=negative)
    translating = a.design.mechanism.output == "translating"
    out = "mm" if translating else "rad"
    units = {q.key: q.unit for q in a.quantities}
    assert units["pressure_angle"] == units["shift_angle"] == "rad"
    assert units["radius"] == "mm"
    assert units["radial_factor"] == ("-" if translating else "rad/mm")
    assert units["dS_worst"] == out
    assert (units["dV_worst"], units["dA_worst"]) == (f"{out}/rad", f"{out}/rad2")
    assert a.travel_unit == out
    assert a.travel == a.design.program.total_travel
    shown = display_analysis(a)
    shown_units = {q.key: q.unit for q in shown.quantities}
    err = "um" if translating else "deg"
    per = "s" if speed_rpm else "rad"
    assert shown.error_unit == err == shown_units["dS_worst"]
    assert (shown_units["dV_worst"], shown_units["dA_worst"]) == (f"{err}/{per}", f"{err}/{per}2")
    assert shown_units["pressure_angle"] == "deg"
    assert shown_units["radial_factor"] == ("-" if translating else "deg/mm")
    assert shown.travel_unit == ("mm" if translating else "deg")
    assert shown.travel == pytest.approx(a.travel * (1.0 if translating else DEG), rel=1e-15)
    w = a.design.omega_rad_s or 1.0
    scale = 1e3 if translating else DEG
    for key, k in (("dS_worst", 0), ("dV_worst", 1), ("dA_worst", 2)):
        q = next(q for q in a.quantities if q.key == key)
        assert display_unit(q, a.design) == DisplayUnit(shown_units[key], scale * w**k)
        assert DisplayUnits.of(a.design).order(k) == display_unit(q, a.design)


def test_display_curves_are_the_internal_curves_times_the_factor() -> None:
    a = _variant("cw06-oscillating", speed_rpm=600.0, negative=True)
    shown = display_curves(a)
    assert list(shown) == list(a.curves)
    for key in a.curves:  # every curve, including ΔV, ΔA per source and the RMS
        f = shown.unit(key).factor
        np.testing.assert_allclose(shown[key], a.curves[key] * f, rtol=1e-15, atol=0.0)
    # a source's internal curve is its sensitivity times its (negative) deviation
    key = a.tolerances[0].key
    src = a.errors.sources[key]
    np.testing.assert_allclose(a.curves[f"dA_{key}"], src.sensitivity_d2 * src.deviation)
    # a factor of 1 hands out the stored array (no copy): mm stay mm
    assert shown["radius"] is a.kinematics.radius_mm


def test_the_analysis_module_holds_no_display_conversion() -> None:
    assert not hasattr(camtol.analysis.result, "DisplayUnits")
    assert not hasattr(Analysis, "error_unit")
    tree = ast.parse(Path(camtol.analysis.result.__file__).read_text(encoding="utf-8"))
    # no display unit keys (um, deg, per s) among the module's strings
    strings = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant)}
    shown = {s for s in strings if isinstance(s, str) and s.startswith(("um", "deg", "/s"))}
    assert not shown
    # no name of a display helper, and no variable scaled by the cam speed ω
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    assert not any(n.startswith(("Display", "display")) or "omega" in n for n in names)
