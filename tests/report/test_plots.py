"""Figures: labels with units on every axis, jumps drawn as steps, lazy matplotlib import."""

from __future__ import annotations

import io
import re
import subprocess
import sys
from functools import cache
from typing import Any

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from camtol.analysis.drawing import analysis_drawing, cam_drawing
from camtol.analysis.kinematics import kinematics
from camtol.analysis.result import Analysis, analyse
from camtol.config.design_file import example_names, load_example
from camtol.pair.fixture import FixtureInspection, inspect_conjugate
from camtol.pair.fixture_spec import FixtureSpec
from camtol.report import plots
from camtol.report.display import display_curves

EXAMPLES = example_names()
UNIT = re.compile(r"\S.*\[[^\]]+\]$")  # "quantity [unit]"


@cache
def analysis_of(name: str) -> Analysis:
    return analyse(load_example(name), step_deg=0.5)


@cache
def fixture_of(name: str) -> tuple[FixtureInspection, FixtureSpec]:
    design = load_example(name)
    spec = design.inspection
    assert spec is not None
    return inspect_conjugate(design, spec, step_deg=0.5), spec


def assert_labelled(fig: Figure) -> None:
    """Every visible axis of every drawn Axes carries 'quantity [unit]'."""
    drawn = [ax for ax in fig.axes if ax.axison]
    assert drawn
    for ax in drawn:
        for axis, label in ((ax.xaxis, ax.get_xlabel()), (ax.yaxis, ax.get_ylabel())):
            if axis.get_visible():
                assert UNIT.match(label), f"axis label {label!r} of {ax.get_title()!r}"


@pytest.mark.parametrize("name", EXAMPLES)
def test_analysis_figure_axes_carry_units(name: str) -> None:
    a = analysis_of(name)
    fig = plots.analysis_figure(a, analysis_drawing(a))
    assert isinstance(fig, Figure)
    assert len([ax for ax in fig.axes if ax.axison]) >= 6
    assert_labelled(fig)
    assert name in fig.get_suptitle()


