"""A self-contained HTML report of a design's analysis (`camtol report`).

One file: inline CSS, figures embedded as inline SVG, no script and nothing fetched from
anywhere, so it opens offline and can be archived with the part. It states the inputs, the
conventions in force (THEORY §0 and the IT-grade conventions of §3.6), the verdicts, the
extremes table, the figures and the camtol version.
"""

from __future__ import annotations

import datetime as _dt
import html
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.analysis.kinematics import beyond_pressure_angle_limit
from camtol.design.cam_design import IT_CONVENTIONS, CamDesign
from camtol.report.display import accuracy_words, analysis_notes, display_analysis
from camtol.report.inline_svg import figure_svg
from camtol.report.qa import (
    BASE_CSS,
    PRINT_CSS,
    TRACEABILITY_FIELDS,
    CmmPart,
    InspectionReport,
    OverallVerdict,
    _where,
    overall_verdict,
    radius_table_html,
)

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis.radius_table import RadiusTable
    from camtol.analysis.result import Analysis
    from camtol.study import Study

__all__ = ["CONVENTIONS", "InspectionReport", "report_html", "write_report"]

#: Sentinel: "the study's own fixture inspection" (the default of report_html).
_FROM_STUDY: Any = object()

#: Conventions of THEORY §0 stated in every report.
CONVENTIONS: tuple[str, ...] = (
    "lengths in millimetres; length errors in micrometres; angles in degrees",
    "the cam turns clockwise at constant speed; the frame X-Y is fixed on the cam with its"
    " origin at the cam pivot O2, and θ is measured counterclockwise from the cam's reference"
    " radial (from the line of centres for oscillating followers)",
    "an oscillating follower turns in the same sense as the cam during a rise",
    "velocity and acceleration errors are per radian of cam angle (reduced derivatives)"
    " unless a cam speed is given, then per second",
    "a profile error is positive where material is added; Δr is the radial-dimension error,"
    " Δn the error along the profile normal",
    "each error source is taken at its tolerance, independently (linear theory, equivalent"
    " linkage); the worst case is Σ|ΔS_p| and the RMS is sqrt(Σ ΔS_p²)",
)

_CSS = (
    BASE_CSS
    + """.figure{margin:1em 0}.figure svg{max-width:100%;height:auto}
.figure figcaption{color:#444;font-size:.92em}code{background:#f5f5f5;padding:0 .2em}
"""
)


def _e(text: object) -> str:
    return html.escape(str(text), quote=True)


def _pretty(unit: str) -> str:
    from camtol.report.plots import pretty_unit

    return pretty_unit(unit)


def _quantity(v: float, unit: str) -> str:
    u = _pretty(unit)
    return f"{_fmt(v)}{u}" if u == "°" else f"{_fmt(v)} {u}"


def _fmt(v: float) -> str:
    if not np.isfinite(v):
        return str(v)
    if v == 0:
        return "0"
    mag = int(np.floor(np.log10(abs(v))))
    return f"{v:.{max(0, 4 - mag)}f}" if mag < 4 else f"{v:.0f}"


def _table(head: list[str], rows: list[list[str]], numeric: set[int] | None = None) -> str:
    numeric = numeric or set()
    out = ["<table><thead><tr>", *(f"<th>{_e(h)}</th>" for h in head), "</tr></thead><tbody>"]
    for row in rows:
        out.append("<tr>")
        for i, cell in enumerate(row):
            cls = ' class="num"' if i in numeric else ""
            out.append(f"<td{cls}>{_e(cell)}</td>")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def _inspection(study: Study) -> InspectionReport | None:
    if study.fixture is None or study.fixture_spec is None:
        return None
    return InspectionReport(study.fixture, study.fixture_spec)


def _banner(v: OverallVerdict) -> str:
    cls = {"PASS": "pass", "FAIL": "fail"}.get(v.status, "info")
    what = "Inspected part" if v.inspected else "Design check (no measured part)"
    items = "".join(f"<li>{_e(r)}</li>" for r in v.reasons)
    return (
        f'<div class="banner {cls}" id="verdict" role="status"><strong>{_e(v.status)}</strong>'
        f" &mdash; {_e(what)}<ul>{items}</ul></div>"
    )


def _traceability(design: CamDesign, given: dict[str, str] | None) -> list[list[str]]:
    fields: dict[str, str] = {}
    raw = design.extras.get("traceability")
    if isinstance(raw, dict):
        fields.update({str(k): str(v) for k, v in raw.items()})
    fields.update({k: v for k, v in (given or {}).items() if v})
    return [[label, fields[key]] for key, label in TRACEABILITY_FIELDS if key in fields]


