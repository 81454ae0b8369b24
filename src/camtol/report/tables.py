"""Terminal tables, JSON and CSV curves for `camtol analyze` (ARCHITECTURE: report).

Units are in every column name and table heading: µm (``um`` in files) for the length
errors of a translating follower, degrees for angles and for the errors of an oscillating
follower; derivatives per radian of cam angle (``um_per_rad``), or per second when the
design gives a cam speed (``um_per_s``).
"""

from __future__ import annotations

import csv
import io
import math
import sys
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from camtol import __version__
from camtol.analysis import Analysis
from camtol.design import IT_CONVENTIONS
from camtol.extremes import Extreme
from camtol.report.files import atomic_write

__all__ = [
    "analysis_json",
    "curves_columns",
    "print_analysis",
    "write_curves_csv",
    "atomic_write_text",
]


def _file_unit(unit: str) -> str:
    """Display unit -> ASCII column suffix: ``um/rad2`` -> ``um_per_rad2``."""
    return unit.replace("/", "_per_").replace("µ", "u")


def _pretty_unit(unit: str) -> str:
    return unit.replace("um", "µm").replace("deg", "°").replace("rad2", "rad²").replace("s2", "s²")


def _extreme_json(e: Extreme) -> dict[str, Any]:
    return {
        "value": e.value,
        "theta_deg": round(e.theta_deg, 4),
        "ranges_deg": [[round(a, 4), round(b, 4)] for a, b in e.ranges_deg],
    }


def analysis_json(a: Analysis) -> dict[str, Any]:
    """Return the analysis as a JSON-ready dict: design, tolerances, conventions, extremes.

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.analyse` for the design.

    Returns
    -------
    dict
        JSON-ready dict; units are given in the keys or alongside the values.
    """
    k = a.kinematics
    mech = a.design.mechanism
    rho_i = int(np.argmin(k.curvature_radius_mm))
    out: dict[str, Any] = {
        "camtol_version": __version__,
        "design": {
            "name": a.design.name,
            "follower": mech.kind,
            "parameters": dict(mech.summary()),
            "motion": a.design.describe_motion(),
            "speed_rpm": a.design.speed_rpm,
        },
        "step_deg": a.step_deg,
        "conventions": list(IT_CONVENTIONS),
        "tolerances": [
            {"source": t.key, "deviation": t.display, "origin": t.origin} for t in a.tolerances
        ],
        "max_radius_mm": a.max_radius_mm,
        "travel": {"value": a.travel, "unit": a.travel_unit},
        "accuracy": a.accuracy.describe(),
        "notes": list(a.notes),
        "validity": {
            "min_curvature_radius_mm": float(k.curvature_radius_mm[rho_i]),
            "min_curvature_at_deg": float(np.degrees(k.theta_rad[rho_i])),
            "pressure_angle_deg": [
                float(np.degrees(k.pressure_angle_rad.min())),
                float(np.degrees(k.pressure_angle_rad.max())),
            ],
        },
        "extremes": [
            {
                "quantity": q.key,
                "label": q.label,
                "unit": q.unit,
                "max": _extreme_json(a.extremes[q.key][0]),
                "min": _extreme_json(a.extremes[q.key][1]),
            }
            for q in a.quantities
        ],
    }
    if len(a.design.cams()) > 1:  # the errors above are cam A's; cam B's geometry here
        from camtol.report.conjugate import conjugate_analysis_json

        out["cam_b"] = conjugate_analysis_json(a)
    if k.face_contact_mm is not None:
        out["validity"]["face_contact_mm"] = [
            float(k.face_contact_mm.min()),
            float(k.face_contact_mm.max()),
        ]
    return out


