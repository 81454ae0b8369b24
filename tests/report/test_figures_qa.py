"""Figures for a designer and a QA engineer (issue 13 item 10).

Legends never hide the worst-case maximum, the analyze figure has the SVAJ panel, the
pressure-angle limit, the pitch curve and the worst-case envelopes; the fixture figure
names the design, keeps A's and B's tolerance lines apart and draws u_f and the record's
upper/lower estimates; every figure names the design and the camtol version.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from camtol import __version__
from camtol.analysis.drawing import analysis_drawing, cam_drawing
from camtol.analysis.result import Analysis, analyse
from camtol.analysis.summary import motion_peaks
from camtol.config.design_file import example_names, load_example
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.indicator import process_record, record_estimates, to_error_function
from camtol.pair.twin import simulate_record
from camtol.report import plots
from camtol.report.display import display_curves

EXAMPLES = example_names()


@cache
def analysis_of(name: str) -> Analysis:
    return analyse(load_example(name), step_deg=0.5)


def _texts(fig: Figure) -> str:
    parts = [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))]
    sup = fig.get_suptitle()
    return "\n".join([sup, *parts])


def _error_axes(fig: Figure, title: str) -> Any:
    return next(ax for ax in fig.axes if ax.get_title() == title)


@pytest.mark.parametrize("name", EXAMPLES)
def test_legend_does_not_cover_the_worst_case_maximum(name: str) -> None:
    a = analysis_of(name)
    fig = plots.analysis_figure(a, analysis_drawing(a))
    FigureCanvasAgg(fig).draw()
    ax = _error_axes(fig, "Displacement errors ΔS")
    worst = display_curves(a)["dS_worst"]  # as plotted: µm or °
    i = int(np.argmax(worst))
    t = np.degrees(a.kinematics.theta_rad)[i]
    point = ax.transData.transform((t, worst[i]))
    legend = ax.get_legend()
    assert legend is not None
    box = legend.get_window_extent()
    assert not box.contains(*point), (name, box, point)
    # and no legend of any panel hides any data point of its own axes
    for axx in fig.axes:
        leg = axx.get_legend()
        if leg is None:
            continue
        bb = leg.get_window_extent()
        for line in axx.get_lines():
            xy = axx.transData.transform(np.column_stack(line.get_data()))
            inside = (
                (xy[:, 0] > bb.x0) & (xy[:, 0] < bb.x1) & (xy[:, 1] > bb.y0) & (xy[:, 1] < bb.y1)
            )
            assert not inside.any(), (name, axx.get_title(), line.get_label())


@pytest.mark.parametrize("name", ["roller-translating", "cw06-oscillating"])
def test_analysis_figure_has_svaj_at_speed(name: str) -> None:
    a = analysis_of(name)
    fig = plots.analysis_figure(a, analysis_drawing(a))
    labels = {ax.get_ylabel() for ax in fig.axes}
    w = a.design.omega_rad_s
    if a.design.mechanism.output == "translating":
        expect = {"S [mm]", "V [m/s]", "A [m/s²]", "J [m/s³]"} if w else {"S [mm]", "V [mm/rad]"}
    else:
        expect = {"ξ [°]", "V [rad/s]"} if w else {"ξ [°]", "V [rad/rad]", "A [rad/rad²]"}
    assert expect <= labels, labels
    # the A panel draws the nominal acceleration at speed, and names its peak
    ax_a = next(ax for ax in fig.axes if ax.get_ylabel().startswith("A ["))
    y = ax_a.get_lines()[0].get_ydata()
    peaks = motion_peaks(a.kinematics, output=a.design.mechanism.output, omega_rad_s=w)
    scale = (w**2 * (1e-3 if a.design.mechanism.output == "translating" else 1.0)) if w else 1.0
    assert np.max(np.abs(y)) == pytest.approx(peaks.acceleration.abs_max * scale, rel=1e-12)
    assert f"{peaks.acceleration.abs_max * scale:.4g}" in ax_a.get_title(loc="right")


def test_pressure_angle_limit_line_and_pitch_curve() -> None:
    a = analysis_of("roller-translating")
    limit = a.design.pressure_angle_limit_deg
    assert limit is not None
    fig = plots.analysis_figure(a, analysis_drawing(a))
    ax = _error_axes(fig, "Shift angle, pressure angle")
    ys = {
        round(float(line.get_ydata()[0]), 9)
        for line in ax.get_lines()
        if "limit" in str(line.get_label()) or line.get_linestyle() == ":"
    }
    assert {limit, -limit} <= ys
    cam_ax = fig.axes[0]
    pitch = [ln for ln in cam_ax.get_lines() if ln.get_label() == "pitch curve"]
    assert len(pitch) == 1
    r = np.hypot(*pitch[0].get_data())
    # the roller centre is at distance r_b + r_f + S from ... at least r_b + r_f away
    mech: Any = a.design.mechanism
    assert r.min() >= mech.base_radius_mm + mech.roller_radius_mm - 1e-6


@pytest.mark.parametrize("title", ["Velocity errors ΔV", "Acceleration errors ΔA"])
def test_worst_case_envelopes_on_dv_and_da(title: str) -> None:
    a = analysis_of("roller-translating")
    fig = plots.analysis_figure(a, analysis_drawing(a))
    ax = _error_axes(fig, title)
    env = [c for c in ax.collections if "envelope" in str(c.get_label())]
    assert len(env) == 1
    key = "dV_worst" if "ΔV" in title else "dA_worst"
    top = env[0].get_paths()[0].vertices[:, 1].max()
    assert top == pytest.approx(float(np.max(display_curves(a)[key])), rel=1e-9)


def _record_run() -> tuple[Any, Any, Any]:
    d = load_example("cw11-conjugate")
    spec = d.inspection
    assert spec is not None
    rec = simulate_record(lambda t: np.full_like(t, 10.0), noise_um=1.0, rng=1, revolutions=4)
    processed = process_record(rec, step_deg=0.5)
    import dataclasses

    spec = dataclasses.replace(spec, df_mea=to_error_function(processed))
    res = inspect_conjugate(d, spec, step_deg=0.5)
    return res, spec, record_estimates(d, spec, processed, res.theta_rad)


def test_fixture_figure_names_design_and_draws_u_f_and_estimates() -> None:
    res, spec, est = _record_run()
    fig = plots.fixture_figure(
        res,
        tolerance_a_um=spec.tolerance_a_um,
        tolerance_b_um=spec.tolerance_b_um,
        design_name="cw11-conjugate",
        record=est,
    )
    title = fig.get_suptitle()
    assert "cw11-conjugate" in title and __version__ in title and "THEORY §4)" not in title
    labels = [str(c.get_label()) for ax in fig.axes for c in ax.collections]
    assert labels.count("Δf_mea ± u_f") == 2  # both acceptance panels
    assert "Δr_A,est at Δf_mea ± u_f" in labels and "Δr_B,est at Δf_mea ± u_f" in labels
    band = next(c for ax in fig.axes for c in ax.collections if c.get_label() == "Δf_mea ± u_f")
    assert isinstance(band, PolyCollection)
    height = np.ptp(band.get_paths()[0].vertices[:, 1])
    assert height >= 2 * est.u_f_um.max() - 1e-9
    # A's and B's equal tolerance lines are told apart: style, width and an end label
    est_ax = next(ax for ax in fig.axes if ax.get_title() == "Estimated radial profile errors")
    tol = {
        str(ln.get_gid()): ln for ln in est_ax.get_lines() if str(ln.get_gid()).startswith("tol")
    }
    a_up, b_up = tol["tolerance_A_upper"], tol["tolerance_B_upper"]
    assert a_up.get_ydata()[0] == b_up.get_ydata()[0]  # same value: must not look the same
    assert (a_up.get_linestyle(), a_up.get_linewidth()) != (
        b_up.get_linestyle(),
        b_up.get_linewidth(),
    )
    texts = {t.get_text() for t in est_ax.texts}
    assert {"A +22", "B +22", "A -22", "B -22"} <= texts


def _all_figures() -> list[tuple[str, Figure]]:
    a = analysis_of("cw06-translating")
    res, spec, est = _record_run()
    figs: list[tuple[str, Figure]] = [
        ("cw06-translating", plots.analysis_figure(a, analysis_drawing(a)))
    ]
    figs.append(("cw11-conjugate", plots.fixture_figure(res, design_name="cw11-conjugate")))
    for fn in (
        plots.shift_angle_plot,
        plots.radial_factor_plot,
        plots.lift_error_plot,
        plots.velocity_error_plot,
        plots.acceleration_error_plot,
    ):
        arts = fn(a)
        figs.append(("cw06-translating", arts[0].get_figure()))
    figs.append(("cw06-translating", plots.svaj_plot(a)[0].get_figure()))
    figs.append(("cw06-translating", plots.cam_plot(cam_drawing(a.design, 30.0))[0].get_figure()))
    for fn2 in (plots.conjugate_variation_plot, plots.profile_error_estimate_plot):
        figs.append(("cw11-conjugate", fn2(res, design_name="cw11-conjugate")[0].get_figure()))
    figs.append(
        ("cw11-conjugate", plots.acceptance_plot(res, design_name="cw11-conjugate")[0].get_figure())
    )
    return figs


def test_every_figure_names_design_and_version() -> None:
    figs = _all_figures()
    assert len(figs) == 12
    for name, fig in figs:
        title = fig.get_suptitle()
        assert name in title and f"camtol {__version__}" in title, title


def test_rendered_figure_png(tmp_path: Path) -> None:
    # The file a user gets from `camtol analyze --plot`: a real PNG of the whole figure.
    fig = plots.analysis_figure(
        analysis_of("roller-translating"), analysis_drawing(analysis_of("roller-translating"))
    )
    out = tmp_path / "f.png"
    fig.savefig(out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "roller-translating" in _texts(fig)
