"""DXF/SVG export annotations (issue 13 item 11), read back with ezdxf and xml.etree.

Zero-angle timing mark on the reference radial (+X, THEORY §0), the clockwise rotation
arrow, the bore/hub of the design's optional ``[drawing]`` table, labels, and cams A and B
on distinct layers and colours.
"""

from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from camtol import __version__
from camtol.cli.app import main
from camtol.config.design_file import load_design, load_example
from camtol.export import write_profile
from camtol.report.export import ExportError

SVG = {"s": "http://www.w3.org/2000/svg"}


def _dxf(path: Path) -> ezdxf.document.Drawing:
    return ezdxf.readfile(path)


def test_dxf_timing_mark_rotation_and_labels(tmp_path: Path) -> None:
    out = tmp_path / "cam.dxf"
    pts = write_profile(load_example("roller-translating"), out)
    doc = _dxf(out)
    msp = doc.modelspace()
    r_max = max(float(np.hypot(c.x_mm, c.y_mm).max()) for c in pts.curves)
    # timing mark: a radial segment on +X (θ = 0 reference radial) outside every curve
    mark = [e for e in msp.query("LWPOLYLINE") if e.dxf.layer == "CAM_TIMING_MARK"]
    assert len(mark) == 1
    xy = np.array(mark[0].get_points("xy"))
    assert np.allclose(xy[:, 1], 0.0) and xy[:, 0].min() > r_max
    # rotation: an arc whose polar angle decreases along it (clockwise) and an arrowhead
    rot = [e for e in msp.query("LWPOLYLINE") if e.dxf.layer == "CAM_ROTATION"]
    arc = next(e for e in rot if not e.closed)
    pa = np.degrees(np.arctan2(*np.array(arc.get_points("xy"))[:, ::-1].T))
    assert np.all(np.diff(pa) < 0)
    assert any(e.closed for e in rot)
    texts = {e.dxf.text: e.dxf.layer for e in msp.query("TEXT")}
    assert texts.get("0°") == "CAM_TIMING_MARK" and texts.get("CW") == "CAM_ROTATION"
    title = next(t for t, layer in texts.items() if layer == "CAM_LABELS")
    assert "roller-translating" in title and __version__ in title
    layers = {layer.dxf.name: layer.color for layer in doc.layers}
    assert {"CAM_TIMING_MARK", "CAM_ROTATION", "CAM_LABELS"} <= set(layers)
    assert "CAM_BORE" not in layers  # the example gives no bore


def test_conjugate_cams_on_distinct_layers_and_colours(tmp_path: Path) -> None:
    dxf, svg = tmp_path / "c.dxf", tmp_path / "c.svg"
    d = load_example("cw11-conjugate")
    write_profile(d, dxf)
    write_profile(d, svg)
    layers = {layer.dxf.name: layer.color for layer in _dxf(dxf).layers}
    assert layers["CAM_A_PROFILE"] != layers["CAM_B_PROFILE"]
    assert layers["CAM_A_PITCH_CURVE"] != layers["CAM_B_PITCH_CURVE"]
    labels = {e.dxf.text for e in _dxf(dxf).modelspace().query("TEXT")}
    assert {"cam A", "cam B"} <= labels
    root = ET.parse(svg).getroot()
    groups = {g.attrib["id"]: g for g in root.iter(f"{{{SVG['s']}}}g")}
    stroke = {
        k: groups[k].find("s:path", SVG).attrib["stroke"]  # type: ignore[union-attr]
        for k in ("CAM_A_PROFILE", "CAM_B_PROFILE", "CAM_A_PITCH_CURVE", "CAM_B_PITCH_CURVE")
    }
    assert stroke["CAM_A_PROFILE"] != stroke["CAM_B_PROFILE"]
    assert stroke["CAM_A_PITCH_CURVE"] != stroke["CAM_B_PITCH_CURVE"]
    svg_texts = {t.text for t in root.iter(f"{{{SVG['s']}}}text")}
    assert {"cam A", "cam B", "0°", "CW"} <= svg_texts


def test_svg_timing_mark_and_rotation_groups(tmp_path: Path) -> None:
    out = tmp_path / "p.svg"
    write_profile(load_example("cw06-translating"), out)
    root = ET.parse(out).getroot()
    groups = {g.attrib["id"]: g for g in root.iter(f"{{{SVG['s']}}}g")}
    assert {"CAM_TIMING_MARK", "CAM_ROTATION", "CAM_LABELS"} <= set(groups)
    d = groups["CAM_TIMING_MARK"].find("s:path", SVG).attrib["d"]  # type: ignore[union-attr]
    ys = [float(p.split(",")[1]) for p in d.replace("M", " ").replace("L", " ").split()]
    assert ys == [0.0, 0.0]  # on the X axis (SVG y = -Y)
    # the viewBox holds the marks
    x0, y0, w, h = (float(v) for v in root.attrib["viewBox"].split())
    xs = [float(p.split(",")[0]) for p in d.replace("M", " ").replace("L", " ").split()]
    assert x0 <= min(xs) and max(xs) <= x0 + w


def _with_drawing(tmp_path: Path, table: str) -> Path:
    src = Path(__file__).parents[2] / "src/camtol/data/examples/roller-translating.toml"
    text = src.read_text(encoding="utf-8") + "\n[drawing]\n" + table + "\n"
    p = tmp_path / "d.toml"
    p.write_text(text, encoding="utf-8")
    return p


def test_bore_and_hub_from_the_design(tmp_path: Path) -> None:
    d = load_design(_with_drawing(tmp_path, "bore_diameter_mm = 20\nhub_diameter_mm = 40"))
    assert d.extras["bore_diameter_mm"] == 20 and d.extras["hub_diameter_mm"] == 40
    for suffix in (".dxf", ".svg"):
        write_profile(d, tmp_path / f"b{suffix}")
    circles = {
        e.dxf.layer: e.dxf.radius for e in _dxf(tmp_path / "b.dxf").modelspace().query("CIRCLE")
    }
    assert circles == {"CAM_BORE": pytest.approx(10.0), "CAM_HUB": pytest.approx(20.0)}
    root = ET.parse(tmp_path / "b.svg").getroot()
    radii = {
        g.attrib["id"]: float(g.find("s:circle", SVG).attrib["r"])  # type: ignore[union-attr]
        for g in root.iter(f"{{{SVG['s']}}}g")
        if g.find("s:circle", SVG) is not None
    }
    assert radii == {"CAM_BORE": pytest.approx(10.0), "CAM_HUB": pytest.approx(20.0)}


def test_bore_larger_than_the_cam_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    d = load_design(_with_drawing(tmp_path, "bore_diameter_mm = 500"))
    with pytest.raises(ExportError, match="drawing.bore_diameter_mm=500"):
        write_profile(d, tmp_path / "x.dxf")
    assert not (tmp_path / "x.dxf").exists()
    d2 = dataclasses.replace(d, extras={"bore_diameter_mm": 30.0, "hub_diameter_mm": 20.0})
    with pytest.raises(ExportError, match="smaller than drawing.hub_diameter_mm"):
        write_profile(d2, tmp_path / "x.svg")
    bad = _with_drawing(tmp_path, "bore_diameter_mm = -1")
    assert main(["profile", str(bad), "-o", str(tmp_path / "y.dxf")]) == 2
    err = capsys.readouterr().err
    assert "drawing.bore_diameter_mm" in err and err.count("\n") == 1
