"""Outputs of ``camtol inspect``: JSON, CSV files, text summary and HTML report.

File columns and JSON keys are fixed (issue 12, docs/cmm-inspection.md):

- curves CSV, one row per measured point: ``x_mm, y_mm, theta_deg, dn_um, dr_um`` (after
  registration, in the cam frame; ``theta_deg`` the polar angle of the point);
- motion CSV, one row per cam angle: ``theta_deg, dS_measured_<unit>, dS_linear_<unit>``
  with ``<unit>`` ``um`` (translating follower) or ``deg`` (oscillating);
- JSON (schema_version 2.0, issue 31): ``verdict`` (the profile and, with a motion spec,
  the follower error), ``profile_verdict``, ``zone`` (ISO 1101 limits, width, offset,
  floating or located), ``decision`` (ISO 14253-1 rule, U, acceptance limits),
  ``registration`` (random and form uncertainties, 95 % expanded), ``form_um``,
  ``max_dn_um``, ``min_dn_um``, ``outliers``, ``failing_intervals_deg`` and the merged
  ``failing_stretches_deg``, ``motion`` (every figure's key carries its unit:
  ``max_abs_ds_um`` for a lift, ``max_abs_ds_deg`` for a swing), ``traceability`` and
  context keys.

One unit per quantity: a translating follower's motion error is in µm, an oscillating
one's in degrees, in the terminal, JSON, CSV, the plot, the store and the HTML report.

Why one module: every output is the same inspection, written from one JSON-ready dict
(:func:`inspection_json`): the text, the CSV files, the part report and the QA report's
section must say the same thing in the same units.
"""

from __future__ import annotations

import html
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.files import atomic_write
from camtol.report.csv_text import csv_text
from camtol.report.display import output_error_unit

if TYPE_CHECKING:
    from camtol.design.cam_design import CamDesign
    from camtol.inspection.deviations import CmmInspection
    from camtol.inspection.functional import FunctionalDeviation

__all__ = [
    "INSPECT_SCHEMA_VERSION",
    "STRETCH_GAP_DEG",
    "cmm_section_html",
    "failing_stretches",
    "inspection_json",
    "stretch_gap_deg",
    "inspection_report_html",
    "inspection_text",
    "motion_unit",
    "traceability_json",
    "wrap_line",
    "write_curves_csv",
    "write_motion_csv",
]

#: Version of the ``camtol inspect --json`` document (2.0: zone, decision, unit-named
#: motion keys, traceability; issue 31).
INSPECT_SCHEMA_VERSION = "2.0"

#: Failing angles closer than this are one stretch (as ``camtol conjugate`` merges). [deg]
STRETCH_GAP_DEG = 1.0

#: Traceability keys of a part report, in the order shown (the ``[traceability]`` names).
_TRACE_KEYS = (
    ("part_number", "part number"),
    ("drawing_number", "drawing number"),
    ("revision", "revision"),
    ("serial", "serial number"),
    ("lot", "lot"),
    ("inspector", "inspector"),
    ("instrument", "instrument"),
    ("date", "inspection date"),
)


def failing_stretches(
    intervals: list[tuple[float, float]], gap_deg: float = STRETCH_GAP_DEG
) -> list[tuple[float, float]]:
    """Failing angles merged into stretches, as ``camtol conjugate`` does.

    Parameters
    ----------
    intervals : list of (float, float)
        Sorted polar-angle intervals of consecutive failing points. [deg]
    gap_deg : float
        Gaps shorter than this are closed. [deg]

    Returns
    -------
    list of (float, float)
        The stretches (a stretch through 0° is joined: end < start). [deg]
    """
    from camtol.pair.acceptance import merge_intervals

    ordinary = sorted((a, b) for a, b in intervals if b >= a)
    wrapping = [(a, b) for a, b in intervals if b < a]
    out = merge_intervals(ordinary, gap_deg)
    if wrapping:  # at most one interval wraps through 0°: join its neighbours across 0°
        a, b = wrapping[0]
        while out and out[0][0] - b < gap_deg:
            b = max(b, out.pop(0)[1])
        while out and a - out[-1][1] < gap_deg:
            a = min(a, out.pop()[0])
        out.append((a, b))
    elif len(out) > 1 and out[0][0] + 360.0 - out[-1][1] < gap_deg:
        first, last = out.pop(0), out.pop()
        out.append((last[0], first[1]))
    return out


