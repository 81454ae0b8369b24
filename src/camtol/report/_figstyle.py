"""Shared drawing helpers of the camtol figures: axes, labels, legends, the title stamp.

Private to :mod:`camtol.report`; the public figure functions live in
:mod:`camtol.report.plots`, :mod:`camtol.report.cam_drawing` and
:mod:`camtol.report.fixture_plots`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

__all__ = ["pretty_unit"]

_THETA_LABEL = "cam angle θ [°]"
_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2")


def pretty_unit(unit: str) -> str:
    """Display form of a unit key: ``um/rad2`` → ``µm/rad²``, ``deg`` → ``°``.

    Parameters
    ----------
    unit : str
        ASCII unit key, e.g. ``"um/rad2"``; ``""`` or ``"-"`` for dimensionless.

    Returns
    -------
    str
        The unit for display; ``"-"`` for a dimensionless quantity.
    """
    if unit in ("-", ""):
        return "-"
    return unit.replace("um", "µm").replace("deg", "°").replace("rad2", "rad²").replace("s2", "s²")


def _label(quantity: str, unit: str) -> str:
    return f"{quantity} [{pretty_unit(unit)}]"


def _axes(ax: Axes | None, figsize: tuple[float, float] = (7.0, 4.0)) -> Axes:
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def _theta_axis(ax: Axes) -> None:
    ax.set_xlabel(_THETA_LABEL)
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0.0, 361.0, 60.0))
    ax.grid(True, linewidth=0.4, alpha=0.6)


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
    from camtol import __version__

    fig: Any = ax.get_figure()
    fig.suptitle(f"{name} (camtol {__version__})", fontsize="medium")
