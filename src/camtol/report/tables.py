"""Terminal tables, JSON and CSV curves for `camtol analyze` (ARCHITECTURE: report).

Units are in every column name and table heading: µm (``um`` in files) for the length
errors of a translating follower, degrees for angles and for the errors of an oscillating
follower; derivatives per radian of cam angle (``um_per_rad``), or per second when the
design gives a cam speed (``um_per_s``).

Why one module: it is the output of ``camtol analyze`` in its three forms, terminal tables,
JSON and CSV curves, all written from the same displayed analysis
(:func:`~camtol.report.display.display_analysis`) and the same S, V, A, J units
(:func:`motion_units`), so that a table row, a JSON key and a CSV column of one quantity
agree.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol._version import __version__
from camtol.analysis.extremes import Extreme
from camtol.analysis.kinematics import beyond_pressure_angle_limit
from camtol.analysis.result import Analysis
from camtol.analysis.summary import STANDARD_GRAVITY, CamGeometry
from camtol.design.cam_design import IT_CONVENTIONS, ResolvedTolerance
from camtol.files import atomic_write
from camtol.iso286 import GradeBracket
from camtol.report.csv_text import csv_text
from camtol.report.display import accuracy_words, analysis_notes, display_analysis
from camtol.report.terminal import NO_BREAK
from camtol.report.units import file_unit, fmt, json_ready, magnitude_unit, pretty_unit

if TYPE_CHECKING:  # pragma: no cover
    from camtol.report.terminal import Terminal

__all__ = [
    "atomic_write_text",
    "SCHEMA_VERSION",
    "accuracy_json",
    "analysis_json",
    "motion_curves",
    "motion_units",
    "curves_columns",
    "print_analysis",
    "write_curves_csv",
]


#: Version of the JSON documents of every command (``schema_version``); the JSON Schema
#: files in ``camtol/data/schemas`` describe it.
SCHEMA_VERSION = "1.0"


def _file_unit(unit: str) -> str:
    """Display unit -> ASCII column suffix: ``um/rad2`` -> ``um_per_rad2``."""
    return file_unit(unit)


def _pretty_unit(unit: str) -> str:
    return pretty_unit(unit)


def _extreme_json(e: Extreme) -> dict[str, Any]:
    return {
        "value": e.value,
        "theta_deg": e.theta_deg,
        "ranges_deg": [[a, b] for a, b in e.ranges_deg],
    }


def motion_units(a: Analysis) -> tuple[str, str, str, str]:
    """ASCII units of the nominal S, V, A, J of the analysis (see :func:`motion_curves`).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse`.

    Returns
    -------
    tuple of str
        Lift, velocity, acceleration and jerk units: ``mm``, ``m/s``, ``m/s2``, ``m/s3``
        at a design speed (``rad/s``… for an oscillating follower), else per radian of cam
        angle (``mm/rad``…, ``rad/rad``…); the lift of an oscillating follower in ``deg``.
    """
    translating = a.design.mechanism.output == "translating"
    if a.design.omega_rad_s is not None:
        base = "m" if translating else "rad"
        return ("mm" if translating else "deg", f"{base}/s", f"{base}/s2", f"{base}/s3")
    base = "mm" if translating else "rad"
    return ("mm" if translating else "deg", f"{base}/rad", f"{base}/rad2", f"{base}/rad3")


def motion_curves(a: Analysis) -> tuple[np.ndarray[Any, Any], ...]:
    """Nominal lift, velocity, acceleration and jerk on the grid in :func:`motion_units`.

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse`.

    Returns
    -------
    tuple of ndarray
        S, V, A, J (THEORY §0: V, A, J per radian times ω, ω², ω³ at speed).
    """
    k = a.kinematics
    translating = a.design.mechanism.output == "translating"
    lift = k.lift if translating else np.degrees(k.lift)
    w = a.design.omega_rad_s
    if w is None:
        return lift, k.velocity, k.acceleration, k.jerk
    si = 1e-3 if translating else 1.0
    return lift, k.velocity * w * si, k.acceleration * w**2 * si, k.jerk * w**3 * si


def _motion_json(a: Analysis) -> dict[str, Any]:
    assert a.motion is not None
    _, vu, au, ju = motion_units(a)
    speed = a.motion.at_speed()
    peaks = (
        speed if speed is not None else (a.motion.velocity, a.motion.acceleration, a.motion.jerk)
    )
    out: dict[str, Any] = {"speed_rpm": a.design.speed_rpm}
    for name, unit, p in zip(
        ("velocity", "acceleration", "jerk"), (vu, au, ju), peaks, strict=True
    ):
        suffix = file_unit(unit)
        out[f"{name}_max_{suffix}"] = p.max
        out[f"{name}_max_at_deg"] = p.max_at_deg
        out[f"{name}_min_{suffix}"] = p.min
        out[f"{name}_min_at_deg"] = p.min_at_deg
    if speed is not None and a.design.mechanism.output == "translating":
        out["acceleration_abs_max_g"] = speed[1].abs_max / STANDARD_GRAVITY
    return out


def _geometry_json(g: CamGeometry) -> dict[str, Any]:
    return {
        "cam": g.label,
        "max_radius_mm": g.max_radius_mm,
        "pressure_angle_min_deg": g.pressure_angle_deg.min,
        "pressure_angle_min_at_deg": g.pressure_angle_deg.min_at_deg,
        "pressure_angle_max_deg": g.pressure_angle_deg.max,
        "pressure_angle_max_at_deg": g.pressure_angle_deg.max_at_deg,
        "pressure_angle_limit_deg": g.pressure_angle_limit_deg,
        "pressure_angle_exceeds_limit": g.exceeds_pressure_angle_limit,
        "min_convex_radius_mm": g.min_convex_radius_mm,
        "min_convex_radius_at_deg": g.min_convex_radius_at_deg,
        "convex_limit": g.convex_limit,
        "min_concave_radius_mm": g.min_concave_radius_mm,
        "min_concave_radius_at_deg": g.min_concave_radius_at_deg,
        "concave_limit": g.concave_limit,
        "undercut": g.undercut,
    }


def mechanism_parameters(mech: Any) -> dict[str, Any]:
    """Return the follower's dimensions as snake_case keys with units (``base_radius_mm``).

    Angles held in radians are given in degrees (``arm_angle_rad`` -> ``arm_angle_deg``).

    Parameters
    ----------
    mech : Mechanism
        The design's mechanism (a dataclass of numbers).

    Returns
    -------
    dict
        Parameter name -> number (or null when not set).
    """
    out: dict[str, Any] = {}
    if not dataclasses.is_dataclass(mech):
        return out
    for f in dataclasses.fields(mech):
        v = getattr(mech, f.name)
        if v is not None and not isinstance(v, (int, float)):
            continue
        if f.name.endswith("_rad"):
            out[f.name[:-4] + "_deg"] = None if v is None else math.degrees(v)
        else:
            out[f.name] = v
    return out


def accuracy_json(b: GradeBracket | None) -> dict[str, Any]:
    """Structured accuracy grade: the bracketing IT grades and their values.

    Parameters
    ----------
    b : iso286.GradeBracket or None
        The grades bracketing a deviation; None for a design that tolerances nothing.

    Returns
    -------
    dict
        ``lower_grade``/``upper_grade`` (e.g. ``"IT7"``, or null beyond the table), their
        values in µm (``lower_um``/``upper_um``, thousandths of a degree for an angle) and
        ``text``; without tolerances all four null and ``text``
        :data:`~camtol.report.display.ACCURACY_NOT_ASSESSED`.
    """
    if b is None:
        return {
            "lower_grade": None,
            "lower_um": None,
            "upper_grade": None,
            "upper_um": None,
            "text": accuracy_words(None),
        }
    return {
        "lower_grade": b.lower,
        "lower_um": b.lower_um,
        "upper_grade": b.upper,
        "upper_um": b.upper_um,
        "text": b.describe(),
    }


def analysis_json(a: Analysis) -> dict[str, Any]:
    """Return the analysis as a JSON-ready dict (schema ``analyze.schema.json``).

    Keys are ASCII snake_case with units in the names; numbers are numbers rounded to 10
    significant digits; infinities and NaN are null.

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.

    Returns
    -------
    dict
        JSON-ready dict.
    """
    k = a.kinematics
    mech = a.design.mechanism
    shown = display_analysis(a)
    out: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION,
        "command": "analyze",
        "camtol_version": __version__,
        "design": {
            "name": a.design.name,
            "follower": mech.kind,
            "parameters": mechanism_parameters(mech),
            "motion": a.design.describe_motion(),
            "speed_rpm": a.design.speed_rpm,
        },
        "step_deg": a.step_deg,
        "conventions": list(IT_CONVENTIONS),
        "tolerances": [_tolerance_json(t) for t in a.tolerances],
        "max_radius_mm": a.max_radius_mm,
        "travel": {"value": shown.travel, "unit": shown.travel_unit},
        "accuracy": accuracy_json(a.accuracy),
        "notes": list(analysis_notes(a)),
        "motion": _motion_json(a),
        "cams": [_geometry_json(g) for g in a.geometry],
        "pressure_angle_exceeds_limit": a.pressure_angle_exceeds_limit,
        "extremes": [
            {
                "quantity": q.key,
                "label": q.label,
                "unit": q.unit,
                "max": _extreme_json(shown.extremes[q.key][0]),
                "min": _extreme_json(shown.extremes[q.key][1]),
            }
            for q in shown.quantities
            if q.key != "curvature_radius"  # see "cams": smallest convex and concave radii
        ],
    }
    if k.face_contact_mm is not None:
        out["face_contact_min_mm"] = float(k.face_contact_mm.min())
        out["face_contact_max_mm"] = float(k.face_contact_mm.max())
    return dict(json_ready(out))


def _tolerance_json(t: ResolvedTolerance) -> dict[str, Any]:
    if t.unit == "mm":
        return {"source": t.key, "deviation_um": t.deviation * 1e3, "origin": t.origin}
    return {"source": t.key, "deviation_deg": math.degrees(t.deviation), "origin": t.origin}


def curves_columns(a: Analysis) -> dict[str, np.ndarray[Any, Any]]:
    """Every curve on the grid, keyed by CSV column name (units in the names).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.

    Returns
    -------
    dict of str to ndarray
        Columns in CSV order; a conjugate design gets both cams' profile columns
        (:func:`camtol.report.conjugate.conjugate_profile_columns`).
    """
    k = a.kinematics
    su, vu, au, ju = motion_units(a)
    lift, vel, acc, jerk = motion_curves(a)
    cols: dict[str, np.ndarray[Any, Any]] = {
        "theta_deg": np.degrees(k.theta_rad),
        "x_mm": k.contact_x_mm,
        "y_mm": k.contact_y_mm,
        "radius_mm": k.radius_mm,
        "pressure_angle_deg": np.degrees(k.pressure_angle_rad),
        "shift_angle_deg": np.degrees(k.shift_angle_rad),
        "curvature_radius_mm": k.curvature_radius_mm,
        f"lift_{su}": lift,
        f"velocity_{file_unit(vu)}": vel,
        f"acceleration_{file_unit(au)}": acc,
        f"jerk_{file_unit(ju)}": jerk,
    }
    if k.face_contact_mm is not None:
        cols["face_contact_mm"] = k.face_contact_mm
    if k.follower_angle_rad is not None:
        cols["follower_angle_deg"] = np.degrees(k.follower_angle_rad)
    shown = display_analysis(a)
    units = {q.key: q.unit for q in shown.quantities}
    rf_unit = units["radial_factor"]
    cols["radial_factor" if rf_unit == "-" else f"radial_factor_{_file_unit(rf_unit)}"] = (
        shown.curves["radial_factor"]
    )
    err_unit = shown.error_unit
    vunit = units["dV_worst"]
    aunit = units["dA_worst"]
    names = [*a.errors.sources, "worst", "rms"]
    for prefix, unit in (("dS", err_unit), ("dV", vunit), ("dA", aunit)):
        for n in names:
            cols[f"{prefix}_{n}_{_file_unit(unit)}"] = shown.curves[f"{prefix}_{n}"]
    if len(a.design.cams()) > 1:  # both cams' profiles and angles
        from camtol.report.conjugate import conjugate_profile_columns

        cols = conjugate_profile_columns(a, cols)
    return cols


def write_curves_csv(a: Analysis, path: str | Path) -> None:
    """Write one row per grid angle (a segment boundary appears twice: left, right limit).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.
    path : str or Path
        CSV file to write; replaced if it exists.
    """
    from camtol.report.finite import require_finite_columns

    cols = curves_columns(a)
    require_finite_columns(cols, where=str(path))
    data = np.column_stack(list(cols.values()))
    atomic_write(path, csv_text(list(cols), data))


def _fmt(v: float) -> str:
    return fmt(v)


def _row_cells(
    q_label: str, unit: str, mx: Extreme, mn: Extreme
) -> tuple[str, str, str, str, str, str]:
    shown, factor = magnitude_unit(unit, max(abs(mx.value), abs(mn.value)))
    return (
        q_label,
        pretty_unit(shown),
        fmt(mx.value * factor),
        "\n".join(mx.where.split(", ")),
        fmt(mn.value * factor),
        "\n".join(mn.where.split(", ")),
    )


def _rows(a: Analysis) -> Iterable[tuple[str, str, str, str, str, str]]:
    limit = a.design.pressure_angle_limit_deg
    shown = display_analysis(a)
    for q in shown.quantities:
        if q.key == "curvature_radius":  # meaningless across concave stretches: see summary
            continue
        mx, mn = shown.extremes[q.key]
        label = q.label
        if q.key == "pressure_angle" and limit is not None:
            if beyond_pressure_angle_limit(max(abs(mx.value), abs(mn.value)), limit):
                label += " " + f"> {limit:g}° LIMIT".replace(" ", NO_BREAK)
        yield _row_cells(label, q.unit, mx, mn)


def _at(deg: float) -> str:
    return f"{deg:.2f}°"


def _geometry_rows(g: CamGeometry) -> list[tuple[str, str]]:
    cam = f"cam {g.label} " if g.label else ""
    p = g.pressure_angle_deg
    pa = f"{p.min:.2f}° at {_at(p.min_at_deg)} .. {p.max:.2f}° at {_at(p.max_at_deg)}"
    if g.pressure_angle_limit_deg is not None:
        flag = "EXCEEDS" if g.exceeds_pressure_angle_limit else "within"
        pa += f" ({flag} the {g.pressure_angle_limit_deg:g}° limit)"
    rows = [
        (f"{cam}max radial dimension", f"{fmt(g.max_radius_mm)} mm"),
        (f"{cam}pressure angle", pa),
    ]
    if math.isfinite(g.min_convex_radius_mm):
        convex = f"{fmt(g.min_convex_radius_mm)} mm at {_at(g.min_convex_radius_at_deg)}"
    else:
        convex = "none (no convex stretch)"
    rows.append((f"{cam}smallest convex radius", f"{convex}; {g.convex_limit}"))
    if math.isfinite(g.min_concave_radius_mm):
        concave = f"{fmt(g.min_concave_radius_mm)} mm at {_at(g.min_concave_radius_at_deg)}"
        rows.append((f"{cam}smallest concave radius", f"{concave}; {g.concave_limit}"))
    else:
        rows.append((f"{cam}smallest concave radius", "none (no concave stretch: any cutter)"))
    if g.undercut:
        rows.append((f"{cam}UNDERCUT", "the follower cannot generate the profile"))
    return rows


def _motion_rows(a: Analysis) -> list[tuple[str, str]]:
    if a.motion is None:
        return []
    _, vu, au, ju = motion_units(a)
    speed = a.motion.at_speed()
    peaks = (
        speed if speed is not None else (a.motion.velocity, a.motion.acceleration, a.motion.jerk)
    )
    where = f"at {a.design.speed_rpm:g} rpm" if speed is not None else "(per radian)"
    rows = []
    for name, unit, pk in zip(
        ("velocity", "acceleration", "jerk"), (vu, au, ju), peaks, strict=True
    ):
        top = pk.max if abs(pk.max) >= abs(pk.min) else pk.min
        at = pk.max_at_deg if top == pk.max else pk.min_at_deg
        text = f"{fmt(abs(top))} {pretty_unit(unit)} at {_at(at)}"
        if (
            name == "acceleration"
            and speed is not None
            and a.design.mechanism.output == "translating"
        ):
            text += f" ({fmt(pk.abs_max / STANDARD_GRAVITY, 4)} g)"
        rows.append(
            (
                f"peak |{name[0].upper()}| {where}"
                if name == "velocity"
                else f"peak |{name[0].upper()}|",
                text,
            )
        )
    return rows


def print_analysis(a: Analysis, *, terminal: Terminal | None = None, verbose: bool = False) -> None:
    """Print the design summary and the extremes table (colour only on a terminal).

    Fits the width (80 columns when not a terminal): angle ranges are never split, the
    key/value block is only as wide as its content.

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.
    terminal : Terminal, optional
        Where to print (:class:`camtol.report.terminal.Terminal`); standard output by
        default.
    verbose : bool
        Also print the IT-grade conventions in force (THEORY §3.6).
    """
    from camtol.report.terminal import EXTREMES_COLUMNS, Terminal

    term = terminal or Terminal()
    d = a.design
    shown = display_analysis(a)
    term.paragraph(f"{d.name}  (camtol {__version__})", "bold")
    if d.description:
        term.paragraph(d.description.strip())
    params = [*d.mechanism.summary(), ("motion", d.describe_motion())]
    if d.speed_rpm is not None:
        params.append(("cam speed", f"{d.speed_rpm:g} rpm"))
    params += _motion_rows(a)
    for g in a.geometry:
        params += _geometry_rows(g)
    k = a.kinematics
    if k.face_contact_mm is not None:
        params.append(
            (
                "contact on face u",
                f"{k.face_contact_mm.min():.3f} .. {k.face_contact_mm.max():.3f} mm"
                " (size the face)",
            )
        )
    params += [(f"tolerance {t.key}", f"{t.display} [{t.origin}]") for t in a.tolerances]
    term.key_values(params)
    title = f"Extremes over 0-360° (grid {a.step_deg:g}°, refined)"
    term.table(EXTREMES_COLUMNS, list(_rows(a)), title=title)
    if a.accuracy is None:
        term.paragraph(f"Output accuracy: {accuracy_words(None)}")
    else:
        term.paragraph(
            f"Output accuracy: max |ΔS worst| = {_fmt(shown.extremes['dS_worst'][0].value)}"
            f" {_pretty_unit(shown.error_unit)} over a travel of {shown.travel:g}"
            f" {_pretty_unit(shown.travel_unit)}: {accuracy_words(a.accuracy)}"
        )
    if a.pressure_angle_exceeds_limit:
        term.paragraph(
            f"PRESSURE ANGLE EXCEEDS THE {d.pressure_angle_limit_deg:g}° DESIGN LIMIT"
            " (exit status 1 with --strict)",
            "bold red",
        )
    for note in analysis_notes(a):
        term.paragraph(f"Note: {note}.", "yellow")
    if verbose:
        term.paragraph("Conventions: " + "; ".join(IT_CONVENTIONS) + ".", "dim")


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write a text file atomically (see :mod:`camtol.files`).

    Parameters
    ----------
    path : str or Path
        File to write; replaced if it exists.
    text : str
        Content, written as UTF-8 with newlines as given.
    """
    atomic_write(path, text)
