"""Figure helpers: legends beside the axes, the title stamp, the fixed layout.

The legends and the stamp serve the issue-13 figures; the analysis figure is laid out
once, its gaps sized to those legends (issue 32). Private to :mod:`camtol.report`; the
shared look (axes, labels, colours) is :mod:`camtol.report.plot_style`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__: list[str] = []


def _legend_outside(ax: Axes, handles: list[Any] | None = None) -> Any:
    """Put the legend to the right of the axes, where it can never hide a curve."""
    kw: dict[str, Any] = {"handles": handles} if handles is not None else {}
    return ax.legend(
        loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize="small", **kw
    )


def _stamp(ax: Axes, name: str, made_here: bool) -> None:
    """Name the design and the camtol version on a figure this module made."""
    if not made_here:
        return
    from camtol._version import __version__

    fig: Any = ax.get_figure()
    fig.suptitle(f"{name} (camtol {__version__})", fontsize="medium")


#: The analysis figure's fixed margins (issue 32: laid out once, not by constrained layout,
#: which took a third of the report's time). [in]
_MARGIN_LEFT_IN = 0.95  # y tick labels and the y label of the left column
_MARGIN_TOP_IN = 0.6  # the figure title and the first row's titles
_MARGIN_BOTTOM_IN = 0.6  # x tick labels and the θ label of the last row
_ROW_GAP_IN = 1.05  # x tick labels and θ label of a row, the title of the next
_Y_LABELS_IN = 0.95  # y tick labels and the y label of the right column
_LEGEND_PAD_IN = 0.15  # clearance beyond a legend


def _fit_grid_to_legends(fig: Any, gs: Any) -> None:
    """Place a two-column grid so that legends beside the axes stay on the figure.

    Legends stand to the right of their axes (:func:`_legend_outside`); the gap between
    the columns and the right margin are made as wide as the widest legend of the column
    to their left, measured (text metrics only, no drawing). Margins for tick labels,
    axis labels and titles are fixed (:data:`_MARGIN_LEFT_IN` ...), sized for the labels
    the analysis panels draw.
    """
    from matplotlib.backends.backend_agg import RendererAgg

    # Text metrics do not depend on the canvas: one 1 x 1 pixel renderer measures every
    # legend (a legend measured without one makes a full-size canvas each time).
    renderer = RendererAgg(1, 1, fig.dpi)  # type: ignore[no-untyped-call]
    width_in, height_in = fig.get_size_inches()
    rows = gs.get_geometry()[0]
    usable_h = height_in - _MARGIN_TOP_IN - _MARGIN_BOTTOM_IN - (rows - 1) * _ROW_GAP_IN
    left_gap, right_gap = _Y_LABELS_IN + 1.0, 1.5  # first guess, refined below
    # Three placements: a guess, then twice the measured widths (a legend anchored at a
    # fraction of its axes' width moves when the axes narrow).
    for attempt in range(3):
        usable_w = width_in - _MARGIN_LEFT_IN - right_gap - left_gap
        gs.update(
            left=_MARGIN_LEFT_IN / width_in,
            right=1.0 - right_gap / width_in,
            top=1.0 - _MARGIN_TOP_IN / height_in,
            bottom=_MARGIN_BOTTOM_IN / height_in,
            wspace=left_gap / (usable_w / 2.0),
            hspace=_ROW_GAP_IN / (usable_h / rows),
        )
        for ax in fig.axes:  # the nested grids' axes (SVAJ) follow the outer grid
            spec = ax.get_subplotspec()
            if spec is not None:
                ax.set_position(spec.get_position(fig))
        if attempt == 2:
            return
        left_over, right_over = 0.0, 0.0
        middle = _MARGIN_LEFT_IN + usable_w / 2.0
        for ax in fig.axes:
            legend = ax.get_legend()
            if legend is None:
                continue
            # Before drawing a legend knows its size, not yet its place: it starts at
            # its anchor (loc "upper left" of bbox_to_anchor), offset by its pad.
            left = legend.get_bbox_to_anchor().x0 / fig.dpi
            pad = legend.borderaxespad * legend.prop.get_size_in_points() / 72.0
            width = legend.get_window_extent(renderer).width / fig.dpi
            axes_right = ax.get_position().x1 * width_in
            over = left + pad + width - axes_right + _LEGEND_PAD_IN
            if axes_right <= middle + 1e-6:
                left_over = max(left_over, over)
            else:
                right_over = max(right_over, over)
        left_gap, right_gap = left_over + _Y_LABELS_IN, max(right_over, 0.3)
