"""The Monte Carlo figure (issue 28, item 7): band, max |ΔS| histogram, Pareto chart."""

from __future__ import annotations

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.report.tolerancing_display import display_montecarlo
from camtol.tolerancing import monte_carlo

matplotlib = pytest.importorskip("matplotlib")

CW06 = load_example("cw06-translating")


def _figure(**kw: object) -> tuple[object, list[object]]:
    from camtol.report.tolerancing import montecarlo_figure

    res = monte_carlo(CW06, 3000, seed=2, step_deg=2.0, **kw)  # type: ignore[arg-type]
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = montecarlo_figure(display_montecarlo(res, CW06))
    FigureCanvasAgg(fig).draw()  # lay it out as a PNG would be
    return fig, fig.axes  # type: ignore[attr-defined]


def test_the_legend_stands_outside_the_band() -> None:
    fig, axes = _figure(spec=0.015)
    band = axes[0]
    legend = band.get_legend()
    assert legend is not None
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    box = legend.get_window_extent(renderer)
    assert box.x0 >= band.get_window_extent(renderer).x1  # right of the axes, never on it
    texts = [t.get_text() for t in legend.get_texts()]
    assert any("deterministic" in t for t in texts)  # the band needs no samples
    assert "spec limits" in texts


def test_histogram_of_max_abs_against_the_spec_and_pareto_of_shares() -> None:
    _, axes = _figure(spec=0.015)
    hist, pareto = axes[1], axes[2]
    counts = [p.get_height() for p in hist.patches]
    assert sum(counts) == 3000  # every sample in a bar
    lines = {line.get_label(): line for line in hist.get_lines()}
    assert "spec" in lines and np.allclose(lines["spec"].get_xdata(), 15.0)  # µm
    assert "sampled" in hist.get_title()
    heights = [p.get_height() for p in pareto.patches]
    assert heights == sorted(heights, reverse=True) and heights[0] > 90  # r dominates
    assert sum(heights) == pytest.approx(100.0)
    assert [t.get_text() for t in pareto.get_xticklabels()] == ["r", "e", "phi"]


def test_a_band_is_drawn_by_its_tightest_and_widest_limits() -> None:
    from camtol.tolerancing.study import prepare

    theta = prepare(CW06, step_deg=2.0).theta_rad
    band = (-0.012 - 0.003 * np.cos(theta), 0.015 + 0.002 * np.sin(theta))
    _, axes = _figure(band=band)
    labels = [line.get_label() for line in axes[1].get_lines()]
    assert "band, tightest" in labels and "band, widest" in labels
