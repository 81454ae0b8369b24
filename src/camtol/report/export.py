"""Profile exports for CAD/CAM: CSV, DXF and SVG of the analytic cam profile (THEORY §2).

The adaptive sampling within a chordal tolerance, with its verification, is core
(:mod:`camtol.analysis.profile`, which documents the method and the cam frame); this module only
writes its result, coordinates in mm in the cam frame. :func:`camtol.export.write_profile`
does both for a design.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Literal

import numpy as np

from camtol.analysis.profile import DEFAULT_TOLERANCE_MM, ProfileCurve, ProfilePoints
from camtol.design.cam_design import CamDesign
from camtol.exceptions import ExportError
from camtol.files import atomic_write
from camtol.jet import FloatArray
from camtol.report.csv_text import csv_text

__all__ = [
    "DEFAULT_TOLERANCE_MM",
    "EXPORT_SUFFIXES",
    "ExportError",
    "ProfileCurve",
    "ProfilePoints",
    "export_format",
    "write_profile_points",
]

#: File suffixes :func:`write_profile_points` understands.
EXPORT_SUFFIXES: tuple[str, ...] = (".csv", ".dxf", ".svg")

ExportFormat = Literal["csv", "dxf", "svg"]


# ---------------------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------------------
def _csv_text(cols: dict[str, FloatArray]) -> str:
    """One row per cam angle: the columns of :func:`camtol.analysis.profile.profile_table`."""
    return csv_text(list(cols), np.column_stack(list(cols.values())), digits=12)


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


def write_profile_points(
    design: CamDesign,
    points: ProfilePoints,
    path: str | Path,
    *,
    table: Mapping[str, FloatArray] | None = None,
) -> ProfilePoints:
    """Write sampled profile curves for CAD/CAM; the format follows the file suffix.

    The sampling is core (:func:`camtol.analysis.profile.profile_points`);
    :func:`camtol.export.write_profile` samples a design and calls this.

    Parameters
    ----------
    design : CamDesign
        The design the curves belong to (for the drawing marks of DXF and SVG).
    points : ProfilePoints
        The sampled curves, from :func:`camtol.analysis.profile.profile_points`.
    path : str or Path
        Output file: ``.csv`` (one row per cam angle: ``theta_deg`` and ``<layer>_x_mm``,
        ``<layer>_y_mm`` of every curve), ``.dxf`` (closed LWPOLYLINEs, one layer per
        curve, units mm) or ``.svg`` (one group per curve, millimetres); DXF and SVG also
        carry the timing mark, rotation arrow, bore/hub and labels of
        :mod:`camtol.report.drawing_marks`.
    table : mapping of str to ndarray, optional
        The CSV columns, from :func:`camtol.analysis.profile.profile_table` (required for CSV).
        [deg, mm]

    Returns
    -------
    ProfilePoints
        ``points``, as written.

    Raises
    ------
    ExportError
        Unknown suffix, missing directory, or CSV without its table; nothing is written.

    Notes
    -----
    The file is written to a temporary name in the same directory and renamed into place,
    so a failure never leaves a partial file.
    """
    p = Path(path)
    fmt = export_format(p)
    if not p.parent.is_dir():
        raise ExportError(f"output file {str(p)!r}: directory {str(p.parent)!r} does not exist")
    if fmt == "csv" and table is None:
        raise ExportError(
            f"output file {str(p)!r}: a CSV export needs the table of"
            " camtol.analysis.profile.profile_table"
        )
    from camtol.report.finite import require_finite

    for c in points.curves:
        deg = np.degrees(c.theta_rad)
        require_finite(f"{c.layer} x_mm", c.x_mm, theta_deg=deg, where=str(p))
        require_finite(f"{c.layer} y_mm", c.y_mm, theta_deg=deg, where=str(p))
    if fmt == "csv":
        assert table is not None
        data = _csv_text(dict(table)).encode("utf-8")
    else:
        from camtol._version import __version__
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