def _verdicts(a: Analysis, fixture: InspectionReport | None) -> str:
    d = a.design
    k = a.kinematics
    shown = display_analysis(a)
    worst = shown.extremes["dS_worst"][0]
    rho = shown.extremes["curvature_radius"][1]
    pa = float(np.degrees(np.max(np.abs(k.pressure_angle_rad))))
    accuracy = (
        f"Output accuracy: max |ΔS worst case| = {_quantity(worst.value, shown.error_unit)}"
        f" at θ = {worst.where} over a travel of {_quantity(shown.travel, shown.travel_unit)}:"
        f" <strong>{_e(accuracy_words(a.accuracy))}</strong> (THEORY §3.6)."
        if a.accuracy is not None
        else f"Output accuracy: <strong>{_e(accuracy_words(None))}</strong> (THEORY §3.6)."
    )
    items = [
        accuracy,
        f"Profile: smallest radius of curvature {_fmt(rho.value)} mm at θ = {_e(rho.where)};"
        ' <span class="pass">no undercut or cusp</span> (checked over the whole revolution).',
    ]
    if len(d.cams()) > 1:
        from camtol.report.conjugate import conjugate_analysis_json

        b = conjugate_analysis_json(a)
        lo, hi = b["pressure_angle_deg"]
        items.append(
            f"Cam B: smallest radius of curvature {_fmt(b['min_curvature_radius_mm'])} mm at"
            f" θ = {b['min_curvature_at_deg']:.2f}°, pressure angle {lo:.2f}° .. {hi:.2f}°,"
            f" max radial dimension {b['max_radius_mm']:.4f} mm."
        )
    limit = d.pressure_angle_limit_deg
    if limit is None:
        items.append(f"Pressure angle: largest |φ| = {pa:.2f}° (no design limit given).")
    else:
        ok = not beyond_pressure_angle_limit(pa, limit)
        cls, word = ("pass", "within") if ok else ("fail", "BEYOND")
        items.append(
            f'Pressure angle: largest |φ| = {pa:.2f}° <span class="{cls}">{word}</span> the'
            f" design limit {limit:g}°."
        )
    if fixture is not None:
        res = fixture.inspection
        if res.verdicts:
            from camtol.pair.decision import decision_rule_text

            items.append(f"Decision rule: {_e(decision_rule_text(fixture.decision))}.")
        if fixture.record is not None:
            p = fixture.record.processed
            items.append(
                f"Indicator record: {p.revolutions} revolutions, measurement uncertainty"
                f" u_f up to {_fmt(p.u_f_max_um)} µm (rms {_fmt(p.u_f_rms_um)} µm,"
                " THEORY §4.4)."
            )
        if not res.verdicts:
            items.append("Fixture: no measured Δf in the design file; acceptance bands only.")
        for cam, v in sorted(res.verdicts.items()):
            if v.passed:
                items.append(
                    f'Fixture, cam {cam}: <span class="pass">passes</span> (smallest margin'
                    f" {_fmt(v.min_margin_um)} µm; a necessary condition, THEORY §4.3)."
                )
            else:
                where = _where(v, shown=12)
                items.append(
                    f'Fixture, cam {cam}: <span class="fail">FAILS</span> at θ = {_e(where)}'
                    f" (smallest margin {_fmt(v.min_margin_um)} µm, THEORY §4.3)."
                )
    return "<ul>" + "".join(f"<li>{i}</li>" for i in items) + "</ul>"


