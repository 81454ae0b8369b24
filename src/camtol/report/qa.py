"""The QA parts of the HTML report: overall verdict, traceability, radius table, print CSS.

* :func:`overall_verdict`: PASS/FAIL first (issue 13 item 13). An inspected part (a
  measured conjugate pair, THEORY §4.3) passes when every inspected cam passes under the
  decision rule in force (:mod:`camtol.pair.decision`, ISO 14253-1); a design
  without a measurement gets the design checks (pressure-angle limit; undercut is an
  error before any report is made).
* :func:`radius_table_html`: the cam drawing's table of
  :func:`camtol.analysis.radius_table.radius_table`, formatted.
* :data:`TRACEABILITY_FIELDS` and :data:`PRINT_CSS`.
* :class:`CmmPart`: a single cam's CMM inspection in the report (``camtol report
  --cmm``, issue 31): its verdict is the headline's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis.radius_table import RadiusTable
    from camtol.analysis.result import Analysis
    from camtol.pair.acceptance import CamVerdict
    from camtol.pair.decision import DecisionRule
    from camtol.pair.fixture import FixtureInspection
    from camtol.pair.fixture_spec import FixtureSpec
    from camtol.pair.indicator import RecordEstimates

__all__ = [
    "PRINT_CSS",
    "TRACEABILITY_FIELDS",
    "CmmPart",
    "InspectionReport",
    "OverallVerdict",
    "overall_verdict",
    "radius_table_html",
]

#: Traceability fields of a QA report: (key, label). Keys as in the design's
#: ``[traceability]`` table and the ``camtol report`` options (``--part-number`` ...).
TRACEABILITY_FIELDS: tuple[tuple[str, str], ...] = (
    ("part_number", "part number"),
    ("drawing_number", "drawing number"),
    ("revision", "revision"),
    ("serial", "serial number"),
    ("inspector", "inspector"),
    ("instrument", "instrument"),
    ("date", "inspection date"),
)

#: The screen style every camtol HTML report shares (part report, lot report).
BASE_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:2em auto;
max-width:1100px;padding:0 1em;color:#1a1a1a;line-height:1.45}
h1{font-size:1.6em;margin-bottom:.2em}h2{border-bottom:1px solid #ccc;padding-bottom:.2em;
margin-top:1.6em}table{border-collapse:collapse;margin:.6em 0}
th,td{border:1px solid #ccc;padding:.25em .6em;text-align:left;vertical-align:top}
td.num{text-align:right;font-variant-numeric:tabular-nums}th{background:#f2f2f2}
.meta{color:#555}.pass{color:#11702b;font-weight:600}.fail{color:#b00020;font-weight:600}
"""

#: Print rules: A4, no table, figure or banner split over pages, no heading left alone
#: at the foot of a page; long tables (class ``long``) may break between rows and repeat
#: their header.
PRINT_CSS = """
@page{size:A4;margin:14mm}
h1,h2,h3{break-after:avoid;page-break-after:avoid}
table,figure,.banner,ul{break-inside:avoid;page-break-inside:avoid}
table.long{break-inside:auto;page-break-inside:auto}
table.long tr{break-inside:avoid;page-break-inside:avoid}
thead{display:table-header-group}
.banner{padding:.6em 1em;border-radius:4px;font-size:1.25em;margin:.8em 0}
.banner.pass{background:#e3f4e8;border:2px solid #11702b}
.banner.fail{background:#fbe5e8;border:2px solid #b00020}
.banner.info{background:#eef2f7;border:2px solid #56708f;color:#1a1a1a;font-weight:600}
table.long td{padding:.05em .4em;font-size:.85em}
@media print{body{max-width:none;margin:0;padding:0;font-size:10pt}
.figure svg{max-height:23cm;width:auto;max-width:100%;height:auto}
.appendix{break-before:page;page-break-before:always}}
"""


@dataclass(frozen=True)
class InspectionReport:
    """A finished fixture inspection to report (THEORY §4): results passed in, not run.

    Attributes
    ----------
    inspection : FixtureInspection
        The inspection; its verdicts are those of ``decision``.
    spec : FixtureSpec
        The specification it was run with.
    record : RecordEstimates or None
        With an indicator record: u_f and the estimates at Δf_mea ± u_f.
    decision : {"simple", "guard-band"}
        The decision rule the verdicts were taken with (ISO 14253-1).
    """

    inspection: FixtureInspection
    spec: FixtureSpec
    record: RecordEstimates | None = None
    decision: DecisionRule = "simple"


@dataclass(frozen=True)
class CmmPart:
    """A single cam's CMM inspection, finished, for the report (results passed in).

    Attributes
    ----------
    data : dict
        The inspection as :func:`camtol.report.inspection_report.inspection_json` gives
        it (with ``traceability``).
    """

    data: dict[str, Any]

    @property
    def passed(self) -> bool:
        """Whether the cam passed (profile zone and, with a spec, the follower error)."""
        return bool(self.data["verdict"] == "pass")


@dataclass(frozen=True)
class OverallVerdict:
    """The report's headline.

    Attributes
    ----------
    status : {"PASS", "FAIL", "NOT INSPECTED"}
        PASS/FAIL of the inspected part, or of the design checks without a measurement
        (then ``inspected`` is False).
    inspected : bool
        True when a measured part was judged (``camtol report`` exits 1 on its FAIL).
    headline : str
        One line: the status and why.
    reasons : tuple of str
        The individual findings.
    """

    status: str
    inspected: bool
    headline: str
    reasons: tuple[str, ...]

    @property
    def passed(self) -> bool:
        """True unless the status is FAIL."""
        return self.status != "FAIL"


