"""The QA parts of the HTML report: overall verdict, traceability, radius table, print CSS.

* :func:`overall_verdict`: PASS/FAIL first (issue 13 item 13). An inspected part (a
  measured conjugate pair, THEORY §4.3) passes when every inspected cam passes under the
  decision rule in force (:mod:`camtol.inspection.decision`, ISO 14253-1); a design
  without a measurement gets the design checks (pressure-angle limit; undercut is an
  error before any report is made).
* :func:`radius_table`: the cam drawing's table, the profile radius every 1° of polar
  angle in the cam frame (THEORY §0), with the pitch-curve radius of a roller.
* :data:`TRACEABILITY_FIELDS` and :data:`PRINT_CSS`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis import Analysis
    from camtol.design import CamDesign
    from camtol.inspection.acceptance import CamVerdict
    from camtol.inspection.decision import DecisionRule
    from camtol.inspection.fixture import FixtureInspection
    from camtol.inspection.record import RecordEstimates
    from camtol.inspection.spec import FixtureSpec

__all__ = [
    "PRINT_CSS",
    "TRACEABILITY_FIELDS",
    "InspectionReport",
    "OverallVerdict",
    "RadiusTable",
    "overall_verdict",
    "radius_table",
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
    from camtol.inspection.acceptance import merge_intervals

    spans = merge_intervals(v.failing_intervals_deg, 1.0)
    text = ", ".join(f"{s:.2f}-{e:.2f}°" for s, e in spans[:shown])
    if len(spans) > shown:
        text += f" and {len(spans) - shown} more stretches"
    return text


def overall_verdict(a: Analysis, fixture: InspectionReport | None) -> OverallVerdict:
    """Decide the report's headline from the analysis and the inspection (if any).

    Parameters
    ----------
    a : Analysis
        The design's analysis.
    fixture : InspectionReport or None
        The fixture inspection of a measured conjugate pair.

    Returns
    -------
    OverallVerdict
        Inspected part: PASS when every inspected cam passes under the decision rule.
        Otherwise the design checks: FAIL when |φ| exceeds the design's pressure-angle
        limit, else PASS.
    """
    name = a.design.name
    if fixture is not None and fixture.inspection.verdicts:
        from camtol.inspection.decision import decision_rule_text

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
        ok = pa <= limit
        reasons.append(f"largest |φ| {pa:.2f}° {'within' if ok else 'BEYOND'} the limit {limit:g}°")
    reasons.append(f"output accuracy {a.accuracy.describe()}")
    status = "PASS" if ok else "FAIL"
    return OverallVerdict(
        status,
        False,
        f"design check {status}: {name}: " + "; ".join(reasons) + " (no measured part)",
        tuple(reasons),
    )


@dataclass(frozen=True)
class RadiusTable:
    """The cam drawing's radius table (THEORY §0: cam frame, origin at the pivot O2).

    Attributes
    ----------
    polar_deg : ndarray
        Polar angle of the profile point in the cam frame, 0, 1, ..., 359. [deg]
    columns : dict of str to ndarray
        ``"R_mm"`` profile radius (``"R_A_mm"``, ``"R_B_mm"`` for a conjugate pair) and
        ``"R_pitch_mm"`` (``..._A_``/``_B_``) the pitch-curve radius of a roller. [mm]
    """

    polar_deg: FloatArray
    columns: dict[str, FloatArray]


def _polar_radius(x: FloatArray, y: FloatArray, polar_deg: FloatArray) -> FloatArray:
    """Radius of a closed star-shaped curve (about the origin) at the given polar angles."""
    ang = np.mod(np.degrees(np.arctan2(y, x)), 360.0)
    r = np.hypot(x, y)
    order = np.argsort(ang, kind="stable")
    ang, r = ang[order], r[order]
    ang = np.concatenate([ang[-1:] - 360.0, ang, ang[:1] + 360.0])
    r = np.concatenate([r[-1:], r, r[:1]])
    return np.asarray(np.interp(polar_deg, ang, r))


def radius_table(design: CamDesign, *, step_deg: float = 1.0) -> RadiusTable:
    """Tabulate the profile radius every ``step_deg`` of polar angle (the drawing's table).

    Parameters
    ----------
    design : CamDesign
        The design (both cams of a conjugate pair).
    step_deg : float
        Table step of polar angle. [deg]

    Returns
    -------
    RadiusTable
        Radii at polar angles 0, step, ... < 360 in the cam frame.

    Notes
    -----
    The profile is sampled at 0.02° of cam angle by :func:`camtol.kinematics.kinematics`
    and interpolated linearly in polar angle; the chord error of a 0.02° step on a cam of
    radius R and curvature radius ρ is about R²(0.02°)²/(8ρ), far below 0.1 µm for the
    built-in examples. The profile must be star-shaped about O2 (every disk cam is).
    """
    from camtol import jet
    from camtol.kinematics import analysis_grid, kinematics

    polar = np.arange(0.0, 360.0, step_deg)
    grid, left = analysis_grid(0.02, design.program.boundaries_rad)
    cams: list[tuple[str, CamDesign]] = [
        (f"_{c.label}" if c.label else "", c.design) for c in design.cams()
    ]
    cols: dict[str, FloatArray] = {}
    for tag, d in cams:
        k = kinematics(d, grid, left_limit=left, check=False)
        cols[f"R{tag}_mm"] = _polar_radius(k.contact_x_mm, k.contact_y_mm, polar)
        g = d.mechanism.contact(k.theta_rad, k.lift, k.velocity)
        if "pitch_x" in g.extras:
            px = np.asarray(jet.value(g.extras["pitch_x"]), dtype=float)
            py = np.asarray(jet.value(g.extras["pitch_y"]), dtype=float)
            cols[f"R_pitch{tag}_mm"] = _polar_radius(px, py, polar)
    return RadiusTable(polar, cols)


def radius_table_html(table: RadiusTable, escape: Any) -> str:
    """Render the radius table as a long HTML table (breaks between rows when printed).

    Parameters
    ----------
    table : RadiusTable
        From :func:`radius_table`.
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
