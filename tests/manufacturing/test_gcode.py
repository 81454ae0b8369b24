"""G-code of the cutter-centre path (THEORY §6): read back and measured between blocks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from manufacturing_designs import concave_roller_design

from camtol.config.design_file import load_example
from camtol.exceptions import DesignError, UndercutError
from camtol.manufacturing.gcode import GcodePath, path_deviation, read_gcode, write_gcode
from camtol.manufacturing.toolpath import single_cams

#: A cutting feed for the programs of these tests. [mm/min]
FEED = 250.0


@pytest.mark.parametrize("mode", ["arcs", "lines"])
@pytest.mark.parametrize(
    ("name", "radius", "tol"),
    [
        ("popa-eccentric", 5.0, 1e-3),
        ("cw06-translating", 3.0, 1e-3),
        ("cw06-oscillating", 6.0, 1e-4),
        ("roller-translating", 10.0, 1e-3),
        ("cw11-conjugate", 4.0, 1e-3),
    ],
)
def test_read_back_lies_within_tolerance_between_blocks(
    name: str, radius: float, tol: float, mode: str
) -> None:
    d = load_example(name)
    prog = write_gcode(d, feed_mm_min=FEED, tool_radius_mm=radius, tolerance_mm=tol, mode=mode)  # type: ignore[arg-type]
    paths = read_gcode(prog.text)
    cams = single_cams(d)
    assert len(paths) == len(cams)
    for path, (_, cam) in zip(paths, cams, strict=True):
        # 16 points along every block, ends included: the interior is checked, not only
        # the vertices; the written numbers are rounded, as the machine reads them.
        assert path_deviation(path, cam, radius, per_block=16) <= tol
        # The contour closes on itself.
        assert math.hypot(path.x1_mm[-1] - path.x0_mm[0], path.y1_mm[-1] - path.y0_mm[0]) < 1e-9
        if mode == "arcs":
            assert np.all(path.is_arc | ~path.is_arc)  # G01 only where nearly straight
            assert np.mean(path.is_arc) > 0.9


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.asarray(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def _tangents(path: GcodePath) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents at the start and at the end of every block."""
    out = []
    for px, py in ((path.x0_mm, path.y0_mm), (path.x1_mm, path.y1_mm)):
        rx, ry = px - path.centre_x_mm, py - path.centre_y_mm
        sgn = np.where(path.ccw, 1.0, -1.0)
        tx, ty = -ry * sgn, rx * sgn
        lx, ly = path.x1_mm - path.x0_mm, path.y1_mm - path.y0_mm
        tx, ty = np.where(path.is_arc, tx, lx), np.where(path.is_arc, ty, ly)
        n = np.hypot(tx, ty)
        out.append(np.column_stack([tx / n, ty / n]))
    return out[0], out[1]


@pytest.mark.parametrize("name", ["cw06-translating", "roller-oscillating"])
def test_biarcs_are_tangent_continuous(name: str) -> None:
    d = load_example(name)
    prog = write_gcode(d, feed_mm_min=FEED, tool_radius_mm=5.0, tolerance_mm=1e-3)
    fitted = prog.paths[0]
    start, end = _tangents(fitted)
    # Each block starts with the tangent the previous one ended with (closed contour).
    turn = np.abs(_cross(np.roll(end, 1, axis=0), start))
    assert np.max(turn) < 1e-9
    assert np.min(np.sum(np.roll(end, 1, axis=0) * start, axis=1)) > 0
    # Read back from the rounded program: still tangent-continuous to the rounding.
    start, end = _tangents(read_gcode(prog.text)[0])
    assert np.max(np.abs(_cross(np.roll(end, 1, axis=0), start))) < 1e-4
    # Far fewer blocks than chords at the same tolerance.
    lines = write_gcode(d, feed_mm_min=FEED, tool_radius_mm=5.0, tolerance_mm=1e-3, mode="lines")
    assert prog.blocks < 0.5 * lines.blocks


def test_header_and_wire_edm_offset() -> None:
    d = load_example("popa-eccentric")
    prog = write_gcode(
        d, feed_mm_min=FEED, wire_radius_mm=0.125, spark_gap_mm=0.025, tolerance_mm=1e-3
    )
    assert prog.tool_radius_mm == pytest.approx(0.15)
    head = prog.text.split("G00", 1)[0]  # everything before the first move
    assert "camtol" in head and "popa-eccentric" in head
    assert "wire radius 0.125 mm + spark gap 0.025 mm = offset 0.15 mm" in head
    assert "tolerance: 1 um" in head
    for code in ("G21", "G17", "G90", "G40", "G94"):  # units, plane, absolute, no comp.
        assert f"\n{code} (" in head
    path = read_gcode(prog.text)[0]
    # The path is the eccentric circle grown by the offset: radius 30.15 mm about (−5, 0).
    assert path_deviation(path, d, 0.15) <= 1e-3
    r = np.hypot(path.x0_mm + 5.0, path.y0_mm)
    assert np.allclose(r, 30.15, atol=1e-5)


def test_gouging_tool_and_bad_options_are_refused() -> None:
    with pytest.raises(UndercutError, match="gouge"):
        write_gcode(concave_roller_design(), feed_mm_min=FEED, tool_radius_mm=20.0)
    d = load_example("popa-eccentric")
    with pytest.raises(DesignError, match="exactly one"):
        write_gcode(d, feed_mm_min=FEED)
    with pytest.raises(DesignError, match="tolerance_mm"):
        write_gcode(d, feed_mm_min=FEED, tool_radius_mm=1.0, tolerance_mm=0.0)
    for kw in ({"tool_radius_mm": 1e30}, {"wire_radius_mm": 99_999.0, "spark_gap_mm": 2.0}):
        with pytest.raises(DesignError, match="tool offset .* at most 100000 mm"):
            write_gcode(d, feed_mm_min=FEED, **kw)  # type: ignore[arg-type]


@settings(max_examples=12)
@given(
    radius=st.floats(0.0, 12.0),
    tol_um=st.sampled_from([0.5, 1.0, 5.0, 20.0]),
    mode=st.sampled_from(["arcs", "lines"]),
    name=st.sampled_from(["cw06-translating", "roller-oscillating", "popa-eccentric"]),
)
def test_any_tool_and_tolerance_reads_back_within_tolerance(
    radius: float, tol_um: float, mode: str, name: str
) -> None:
    d = load_example(name)
    prog = write_gcode(
        d, feed_mm_min=FEED, tool_radius_mm=radius, tolerance_mm=tol_um * 1e-3, mode=mode
    )  # type: ignore[arg-type]
    path = read_gcode(prog.text)[0]
    assert path_deviation(path, d, radius, per_block=12) <= tol_um * 1e-3
