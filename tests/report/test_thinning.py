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
