"""A production lot's statistics for people: terminal table, charts, HTML report.

Everything here formats the ``records stats --json`` document
(:meth:`camtol.records.lot_summary.LotSummary.to_dict`, a plain dict): the report layer
sits beside the store and never computes a statistic itself.

* :func:`lot_text`: ``camtol records stats`` as a table within 80 columns;
* :func:`chart_svg`, :func:`histogram_svg`: the control chart (limits, flagged points,
  optionally each point a link to its record) and the histogram (specification limits, the
  fitted normal density), hand-written inline SVG: light, no script, no font, fast enough
  for the quality department's page over 10,000 parts;
* :func:`write_lot_plot`: the same two panels with matplotlib (``--plot FILE.png``);
* :func:`lot_report_html`: the self-contained, printable lot report (``--report``).

Why one module: the table, the two charts and the report show one document the same way
(the same digits, units, index names, flagged points and judgement wording), and the
report and the quality page assemble them; kept together they cannot drift apart.
"""

from __future__ import annotations

import html
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from camtol.report.qa import BASE_CSS, PRINT_CSS

__all__ = [
    "INDEX_NAMES",
    "chart_svg",
    "histogram_svg",
    "lot_report_html",
    "lot_text",
    "sparkline_svg",
    "write_lot_plot",
]

#: JSON key → printed name of the capability indices, in the order printed.
INDEX_NAMES: dict[str, str] = {
    "pp": "Pp",
    "ppk": "Ppk",
    "ppu": "Ppu",
    "ppl": "Ppl",
    "cp": "Cp",
    "cpk": "Cpk",
    "cpu": "Cpu",
    "cpl": "Cpl",
}

_UNITS = {"um": "µm", "deg": "deg"}
_CHART_NAMES = {"imr": "individuals (I-MR)", "xbar-r": "X̄-R", "xbar-s": "X̄-S"}


def _g(x: float | None, digits: int = 3) -> str:
    """Format a figure to ``digits`` significant digits, "-" when undefined."""
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x:.{digits}g}"


def _f(x: float | None, decimals: int = 2) -> str:
    if x is None or not math.isfinite(x):
        return "-"
    return f"{x:.{decimals}f}"


def unit_of(doc: dict[str, Any]) -> str:
    """Return the printed unit of the characteristic (µm, or deg for a swing)."""
    return _UNITS.get(str(doc.get("unit")), str(doc.get("unit")))


def _index_rows(doc: dict[str, Any]) -> list[tuple[str, str, str, str]]:
    rows = []
    for key, name in INDEX_NAMES.items():
        if key in doc:
            v = doc[key]
            lo, hi = v["ci95"]
            within = key.startswith("c")
            rows.append(
                (name, _f(v["value"]), f"[{_f(lo)}, {_f(hi)}]", "within" if within else "overall")
            )
    return rows


