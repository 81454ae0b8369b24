"""Fewer points per curve where the figure cannot show them (issue 32, report start-up)."""

from __future__ import annotations

import numpy as np
import pytest

from camtol.report.thinning import COLUMNS_PER_INCH, thin_lines, thinned_indices


def test_min_max_decimation_keeps_every_column_extreme() -> None:
    x = np.linspace(0.0, 360.0, 3601)
    y = np.sin(np.radians(7 * x)) + np.where(x >= 200.05, 0.5, 0.0)  # a jump at 200.05°
    y[1234] = 3.0  # a one-sample spike must survive
    columns = 400
    keep = thinned_indices(x, y, columns)
    assert keep is not None and keep.size < 0.8 * x.size
    assert np.all(np.diff(keep) > 0) and keep[0] == 0 and keep[-1] == x.size - 1
    col = np.minimum((x * columns / 360.0).astype(int), columns - 1)
    for c in np.unique(col):  # the same extremes in every column (what a pixel shows)
        full, thin = y[col == c], y[keep][col[keep] == c]
        assert thin.max() == full.max() and thin.min() == full.min()
    assert 1234 in keep
    # The jump's column spans it: its min and max straddle the step, as the pixels do.
    c = col[int(np.argmax(x >= 200.05))]
    assert np.ptp(y[keep][col[keep] == c]) >= 0.5 - 0.1


def test_short_or_non_monotonic_curves_are_left_alone() -> None:
    x = np.linspace(0.0, 1.0, 100)
    assert thinned_indices(x, x, 400) is None  # already fewer points than columns


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_report_figure_keeps_its_curves_extremes_and_is_rendered() -> None:
    from camtol.analysis.drawing import analysis_drawing
    from camtol.analysis.result import analyse
    from camtol.config.design_file import load_example
    from camtol.report.inline_svg import figure_svg
    from camtol.report.plots import analysis_figure

    a = analyse(load_example("cw06-translating"), step_deg=0.1)
    fig = analysis_figure(a, analysis_drawing(a))
    before = [
        (line, np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
        for ax in fig.axes
        for line in ax.get_lines()
    ]
    dropped = thin_lines(fig)
    assert dropped > 0
    for line, x, y in before:
        xt, yt = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
        if not np.all(np.isfinite(y)):
            continue
        assert yt.max() == y.max() and yt.min() == y.min()  # peaks are never lost
        assert xt[0] == x[0] and xt[-1] == x[-1]
        ax_width_in = line.axes.get_position().width * fig.get_figwidth()
        assert xt.size == x.size or xt.size <= 4 * np.ceil(ax_width_in * COLUMNS_PER_INCH)
    svg = figure_svg(fig, prefix="t")
    assert svg.startswith("<svg") and svg.count("<path") > 100


def test_a_band_keeps_each_edge_extremes_per_column() -> None:
    # The worst-case envelope ±Σ|ΔX_p| of the ΔV and ΔA panels: fill_between's polygon.
    from matplotlib.figure import Figure

    from camtol.report.thinning import thinned_band

    x = np.linspace(0.0, 360.0, 3601)
    upper = 1.0 + np.abs(np.sin(np.radians(5 * x)))
    upper[2000] = 9.0  # a spike of the upper edge
    lower = -upper
    ax = Figure(figsize=(6, 3)).add_subplot()
    band = ax.fill_between(x, lower, upper)
    (path,) = band.get_paths()
    columns = 500
    thin = thinned_band(path.vertices, columns)
    assert thin is not None and len(thin) < 0.6 * len(path.vertices)
    turn = int(np.argmax(np.diff(thin[:, 0]) < 0))
    edges = sorted((thin[: turn + 1], thin[turn + 1 :]), key=lambda e: float(e[:, 1].mean()))
    bottom, top = edges  # fill_between's order of the edges is its own business
    assert top[:, 1].max() == 9.0 and bottom[:, 1].min() == -9.0  # the spike kept
    col = np.minimum((x * columns / 360.0).astype(int), columns - 1)
    col_top = np.minimum((top[:, 0] * columns / 360.0).astype(int), columns - 1)
    for c in range(0, columns, 7):  # what each pixel column shows is kept
        assert top[col_top == c, 1].max() == upper[col == c].max()
    # A polygon that is not one forward and one backward edge is left alone.
    t = np.linspace(0, 2 * np.pi, 4000)
    assert thinned_band(np.c_[np.cos(t), np.sin(t)], columns) is None


def test_report_figure_bands_are_thinned() -> None:
    from matplotlib.collections import PolyCollection

    from camtol.analysis.drawing import analysis_drawing
    from camtol.analysis.result import analyse
    from camtol.config.design_file import load_example
    from camtol.report.plots import analysis_figure

    a = analyse(load_example("cw06-translating"), step_deg=0.1)
    fig = analysis_figure(a, analysis_drawing(a))
    bands = [c for ax in fig.axes for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(bands) == 2  # the ΔV and ΔA envelopes
    before = [len(c.get_paths()[0].vertices) for c in bands]
    thin_lines(fig)
    after = [len(c.get_paths()[0].vertices) for c in bands]
    assert all(b < 0.6 * n for b, n in zip(after, before, strict=True))
