"""Figure helpers of the issue-13 figures: legends beside the axes, the title stamp.

Private to :mod:`camtol.report`; the shared look (axes, labels, colours) is
:mod:`camtol.report.plot_style`.
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
