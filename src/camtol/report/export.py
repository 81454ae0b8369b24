"""Profile exports for CAD/CAM: CSV, DXF and SVG of the analytic cam profile (THEORY §2).

The adaptive sampling within a chordal tolerance, with its verification, is core
(:mod:`camtol.profile`, which documents the method and the cam frame); this module only
writes its result, coordinates in mm in the cam frame.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Literal

import numpy as np

from camtol.design import CamDesign
from camtol.exceptions import ExportError
from camtol.files import atomic_write
from camtol.jet import FloatArray
from camtol.profile import (
    DEFAULT_TOLERANCE_MM,
    ProfileCurve,
    ProfilePoints,
    profile_points,
    profile_table,
)

__all__ = [
    "DEFAULT_TOLERANCE_MM",
    "EXPORT_SUFFIXES",
    "ExportError",
    "ProfileCurve",
    "ProfilePoints",
    "export_format",
    "profile_points",
    "write_profile",
]

#: File suffixes :func:`write_profile` understands.
EXPORT_SUFFIXES: tuple[str, ...] = (".csv", ".dxf", ".svg")

ExportFormat = Literal["csv", "dxf", "svg"]


# ---------------------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------------------
def _csv_text(cols: dict[str, FloatArray]) -> str:
    """One row per cam angle: the columns of :func:`camtol.profile.profile_table`."""
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    data = np.column_stack(list(cols.values()))
    for row in data:
        buf.write(",".join(f"{v:.12g}" for v in row) + "\n")
    return buf.getvalue()


def export_format(path: str | Path) -> ExportFormat:
    """Return the export format chosen by a file name's suffix.

    Parameters
    ----------
    path : str or Path
        Output file name.

    Raises
    ------
    ExportError
        If the suffix is not one of :data:`EXPORT_SUFFIXES`.
    """
    suffix = Path(path).suffix.lower()
    if suffix not in EXPORT_SUFFIXES:
        raise ExportError(
            f"output file {str(path)!r} has suffix {suffix or '(none)'!r}; allowed:"
            f" {', '.join(EXPORT_SUFFIXES)}"
        )
    fmt: ExportFormat = "csv" if suffix == ".csv" else "dxf" if suffix == ".dxf" else "svg"
    return fmt


def write_profile(
    design: CamDesign,
    path: str | Path,
    *,
    tolerance_mm: float = DEFAULT_TOLERANCE_MM,
    cutter_radius_mm: float | None = None,
) -> ProfilePoints:
    """Write the cam profile for CAD/CAM; the format follows the file suffix.

    Parameters
    ----------
    design : CamDesign
        The design.
    path : str or Path
        Output file: ``.csv`` (one row per cam angle: ``theta_deg`` and ``<layer>_x_mm``,
        ``<layer>_y_mm`` of every curve), ``.dxf`` (closed LWPOLYLINEs, one layer per
        curve, units mm) or ``.svg`` (one group per curve, millimetres); DXF and SVG also
        carry the timing mark, rotation arrow, bore/hub and labels of
        :mod:`camtol.report.drawing_marks`.
    tolerance_mm : float
        Chordal tolerance of the polylines, 1e-7..1 (default 0.1 µm). [mm]
    cutter_radius_mm : float, optional
        Add the cutter-centre path for a cutter of this radius. [mm]

    Returns
    -------
    ProfilePoints
        The sampled curves that were written.

    Raises
    ------
    ExportError
        Unknown suffix, missing directory, or an option out of range; nothing is written.
    GeometryError, UndercutError
        The design (or the cutter path) cannot be made; nothing is written.

    Notes
    -----
    The file is written to a temporary name in the same directory and renamed into place,
    so a failure never leaves a partial file. See :func:`profile_points` for the sampling.
    """
    p = Path(path)
    fmt = export_format(p)
    if not p.parent.is_dir():
        raise ExportError(f"output file {str(p)!r}: directory {str(p.parent)!r} does not exist")
    points = profile_points(design, tolerance_mm=tolerance_mm, cutter_radius_mm=cutter_radius_mm)
    from camtol.report.finite import require_finite

    for c in points.curves:
        deg = np.degrees(c.theta_rad)
        require_finite(f"{c.layer} x_mm", c.x_mm, theta_deg=deg, where=str(p))
        require_finite(f"{c.layer} y_mm", c.y_mm, theta_deg=deg, where=str(p))
    if fmt == "csv":
        data = _csv_text(profile_table(design, points)).encode("utf-8")
    else:
        from camtol import __version__
        from camtol.report.drawing_marks import drawing_marks
        from camtol.report.profile_writers import dxf_bytes, svg_text

        profiles = [
            (c.description.removesuffix(" profile"), c.x_mm, c.y_mm)
            for c in points.curves
            if c.layer.endswith("PROFILE")
        ]
        extent = max(float(np.hypot(c.x_mm, c.y_mm).max()) for c in points.curves)
        marks = drawing_marks(design, profiles, version=__version__, extent_mm=extent)
        data = dxf_bytes(points, marks) if fmt == "dxf" else svg_text(points, marks).encode()
    atomic_write(p, data)
    return points