def _where(v: CamVerdict, shown: int = 4) -> str:
    """Failing stretches (intervals joined across gaps < 1°), at most ``shown`` of them."""
    from camtol.pair.acceptance import merge_intervals

    spans = merge_intervals(v.failing_intervals_deg, 1.0)
    text = ", ".join(f"{s:.2f}-{e:.2f}°" for s, e in spans[:shown])
    if len(spans) > shown:
        text += f" and {len(spans) - shown} more stretches"
    return text


def overall_verdict(
    a: Analysis, fixture: InspectionReport | None, *, cmm: CmmPart | None = None
) -> OverallVerdict:
    """Decide the report's headline from the analysis and the inspection (if any).

    Parameters
    ----------
    a : Analysis
        The design's analysis.
    fixture : InspectionReport or None
        The fixture inspection of a measured conjugate pair.
    cmm : CmmPart, optional
        A single cam's CMM inspection (``camtol report --cmm``).

    Returns
    -------
    OverallVerdict
        Inspected part: PASS when every inspected cam passes under the decision rule.
        Otherwise the design checks: FAIL when |φ| exceeds the design's pressure-angle
        limit, else PASS.
    """
    name = a.design.name
    if cmm is not None:
        from camtol.report.inspection_report import failing_stretches, stretch_gap_deg

        z = cmm.data["zone"]
        dec = cmm.data["decision"]
        zone = (
            f"zone [{z['lower_um']:+g}, {z['upper_um']:+g}] µm (t = {z['width_um']:g} µm,"
            f" {z['placement']})"
        )
        if cmm.data["profile_verdict"] == "pass":
            reasons = [f"cam {cmm.data['cam']} passes its profile {zone}"]
        else:
            spans = failing_stretches(
                [(float(a_), float(b_)) for a_, b_ in cmm.data["failing_intervals_deg"]],
                stretch_gap_deg(int(cmm.data["points"])),
            )
            where = ", ".join(f"{s:.1f}-{e:.1f}°" for s, e in spans[:4])
            more = f" and {len(spans) - 4} more stretches" if len(spans) > 4 else ""
            reasons = [f"cam {cmm.data['cam']} FAILS its profile {zone} at {where}{more}"]
        motion = cmm.data.get("motion") or {}
        if motion.get("verdict") is not None:
            reasons.append(f"follower error {motion['verdict'].upper()} against its spec")
        reasons.append(f"decision rule: {dec['statement'].split(':')[0]}")
        status = "PASS" if cmm.passed else "FAIL"
        return OverallVerdict(
            status, True, f"{status}: {name}: " + "; ".join(reasons), tuple(reasons)
        )
    if fixture is not None and fixture.inspection.verdicts:
        from camtol.pair.decision import decision_rule_text

        reasons = []
        for cam, v in sorted(fixture.inspection.verdicts.items()):
            if v.passed:
                reasons.append(f"cam {cam} passes (smallest margin {v.min_margin_um:.3g} µm)")
            else:
                reasons.append(
                    f"cam {cam} FAILS at θ = {_where(v)} (margin {v.min_margin_um:.3g} µm)"
                )
        ok = all(v.passed for v in fixture.inspection.verdicts.values())
        rule = decision_rule_text(fixture.decision).split(":")[0]
        reasons.append(f"decision rule: {rule}")
        status = "PASS" if ok else "FAIL"
        return OverallVerdict(
            status, True, f"{status}: {name}: " + "; ".join(reasons), tuple(reasons)
        )
    limit = a.design.pressure_angle_limit_deg
    pa = float(np.degrees(np.max(np.abs(a.kinematics.pressure_angle_rad))))
    reasons = ["no undercut or cusp"]
    ok = True
    if limit is not None:
        from camtol.analysis.kinematics import beyond_pressure_angle_limit

        ok = not beyond_pressure_angle_limit(pa, limit)
        reasons.append(f"largest |φ| {pa:.2f}° {'within' if ok else 'BEYOND'} the limit {limit:g}°")
    from camtol.report.display import accuracy_words

    reasons.append(f"output accuracy {accuracy_words(a.accuracy)}")
    status = "PASS" if ok else "FAIL"
    return OverallVerdict(
        status,
        False,
        f"design check {status}: {name}: " + "; ".join(reasons) + " (no measured part)",
        tuple(reasons),
    )


def radius_table_html(table: RadiusTable, escape: Any) -> str:
    """Render the radius table as a long HTML table (breaks between rows when printed).

    Parameters
    ----------
    table : RadiusTable
        From :func:`camtol.analysis.radius_table.radius_table`.
    escape : callable
        HTML escaping of the header texts.

    Returns
    -------
    str
        The ``<table class="long radius-table">`` element.
    """
    heads = ["polar angle [°]"] + [
        k.removesuffix("_mm").replace("_pitch", " pitch").replace("_", " ") + " [mm]"
        for k in table.columns
    ]
    out = ['<table class="long radius-table"><thead><tr>']
    out += [f"<th>{escape(h)}</th>" for h in heads]
    out.append("</tr></thead><tbody>")
    for i, p in enumerate(table.polar_deg):
        cells = [f"{p:g}"] + [f"{v[i]:.4f}" for v in table.columns.values()]
        out.append("<tr>" + "".join(f'<td class="num">{c}</td>' for c in cells) + "</tr>")
    out.append("</tbody></table>")
    return "".join(out)