def curves_columns(a: Analysis) -> dict[str, np.ndarray[Any, Any]]:
    """Every curve on the grid, keyed by CSV column name (units in the names).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.analyse` for the design.

    Returns
    -------
    dict of str to ndarray
        Columns in CSV order; a conjugate design gets both cams' profile columns
        (:func:`camtol.report.conjugate.conjugate_profile_columns`).
    """
    k = a.kinematics
    out_unit = "mm" if a.design.mechanism.output == "translating" else "deg"
    lift = k.lift if out_unit == "mm" else np.degrees(k.lift)
    cols: dict[str, np.ndarray[Any, Any]] = {
        "theta_deg": np.degrees(k.theta_rad),
        "x_mm": k.contact_x_mm,
        "y_mm": k.contact_y_mm,
        "radius_mm": k.radius_mm,
        "pressure_angle_deg": np.degrees(k.pressure_angle_rad),
        "shift_angle_deg": np.degrees(k.shift_angle_rad),
        "curvature_radius_mm": k.curvature_radius_mm,
        f"lift_{out_unit}": lift,
    }
    if k.face_contact_mm is not None:
        cols["face_contact_mm"] = k.face_contact_mm
    if k.follower_angle_rad is not None:
        cols["follower_angle_deg"] = np.degrees(k.follower_angle_rad)
    units = {q.key: q.unit for q in a.quantities}
    rf_unit = units["radial_factor"]
    cols["radial_factor" if rf_unit == "-" else f"radial_factor_{_file_unit(rf_unit)}"] = a.curves[
        "radial_factor"
    ]
    err_unit = a.error_unit
    vunit = units["dV_worst"]
    aunit = units["dA_worst"]
    names = [*a.errors.sources, "worst", "rms"]
    for prefix, unit in (("dS", err_unit), ("dV", vunit), ("dA", aunit)):
        for n in names:
            cols[f"{prefix}_{n}_{_file_unit(unit)}"] = a.curves[f"{prefix}_{n}"]
    if len(a.design.cams()) > 1:  # both cams' profiles and angles
        from camtol.report.conjugate import conjugate_profile_columns

        cols = conjugate_profile_columns(a, cols)
    return cols


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write a text file atomically (see :mod:`camtol.report.files`).

    Parameters
    ----------
    path : str or Path
        File to write; replaced if it exists.
    text : str
        Content, written as UTF-8 with newlines as given.
    """
    atomic_write(path, text)


def write_curves_csv(a: Analysis, path: str | Path) -> None:
    """Write one row per grid angle (a segment boundary appears twice: left, right limit).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.analyse` for the design.
    path : str or Path
        CSV file to write; replaced if it exists.
    """
    cols = curves_columns(a)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    data = np.column_stack(list(cols.values()))
    w.writerows([[f"{v:.10g}" for v in row] for row in data])
    atomic_write_text(path, buf.getvalue())


def _fmt(v: float) -> str:
    if v == 0 or not math.isfinite(v):
        return f"{v:g}"
    mag = math.floor(math.log10(abs(v)))
    if mag < -4:  # e.g. a numerically zero error on a dwell
        return f"{v:.3e}"
    return f"{v:.{max(0, 4 - mag)}f}" if mag < 4 else f"{v:.0f}"


def _rows(a: Analysis) -> Iterable[tuple[str, str, str, str, str, str]]:
    for q in a.quantities:
        mx, mn = a.extremes[q.key]
        yield (q.label, _pretty_unit(q.unit), _fmt(mx.value), mx.where, _fmt(mn.value), mn.where)


def print_analysis(a: Analysis, *, console: Any = None) -> None:
    """Print the design summary and the extremes table (rich; colour only on a terminal).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.analyse` for the design.
    console : rich.console.Console, optional
        Console to print to; by default a new one on standard output (132 columns when
        not a terminal).
    """
    from rich.console import Console
    from rich.table import Table

    # Off a terminal rich assumes 80 columns; keep the table unwrapped for files and pipes.
    con = console or Console(width=None if sys.stdout.isatty() else 132)
    d = a.design
    con.print(f"[bold]{d.name}[/bold]  (camtol {__version__})")
    if d.description:
        con.print(d.description.strip())
    params = Table(show_header=False, box=None, pad_edge=False)
    for name, val in d.mechanism.summary():
        params.add_row(name, val)
    params.add_row("motion", d.describe_motion())
    params.add_row("max radial dimension", f"{a.max_radius_mm:.4f} mm")
    k = a.kinematics
    rho_min = a.extremes["curvature_radius"][1]
    params.add_row(
        "min radius of curvature",
        f"{rho_min.value:.4f} mm at {rho_min.where} (no cusp or undercut)",
    )
    if k.face_contact_mm is not None:
        params.add_row(
            "contact on face u",
            f"{k.face_contact_mm.min():.3f} .. {k.face_contact_mm.max():.3f} mm (size the face)",
        )
    if len(d.cams()) > 1:  # the rows above are cam A's; cam B's geometry here
        from camtol.report.conjugate import conjugate_analysis_json

        b = conjugate_analysis_json(a)
        params.add_row("cam B max radial dimension", f"{b['max_radius_mm']:.4f} mm")
        params.add_row(
            "cam B min radius of curvature",
            f"{b['min_curvature_radius_mm']:.4f} mm at {b['min_curvature_at_deg']:.2f}°",
        )
        params.add_row(
            "cam B pressure angle",
            "{:.3f} .. {:.3f}°".format(*b["pressure_angle_deg"]),
        )
        params.add_row("cam B shift angle", "{:.3f} .. {:.3f}°".format(*b["shift_angle_deg"]))
    if d.speed_rpm is not None:
        params.add_row("cam speed", f"{d.speed_rpm:g} rpm")
    for t in a.tolerances:
        params.add_row(f"tolerance {t.key}", f"{t.display}  [{t.origin}]")
    con.print(params)
    table = Table(title=f"Extremes over 0-360° (grid {a.step_deg:g}°, refined)")
    for col, just in (
        ("quantity", "left"),
        ("unit", "left"),
        ("max", "right"),
        ("at θ", "left"),
        ("min", "right"),
        ("at θ", "left"),
    ):
        table.add_column(col, justify=just, overflow="fold")  # type: ignore[arg-type]
    for row in _rows(a):
        table.add_row(*row)
    con.print(table)
    con.print(
        f"Output accuracy: max |ΔS worst| = {_fmt(a.extremes['dS_worst'][0].value)}"
        f" {_pretty_unit(a.error_unit)} over a travel of {a.travel:g}"
        f" {_pretty_unit(a.travel_unit)}: {a.accuracy.describe()}"
    )
    for note in a.notes:
        con.print(f"Note: {note}.", style="yellow", markup=False)
    con.print("Conventions: " + "; ".join(IT_CONVENTIONS) + ".", style="dim")
