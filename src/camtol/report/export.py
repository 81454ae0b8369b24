r"""Profile exports for CAD/CAM: CSV, DXF and SVG of the analytic cam profile (THEORY §2).

The sampling itself is core (:mod:`camtol.profile`); this module writes its result.

The profile (and, for roller followers, the pitch curve; for conjugate designs both cams;
on request the cutter-centre path) is sampled *adaptively*: the vertices lie exactly on
the analytic curve and are spaced by its radius of curvature so that every chord deviates
from the curve by less than a tolerance (0.1 µm by default). The spacing comes from the
sagitta of a circular arc,

.. math:: h = ρ\left(1 - \cos\frac{Δs}{2ρ}\right) \approx \frac{Δs^2}{8ρ},

and is then *verified*: the analytic curve is evaluated at the quarter points of every
chord, and any chord whose deviation exceeds the tolerance is bisected until none does.

Coordinates are in the cam frame X-Y of THEORY §0 (origin at the cam pivot O2, θ measured
counterclockwise from the cam's reference radial; for oscillating followers from the line
of centres), in millimetres.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Literal

import numpy as np

from camtol.design import CamDesign
from camtol.exceptions import ExportError
from camtol.jet import FloatArray
from camtol.profile import (
    DEFAULT_TOLERANCE_MM,
    ProfileCurve,
    ProfilePoints,
    profile_points,
    profile_table,
)
from camtol.report.files import atomic_write

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


_DXF_COLOURS = {"PROFILE": 7, "PITCH_CURVE": 3, "CUTTER_PATH": 1}


def _dxf_bytes(points: ProfilePoints) -> bytes:
    from ezdxf.document import Drawing
    from ezdxf.filemanagement import new

    doc: Drawing = new("R2013", units=4)  # 4 = millimetres
    doc.header["$MEASUREMENT"] = 1  # metric
    msp = doc.modelspace()
    for c in points.curves:
        colour = next((v for k, v in _DXF_COLOURS.items() if c.layer.endswith(k)), 7)
        if c.layer.startswith("CAM_B_"):
            colour = {7: 5, 3: 4, 1: 6}.get(colour, colour)
        doc.layers.add(c.layer, color=colour)
        msp.add_lwpolyline(
            np.column_stack([c.x_mm, c.y_mm]).tolist(),
            format="xy",
            close=True,
            dxfattribs={"layer": c.layer},
        )
    doc.layers.add("CAM_CENTRE", color=2)
    msp.add_point((0.0, 0.0), dxfattribs={"layer": "CAM_CENTRE"})
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode(doc.output_encoding)


_SVG_COLOURS = {"PROFILE": "#000000", "PITCH_CURVE": "#2ca02c", "CUTTER_PATH": "#d62728"}


def _svg_text(points: ProfilePoints) -> str:
    """SVG in millimetres; y is flipped so the drawing looks as in the cam frame."""
    from camtol import __version__

    xs = np.concatenate([c.x_mm for c in points.curves])
    ys = np.concatenate([c.y_mm for c in points.curves])
    margin = 0.05 * float(max(np.ptp(xs), np.ptp(ys))) + 1.0
    x0, x1 = float(xs.min()) - margin, float(xs.max()) + margin
    y0, y1 = float(-ys.max()) - margin, float(-ys.min()) + margin
    w, h = x1 - x0, y1 - y0
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3f}mm" height="{h:.3f}mm"'
        f' viewBox="{x0:.6f} {y0:.6f} {w:.6f} {h:.6f}">',
        f"<title>{_xml_escape(points.design_name)}: cam profile (camtol {__version__})</title>",
        "<desc>Cam frame X-Y of THEORY §0 in millimetres, origin at the cam pivot O2;"
        " SVG y = -Y. Chordal tolerance"
        f" {points.tolerance_mm * 1e3:g} µm.</desc>",
    ]
    for c in points.curves:
        colour = next((v for k, v in _SVG_COLOURS.items() if c.layer.endswith(k)), "#000000")
        d = " ".join(
            f"{'M' if i == 0 else 'L'}{x:.6f},{-y:.6f}"
            for i, (x, y) in enumerate(zip(c.x_mm, c.y_mm, strict=True))
        )
        out.append(
            f'<g id="{c.layer}"><title>{_xml_escape(c.description)}</title>'
            f'<path d="{d} Z" fill="none" stroke="{colour}" stroke-width="0.15"/></g>'
        )
    s = 0.02 * (w + h)
    out.append(
        f'<g id="CAM_CENTRE"><path d="M{-s:.4f},0 L{s:.4f},0 M0,{-s:.4f} L0,{s:.4f}"'
        ' stroke="#888888" stroke-width="0.1" fill="none"/></g>'
    )
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _xml_escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


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
        curve, units mm) or ``.svg`` (one group per curve, millimetres).
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
    if fmt == "csv":
        data = _csv_text(profile_table(design, points)).encode("utf-8")
    elif fmt == "dxf":
        data = _dxf_bytes(points)
    else:
        data = _svg_text(points).encode("utf-8")
    atomic_write(p, data)
    return points