def lot_text(doc: dict[str, Any]) -> list[str]:
    """``camtol records stats`` for the terminal: lines within 80 columns.

    Parameters
    ----------
    doc : dict
        The ``records stats --json`` document.

    Returns
    -------
    list of str
    """
    u = unit_of(doc)
    spec = doc["spec"]
    limit = (
        f"upper limit {_g(spec['usl'], 4)} {u}"
        if spec["usl"] is not None
        else f"lower limit {_g(spec['lsl'], 4)} {u}"
    )
    lot = doc["lot"] if doc["lot"] is not None else "(all lots)"
    cam = f", cam {doc['cam']}" if doc["cam"] else ""
    sig = doc["sigma"]
    y = doc["yield"]
    lines = [
        f"{doc['design_name']}{cam}, lot {lot}: {doc['count']} parts"
        f" ({', '.join(doc['methods'])}, judged on {doc['judged_on'] or '?'})",
        f"characteristic  {doc['characteristic']} [{u}], {limit}",
        f"mean            {_f(doc['mean'])} {u}",
        f"σ overall       {_f(sig['overall'])} {u} (ν = {_g(sig['dof_overall'])})",
        f"σ within        {_f(sig['within'])} {u} ({sig['within_method']},"
        f" ν = {_g(sig['dof_within'])})",
        f"yield           {100 * y['value']:.1f} % (95 % CI {100 * y['ci95'][0]:.1f}"
        f" to {100 * y['ci95'][1]:.1f} %), {doc['n_failing']} failing",
        "",
        f"{'index':8}{'value':>8}  {'95 % interval':16}σ",
    ]
    lines += [f"{n:8}{v:>8}  {ci:16}{s}" for n, v, ci, s in _index_rows(doc)]
    norm = doc["normality"]
    lines += [
        "",
        f"normality       Anderson-Darling A² = {_g(norm['statistic'])},"
        f" p = {_g(norm['p_value'], 2)}: {'normal' if norm['normal'] else 'NOT normal'}",
    ]
    if doc["percentile"]:
        p = doc["percentile"]
        figs = ", ".join(f"{INDEX_NAMES[k]} {_f(v)}" for k, v in p.items() if k != "method")
        lines.append(f"percentile      {figs}")
        lines.append(f"                ({p['method']})")
    lines.append(f"judgement       {judgement(doc)}")
    c = doc["chart"]
    frozen = ", limits frozen from the reference lot" if c["frozen"] else ""
    sub = f", subgroups of {c['subgroup']}" if c["subgroup"] > 1 else ""
    lines += [
        "",
        f"chart           {_CHART_NAMES[c['kind']]}{sub}{frozen}",
        f"  location      CL {_f(c['center'])}, LCL {_f(c['lcl'])}, UCL {_f(c['ucl'])} {u}",
        f"  dispersion    CL {_f(c['dispersion_center'])}, LCL {_f(c['dispersion_lcl'])},"
        f" UCL {_f(c['dispersion_ucl'])} {u}",
    ]
    ooc = doc["out_of_control"]
    rules = "Western Electric" if doc["rules"] == "we" else "Nelson"
    if not ooc:
        lines.append(f"out of control  none ({rules} rules)")
    else:
        lines.append(f"out of control  {len(ooc)} signal(s) ({rules} rules):")
        shown = ooc[:20]
        for o in shown:
            lines.append(f"  record {o['record_id']:>6}  serial {o['serial'][:20]:20}  {o['rule']}")
        if len(ooc) > len(shown):
            lines.append(f"  ... and {len(ooc) - len(shown)} more (see --json)")
    trend = doc["trend_um_per_part"]
    if trend is not None:
        err = doc["trend_stderr_um_per_part"]
        lines.append(
            f"trend of max    {_g(trend)} ± {_g(err)} µm per part (by {doc['trend_basis']})"
        )
    lines += [f"warning: {w}" for w in doc["warnings"]]
    return _fit(lines)


def _fit(lines: list[str], width: int = 80) -> list[str]:
    """Wrap lines longer than ``width`` columns, continuing them indented."""
    import textwrap

    out: list[str] = []
    for line in lines:
        if len(line) <= width:
            out.append(line)
        else:
            indent = " " * min(len(line) - len(line.lstrip()) + 2, 16)
            out += textwrap.wrap(line, width, subsequent_indent=indent, break_on_hyphens=False)
    return out


def judgement(doc: dict[str, Any]) -> str:
    """Return the capability judgement in words, with the bound it was taken on."""
    key = next(k for k in ("ppk", "ppu", "ppl") if k in doc)
    bound = doc[key]["ci95"][0]
    verdict = "CAPABLE" if doc["capable"] else "NOT capable"
    return (
        f"{verdict}: lower 95 % bound of {INDEX_NAMES[key]} {_f(bound)}"
        f" ({'≥' if bound is not None and bound >= doc['capable_at'] else '<'}"
        f" {doc['capable_at']:g})" + ("; values not normal" if doc["percentile"] else "")
    )


# --------------------------------------------------------------------------- SVG charts
_W, _H = 720, 260
_ML, _MR, _MT, _MB = 56, 16, 14, 30


def _scale(lo: float, hi: float, a: float, b: float) -> Callable[[Any], Any]:
    span = hi - lo if hi > lo else 1.0
    return lambda v: a + (np.asarray(v, dtype=np.float64) - lo) * (b - a) / span