def report_html(
    study: Study,
    *,
    fixture: InspectionReport | None = _FROM_STUDY,
    traceability: dict[str, str] | None = None,
    radius_table: RadiusTable | None = None,
    sections: Sequence[str] = (),
    cmm: CmmPart | None = None,
) -> str:
    """Build the HTML report of a design as a string (see :func:`write_report`).

    Parameters
    ----------
    study : Study
        Every result the report shows, from :func:`camtol.study.study`; the report only
        formats it.
    fixture : InspectionReport or None, optional
        A finished fixture inspection to report (``camtol report --df-mea/--record``,
        with its decision rule and record); None for none; by default the study's own
        fixture inspection (simple decision rule).
    traceability : dict of str to str, optional
        Traceability fields (keys of :data:`camtol.report.qa.TRACEABILITY_FIELDS`); they
        override the design's ``[traceability]`` table.
    radius_table : RadiusTable, optional
        Append this radius table (:func:`camtol.analysis.radius_table.radius_table`, every 1° of
        polar angle) as an appendix.
    sections : sequence of str
        Extra HTML sections inserted before the figures (e.g. the Monte Carlo section of
        :func:`camtol.report.tolerancing.montecarlo_section`).
    cmm : CmmPart, optional
        A single cam's CMM inspection (``camtol report --cmm``): its verdict is the
        banner's (:func:`camtol.report.qa.overall_verdict`); its section is one of
        ``sections``.

    Returns
    -------
    str
        The complete HTML document; the overall PASS/FAIL banner comes first.
    """
    from camtol._version import __version__
    from camtol.report.plots import analysis_figure, fixture_figure

    a = study.analysis
    d = a.design
    if fixture is _FROM_STUDY:
        fixture = _inspection(study)
    verdict = overall_verdict(a, fixture, cmm=cmm)
    now = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    parts: list[str] = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        '<link rel="icon" href="data:,">',
        f"<title>{_e(d.name)}: camtol report</title>",
        f"<style>{_CSS}{PRINT_CSS}</style></head><body>",
        f"<h1>{_e(d.name)}</h1>",
        _banner(verdict),
        f'<p class="meta">camtol {_e(__version__)} report, generated {now}.'
        f" Analysis grid {a.step_deg:g}°, extremes refined to step/1000.</p>",
    ]
    if d.description:
        parts.append(
            "<p>" + "<br>".join(_e(x) for x in d.description.strip().splitlines()) + "</p>"
        )
    if d.reference:
        parts.append(f'<p class="meta">Reference: {_e(d.reference)}</p>')

    trace = _traceability(d, traceability)
    if trace:
        parts.append("<h2>Traceability</h2>")
        parts.append(_table(["field", "value"], trace))
    parts.append("<h2>Verdicts</h2>")
    parts.append(_verdicts(a, fixture))

    parts.append("<h2>Inputs</h2>")
    rows = [[name, value] for name, value in d.mechanism.summary()]
    rows.append(["motion", d.describe_motion()])
    rows.append(["cam speed", f"{d.speed_rpm:g} rpm" if d.speed_rpm else "not given (per rad)"])
    if d.pressure_angle_limit_deg is not None:
        rows.append(["pressure-angle limit", f"{d.pressure_angle_limit_deg:g}°"])
    rows.append(["max radial dimension", f"{a.max_radius_mm:.4f} mm"])
    parts.append(_table(["parameter", "value"], rows))
    if a.tolerances:
        trows = [
            [t.key, d.mechanism.source(t.key).description, t.display, t.origin]
            for t in a.tolerances
        ]
        parts.append("<h3>Tolerances</h3>")
        parts.append(_table(["source", "error", "deviation", "obtained from"], trows))
    if fixture is not None:
        spec = fixture.spec
        er = spec.errors
        frows = [
            [
                "radial tolerance of cam A",
                f"{spec.tolerance_a_um[0]:g} .. {spec.tolerance_a_um[1]:g} µm",
            ],
            [
                "radial tolerance of cam B",
                f"{spec.tolerance_b_um[0]:g} .. {spec.tolerance_b_um[1]:g} µm",
            ],
            ["arm-length errors Δl_A, Δl_B", f"{er.dl_a_mm * 1e3:g} µm, {er.dl_b_mm * 1e3:g} µm"],
            [
                "roller-radius errors Δr_rC, Δr_rD",
                f"{er.drr_c_mm * 1e3:g} µm, {er.drr_d_mm * 1e3:g} µm",
            ],
            ["arm-angle error Δη", f"{np.degrees(er.deta_rad):g}°"],
            ["master cam A error", spec.master_a.description],
            ["master cam B error", spec.master_b.description],
            ["measured Δf", spec.df_mea.description if spec.df_mea is not None else "none"],
        ]
        parts.append("<h3>Measuring fixture (THEORY §4)</h3>")
        parts.append(_table(["input", "value"], frows))

    parts.append("<h2>Conventions and assumptions</h2><ul>")
    parts += [f"<li>{_e(c)}</li>" for c in CONVENTIONS]
    parts += [f"<li>IT grades: {_e(c)}</li>" for c in IT_CONVENTIONS]
    if len(d.cams()) > 1:
        parts.append(
            "<li>conjugate pair: the single-contact errors, extremes and figures are cam A's"
            " (roller C); the cam drawing shows both cams</li>"
        )
    parts += [f"<li><strong>Note:</strong> {_e(n)}</li>" for n in analysis_notes(a)]
    parts.append("</ul>")

    parts.append("<h2>Extremes over 0-360°</h2>")
    erows = []
    shown = display_analysis(a)
    for q in shown.quantities:
        mx, mn = shown.extremes[q.key]
        erows.append([q.label, _pretty(q.unit), _fmt(mx.value), mx.where, _fmt(mn.value), mn.where])
    parts.append(_table(["quantity", "unit", "max", "at θ", "min", "at θ"], erows, {2, 4}))

    parts.extend(sections)
    parts.append("<h2>Figures</h2>")
    figures: list[tuple[Any, str]] = [
        (
            analysis_figure(a, study.drawing),
            "The cam and follower at the angle of the largest worst-case error (with the"
            " pitch curve of a roller); the nominal motion S, V, A, J (at the design speed"
            " when given); shift and pressure angles with the pressure-angle limit;"
            " radial-error factor; displacement errors per source with worst case and RMS;"
            " velocity and acceleration errors per source inside their worst-case envelopes"
            " (THEORY §1-3, CW06 Figs. 4-9).",
        )
    ]
    if fixture is not None:
        spec = fixture.spec
        figures.append(
            (
                fixture_figure(
                    fixture.inspection,
                    tolerance_a_um=spec.tolerance_a_um,
                    tolerance_b_um=spec.tolerance_b_um,
                    design_name=d.name,
                    record=fixture.record,
                    decision_rule=fixture.decision,
                ),
                "Centre-distance variation Δf and its components, estimated profile errors with"
                " the tolerances, and the acceptance bands with the measured Δf; failing"
                " intervals shaded (THEORY §4, CW11 §3).",
            )
        )
    for i, (fig, caption) in enumerate(figures, start=1):
        parts.append(
            f'<figure class="figure" id="figure-{i}">{figure_svg(fig, prefix=f"fig{i}")}'
            f"<figcaption>Figure {i}. {_e(caption)}</figcaption></figure>"
        )
    if radius_table is not None:
        parts.append('<section class="appendix"><h2>Appendix: radius table</h2>')
        parts.append(
            '<p class="meta">Profile radius R (and pitch-curve radius of a roller) every 1° of'
            " polar angle in the cam frame X-Y (origin at the pivot O2, angle counterclockwise"
            " from X; THEORY §0), interpolated from a 0.02° sampling of the exact profile.</p>"
        )
        parts.append(radius_table_html(radius_table, _e))
        parts.append("</section>")
    parts.append(
        f'<hr><p class="meta">Generated by camtol {_e(__version__)}. Equations, sign'
        " conventions and sources (CW06, CW11, WC05, Wu03): the Theory page of the camtol"
        " documentation, docs/theory.md in the camtol repository; “THEORY §x”"
        " in this report is its section x.</p>"
    )
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def write_report(
    study: Study,
    path: str | Path,
    *,
    fixture: InspectionReport | None = _FROM_STUDY,
    traceability: dict[str, str] | None = None,
    radius_table: RadiusTable | None = None,
    sections: Sequence[str] = (),
    cmm: CmmPart | None = None,
) -> Analysis:
    """Write a self-contained HTML report (inline CSS and SVG, no scripts, works offline).

    Parameters
    ----------
    study : Study
        Every result the report shows, from :func:`camtol.study.study`.
    path : str or Path
        Output file; must end in ``.html`` or ``.htm``.
    fixture : InspectionReport or None, optional
        As for :func:`report_html`.
    traceability : dict of str to str, optional
        As for :func:`report_html`.
    radius_table : RadiusTable, optional
        As for :func:`report_html`.
    sections : sequence of str
        As for :func:`report_html`.
    cmm : CmmPart, optional
        As for :func:`report_html`.

    Returns
    -------
    Analysis
        The analysis that was reported.

    Raises
    ------
    camtol.exceptions.ExportError
        Wrong suffix or missing directory; nothing is written.

    Notes
    -----
    The page holds the inputs, the conventions (THEORY §0, §3.6), the verdicts (accuracy
    grade of the output, THEORY §3.6; curvature; pressure angle; the fixture acceptance of
    THEORY §4.3 for a conjugate design with an ``[inspection]`` table), the extremes table
    and the figures of :func:`camtol.report.plots.analysis_figure` (and
    :func:`~camtol.report.plots.fixture_figure`). The file is written to a temporary name
    and renamed into place.
    """
    from camtol.exceptions import ExportError
    from camtol.files import atomic_write

    p = Path(path)
    if p.suffix.lower() not in (".html", ".htm"):
        raise ExportError(
            f"output file {str(p)!r} has suffix {p.suffix or '(none)'!r}; allowed: .html, .htm"
        )
    if not p.parent.is_dir():
        raise ExportError(f"output file {str(p)!r}: directory {str(p.parent)!r} does not exist")
    from camtol.report.finite import require_finite_columns
    from camtol.report.tables import curves_columns

    require_finite_columns(curves_columns(study.analysis), where=str(p))
    atomic_write(
        p,
        report_html(
            study,
            fixture=fixture,
            traceability=traceability,
            radius_table=radius_table,
            sections=sections,
            cmm=cmm,
        ),
    )
    return study.analysis
