"""A figure as inline SVG (camtol.report.inline_svg): ids prefixed, text kept as text."""

from __future__ import annotations

import re

from matplotlib.figure import Figure

from camtol.report.inline_svg import figure_svg


def _figure() -> Figure:
    fig = Figure(figsize=(3, 2))
    ax = fig.add_subplot()
    ax.plot([0, 1, 2], [0, 1, 0], label="ΔS_r (19 µm)")
    ax.set_xlabel("cam angle θ [°]")
    ax.legend()
    return fig


def test_every_id_and_reference_carries_the_prefix() -> None:
    svg = figure_svg(_figure(), prefix="f7")
    assert svg.startswith("<svg")
    ids = re.findall(r'\bid="([^"]+)"', svg)
    refs = re.findall(r'href="#([^"]+)"', svg) + re.findall(r"url\(#([^)]+)\)", svg)
    assert ids and refs
    assert all(i.startswith("f7-") for i in ids)
    assert all(r.startswith("f7-") for r in refs)
    assert set(refs) <= set(ids)  # every reference still points at an element


def test_two_figures_share_a_page_without_clashing_ids() -> None:
    a = re.findall(r'\bid="([^"]+)"', figure_svg(_figure(), prefix="a"))
    b = re.findall(r'\bid="([^"]+)"', figure_svg(_figure(), prefix="b"))
    assert not set(a) & set(b)


def test_text_stays_text() -> None:
    # Searchable and read by screen readers; no glyph outlines (issue 32).
    svg = figure_svg(_figure(), prefix="t")
    texts = "".join(re.findall(r"<text[^>]*>([^<]*)</text>", svg))
    assert "ΔS_r (19 µm)" in texts and "cam angle θ [°]" in texts
    assert "DejaVuSans-" not in svg  # the ids of glyph outlines, when text is drawn as paths
    # matplotlib 3.8 writes "font: 10px 'DejaVu Sans', ...", later ones "font-family: ..."
    assert re.search(r"font(-family)?: [^;\"]*'DejaVu Sans'[^;\"]*sans-serif", svg)