def stretch_gap_deg(points: int) -> float:
    """Return the gap that failing stretches are merged across for a scan of ``points``.

    :data:`STRETCH_GAP_DEG` (1°, as ``camtol conjugate`` on its 0.1° grid), or four point
    spacings of a sparser scan (a single passing point between failing ones does not
    split a stretch). [deg]

    Parameters
    ----------
    points : int
        Profile points of the scan.
    """
    return max(STRETCH_GAP_DEG, 4.0 * 360.0 / max(points, 1))


def traceability_json(
    given: dict[str, str], *, design: CamDesign, scan_path: str | None
) -> dict[str, Any]:
    """Return the part's identity: traceability, camtol version, design and scan hashes.

    The design's ``[traceability]`` table fills what the options do not give.

    Parameters
    ----------
    given : dict of str to str
        From the options (``part_number``, ``drawing_number``, ``revision``, ``serial``,
        ``lot``, ``inspector``, ``instrument``, ``date``).
    design : CamDesign
        The design (its content hash and ``[traceability]`` table).
    scan_path : str or None
        The scan file (its SHA-256).

    Returns
    -------
    dict
        The keys above (those known), ``camtol_version``, ``design_hash``
        (``sha256:<hex>``) and ``scan_sha256`` (``sha256:<hex>``, None without a scan).
    """
    import hashlib

    from camtol._version import __version__

    out: dict[str, Any] = {}
    table = design.extras.get("traceability")
    if isinstance(table, dict):
        out.update({str(k): str(v) for k, v in table.items() if v is not None})
    out.update({k: v for k, v in given.items() if v})
    digest = None
    if scan_path is not None:
        h = hashlib.sha256()
        with open(scan_path, "rb") as fh:
            for chunk in iter(lambda: fh.read(1 << 20), b""):
                h.update(chunk)
        digest = "sha256:" + h.hexdigest()
    out.update(
        camtol_version=__version__,
        design_hash="sha256:" + design.content_hash,
        scan_sha256=digest,
    )
    return out


def motion_unit(functional: FunctionalDeviation) -> tuple[str, float]:
    """Return the file unit of ΔS and the factor from the library's unit.

    Parameters
    ----------
    functional : FunctionalDeviation
        The follower-motion error (S in mm or rad).

    Returns
    -------
    (str, float)
        (``um``, 1e3) for a translating follower, (``deg``, 180/π) for an oscillating one.
    """
    shown = output_error_unit(functional.unit)
    return shown.unit, shown.factor


