"""Shared look of camtol's figures: axes, labels, units, colours (no computation)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camtol.jet import FloatArray

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

    from camtol.analysis.result import Analysis

__all__ = ["COLOURS", "THETA_LABEL", "axes", "axis_label", "pretty_unit", "theta_axis"]

THETA_LABEL = "cam angle θ [°]"
COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2")


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


def axis_label(quantity: str, unit: str) -> str:
    """Return the axis label ``quantity [unit]`` with the unit in display form.

    Parameters
    ----------
    quantity : str
        Symbol or name, e.g. ``"ΔS"``.
    unit : str
        ASCII unit key (see :func:`pretty_unit`).

    Returns
    -------
    str
        The label.
    """
    return f"{quantity} [{pretty_unit(unit)}]"


def axes(ax: Axes | None, figsize: tuple[float, float] = (7.0, 4.0)) -> Axes:
    """Return ``ax``, or the axes of a new figure (no pyplot).

    Parameters
    ----------
    ax : matplotlib Axes or None
        Axes to draw on.
    figsize : tuple of float
        Size of a new figure. [in]

    Returns
    -------
    matplotlib Axes
        Where to draw.
    """
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def theta_axis(ax: Axes) -> None:
    """Format a cam-angle axis: 0-360° with a tick every 60°.

    Parameters
    ----------
    ax : matplotlib Axes
        The axes whose x axis is the cam angle. [deg]
    """
    ax.set_xlabel(THETA_LABEL)
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0.0, 361.0, 60.0))
    ax.grid(True, linewidth=0.4, alpha=0.6)


def _theta_deg(analysis: Analysis) -> FloatArray:
    return np.asarray(np.degrees(analysis.kinematics.theta_rad))


def _source_keys(analysis: Analysis) -> list[str]:
    return list(analysis.errors.sources)


def _source_label(analysis: Analysis, key: str) -> str:
    for t in analysis.tolerances:
        if t.key == key:
            return f"{key} ({t.display})"
    return key
