"""A matplotlib figure as an inline ``<svg>`` element of an HTML page.

Every HTML page camtol writes (the design report, the inspection and CMM reports, the
Monte Carlo and dynamics sections) embeds its figures this way: no image file beside the
page, no font to install (text stays text), and element ids prefixed so that several
figures share one page.
"""

from __future__ import annotations

import io
import re
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["figure_svg"]


#: An id of an SVG element, or a reference to one (``href="#..."``, ``url(#...)``).
_SVG_IDS = re.compile(r'(\bid="|href="#|url\(#)')


def figure_svg(fig: Figure, *, prefix: str) -> str:
    """Render a figure as an inline ``<svg>`` element with ids prefixed by ``prefix``.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    prefix : str
        Unique prefix for the SVG's element ids, so that several figures can share one
        HTML page without id clashes.

    Returns
    -------
    str
        The ``<svg ...>...</svg>`` markup (no XML declaration or DOCTYPE). Long curves
        keep the points a screen can show (:mod:`camtol.report.thinning`).

    Notes
    -----
    Text stays text (``svg.fonttype = "none"``): a reader can search, select and copy it
    and a screen reader reads it, and the page is smaller and written a quarter faster
    than with every glyph drawn as a path (issue 32). It is shown in DejaVu Sans, or the
    first font of matplotlib's sans-serif list the viewer has (Verdana, then Arial, are
    close in width); every label is anchored (start, middle or end) where matplotlib
    placed it, so a font of another width does not shift it off its tick.
    """
    import matplotlib

    from camtol.report.thinning import thin_lines

    thin_lines(fig)
    buf = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": prefix}):
        fig.savefig(buf, format="svg", metadata={"Date": None})
    text = buf.getvalue()
    text = text[text.index("<svg") :]
    # One pass over the markup: ids, and the references to them, get the prefix.
    return _SVG_IDS.sub(lambda m: f"{m[1]}{prefix}-", text)