@pytest.mark.parametrize("name", EXAMPLES)
def test_analysis_figure_fixed_layout_keeps_everything_apart(name: str) -> None:
    """The figure is laid out once, without constrained layout (issue 32): every panel's
    decorations (tick labels, axis labels, title, legend) stay on the figure, and no
    legend or decoration of one panel reaches into the data area of another."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    a = analysis_of(name)
    fig = plots.analysis_figure(a, analysis_drawing(a))
    assert fig.get_layout_engine() is None
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    page = fig.bbox
    tol = 1.0  # [px] a glyph's anti-aliased edge
    drawn = [ax for ax in fig.axes if ax.axison]
    for ax in drawn:
        tight = ax.get_tightbbox(renderer)
        assert tight is not None
        assert tight.x0 >= page.x0 - tol and tight.x1 <= page.x1 + tol, ax.get_title()
        assert tight.y0 >= page.y0 - tol and tight.y1 <= page.y1 + tol, ax.get_title()
        legend = ax.get_legend()
        boxes = [ax.yaxis.get_tightbbox(renderer), ax.xaxis.get_tightbbox(renderer)]
        boxes += [legend.get_window_extent(renderer)] if legend is not None else []
        for other in drawn:
            if other is ax or other.bbox.overlaps(ax.bbox):  # itself, or its twin
                continue
            inner = other.bbox.padded(-tol)
            for box in boxes:
                if box is not None:
                    assert not box.overlaps(inner), (ax.get_title(), other.get_title())


@pytest.mark.parametrize(
    "fn",
    [
        plots.shift_angle_plot,
        plots.radial_factor_plot,
        plots.lift_error_plot,
        plots.velocity_error_plot,
        plots.acceleration_error_plot,
    ],
)
def test_panel_functions_return_artists_and_make_labelled_figures(fn: Any) -> None:
    arts = fn(analysis_of("cw06-translating"))
    assert arts and all(hasattr(a, "get_figure") for a in arts)
    fig = arts[0].get_figure()
    assert_labelled(fig)


def test_panel_draws_on_given_axes() -> None:
    fig = Figure()
    ax = fig.add_subplot()
    arts = plots.lift_error_plot(analysis_of("cw06-oscillating"), ax=ax)
    assert all(a.axes is ax for a in arts)
    # Per source, worst case and RMS; oscillating errors are in degrees.
    labels = [a.get_label() for a in arts]
    assert "worst case" in labels and "RMS" in labels
    assert ax.get_ylabel() == "ΔS [°]"


def test_lift_error_curves_are_the_analysis_curves() -> None:
    a = analysis_of("cw06-translating")
    arts = plots.lift_error_plot(a)
    worst = next(x for x in arts if x.get_label() == "worst case")
    np.testing.assert_array_equal(worst.get_ydata(), display_curves(a)["dS_worst"])
    np.testing.assert_array_equal(worst.get_xdata(), np.degrees(a.kinematics.theta_rad))


def test_acceleration_jump_is_a_vertical_step() -> None:
    # CW06 §4: ΔA_φ of the translating follower jumps at the end of the rise (120°).
    a = analysis_of("cw06-translating")
    arts = plots.acceleration_error_plot(a)
    line = next(x for x in arts if str(x.get_label()).startswith("ΔA_phi"))
    x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    i = np.flatnonzero(np.isclose(x, 120.0))
    assert i.size == 2 and i[1] == i[0] + 1  # left then right limit, drawn consecutively
    assert abs(y[i[1]] - y[i[0]]) > 5.0  # a jump of ~18 µm/rad², not smeared


@pytest.mark.parametrize("name", EXAMPLES)
@pytest.mark.parametrize("theta_deg", [0.0, 60.0, 222.5])
def test_cam_plot_marks_contact_point(name: str, theta_deg: float) -> None:
    design = load_example(name)
    arts = plots.cam_plot(cam_drawing(design, theta_deg))
    ax = arts[0].axes
    assert ax.get_xlabel() == "X [mm]" and ax.get_ylabel() == "Y [mm]"
    assert_labelled(ax.figure)
    if design.mechanism.kind == "conjugate":
        from camtol.pair.kinematics import cam_design

        design = cam_design(design, "A")
    k = kinematics(design, np.radians([theta_deg]), check=False)
    a = (k.contact_x_mm[0], k.contact_y_mm[0])
    markers = [
        (x.get_xdata()[0], x.get_ydata()[0])
        for x in arts
        if isinstance(x, Line2D) and x.get_marker() == "o" and len(x.get_xdata()) == 1
    ]
    assert any(np.hypot(mx - a[0], my - a[1]) < 1e-9 for mx, my in markers)
    labels = {x.get_label() for x in arts if isinstance(x, Line2D)}
    if hasattr(load_example(name).mechanism, "base_radius_mm"):
        assert "base circle" in labels


def test_fixture_figure_and_panels() -> None:
    res, spec = fixture_of("cw11-conjugate")
    fig = plots.fixture_figure(
        res, tolerance_a_um=spec.tolerance_a_um, tolerance_b_um=spec.tolerance_b_um
    )
    assert_labelled(fig)
    arts = plots.conjugate_variation_plot(res)
    est = next(x for x in arts if x.get_label() == "Δf_est (sum)")
    np.testing.assert_allclose(est.get_ydata(), res.variation.df_est_um)
    arts = plots.profile_error_estimate_plot(res, tolerance_a_um=(-22.0, 22.0))
    hlines = [
        x for x in arts if isinstance(x, Line2D) and str(x.get_gid()).startswith("tolerance_A")
    ]
    assert sorted(h.get_ydata()[0] for h in hlines) == [-22.0, 22.0]


@pytest.mark.parametrize("cam", ["A", "B"])
def test_acceptance_plot_shades_each_failing_interval(cam: str) -> None:
    res, _ = fixture_of("cw11-conjugate")
    verdict = res.verdicts[cam]
    arts = plots.acceptance_plot(res, cam=cam)
    ax: Axes = arts[0].axes
    spans = [x for x in arts if x.__class__.__name__ in ("Rectangle", "Polygon")]
    expected = sum(1 if e >= s else 2 for s, e in verdict.failing_intervals_deg)
    assert len(spans) == expected
    assert ("FAILS" in ax.get_title()) == (not verdict.passed)
    with pytest.raises(ValueError, match="'A' or 'B'"):
        plots.acceptance_plot(res, cam="C")


def test_estimate_plot_needs_a_measurement() -> None:
    res, _ = fixture_of("cw11-conjugate")
    import dataclasses

    with pytest.raises(ValueError, match="no measured"):
        plots.profile_error_estimate_plot(dataclasses.replace(res, estimate=None))


@pytest.mark.parametrize("fmt,magic", [("png", b"\x89PNG"), ("svg", b"<?xml")])
def test_figure_saves_without_pyplot(fmt: str, magic: bytes) -> None:
    buf = io.BytesIO()
    a = analysis_of("cw06-oscillating")
    plots.analysis_figure(a, analysis_drawing(a)).savefig(buf, format=fmt)
    assert buf.getvalue().startswith(magic)


def test_pretty_unit() -> None:
    assert plots.pretty_unit("um/rad2") == "µm/rad²"
    assert plots.pretty_unit("deg/s2") == "°/s²"
    assert plots.pretty_unit("-") == "-"


def test_import_camtol_does_not_import_matplotlib_or_ezdxf() -> None:
    code = (
        "import sys, camtol, camtol.analysis.result, camtol.config.design_file, camtol.cli.app,"
        " camtol.report.plots, camtol.report.export, camtol.report.html;"
        " bad = [m for m in ('matplotlib', 'ezdxf') if m in sys.modules];"
        " print(bad); sys.exit(1 if bad else 0)"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr


def test_cam_plot_and_figure_of_roller_followers() -> None:
    import math

    from camtol.design.cam_design import CamDesign
    from camtol.design.motion import Segment, SegmentProgram
    from camtol.mechanisms import RollerOscillating, RollerTranslating

    def program(h: float) -> SegmentProgram:
        r = math.radians
        return SegmentProgram(
            (
                Segment("rise", 0.0, r(120), "cycloidal", h),
                Segment("dwell", r(120), r(190)),
                Segment("return", r(190), r(290), "cycloidal", h),
                Segment("dwell", r(290), r(360)),
            )
        )

    for design in (
        CamDesign("rt", RollerTranslating(40.0, 10.0, 5.0), program(22.0)),
        CamDesign("ro", RollerOscillating(40.0, 10.0, 80.0, 60.0), program(math.radians(15))),
    ):
        arts = plots.cam_plot(cam_drawing(design, 45.0))
        k = kinematics(design, np.radians([45.0]), check=False)
        g = design.mechanism.contact(np.radians([45.0]), k.lift, k.velocity)
        c = (float(g.extras["pitch_x"][0]), float(g.extras["pitch_y"][0]))  # type: ignore[index]
        rf = design.mechanism.roller_radius_mm  # type: ignore[attr-defined]
        # The roller is drawn as a circle of radius r_f around the roller centre.
        circles = [
            x
            for x in arts
            if isinstance(x, Line2D)
            and len(x.get_xdata()) > 100
            and np.allclose(np.hypot(x.get_xdata() - c[0], x.get_ydata() - c[1]), rf)
        ]
        assert len(circles) == 1
        a = analyse(design, step_deg=1.0)
        fig = plots.analysis_figure(a, analysis_drawing(a))
        assert_labelled(fig)