def _ticks(lo: float, hi: float, n: int = 5) -> list[float]:
    if not hi > lo:
        return [lo]
    step = 10 ** math.floor(math.log10((hi - lo) / n))
    for m in (1, 2, 5, 10):
        if (hi - lo) / (m * step) <= n:
            step *= m
            break
    first = math.ceil(lo / step) * step
    return [first + i * step for i in range(int((hi - first) / step) + 1)]


def chart_svg(
    doc: dict[str, Any], *, record_href: Callable[[int], str] | None = None, prefix: str = "c"
) -> str:
    """Draw the control chart's location panel as inline SVG (flagged points in red).

    Parameters
    ----------
    doc : dict
        The ``records stats --json`` document.
    record_href : callable, optional
        Record id → link of that record: each plotted individual becomes a link.
    prefix : str
        Prefix of the element ids (several charts on one page).

    Returns
    -------
    str
        ``<svg>`` markup with ``class="control-chart"``.
    """
    c = doc["chart"]
    parts = doc["parts"]
    n_points = max((p["point"] for p in parts if p["point"] is not None), default=-1) + 1
    if c["subgroup"] == 1:
        y = np.array([p["value"] for p in parts], dtype=np.float64)
    else:
        sums = np.zeros(n_points)
        for p in parts:
            if p["point"] is not None:
                sums[p["point"]] += p["value"]
        y = sums / c["subgroup"]
    flagged_ids = {o["record_id"] for o in doc["out_of_control"]}
    flagged = np.zeros(y.size, dtype=bool)
    first_id: list[int] = [0] * y.size
    for p in parts:
        k = p["point"]
        if k is not None:
            first_id[k] = first_id[k] or p["record_id"]
            flagged[k] |= p["record_id"] in flagged_ids
    lo = float(min(np.min(y), c["lcl"]))
    hi = float(max(np.max(y), c["ucl"]))
    pad = 0.08 * (hi - lo or 1.0)
    lo, hi = lo - pad, hi + pad
    sx = _scale(0, max(y.size - 1, 1), _ML, _W - _MR)
    sy = _scale(lo, hi, _H - _MB, _MT)
    xs, ys = sx(np.arange(y.size)), sy(y)
    u = unit_of(doc)
    out = [
        f'<svg class="control-chart" id="{prefix}-chart" xmlns="http://www.w3.org/2000/svg"'
        f' viewBox="0 0 {_W} {_H}" width="{_W}" height="{_H}" role="img"'
        f' aria-label="control chart of {html.escape(doc["characteristic"])}">',
        f'<rect x="{_ML}" y="{_MT}" width="{_W - _ML - _MR}" height="{_H - _MT - _MB}"'
        ' fill="none" stroke="#999"/>',
    ]
    for t in _ticks(lo, hi):
        ty = float(sy(t))
        out.append(
            f'<text x="{_ML - 4}" y="{ty + 4:.1f}" font-size="11" text-anchor="end">{t:g}</text>'
        )
    for name, v, colour, dash in (
        ("UCL", c["ucl"], "#b00020", "6 4"),
        ("CL", c["center"], "#11702b", ""),
        ("LCL", c["lcl"], "#b00020", "6 4"),
    ):
        ly = float(sy(v))
        out.append(
            f'<line class="limit" x1="{_ML}" x2="{_W - _MR}" y1="{ly:.1f}" y2="{ly:.1f}"'
            f' stroke="{colour}" stroke-dasharray="{dash}"/>'
            f'<text x="{_W - _MR - 2}" y="{ly - 3:.1f}" font-size="11" text-anchor="end"'
            f' fill="{colour}">{name} {v:.2f}</text>'
        )
    if y.size:
        pts = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(xs, ys, strict=True))
        out.append(f'<polyline points="{pts}" fill="none" stroke="#3465a4" stroke-width="1"/>')
    r = 3.0 if y.size <= 200 else 1.5
    for k in range(y.size):
        colour = "#b00020" if flagged[k] else "#3465a4"
        cls = "point flagged" if flagged[k] else "point"
        dot = f'<circle class="{cls}" cx="{xs[k]:.1f}" cy="{ys[k]:.1f}" r="{r}" fill="{colour}"/>'
        if record_href is not None and c["subgroup"] == 1 and y.size <= 2000:
            dot = f'<a href="{html.escape(record_href(first_id[k]))}">{dot}</a>'
        out.append(dot)
    label = "part" if c["subgroup"] == 1 else f"subgroup of {c['subgroup']}"
    out.append(
        f'<text x="{(_ML + _W - _MR) / 2}" y="{_H - 8}" font-size="12" text-anchor="middle">'
        f"{label} in production order; {html.escape(doc['characteristic'])} [{u}]</text>"
    )
    out.append("</svg>")
    return "".join(out)


