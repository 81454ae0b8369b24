"""Export a design's profile for CAD/CAM in one call: sample (core), then write (report).

:func:`write_profile` is the convenience the command line (``camtol profile -o``) and
callers use. It composes :func:`camtol.analysis.profile.profile_points` (the adaptive sampling
within a chordal tolerance, with its verification) and
:func:`camtol.report.export.write_profile_points` (CSV, DXF, SVG), so that the report
layer only formats results it is given.
"""

from __future__ import annotations

from pathlib import Path

from camtol.analysis.profile import (
    DEFAULT_TOLERANCE_MM,
    ProfilePoints,
    profile_points,
    profile_table,
)
from camtol.design.cam_design import CamDesign
from camtol.exceptions import ExportError
from camtol.report.export import export_format, write_profile_points

__all__ = ["write_profile"]


def write_profile(
    design: CamDesign,
    path: str | Path,
    *,
    tolerance_mm: float = DEFAULT_TOLERANCE_MM,
    cutter_radius_mm: float | None = None,
) -> ProfilePoints:
    """Sample the cam profile and write it for CAD/CAM; the format follows the suffix.

    Parameters
    ----------
    design : CamDesign
        The design.
    path : str or Path
        Output file: ``.csv``, ``.dxf`` or ``.svg`` (see
        :func:`camtol.report.export.write_profile_points`).
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
    """
    p = Path(path)
    fmt = export_format(p)  # a bad suffix or directory fails before the sampling
    if not p.parent.is_dir():
        raise ExportError(f"output file {str(p)!r}: directory {str(p.parent)!r} does not exist")
    points = profile_points(design, tolerance_mm=tolerance_mm, cutter_radius_mm=cutter_radius_mm)
    table = profile_table(design, points) if fmt == "csv" else None
    return write_profile_points(design, points, p, table=table)