def inspection_json(
    insp: CmmInspection,
    functional: FunctionalDeviation | None,
    *,
    design: str,
    stylus_radius_mm: float,
) -> dict[str, Any]:
    """Return the inspection as a JSON-ready dict (keys as documented in docs/cmm-inspection.md).

    Parameters
    ----------
    insp : CmmInspection
        The inspection.
    functional : FunctionalDeviation or None
        The follower-motion error, if computed.
    design : str
        Design name.
    stylus_radius_mm : float
        Stylus radius used for compensation. [mm]
    """
    reg = insp.registration
    functional_ok = functional is None or functional.passed is not False
    zone = insp.zone
    accept = insp.acceptance or zone
    u95 = reg.expanded_95
    out: dict[str, Any] = {
        "design": design,
        "cam": insp.cam,
        "scan": insp.source,
        "points": int(insp.dn_um.size),
        "stylus_radius_mm": stylus_radius_mm,
        "verdict": "pass" if insp.passed and functional_ok else "fail",
        "profile_verdict": "pass" if insp.passed else "fail",
        "tolerance_um": list(insp.tolerance_um),
        "tolerance_on": "dn_um" if insp.tolerance_kind == "normal" else "dr_um",
        "zone": {
            "lower_um": zone.lower_um,
            "upper_um": zone.upper_um,
            "width_um": zone.width_um,
            "offset_um": zone.offset_um,
            "on": "dn_um" if zone.on == "normal" else "dr_um",
            "convention": zone.convention,
            "iso1101": zone.on == "normal",
            "source": zone.source,
            "placement": "floating" if insp.floating else "located",
            "excess_um": insp.excess_um,
        },
        "decision": {
            "rule": insp.decision,
            "u_um": insp.u_um,
            "acceptance_um": [accept.lower_um, accept.upper_um],
            "statement": _decision_statement(insp.decision),
        },
        "registration": {
            "mode": reg.mode,
            "fitted": list(reg.fitted),
            "rotation_deg": reg.rotation_deg,
            "dx_mm": reg.dx_mm,
            "dy_mm": reg.dy_mm,
            "u_rotation_deg": reg.u_rotation_deg,
            "u_dx_mm": reg.u_dx_mm,
            "u_dy_mm": reg.u_dy_mm,
            "u_form_rotation_deg": reg.u_form_rotation_deg,
            "u_form_dx_mm": reg.u_form_dx_mm,
            "u_form_dy_mm": reg.u_form_dy_mm,
            "coverage_factors": list(reg.coverage_factors),
            "U95_rotation_deg": u95[0],
            "U95_dx_mm": u95[1],
            "U95_dy_mm": u95[2],
        },
        "form_um": insp.form_um,
        "min_zone_um": insp.min_zone_um,
        "max_dn_um": insp.max_dn_um,
        "min_dn_um": insp.min_dn_um,
        "outliers": {
            "count": int(reg.outliers.size),
            "indices": [int(insp.index[i]) for i in reg.outliers],
        },
        "failing_intervals_deg": [
            [round(a, 4), round(b, 4)] for a, b in insp.failing_intervals_deg
        ],
        "failing_stretches_deg": [
            [round(a, 4), round(b, 4)]
            for a, b in failing_stretches(
                insp.failing_intervals_deg, stretch_gap_deg(int(insp.dn_um.size))
            )
        ],
        "warnings": list(reg.warnings),
    }
    if functional is not None:
        unit, k = motion_unit(functional)
        out["motion"] = {
            "unit": unit,
            "harmonics": functional.harmonics,
            f"max_abs_ds_{unit}": functional.max_abs_measured * k,
            f"max_abs_ds_linear_{unit}": functional.max_abs_linear * k,
            f"max_abs_dv_{unit}_per_rad": float(np.max(np.abs(functional.dv_measured))) * k,
            f"max_abs_da_{unit}_per_rad2": float(np.max(np.abs(functional.da_measured))) * k,
            f"spec_{unit}": None if functional.spec is None else functional.spec * k,
            "verdict": None
            if functional.passed is None
            else ("pass" if functional.passed else "fail"),
        }
    return out


def _decision_statement(rule: str) -> str:
    """State the CMM decision rule in one sentence (ISO 14253-1)."""
    if rule == "guard-band":
        return (
            "guard band (ISO 14253-1 proof of conformance): a cam passes only when its"
            " deviations lie within the zone shrunk by U on both sides"
        )
    return (
        "simple acceptance (ISO 14253-1 shared risk): a cam passes when its deviations lie"
        " within the zone; the uncertainty is not used"
    )


def _csv(columns: dict[str, np.ndarray], comment: str) -> str:
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    return csv_text(names, data, comment=comment)


def write_curves_csv(insp: CmmInspection, path: str) -> None:
    """Write one row per measured point: x_mm, y_mm, theta_deg, dn_um, dr_um (atomic).

    Parameters
    ----------
    insp : CmmInspection
        The inspection.
    path : str
        Output file.
    """
    cols = {
        "x_mm": insp.x_mm,
        "y_mm": insp.y_mm,
        "theta_deg": insp.theta_deg,
        "dn_um": insp.dn_um,
        "dr_um": insp.dr_um,
    }
    atomic_write(
        path, _csv(cols, f"camtol inspect: cam {insp.cam} of {insp.source}, cam frame, file order")
    )


def write_motion_csv(functional: FunctionalDeviation, path: str) -> None:
    """Write one row per cam angle: theta_deg, dS_measured_<unit>, dS_linear_<unit> (atomic).

    Parameters
    ----------
    functional : FunctionalDeviation
        The follower-motion error.
    path : str
        Output file.
    """
    unit, k = motion_unit(functional)
    cols = {
        "theta_deg": np.degrees(functional.theta_rad),
        f"dS_measured_{unit}": functional.ds_measured * k,
        f"dS_linear_{unit}": functional.ds_linear * k,
    }
    atomic_write(
        path, _csv(cols, f"camtol inspect: follower error, Fourier ≤ {functional.harmonics}")
    )