def sparkline_svg(doc: dict[str, Any], *, width: int = 240, height: int = 48) -> str:
    """Draw a small control chart for a list of lots: points, limits, flagged points in red.

    Parameters
    ----------
    doc : dict
        The lot's ``records stats --json`` document.
    width, height : int
        Size of the drawing. [px]

    Returns
    -------
    str
        ``<svg>`` markup with ``class="sparkline"`` (no text: the lot's row says the rest).
    """
    c = doc["chart"]
    parts = [p for p in doc["parts"] if p["point"] is not None]
    if c["subgroup"] == 1:
        y = np.array([p["value"] for p in parts], dtype=np.float64)
    else:
        y = np.zeros(max(p["point"] for p in parts) + 1)
        for p in parts:
            y[p["point"]] += p["value"] / c["subgroup"]
    flagged_ids = {o["record_id"] for o in doc["out_of_control"]}
    bad = np.zeros(y.size, dtype=bool)
    for p in parts:
        bad[p["point"]] |= p["record_id"] in flagged_ids
    lo = float(min(np.min(y), c["lcl"]))
    hi = float(max(np.max(y), c["ucl"]))
    sx = _scale(0, max(y.size - 1, 1), 2, width - 2)
    sy = _scale(lo, hi, height - 3, 3)
    xs, ys = sx(np.arange(y.size)), sy(y)
    step = max(1, y.size // width)  # at most about one point per pixel column
    pts = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(xs[::step], ys[::step], strict=True))
    out = [
        f'<svg class="sparkline" xmlns="http://www.w3.org/2000/svg" width="{width}"'
        f' height="{height}" viewBox="0 0 {width} {height}" role="img"'
        ' aria-label="control chart">'
    ]
    for v, colour in ((c["ucl"], "#b00020"), (c["center"], "#11702b"), (c["lcl"], "#b00020")):
        ly = float(sy(v))
        out.append(
            f'<line x1="0" x2="{width}" y1="{ly:.1f}" y2="{ly:.1f}" stroke="{colour}"'
            ' stroke-width="0.8"/>'
        )
    out.append(f'<polyline points="{pts}" fill="none" stroke="#3465a4" stroke-width="1"/>')
    out += [
        f'<circle class="flagged" cx="{xs[k]:.1f}" cy="{ys[k]:.1f}" r="2.5" fill="#b00020"/>'
        for k in np.flatnonzero(bad)
    ]
    out.append("</svg>")
    return "".join(out)


