"""Drawing annotations of the DXF/SVG profile export: timing mark, rotation, bore, labels.

A bare outline cannot be set up on a machine: the shop needs to know where θ = 0 is and
which way the cam turns. :func:`drawing_marks` computes, in the cam frame X-Y of THEORY §0
(origin at the pivot O2, millimetres), what :mod:`camtol.report.export` adds:

* ``CAM_TIMING_MARK``: the zero-angle timing mark, a radial line on the cam's reference
  radial (+X: where the follower stands at θ = 0, THEORY §0) outside the largest profile
  radius, labelled ``0°``;
* ``CAM_ROTATION``: the direction of rotation, an arc with an arrowhead pointing clockwise
  (the cam turns clockwise, THEORY §0), labelled ``CW``;
* ``CAM_BORE`` / ``CAM_HUB``: circles of the design's ``[drawing]`` ``bore_diameter_mm``
  and ``hub_diameter_mm`` when given;
* ``CAM_LABELS``: the design name, the camtol version and the name of each cam (``cam A``
  and ``cam B`` of a conjugate pair, beside their own profiles).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.jet import FloatArray

__all__ = [
    "MARK_COLOURS",
    "DrawingMarks",
    "MarkText",
    "add_dxf_marks",
    "drawing_marks",
    "svg_marks",
    "xml_escape",
]


@dataclass(frozen=True)
class MarkText:
    """A text label of the drawing.

    Attributes
    ----------
    layer : str
        Layer (DXF) or group (SVG).
    text : str
        The label.
    x_mm, y_mm : float
        Anchor (left end of the baseline) in the cam frame. [mm]
    height_mm : float
        Text height. [mm]
    """

    layer: str
    text: str
    x_mm: float
    y_mm: float
    height_mm: float


@dataclass(frozen=True)
class DrawingMarks:
    """Everything drawn besides the curves.

    Attributes
    ----------
    polylines : list of (layer, x_mm, y_mm, closed)
        Open or closed polylines (timing mark, rotation arc, arrowhead). [mm]
    circles : list of (layer, radius_mm)
        Circles about O2 (bore, hub). [mm]
    texts : list of MarkText
        Labels.
    """

    polylines: list[tuple[str, FloatArray, FloatArray, bool]]
    circles: list[tuple[str, float]]
    texts: list[MarkText]

    @property
    def layers(self) -> list[str]:
        """Every layer used, in order of first use."""
        names = [p[0] for p in self.polylines] + [c[0] for c in self.circles]
        names += [t.layer for t in self.texts]
        return list(dict.fromkeys(names))


def _extra_mm(design: CamDesign, key: str) -> float | None:
    value = design.extras.get(key)
    return float(value) if isinstance(value, (int, float)) else None


def _bore_hub(design: CamDesign, r_min_mm: float) -> list[tuple[str, float]]:
    from camtol.exceptions import ExportError

    bore = _extra_mm(design, "bore_diameter_mm")
    hub = _extra_mm(design, "hub_diameter_mm")
    out: list[tuple[str, float]] = []
    for layer, key, value in (("CAM_BORE", "bore", bore), ("CAM_HUB", "hub", hub)):
        if value is None:
            continue
        if not (0.0 < value < 2.0 * r_min_mm):
            raise ExportError(
                f"drawing.{key}_diameter_mm={value:g} is not allowed; it must be > 0 and"
                f" smaller than the profile's smallest diameter {2 * r_min_mm:.4g} mm"
            )
        out.append((layer, value / 2.0))
    if bore is not None and hub is not None and not bore < hub:
        raise ExportError(
            f"drawing.bore_diameter_mm={bore:g} is not allowed; it must be smaller than"
            f" drawing.hub_diameter_mm={hub:g}"
        )
    return out


def drawing_marks(
    design: CamDesign,
    profiles: list[tuple[str, FloatArray, FloatArray]],
    *,
    version: str,
    extent_mm: float | None = None,
) -> DrawingMarks:
    """Compute the annotations of a profile drawing.

    Parameters
    ----------
    design : CamDesign
        The design (its ``extras`` may hold ``bore_diameter_mm``, ``hub_diameter_mm``).
    profiles : list of (label, x_mm, y_mm)
        The cam profiles drawn (one, or cams A and B), as closed polylines. [mm]
    version : str
        camtol version, written in the title label.
    extent_mm : float, optional
        Largest radius of everything drawn (e.g. a pitch curve outside the profile); the
        marks stand outside it. Default: the profiles' largest radius. [mm]

    Returns
    -------
    DrawingMarks
        Polylines, circles and texts in the cam frame. [mm]

    Raises
    ------
    camtol.exceptions.ExportError
        A bore or hub diameter not smaller than the profile (or a bore not inside the hub).
    """
    r_all = np.concatenate([np.hypot(x, y) for _, x, y in profiles])
    r_max, r_min = float(r_all.max()), float(r_all.min())
    if extent_mm is not None:
        r_max = max(r_max, float(extent_mm))
    h = max(0.04 * r_max, 0.5)  # text height and mark size
    r0, r1 = r_max + 0.5 * h, r_max + 2.5 * h
    polylines: list[tuple[str, FloatArray, FloatArray, bool]] = [
        ("CAM_TIMING_MARK", np.array([r0, r1]), np.array([0.0, 0.0]), False),
    ]
    texts = [MarkText("CAM_TIMING_MARK", "0°", r1 + 0.3 * h, -0.5 * h, h)]
    # Rotation: an arc from polar 70° down to 40° at radius r0+h, arrowhead at 40°,
    # pointing clockwise (decreasing polar angle).
    ra = r0 + h
    phi = np.radians(np.linspace(70.0, 40.0, 31))
    polylines.append(("CAM_ROTATION", ra * np.cos(phi), ra * np.sin(phi), False))
    tip = np.array([ra * math.cos(phi[-1]), ra * math.sin(phi[-1])])
    tangent = np.array([math.sin(phi[-1]), -math.cos(phi[-1])])  # clockwise direction
    normal = np.array([-tangent[1], tangent[0]])
    base = tip - 1.2 * h * tangent
    head = np.array([tip, base + 0.45 * h * normal, base - 0.45 * h * normal])
    polylines.append(("CAM_ROTATION", head[:, 0], head[:, 1], True))
    mid = math.radians(55.0)
    texts.append(
        MarkText(
            "CAM_ROTATION",
            "CW",
            (ra + 0.6 * h) * math.cos(mid),
            (ra + 0.6 * h) * math.sin(mid),
            h,
        )
    )
    for label, x, y in profiles:
        i = int(np.argmax(np.hypot(x, y)))
        if len(profiles) > 1:
            texts.append(
                MarkText("CAM_LABELS", label, float(x[i]) + 0.3 * h, float(y[i]) + 0.3 * h, h)
            )
    texts.append(
        MarkText(
            "CAM_LABELS",
            f"{design.name} (camtol {version}); cam turns clockwise; θ = 0 at the timing mark",
            -r1,
            -r1 - 1.5 * h,
            h,
        )
    )
    return DrawingMarks(polylines, _bore_hub(design, r_min), texts)


#: DXF colour index and SVG colour of each annotation layer.
MARK_COLOURS: dict[str, tuple[int, str]] = {
    "CAM_TIMING_MARK": (1, "#d62728"),
    "CAM_ROTATION": (6, "#9467bd"),
    "CAM_BORE": (8, "#555555"),
    "CAM_HUB": (8, "#888888"),
    "CAM_LABELS": (7, "#000000"),
}


def xml_escape(text: str) -> str:
    """Escape ``&``, ``<`` and ``>`` for SVG text.

    Parameters
    ----------
    text : str
        Plain text.

    Returns
    -------
    str
        The text, safe inside an XML element.
    """
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def add_dxf_marks(doc: Any, msp: Any, marks: DrawingMarks) -> None:
    """Add the annotations to an ezdxf document: one layer each, TEXT labels.

    Parameters
    ----------
    doc : ezdxf Drawing
        The document (its layer table gets the annotation layers).
    msp : ezdxf Modelspace
        Where the entities go.
    marks : DrawingMarks
        The annotations of :func:`drawing_marks`.
    """
    for layer in marks.layers:
        if layer not in doc.layers:
            doc.layers.add(layer, color=MARK_COLOURS.get(layer, (7, ""))[0])
    for layer, x, y, closed in marks.polylines:
        msp.add_lwpolyline(
            np.column_stack([x, y]).tolist(), format="xy", close=closed, dxfattribs={"layer": layer}
        )
    for layer, r in marks.circles:
        msp.add_circle((0.0, 0.0), r, dxfattribs={"layer": layer})
    for t in marks.texts:
        msp.add_text(
            t.text, height=t.height_mm, dxfattribs={"layer": t.layer, "insert": (t.x_mm, t.y_mm)}
        )


def svg_marks(marks: DrawingMarks) -> list[str]:
    """Render the annotations as SVG groups (one ``<g id=LAYER>`` each; SVG y = -Y).

    Parameters
    ----------
    marks : DrawingMarks
        The annotations of :func:`drawing_marks`.

    Returns
    -------
    list of str
        One ``<g>`` element per layer.
    """
    out: list[str] = []
    for layer in marks.layers:
        colour = MARK_COLOURS.get(layer, (7, "#000000"))[1]
        items: list[str] = []
        for lay, x, y, closed in marks.polylines:
            if lay == layer:
                d = " ".join(
                    f"{'M' if i == 0 else 'L'}{a:.4f},{-b:.4f}"
                    for i, (a, b) in enumerate(zip(x, y, strict=True))
                )
                fill = colour if closed else "none"
                items.append(
                    f'<path d="{d}{" Z" if closed else ""}" fill="{fill}" stroke="{colour}"'
                    ' stroke-width="0.2"/>'
                )
        items += [
            f'<circle cx="0" cy="0" r="{r:.4f}" fill="none" stroke="{colour}" stroke-width="0.15"/>'
            for lay, r in marks.circles
            if lay == layer
        ]
        items += [
            f'<text x="{t.x_mm:.4f}" y="{-t.y_mm:.4f}" font-size="{t.height_mm:.3f}"'
            f' font-family="sans-serif" fill="{colour}">{xml_escape(t.text)}</text>'
            for t in marks.texts
            if t.layer == layer
        ]
        out.append(f'<g id="{layer}">' + "".join(items) + "</g>")
    return out
