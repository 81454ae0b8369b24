"""Outputs of ``camtol inspect``: JSON, CSV files, text summary and HTML report.

File columns and JSON keys are fixed (issue 12, docs/cmm-inspection.md):

- curves CSV, one row per measured point: ``x_mm, y_mm, theta_deg, dn_um, dr_um`` (after
  registration, in the cam frame; ``theta_deg`` the polar angle of the point);
- motion CSV, one row per cam angle: ``theta_deg, dS_measured_<unit>, dS_linear_<unit>``
  with ``<unit>`` ``um`` (translating follower) or ``deg`` (oscillating);
- JSON: ``verdict`` (the profile and, with a motion spec, the follower error),
  ``profile_verdict``, ``registration``, ``form_um``, ``max_dn_um``, ``min_dn_um``,
  ``outliers``, ``failing_intervals_deg``, ``motion`` and context keys.
"""

from __future__ import annotations

import html
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.files import atomic_write
from camtol.report.csv_text import csv_text
from camtol.report.display import output_error_unit

if TYPE_CHECKING:
    from camtol.inspection.deviations import CmmInspection
    from camtol.inspection.functional import FunctionalDeviation

__all__ = [
    "inspection_json",
    "inspection_report_html",
    "inspection_text",
    "motion_unit",
    "write_curves_csv",
    "write_motion_csv",
]


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
        "registration": {
            "mode": reg.mode,
            "fitted": list(reg.fitted),
            "rotation_deg": reg.rotation_deg,
            "dx_mm": reg.dx_mm,
            "dy_mm": reg.dy_mm,
            "u_rotation_deg": reg.u_rotation_deg,
            "u_dx_mm": reg.u_dx_mm,
            "u_dy_mm": reg.u_dy_mm,
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
        "warnings": list(reg.warnings),
    }
    if functional is not None:
        unit, k = motion_unit(functional)
        out["motion"] = {
            "unit": unit,
            "harmonics": functional.harmonics,
            "max_abs_dS_measured": functional.max_abs_measured * k,
            "max_abs_dS_linear": functional.max_abs_linear * k,
            "max_abs_dV_measured": float(np.max(np.abs(functional.dv_measured))) * k,
            "max_abs_dA_measured": float(np.max(np.abs(functional.da_measured))) * k,
            "dV_unit": f"{unit}/rad",
            "dA_unit": f"{unit}/rad2",
            "spec": None if functional.spec is None else functional.spec * k,
            "verdict": None
            if functional.passed is None
            else ("pass" if functional.passed else "fail"),
        }
    return out


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


def inspection_text(data: dict[str, Any]) -> list[str]:
    """Return the summary lines printed by ``camtol inspect`` (from :func:`inspection_json`).

    Parameters
    ----------
    data : dict
        The JSON-ready result.
    """
    reg = data["registration"]
    lo, hi = data["tolerance_um"]
    lines = [
        f"{data['design']}: cam {data['cam']}, {data['points']} points from {data['scan']}",
        f"registration ({reg['mode']}): rotation {reg['rotation_deg']:.5f}° ± "
        f"{reg['u_rotation_deg']:.2g}°, centre ({reg['dx_mm'] * 1e3:.2f}, "
        f"{reg['dy_mm'] * 1e3:.2f}) µm ± ({reg['u_dx_mm'] * 1e3:.2g},"
        f" {reg['u_dy_mm'] * 1e3:.2g}) µm",
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
        lines.append(
            f"follower error ΔS: max |ΔS| {m['max_abs_dS_measured']:.4g} {m['unit']} exact,"
            f" {m['max_abs_dS_linear']:.4g} {m['unit']} linear (Fourier ≤ {m['harmonics']})"
            + (
                f"; {m['verdict'].upper()} against the motion spec {m['spec']:g} {m['unit']}"
                if m.get("verdict") is not None
                else ""
            )
        )
    fails = data["failing_intervals_deg"]
    where = ", ".join(f"{a:.1f}-{b:.1f}°" for a, b in fails)
    lines.append(
        f"profile: {data['profile_verdict'].upper()} against [{lo:g}, {hi:g}] µm on"
        f" {'Δn' if data['tolerance_on'] == 'dn_um' else 'Δr'}"
        + (f"; outside at polar angles {where}" if fails else "")
    )
    judged = "profile" + (
        " and follower error" if data.get("motion", {}).get("verdict") is not None else ""
    )
    lines.append(f"verdict: {data['verdict'].upper()} ({judged})")
    return lines


def inspection_report_html(data: dict[str, Any], figure_svg: str | None) -> str:
    """Return a self-contained HTML page of the inspection (summary, registration, figure).

    Parameters
    ----------
    data : dict
        The JSON-ready result of :func:`inspection_json`.
    figure_svg : str or None
        Inline SVG of the inspection figure.
    """
    rows = "".join(f"<li>{html.escape(line)}</li>" for line in inspection_text(data))
    warn = "".join(f"<p class='warn'>⚠ {html.escape(w)}</p>" for w in data["warnings"])
    title = html.escape(f"CMM inspection of cam {data['cam']} of {data['design']}")
    return (
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{title}</title><style>body{{font-family:sans-serif;max-width:80em;margin:auto}}"
        ".warn{color:#a60}</style></head><body>"
        f"<h1>{title}</h1><ul>{rows}</ul>{warn}"
        + (f"<figure>{figure_svg}</figure>" if figure_svg else "")
        + "</body></html>\n"
    )