def histogram_svg(doc: dict[str, Any], *, prefix: str = "h") -> str:
    """Draw the histogram with the specification limit and the fitted normal density.

    Parameters
    ----------
    doc : dict
        The lot's ``records stats --json`` document.
    prefix : str
        Prefix of the SVG element ids, unique per histogram on one page.

    Returns
    -------
    str
        ``<svg>`` markup with ``class="histogram"``.
    """
    x = np.array([p["value"] for p in doc["parts"]], dtype=np.float64)
    spec = doc["spec"]
    limits = [v for v in (spec["lsl"], spec["usl"]) if v is not None]
    mean, s = doc["mean"], doc["sigma"]["overall"] or 0.0
    lo = float(min(x.min(), *limits, mean - 4 * s))
    hi = float(max(x.max(), *limits, mean + 4 * s))
    bins = int(np.clip(np.sqrt(x.size), 5, 40))
    counts, edges = np.histogram(x, bins=bins, range=(float(x.min()), float(x.max()) or 1.0))
    width = float(edges[1] - edges[0]) or 1.0
    grid = np.linspace(lo, hi, 200)
    dens = (
        x.size * width * np.exp(-0.5 * ((grid - mean) / s) ** 2) / (s * math.sqrt(2 * math.pi))
        if s > 0
        else np.zeros_like(grid)
    )
    top = float(max(counts.max(), dens.max())) * 1.1
    sx = _scale(lo, hi, _ML, _W - _MR)
    sy = _scale(0.0, top, _H - _MB, _MT)
    u = unit_of(doc)
    out = [
        f'<svg class="histogram" id="{prefix}-hist" xmlns="http://www.w3.org/2000/svg"'
        f' viewBox="0 0 {_W} {_H}" width="{_W}" height="{_H}" role="img"'
        f' aria-label="histogram of {html.escape(doc["characteristic"])}">',
        f'<rect x="{_ML}" y="{_MT}" width="{_W - _ML - _MR}" height="{_H - _MT - _MB}"'
        ' fill="none" stroke="#999"/>',
    ]
    base = float(sy(0.0))
    for k, cnt in enumerate(counts):
        x0, x1 = float(sx(edges[k])), float(sx(edges[k + 1]))
        y0 = float(sy(cnt))
        out.append(
            f'<rect class="bar" x="{x0:.1f}" y="{y0:.1f}" width="{max(x1 - x0 - 1, 0.5):.1f}"'
            f' height="{base - y0:.1f}" fill="#9db7d8"/>'
        )
    pts = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(sx(grid), sy(dens), strict=True))
    out.append(f'<polyline points="{pts}" fill="none" stroke="#1a1a1a" stroke-width="1.2"/>')
    for name, v in (("LSL", spec["lsl"]), ("USL", spec["usl"])):
        if v is not None:
            lx = float(sx(v))
            out.append(
                f'<line x1="{lx:.1f}" x2="{lx:.1f}" y1="{_MT}" y2="{_H - _MB}" stroke="#b00020"'
                f' stroke-width="2"/><text x="{lx - 3:.1f}" y="{_MT + 12}" font-size="11"'
                f' text-anchor="end" fill="#b00020">{name} {v:g}</text>'
            )
    for t in _ticks(lo, hi, 8):
        tx = float(sx(t))
        out.append(
            f'<text x="{tx:.1f}" y="{_H - _MB + 14}" font-size="11" text-anchor="middle">'
            f"{t:g}</text>"
        )
    out.append(
        f'<text x="{(_ML + _W - _MR) / 2}" y="{_H - 2}" font-size="12" text-anchor="middle">'
        f"{html.escape(doc['characteristic'])} [{u}]; line: normal density (mean, σ overall)"
        "</text></svg>"
    )
    return "".join(out)


