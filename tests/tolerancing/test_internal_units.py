"""Monte Carlo and allocation results are in internal units; the report layer shows them.

Issue 8: the core (``camtol.tolerancing``) returns ΔS in mm (translating follower) or rad
(oscillating), ΔV and ΔA per radian of cam angle, and records that unit;
:func:`camtol.report.tolerancing_display.display_montecarlo` multiplies by the factors of
:class:`camtol.report.display.DisplayUnits` (µm or degrees; per second at the design's
cam speed). These tests check both halves: internal × factor = displayed, exactly (the
same one multiplication the display does), and that the internal numbers really are in
mm/rad (closed forms in mm; independence from the cam speed, which only the display
knows).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.design.cam_design import CamDesign
from camtol.report.display import DisplayUnits
from camtol.report.tolerancing_display import describe_source, display_montecarlo
from camtol.tolerancing import allocate, monte_carlo
from camtol.tolerancing.montecarlo import Study, prepare
from camtol.tolerancing.results import MonteCarloResult

STEP = 1.0
QS = ("lift", "velocity", "acceleration")
FIELDS = ("mean", "std", "q00135", "q50", "q99865")


def _with_speed(name: str, rpm: float) -> CamDesign:
    return dataclasses.replace(load_example(name), speed_rpm=rpm)


def _assert_displayed(res: MonteCarloResult, design: CamDesign) -> None:
    """Every displayed figure is the internal one times its DisplayUnits factor."""
    units = DisplayUnits.of(design)
    shown = display_montecarlo(res, design)
    assert shown.unit == units.lift and shown.scale == units.lift_scale
    for q, s in res.statistics.items():
        d = shown.statistics[q]
        k = QS.index(q)
        assert d.unit == units.order(k).unit
        f = units.order(k).factor
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(d, name), getattr(s, name) * f)
            assert getattr(d.max_abs, name) == getattr(s.max_abs, name) * f
        assert d.resolution == s.resolution * f
    f = units.lift_scale
    for c, dc in zip(res.comparison, shown.comparison, strict=True):
        assert (dc.worst_case, dc.rss, dc.mc_9973) == (c.worst_case * f, c.rss * f, c.mc_9973 * f)
    if res.limits is not None:
        assert shown.limits is not None
        np.testing.assert_array_equal(shown.limits[1], res.limits[1] * f)
    if res.difference is not None:
        assert shown.difference is not None
        assert shown.difference.max_sample == res.difference.max_sample * f


@pytest.mark.parametrize(
    "name, out, shown",
    [("roller-translating", "mm", "um"), ("roller-oscillating", "rad", "deg")],
)
def test_internal_statistics_times_display_factor_are_the_displayed_numbers(
    name: str, out: str, shown: str
) -> None:
    d = _with_speed(name, 300.0)  # ΔV, ΔA shown per second: factor includes ω, ω²
    spec = 0.02 if out == "mm" else math.radians(0.02)
    res = monte_carlo(d, 3000, seed=2, spec=spec, quantities=QS, step_deg=STEP)
    assert [res.statistics[q].unit for q in QS] == [out, f"{out}/rad", f"{out}/rad2"]
    assert res.unit == out
    assert res.yield_estimate is not None and res.yield_estimate.spec == spec  # [mm or rad]
    _assert_displayed(res, d)
    doc = display_montecarlo(res, d).to_dict()
    assert doc["unit"] == shown
    assert doc["max_abs_dV"]["unit"] == f"{shown}/s" and doc["max_abs_dA"]["unit"] == f"{shown}/s2"
    assert doc["yield"]["spec"] == f"max |dS| <= {spec * DisplayUnits.of(d).lift_scale:g} {shown}"


def test_exact_mode_is_internal_too() -> None:
    d = load_example("cw06-oscillating")
    res = monte_carlo(d, 6, mode="exact", seed=1, spec=math.radians(0.02), step_deg=2.0)
    assert res.unit == "rad" and res.statistics["lift"].resolution == 0.0
    _assert_displayed(res, d)


def test_core_numbers_do_not_depend_on_the_cam_speed() -> None:
    """The cam speed is a display matter: the core result is the same at any speed."""
    slow, fast = _with_speed("roller-translating", 60.0), _with_speed("roller-translating", 600.0)
    a = monte_carlo(slow, 2000, seed=4, quantities=QS, step_deg=STEP)
    b = monte_carlo(fast, 2000, seed=4, quantities=QS, step_deg=STEP)
    for q in QS:
        for name in FIELDS:
            np.testing.assert_array_equal(
                getattr(a.statistics[q], name), getattr(b.statistics[q], name)
            )
    # ... while the display of ΔA scales with ω² (10× the speed: 100× the figures)
    sa = display_montecarlo(a, slow).statistics["acceleration"].std
    sb = display_montecarlo(b, fast).statistics["acceleration"].std
    np.testing.assert_allclose(sb, 100.0 * sa, rtol=1e-12)


def test_internal_figures_are_in_mm_not_um() -> None:
    """Closed forms in mm bound and match the internal figures (a µm factor would fail)."""
    d = load_example("cw06-translating")
    st: Study = prepare(d, step_deg=STEP)
    assert not hasattr(st, "scale")
    g = st.sens["lift"]
    worst_mm = float((np.abs(g) @ np.array(st.plan.deviations)).max())
    res = monte_carlo(d, 4000, seed=3, step_deg=STEP)
    lift = res.statistics["lift"]
    assert 0.2 * worst_mm < lift.max_abs.q99865 <= worst_mm
    assert res.comparison[-1].worst_case == pytest.approx(worst_mm, rel=1e-12)
    sigma_mm = np.sqrt((g * g) @ st.plan.column_variance())
    np.testing.assert_allclose(lift.std, sigma_mm, rtol=0.1)  # 4,000 samples: ~1 % error
    # the histogram bins are chosen in mm: at most ~1/1000 of the range of ΔS
    assert 0.0 < lift.resolution < 1e-3 * worst_mm * 10
    # sources: zones in the source's internal unit, shown in µm or degrees
    r = res.sources["r"]
    dev_r = st.plan.deviations[st.plan.labels.index("r")]
    assert r.unit == "mm" and r.upper == pytest.approx(dev_r)  # type: ignore[union-attr]
    assert describe_source(r).endswith(f"[{-dev_r * 1e3:.4g}, {dev_r * 1e3:.4g}] µm")


def test_the_tolerancing_package_has_no_display_scale() -> None:
    import camtol.tolerancing.montecarlo as mc
    import camtol.tolerancing.plan as plan
    import camtol.tolerancing.results as results

    assert not hasattr(plan, "display_scale")
    assert not hasattr(results.MonteCarloResult, "to_dict")  # JSON is the report's
    assert "scale" not in {f.name for f in dataclasses.fields(mc.Study)}


def test_allocation_result_is_internal() -> None:
    d = load_example("cw06-translating")
    a = allocate(d, 0.04, step_deg=STEP, verify_samples=2000)
    assert a.unit == "mm" and a.spec == 0.04
    assert a.achieved <= 0.04  # worst case in mm meets the spec in mm
    assert a.verified.spec == 0.04