def wrap_line(line: str, width: int = 80) -> list[str]:
    """One logical line as terminal lines of at most ``width`` columns.

    Parameters
    ----------
    line : str
        The text.
    width : int
        Columns.
    """
    import textwrap

    return textwrap.wrap(
        line, width, subsequent_indent="  ", break_on_hyphens=False, break_long_words=False
    ) or [""]


def _angles(stretches: list[list[float]], shown: int = 8) -> str:
    """Failing stretches as text, at most ``shown`` of them."""
    parts = [f"{a:.1f}°" if abs(b - a) < 0.05 else f"{a:.1f}-{b:.1f}°" for a, b in stretches]
    more = len(parts) - shown
    return ", ".join(parts[:shown]) + (f" and {more} more" if more > 0 else "")


def inspection_text(data: dict[str, Any]) -> list[str]:
    """Return the summary lines printed by ``camtol inspect`` (from :func:`inspection_json`).

    Every line fits 80 columns (long ones continue on indented lines).

    Parameters
    ----------
    data : dict
        The JSON-ready result.
    """
    reg = data["registration"]
    z = data["zone"]
    dev = "Δn" if z["on"] == "dn_um" else "Δr"
    uz = f", UZ {z['offset_um']:+g} µm" if z["offset_um"] else ""
    iso = "ISO 1101" if z["iso1101"] else "radial band, not ISO 1101"
    free = " and ".join(reg["fitted"])
    where = (
        f"floating in {free} (fitted, not fixed by a datum: the zone judges form there)"
        if z["placement"] == "floating"
        else "located by the datum"
    )
    logical = [
        f"{data['design']}: cam {data['cam']}, {data['points']} points from {data['scan']}"
        + (
            f" (stylus {data['stylus_radius_mm']:g} mm, from its header)"
            if data.get("stylus_radius_source") == "header"
            else ""
        ),
        f"zone: [{z['lower_um']:+g}, {z['upper_um']:+g}] µm (t = {z['width_um']:g} µm{uz}) on"
        f" {dev}, {iso}, {where}" + (f"; from {z['source']}" if z["source"] else ""),
        f"registration ({reg['mode']}): rotation {reg['rotation_deg']:.5f}°, centre"
        f" ({reg['dx_mm'] * 1e3:.2f}, {reg['dy_mm'] * 1e3:.2f}) µm; u random"
        f" {reg['u_rotation_deg']:.2g}°, ({reg['u_dx_mm'] * 1e3:.2g},"
        f" {reg['u_dy_mm'] * 1e3:.2g}) µm; u form {reg['u_form_rotation_deg']:.2g}°,"
        f" ({reg['u_form_dx_mm'] * 1e3:.2g}, {reg['u_form_dy_mm'] * 1e3:.2g}) µm;"
        f" U95 {reg['U95_rotation_deg']:.2g}°,"
        f" ({reg['U95_dx_mm'] * 1e3:.2g}, {reg['U95_dy_mm'] * 1e3:.2g}) µm",
        f"normal deviation Δn: {data['min_dn_um']:.2f} .. {data['max_dn_um']:.2f} µm;"
        f" form {data['form_um']:.2f} µm; minimum zone {data['min_zone_um']:.2f} µm",
        f"outliers: {data['outliers']['count']}"
        + (
            f" (rows {', '.join(map(str, data['outliers']['indices'][:10]))}"
            + (", ..." if data["outliers"]["count"] > 10 else "")
            + ")"
            if data["outliers"]["count"]
            else ""
        ),
    ]
    if "motion" in data:
        m = data["motion"]
        u = m["unit"]
        sym = "°" if u == "deg" else " µm"
        spec = m.get(f"spec_{u}")
        logical.append(
            f"follower error ΔS: max |ΔS| {m[f'max_abs_ds_{u}']:.4g}{sym} exact,"
            f" {m[f'max_abs_ds_linear_{u}']:.4g}{sym} linear (Fourier ≤ {m['harmonics']})"
            + (
                f"; {m['verdict'].upper()} against the motion spec {spec:g}{sym}"
                if m.get("verdict") is not None and spec is not None
                else ""
            )
        )
    dec = data["decision"]
    if dec["rule"] == "guard-band":
        lo, hi = dec["acceptance_um"]
        logical.append(
            f"decision: guard band (ISO 14253-1), U = {dec['u_um']:.3g} µm: acceptance"
            f" [{lo:+.3g}, {hi:+.3g}] µm"
        )
    fails = data["failing_stretches_deg"]
    excess = z["excess_um"]
    logical.append(
        f"profile: {data['profile_verdict'].upper()}"
        + (
            f", {excess:.3g} µm beyond the zone at its best placement"
            if data["profile_verdict"] == "fail" and excess > 0
            else ""
        )
        + (f"; outside at polar angles {_angles(fails)}" if fails else "")
    )
    judged = "profile" + (
        " and follower error" if data.get("motion", {}).get("verdict") is not None else ""
    )
    logical.append(f"verdict: {data['verdict'].upper()} ({judged})")
    return [out for line in logical for out in wrap_line(line)]