def write_lot_plot(doc: dict[str, Any], path: str) -> None:
    """Write the control chart and the histogram as one figure (PNG, SVG or PDF).

    Parameters
    ----------
    doc : dict
        The ``records stats --json`` document.
    path : str
        Output file; written atomically.
    """
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from camtol.files import atomic_write

    c = doc["chart"]
    parts = doc["parts"]
    u = unit_of(doc)
    flagged_ids = {o["record_id"] for o in doc["out_of_control"]}
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(9, 7), layout="constrained")
    if c["subgroup"] == 1:
        y = np.array([p["value"] for p in parts])
        bad = np.array([p["record_id"] in flagged_ids for p in parts])
    else:
        n_points = max(p["point"] for p in parts if p["point"] is not None) + 1
        y = np.zeros(n_points)
        bad = np.zeros(n_points, dtype=bool)
        for p in parts:
            if p["point"] is not None:
                y[p["point"]] += p["value"] / c["subgroup"]
                bad[p["point"]] |= p["record_id"] in flagged_ids
    k = np.arange(1, y.size + 1)
    ax.plot(k, y, "-o", ms=3, lw=0.8, color="#3465a4")
    ax.plot(k[bad], y[bad], "o", ms=7, mfc="none", mec="#b00020", label="out of control")
    lines = (("UCL", c["ucl"], "--"), ("CL", c["center"], "-"), ("LCL", c["lcl"], "--"))
    for name, v, style in lines:
        ax.axhline(v, ls=style, color="#b00020" if name != "CL" else "#11702b", lw=1)
        ax.annotate(f"{name} {v:.2f}", (1.0, v), xycoords=("axes fraction", "data"),
                    ha="right", va="bottom", fontsize=8)  # fmt: skip
    ax.set_xlabel("part" if c["subgroup"] == 1 else f"subgroup of {c['subgroup']}")
    ax.set_ylabel(f"{doc['characteristic']} [{u}]")
    ax.set_title(f"{_CHART_NAMES[c['kind']]} chart, {doc['design_name']} lot {doc['lot'] or 'all'}")
    if bad.any():
        ax.legend(loc="lower left", fontsize=8)
    x = np.array([p["value"] for p in parts])
    bx.hist(x, bins=int(np.clip(np.sqrt(x.size), 5, 40)), color="#9db7d8", density=True)
    mean, s = doc["mean"], doc["sigma"]["overall"] or 0.0
    spec = doc["spec"]
    limits = [v for v in (spec["lsl"], spec["usl"]) if v is not None]
    if s > 0:
        lo = min(x.min(), *limits, mean - 4 * s)
        g = np.linspace(lo, max(x.max(), *limits, mean + 4 * s), 300)
        bx.plot(g, np.exp(-0.5 * ((g - mean) / s) ** 2) / (s * math.sqrt(2 * math.pi)), "k-",
                lw=1, label="normal density (mean, σ overall)")  # fmt: skip
    for name, v in (("LSL", spec["lsl"]), ("USL", spec["usl"])):
        if v is not None:
            bx.axvline(v, color="#b00020", lw=2, label=f"{name} {v:g} {u}")
    bx.set_xlabel(f"{doc['characteristic']} [{u}]")
    bx.set_ylabel("density [1/" + u + "]")
    bx.legend(fontsize=8)
    buf = io.BytesIO()
    fmt = path.rsplit(".", 1)[-1].lower()
    fig.savefig(buf, format=fmt, dpi=120, metadata=None if fmt != "png" else {"Software": None})
    plt.close(fig)
    atomic_write(path, buf.getvalue())


_CSS = BASE_CSS + ".figure svg{max-width:100%;height:auto}code{background:#f5f5f5;padding:0 .2em}\n"


def _e(x: object) -> str:
    return html.escape(str(x), quote=True)


def capability_table_html(doc: dict[str, Any]) -> str:
    """Return the capability indices with their 95 % intervals as an HTML table."""
    rows = "".join(
        f'<tr><td>{n}</td><td class="num">{v}</td><td class="num">{ci}</td><td>{s}</td></tr>'
        for n, v, ci, s in _index_rows(doc)
    )
    return (
        '<table class="capability"><thead><tr><th>index</th><th>value</th>'
        "<th>95 % interval</th><th>σ</th></tr></thead><tbody>" + rows + "</tbody></table>"
    )


def summary_html(doc: dict[str, Any]) -> str:
    """Summary, judgement, capability table and signals of a lot, as HTML (no charts)."""
    u = unit_of(doc)
    cls = "pass" if doc["capable"] else "fail"
    text = lot_text(doc)
    head = "".join(f"<li>{_e(line)}</li>" for line in text[:6])
    ooc = doc["out_of_control"]
    signals = (
        "<p>No out-of-control signal.</p>"
        if not ooc
        else "<ul>"
        + "".join(
            f"<li>record {o['record_id']} (serial {_e(o['serial'])}): {_e(o['rule'])}</li>"
            for o in ooc[:100]
        )
        + "</ul>"
    )
    warn = "".join(f'<p class="fail">warning: {_e(w)}</p>' for w in doc["warnings"])
    return (
        f'<div class="banner {cls}">{_e(judgement(doc))}</div>'
        f"<ul class='meta'>{head}</ul>"
        f"<h2>Capability ({_e(doc['characteristic'])}, {u})</h2>{capability_table_html(doc)}"
        f"<p>Normality (Anderson-Darling): A² = {_g(doc['normality']['statistic'])},"
        f" p = {_g(doc['normality']['p_value'], 2)}"
        f" ({'normal' if doc['normality']['normal'] else 'not normal'}).</p>"
        f"<h2>Out of control</h2>{signals}{warn}"
    )


