"""Velocity and acceleration errors (THEORY §3.5) and the extremes finder."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camtol.analysis.errors import error_analysis
from camtol.analysis.extremes import find_extremes
from camtol.analysis.result import analyse
from camtol.config.design_file import load_example
from camtol.design.cam_design import ResolvedTolerance
from camtol.report.display import display_analysis, display_curves


@pytest.mark.parametrize("name", ["cw06-translating", "cw06-oscillating"])
def test_dv_da_are_derivatives_of_ds_inside_segments(name: str) -> None:
    design = load_example(name)
    tols = design.resolve_tolerances(60.0)
    # points well inside segments; central differences with h = 1e-4 rad (error ~1e-8 rel)
    t = np.radians(np.concatenate([np.linspace(5, 115, 50), np.linspace(200, 270, 30)]))
    h = 1e-4
    e0 = error_analysis(design, tols, t)
    ep = error_analysis(design, tols, t + h)
    em = error_analysis(design, tols, t - h)
    for key, src in e0.sources.items():
        fd_v = (ep.sources[key].delta_lift - em.sources[key].delta_lift) / (2 * h)
        fd_a = (ep.sources[key].delta_lift - 2 * src.delta_lift + em.sources[key].delta_lift) / h**2
        scale_v = max(np.max(np.abs(src.delta_velocity)), 1e-12)
        scale_a = max(np.max(np.abs(src.delta_acceleration)), 1e-12)
        assert np.max(np.abs(fd_v - src.delta_velocity)) < 1e-6 * scale_v + 1e-15, key
        assert np.max(np.abs(fd_a - src.delta_acceleration)) < 1e-4 * scale_a + 1e-12, key


def test_speed_scales_velocity_and_acceleration_errors() -> None:
    import dataclasses

    design = load_example("cw06-translating")
    fast = dataclasses.replace(design, speed_rpm=600.0)
    a1, a2 = analyse(design, step_deg=1.0), analyse(fast, step_deg=1.0)
    omega = 600 * 2 * math.pi / 60
    # The analysis stays per radian of cam angle (internal units): a speed changes nothing.
    for key in ("dS_phi", "dV_phi", "dA_phi"):
        np.testing.assert_array_equal(a2.curves[key], a1.curves[key])
    assert [q.unit for q in a2.quantities] == [q.unit for q in a1.quantities]
    # The report shows them per second: ω and ω² (THEORY §3).
    c1, c2 = display_curves(a1), display_curves(a2)
    assert c2["dV_phi"] == pytest.approx(c1["dV_phi"] * omega)
    assert c2["dA_phi"] == pytest.approx(c1["dA_phi"] * omega**2)
    assert c2["dS_phi"] == pytest.approx(c1["dS_phi"])
    units = {q.key: q.unit for q in display_analysis(a2).quantities}
    assert units["dV_worst"] == "um/s" and units["dA_worst"] == "um/s2"


def test_extremes_refine_beyond_grid() -> None:
    # f(θ) = cos(θ − 1.23456 rad): max at 70.7350°, found to step/1000 from a 1° grid
    t0 = 1.23456
    theta = np.radians(np.arange(0, 361.0))
    ext = find_extremes(
        theta,
        {"f": np.cos(theta - t0)},
        lambda t, names: {"f": np.cos(t - t0)},
        step_deg=1.0,
    )["f"]
    assert ext[0].theta_deg == pytest.approx(math.degrees(t0), abs=1e-3)
    assert ext[1].theta_deg == pytest.approx(math.degrees(t0) + 180, abs=1e-3)
    assert ext[0].ranges_deg == ()


def test_unit_deviation_sensitivity_is_linear() -> None:
    design = load_example("cw06-translating")
    t = np.radians(np.linspace(0, 360, 361))
    one = error_analysis(design, [ResolvedTolerance("r", 0.019, "mm", "")], t)
    two = error_analysis(design, [ResolvedTolerance("r", 0.038, "mm", "")], t)
    assert two.sources["r"].delta_lift == pytest.approx(2 * one.sources["r"].delta_lift)


def test_isolated_plateau_points_print_as_single_angles() -> None:
    from camtol.analysis.extremes import Extreme

    e = Extreme("x", "min", 0.0, 139.8, ((139.8, 139.8), (143.0, 168.0)))
    assert e.where == "139.80°, 143.00-168.00°"


@pytest.mark.parametrize("n", [257, 80_003])  # one row block, and three (the last short)
@pytest.mark.parametrize(
    "kinds",
    [("array", "array", "array"), ("const", "array", "const"), ("const", "const"), ("array",)],
)
def test_worst_case_and_rms_are_the_plain_sums_bit_for_bit(kinds: tuple[str, ...], n: int) -> None:
    """Σ|ΔS_p| and sqrt(Σ ΔS_p²) over array and constant sensitivities, in source order."""
    from camtol.analysis.errors import _SUM_ROWS, ErrorAnalysis, SourceError

    assert 257 < _SUM_ROWS < 80_003 // 2
    rng = np.random.default_rng(17)
    sources = {}
    for i, kind in enumerate(kinds):
        s = rng.normal(size=n) if kind == "array" else np.broadcast_to(rng.normal(), (n,))
        dev = float(rng.normal()) * 1e-3
        sources[f"p{i}"] = SourceError(f"p{i}", dev, s, s, s)
    err = ErrorAnalysis(np.zeros(n), np.zeros(n, bool), sources)
    worst, squares = np.zeros(n), np.zeros(n)
    for src in sources.values():
        worst += np.abs(src.sensitivity) * abs(src.deviation)
        squares += (src.sensitivity * src.deviation) ** 2
    for order in (0, 1, 2):
        np.testing.assert_array_equal(err.worst(order), worst)
        np.testing.assert_array_equal(err.rms(order), np.sqrt(squares))
        # Into a caller's array (what the extremes' scan reuses): the same numbers.
        out = np.full(n, np.nan)
        assert err.worst(order, out=out) is out
        np.testing.assert_array_equal(out, worst)
        assert err.rms(order, out=out) is out
        np.testing.assert_array_equal(out, np.sqrt(squares))


def test_extremes_of_a_broadcast_constant_are_those_of_the_full_array() -> None:
    # A constant sensitivity (ΔS_e of a translating follower) is a read-only broadcast;
    # the search takes it without a pass and must report what it reports for an array.
    theta = np.radians(np.arange(0, 360.5, 0.5))

    def never(t: np.ndarray, names: frozenset[str]) -> dict[str, np.ndarray]:
        return {k: np.full(t.shape, 0.25) for k in names}

    got = find_extremes(theta, {"c": np.broadcast_to(0.25, theta.shape)}, never, step_deg=0.5)
    ref = find_extremes(theta, {"c": np.full(theta.shape, 0.25)}, never, step_deg=0.5)
    assert got == ref
    assert got["c"][0].ranges_deg == ((0.0, 360.0),) and got["c"][1].value == 0.25


@pytest.mark.parametrize("shape", [(), (3, 4)])
def test_worst_case_and_rms_of_other_shapes(shape: tuple[int, ...]) -> None:
    # A grid that is a scalar or a table is summed in one block, as a line is.
    from camtol.analysis.errors import ErrorAnalysis, SourceError

    s1 = np.random.default_rng(5).normal(size=shape)
    s2 = 2.0 * s1
    err = ErrorAnalysis(
        np.zeros(shape),
        np.zeros(shape, bool),
        {"a": SourceError("a", 0.1, s1, s1, s1), "b": SourceError("b", -0.2, s2, s2, s2)},
    )
    np.testing.assert_array_equal(err.worst(0), np.abs(s1) * 0.1 + np.abs(s2) * 0.2)
    np.testing.assert_array_equal(err.rms(1), np.sqrt((s1 * 0.1) ** 2 + (s2 * -0.2) ** 2))