def _text_html(data: dict[str, Any]) -> tuple[str, str]:
    """Return the inspection's text lines and warnings as HTML list items and paragraphs."""
    rows = "".join(f"<li>{html.escape(line)}</li>" for line in inspection_text(data))
    warn = "".join(f"<p class='warn'>⚠ {html.escape(w)}</p>" for w in data["warnings"])
    return rows, warn


def _rows_html(cells: list[tuple[str, Any]]) -> str:
    """Return label/value table rows, leaving out the cells without a value."""
    return "".join(
        f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>" for k, v in cells if v
    )


def inspection_report_html(data: dict[str, Any], figure_svg: str | None) -> str:
    """Return a self-contained HTML page of the inspection: part, verdict, zone, figure.

    The part's identity comes first (part number, drawing, revision, serial, date,
    inspector, instrument as given), with the camtol version, the design hash and the
    scan's SHA-256, so that a printed report traces to its inputs.

    Parameters
    ----------
    data : dict
        The JSON-ready result of :func:`inspection_json` (with ``traceability``).
    figure_svg : str or None
        Inline SVG of the inspection figure.
    """
    rows, warn = _text_html(data)
    title = html.escape(f"CMM inspection of cam {data['cam']} of {data['design']}")
    trace = data.get("traceability") or {}
    cells = [(label, trace[key]) for key, label in _TRACE_KEYS if trace.get(key)]
    cells += [
        ("camtol version", trace.get("camtol_version")),
        ("design hash", trace.get("design_hash")),
        ("scan SHA-256", trace.get("scan_sha256")),
    ]
    table = _rows_html(cells)
    verdict = str(data["verdict"])
    return (
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{title}</title><style>body{{font-family:sans-serif;max-width:80em;margin:auto}}"
        ".warn{color:#a60}th{text-align:left;padding-right:1em}"
        ".pass{color:#11702b}.fail{color:#b00020}</style></head><body>"
        f"<h1>{title}</h1><table id='traceability'>{table}</table>"
        f"<p id='verdict' class='{html.escape(verdict)}'><strong>{html.escape(verdict.upper())}"
        "</strong></p>"
        f"<ul>{rows}</ul>{warn}"
        + (f"<figure>{figure_svg}</figure>" if figure_svg else "")
        + "</body></html>\n"
    )


def cmm_section_html(data: dict[str, Any], figure_svg: str | None) -> str:
    """Return the CMM inspection as a section of the QA report (``camtol report --cmm``).

    Parameters
    ----------
    data : dict
        The JSON-ready result of :func:`inspection_json` (with ``traceability``).
    figure_svg : str or None
        Inline SVG of the inspection figure.
    """
    rows, warn = _text_html(data)
    trace = data.get("traceability") or {}
    ids = [
        ("scan", data["scan"]),
        ("scan SHA-256", trace.get("scan_sha256")),
        ("design hash", trace.get("design_hash")),
        ("camtol version", trace.get("camtol_version")),
    ]
    table = _rows_html(ids)
    return (
        f"<section id='cmm'><h2>CMM inspection of cam {html.escape(str(data['cam']))}</h2>"
        f"<table>{table}</table><ul>{rows}</ul>{warn}"
        + (f"<figure class='figure'>{figure_svg}</figure>" if figure_svg else "")
        + "</section>"
    )