#: Columns of the report's appendix of records: (record key, heading).
_RECORD_COLUMNS = (
    ("id", "record"),
    ("serial", "serial"),
    ("part_number", "part number"),
    ("inspected_at", "inspected (UTC)"),
    ("inspector", "inspector"),
    ("instrument", "instrument"),
    ("method", "method"),
    ("judged_on", "on"),
    ("tolerance_um", "tolerance [µm]"),
    ("max_dev_um", "max [µm]"),
    ("min_dev_um", "min [µm]"),
    ("form_um", "form [µm]"),
    ("verdict", "verdict"),
    ("raw_sha256", "raw data SHA-256"),
)


def _record_cell(key: str, v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.2f}"
    if key == "tolerance_um":
        return f"[{v[0]:g}, {v[1]:g}]"
    if key == "inspected_at":
        return str(v)[:19].replace("T", " ")
    if key == "raw_sha256":
        return str(v)[:19] + "…"
    return str(v)


def _records_html(records: Sequence[dict[str, Any]]) -> str:
    head = "".join(f"<th>{_e(h)}</th>" for _, h in _RECORD_COLUMNS)
    rows = "".join(
        f'<tr id="record-{int(r["id"])}">'
        + "".join(f"<td>{_e(_record_cell(k, r.get(k)))}</td>" for k, _ in _RECORD_COLUMNS)
        + "</tr>"
        for r in records
    )
    return (
        "<h2>Records</h2><p class='meta'>What each part was judged on and where its raw data"
        " is (the store's records, as `camtol records show ID` prints them).</p>"
        f"<table class='long records'><thead><tr>{head}</tr></thead><tbody>{rows}"
        "</tbody></table>"
    )


def lot_report_html(
    doc: dict[str, Any],
    *,
    record_href: Callable[[int], str] | None = None,
    records: Sequence[dict[str, Any]] | None = None,
) -> str:
    """Return the self-contained, printable lot report.

    Parameters
    ----------
    doc : dict
        The ``records stats --json`` document (with ``camtol_version``).
    record_href : callable, optional
        Record id → link to that record (e.g. the quality page's record page).
    records : sequence of dict, optional
        The records' summaries (``InspectionRecord.summary()``): appended as a table, each
        part linking to its row when ``record_href`` is not given.

    Returns
    -------
    str
        One HTML page: inline CSS and SVG, no script, nothing fetched.
    """
    if record_href is None and records is not None:
        record_href = _anchor
    title = f"Lot report: {doc['design_name']} lot {doc['lot'] or '(all)'}"
    flags: dict[int, list[str]] = {}
    for o in doc["out_of_control"]:
        flags.setdefault(o["record_id"], []).append(o["rule"])
    rows = []
    for p in doc["parts"]:
        rid = p["record_id"]
        link = (
            f'<a href="{_e(record_href(rid))}">{rid}</a>' if record_href is not None else str(rid)
        )
        rows.append(
            f"<tr><td>{link}</td><td>{_e(p['serial'])}</td>"
            f'<td class="num">{p["value"]:.2f}</td>'
            f'<td class="{"pass" if p["verdict"] == "pass" else "fail"}">{p["verdict"]}</td>'
            f"<td>{_e(', '.join(flags.get(rid, [])))}</td></tr>"
        )
    return (
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8">'
        f"<title>{_e(title)}</title><style>{_CSS}{PRINT_CSS}</style></head><body>"
        f"<h1>{_e(title)}</h1>"
        f'<p class="meta">camtol {_e(doc.get("camtol_version", ""))}; records stats'
        f" schema {_e(doc.get('schema_version', ''))}</p>"
        + summary_html(doc)
        + "<h2>Control chart</h2><figure class='figure'>"
        + chart_svg(doc, record_href=record_href)
        + "</figure><h2>Histogram</h2><figure class='figure'>"
        + histogram_svg(doc)
        + "</figure><h2>Parts</h2><table class='long parts'><thead><tr><th>record</th>"
        f"<th>serial</th><th>{_e(doc['characteristic'])} [{unit_of(doc)}]</th>"
        "<th>verdict</th><th>signals</th></tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table>"
        + (_records_html(records) if records is not None else "")
        + "</body></html>"
    )


def _anchor(record_id: int) -> str:
    return f"#record-{record_id}"
