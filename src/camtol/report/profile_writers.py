"""DXF and SVG writers of the profile export (:func:`camtol.report.export.write_profile_points`).

Curves go on their own layers (DXF) or groups (SVG): ``CAM_PROFILE``,
``CAM_PITCH_CURVE``, ``CAM_CUTTER_PATH`` (``CAM_A_*`` and ``CAM_B_*`` with distinct colours
for a conjugate pair), ``CAM_CENTRE``, and the annotations of
:mod:`camtol.report.drawing_marks`. Millimetres, cam frame of THEORY §0.
"""

from __future__ import annotations

import io
from typing import TYPE_CHECKING

import numpy as np

from camtol.report.drawing_marks import DrawingMarks, add_dxf_marks, svg_marks, xml_escape

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis.profile import ProfilePoints

__all__ = ["dxf_bytes", "svg_text"]

_DXF_COLOURS = {"PROFILE": 7, "PITCH_CURVE": 3, "CUTTER_PATH": 1}


def dxf_bytes(points: ProfilePoints, marks: DrawingMarks) -> bytes:
    """Write DXF R2013 in millimetres: a closed LWPOLYLINE per curve and the annotations.

    Parameters
    ----------
    points : ProfilePoints
        The sampled curves.
    marks : DrawingMarks
        Timing mark, rotation, bore/hub and labels.

    Returns
    -------
    bytes
        The DXF file's content.
    """
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
    add_dxf_marks(doc, msp, marks)
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode(doc.output_encoding)


_SVG_COLOURS = {"PROFILE": "#000000", "PITCH_CURVE": "#2ca02c", "CUTTER_PATH": "#d62728"}


#: Cam B's colours (a conjugate pair): blue, cyan, magenta for profile, pitch, cutter path.
_SVG_COLOURS_B = {"#000000": "#1f4e9c", "#2ca02c": "#17becf", "#d62728": "#c51b8a"}


def svg_text(points: ProfilePoints, marks: DrawingMarks) -> str:
    """Write SVG in millimetres; y is flipped so the drawing looks as in the cam frame.

    Parameters
    ----------
    points : ProfilePoints
        The sampled curves.
    marks : DrawingMarks
        Timing mark, rotation, bore/hub and labels.

    Returns
    -------
    str
        The SVG document.
    """
    from camtol._version import __version__

    xs = np.concatenate([c.x_mm for c in points.curves] + [p[1] for p in marks.polylines])
    ys = np.concatenate([c.y_mm for c in points.curves] + [p[2] for p in marks.polylines])
    xs = np.append(xs, [t.x_mm for t in marks.texts])
    ys = np.append(ys, [t.y_mm for t in marks.texts])
    margin = 0.05 * float(max(np.ptp(xs), np.ptp(ys))) + 1.0
    x0, x1 = float(xs.min()) - margin, float(xs.max()) + margin
    y0, y1 = float(-ys.max()) - margin, float(-ys.min()) + margin
    w, h = x1 - x0, y1 - y0
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.3f}mm" height="{h:.3f}mm"'
        f' viewBox="{x0:.6f} {y0:.6f} {w:.6f} {h:.6f}">',
        f"<title>{xml_escape(points.design_name)}: cam profile (camtol {__version__})</title>",
        "<desc>Cam frame X-Y of THEORY §0 in millimetres, origin at the cam pivot O2;"
        " SVG y = -Y. Chordal tolerance"
        f" {points.tolerance_mm * 1e3:g} µm.</desc>",
    ]
    for c in points.curves:
        colour = next((v for k, v in _SVG_COLOURS.items() if c.layer.endswith(k)), "#000000")
        if c.layer.startswith("CAM_B_"):  # cam B in blues, as its DXF layers
            colour = _SVG_COLOURS_B.get(colour, colour)
        d = " ".join(
            f"{'M' if i == 0 else 'L'}{x:.6f},{-y:.6f}"
            for i, (x, y) in enumerate(zip(c.x_mm, c.y_mm, strict=True))
        )
        out.append(
            f'<g id="{c.layer}"><title>{xml_escape(c.description)}</title>'
            f'<path d="{d} Z" fill="none" stroke="{colour}" stroke-width="0.15"/></g>'
        )
    s = 0.02 * (w + h)
    out.append(
        f'<g id="CAM_CENTRE"><path d="M{-s:.4f},0 L{s:.4f},0 M0,{-s:.4f} L0,{s:.4f}"'
        ' stroke="#888888" stroke-width="0.1" fill="none"/></g>'
    )
    out += svg_marks(marks)
    out.append("</svg>")
    return "\n".join(out) + "\n"
