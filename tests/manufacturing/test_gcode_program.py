"""The G-code program is one a machine can run (issue 32 item 4), read by another parser.

The program is read back with ``gcodeparser`` (an independent G-code parser from PyPI,
not camtol's own :func:`~camtol.manufacturing.gcode.read_gcode`) and interpreted here as
a controller does (modal position, feed and motion; arcs by their I, J centre from the
block start). Checked: the header's modal codes before the first move, the feed on the
cutting moves, the lead-in and lead-out arcs (90°, tangent, outside the cam), the Z moves
when asked and none otherwise, ``M30`` last; and every contour block, sampled between its
ends, at the tool offset from the cam profile within the tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from camtol.analysis.offset import profile_path
from camtol.cli.app import main
from camtol.config.design_file import design_from_mapping, load_example
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError
from camtol.manufacturing.gcode import GcodePath, path_deviation, write_gcode
from camtol.manufacturing.toolpath import single_cams

gcodeparser = pytest.importorskip("gcodeparser")  # the test extra installs it

TWO_PI = 2.0 * math.pi


@dataclass
class Move:
    """One motion block as a controller executes it."""

    g: int
    x0: float
    y0: float
    x1: float
    y1: float
    z: float | None
    feed: float | None
    cx: float = math.nan
    cy: float = math.nan

    @property
    def xy(self) -> bool:
        return (self.x0, self.y0) != (self.x1, self.y1)


def _run(text: str) -> tuple[list[tuple[str, int]], list[Move]]:
    """Interpret a program: the commands in order, and the moves with their modal state."""
    commands: list[tuple[str, int]] = []
    moves: list[Move] = []
    x = y = math.nan
    z: float | None = None
    feed: float | None = None
    for line in gcodeparser.parse_gcode_lines(text):
        letter, number = line.command
        assert number is not None
        commands.append((letter, number))
        if letter != "G" or number not in (0, 1, 2, 3):
            continue
        p = line.params
        if "F" in p:
            feed = float(p["F"])
        nz = float(p["Z"]) if "Z" in p else z
        nx = float(p.get("X", x))
        ny = float(p.get("Y", y))
        m = Move(number, x, y, nx, ny, nz, feed if number else None)
        if number in (2, 3):
            m.cx, m.cy = x + float(p["I"]), y + float(p["J"])
        moves.append(m)
        x, y, z = nx, ny, nz
    return commands, moves


def _sweep(m: Move) -> float:
    """Signed sweep of an arc block (G03 positive). [rad]"""
    a0 = math.atan2(m.y0 - m.cy, m.x0 - m.cx)
    a1 = math.atan2(m.y1 - m.cy, m.x1 - m.cx)
    return (a1 - a0) % TWO_PI if m.g == 3 else -((a0 - a1) % TWO_PI)


def _end_tangent(m: Move, at_start: bool) -> np.ndarray:
    px, py = (m.x0, m.y0) if at_start else (m.x1, m.y1)
    if m.g == 1:
        t = np.array([m.x1 - m.x0, m.y1 - m.y0])
    else:
        rx, ry = px - m.cx, py - m.cy
        t = np.array([-ry, rx]) if m.g == 3 else np.array([ry, -rx])
    return t / np.hypot(*t)


def _contours(moves: list[Move]) -> list[list[Move]]:
    """The cutting XY moves after each XY rapid: lead-in, contour blocks, lead-out."""
    out: list[list[Move]] = []
    for m in moves:
        if m.g == 0 and m.xy:
            out.append([])
        elif m.g and m.xy:
            out[-1].append(m)
    return out


def _as_path(blocks: list[Move]) -> GcodePath:
    a = np.array([[m.x0, m.y0, m.x1, m.y1, m.cx, m.cy] for m in blocks])
    arc = np.array([m.g in (2, 3) for m in blocks])
    ccw = np.array([m.g == 3 for m in blocks])
    return GcodePath("", a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4], a[:, 5], ccw, arc)


def _offset_error(blocks: list[Move], cam: CamDesign, radius: float) -> float:
    """Largest | distance to the cam profile − tool offset | of points along the blocks.

    The profile itself (offset 0) is sampled every 0.001°: the nearest-sample distance
    then errs by well under 0.01 µm for these cams, so this checks the offset too,
    independently of the cutter-path curve the writer fitted.
    """
    from scipy.spatial import cKDTree

    theta = np.linspace(0.0, TWO_PI, 360_000, endpoint=False)
    prof = profile_path(cam, theta)
    tree = cKDTree(np.column_stack([prof.x_mm, prof.y_mm]))
    u = np.linspace(0.0, 1.0, 17)
    pts = []
    for m in blocks:
        if m.g == 1:
            pts.append(np.column_stack([m.x0 + u * (m.x1 - m.x0), m.y0 + u * (m.y1 - m.y0)]))
        else:
            r = math.hypot(m.x0 - m.cx, m.y0 - m.cy)
            a = math.atan2(m.y0 - m.cy, m.x0 - m.cx) + u * _sweep(m)
            pts.append(np.column_stack([m.cx + r * np.cos(a), m.cy + r * np.sin(a)]))
    dist, _ = tree.query(np.concatenate(pts))
    return float(np.max(np.abs(dist - radius)))


@pytest.mark.parametrize(
    ("name", "radius", "mode", "z"),
    [
        ("cw06-translating", 5.0, "arcs", None),
        ("roller-oscillating", 3.0, "lines", None),
        ("cw11-conjugate", 4.0, "arcs", (5.0, -3.0, 40.0)),
    ],
)
def test_the_program_runs_as_a_controller_reads_it(
    name: str, radius: float, mode: str, z: tuple[float, float, float] | None
) -> None:
    d = load_example(name)
    feed, tol = 320.0, 1e-3
    zkw = {} if z is None else {"safe_z_mm": z[0], "cut_z_mm": z[1], "plunge_feed_mm_min": z[2]}
    prog = write_gcode(
        d,
        feed_mm_min=feed,
        tool_radius_mm=radius,
        tolerance_mm=tol,
        mode=mode,
        **zkw,  # type: ignore[arg-type]
    )
    commands, moves = _run(prog.text)
    first_move = next(i for i, c in enumerate(commands) if c[0] == "G" and c[1] <= 3)
    header = set(commands[:first_move])
    assert {("G", 21), ("G", 17), ("G", 90), ("G", 40), ("G", 94)} <= header
    assert ("G", 20) not in commands and ("G", 91) not in commands  # no inch, no incremental
    assert commands[-1] == ("M", 30)
    cams = single_cams(d)
    # M00 between the cams of a pair, and nowhere else
    assert commands.count(("M", 0)) == len(cams) - 1
    if z is None:
        assert all(m.z is None for m in moves), "a 2D contour has no Z words"
        assert "2D contour: no Z words" in prog.text
    else:
        safe, cut, plunge = z
        for m in moves:
            if m.g == 0 and m.xy:
                assert m.z == safe, "rapids in XY only at the safe height"
            if m.g and m.xy:
                assert m.z == cut, "every cutting XY move at the cutting depth"
            if not m.xy and m.g == 1:
                assert m.z == cut and m.feed == plunge  # the plunge
        assert moves[-1].g == 0 and moves[-1].z == safe  # retracted at the end
    contours = _contours(moves)
    assert len(contours) == len(cams)
    lead = prog.lead_radius_mm
    for blocks, (_, cam) in zip(contours, cams, strict=True):
        assert all(m.feed == feed for m in blocks), "cutting moves at --feed"
        lead_in, body, lead_out = blocks[0], blocks[1:-1], blocks[-1]
        for arc in (lead_in, lead_out):
            assert arc.g in (2, 3)
            assert math.hypot(arc.x0 - arc.cx, arc.y0 - arc.cy) == pytest.approx(lead, abs=1e-4)
            assert abs(_sweep(arc)) == pytest.approx(math.pi / 2, abs=1e-4)
        # tangent entry and exit: along the cutter path's own direction at its start
        p0 = profile_path(cam, np.array([0.0]), offset_mm=radius)
        tangent = np.array([p0.tx[0], p0.ty[0]])
        assert _end_tangent(lead_in, False) @ tangent > 1 - 1e-6
        assert _end_tangent(lead_out, True) @ tangent > 1 - 1e-6
        if mode == "arcs":  # and biarcs continue it (chords cannot)
            assert _end_tangent(lead_in, False) @ _end_tangent(body[0], True) > 1 - 1e-6
        # the contour closes where the lead-in put the tool, and the lead-out leaves there
        start = (body[0].x0, body[0].y0)
        assert (lead_in.x1, lead_in.y1) == start == (lead_out.x0, lead_out.y0)
        assert math.hypot(body[-1].x1 - start[0], body[-1].y1 - start[1]) < 1e-9
        # every contour block, between its ends, at the tool offset from the profile
        assert path_deviation(_as_path(body), cam, radius) <= tol
        assert _offset_error(body, cam, radius) <= tol
        # the lead arcs stay outside the cam: at least the tool offset from the profile
        theta = np.linspace(0.0, TWO_PI, 36_000, endpoint=False)
        prof = profile_path(cam, theta)
        for arc in (lead_in, lead_out):
            a = math.atan2(arc.y0 - arc.cy, arc.x0 - arc.cx) + np.linspace(0, 1, 50) * _sweep(arc)
            px, py = arc.cx + lead * np.cos(a), arc.cy + lead * np.sin(a)
            gap = np.hypot(px[:, None] - prof.x_mm[None, :], py[:, None] - prof.y_mm[None, :])
            assert np.min(gap) >= radius - 1e-3


def _start_in_a_hollow() -> CamDesign:
    """A roller cam whose return ends 10° before θ = 0, so the path curves back there."""
    segs = [
        {"kind": "rise", "law": "cycloidal", "start_deg": 0, "end_deg": 60, "lift_mm": 20.0},
        {"kind": "dwell", "end_deg": 290},
        {"kind": "return", "law": "cycloidal", "end_deg": 350, "lift_mm": 20.0},
        {"kind": "dwell", "end_deg": 360},
    ]
    follower = {"type": "roller_translating", "base_radius_mm": 20.0, "roller_radius_mm": 5.0}
    return design_from_mapping(
        {"name": "hollow", "follower": {**follower, "offset_mm": 0.0}, "motion": {"segments": segs}}
    )


def test_a_lead_arc_that_would_cut_the_cam_is_refused() -> None:
    shapely = pytest.importorskip("shapely")
    d = _start_in_a_hollow()
    ok = write_gcode(d, feed_mm_min=100.0, tool_radius_mm=2.0, lead_radius_mm=10.0)
    _, moves = _run(ok.text)
    with pytest.raises(GeometryError, match="lead radius 50 mm"):
        write_gcode(d, feed_mm_min=100.0, tool_radius_mm=2.0, lead_radius_mm=50.0)
    # The refusal is right: seen by shapely, the 50 mm lead circle enters the region the
    # cutter centre must not enter (inside the cutter path), the 10 mm one does not.
    theta = np.linspace(0.0, TWO_PI, 7200, endpoint=False)
    ring = profile_path(d, theta, offset_mm=2.0)
    forbidden = shapely.Polygon(np.column_stack([ring.x_mm, ring.y_mm])).buffer(-1e-6)
    lead_in = _contours(moves)[0][0]
    nx, ny = lead_in.cx - lead_in.x1, lead_in.cy - lead_in.y1  # outward normal × 10 mm
    for lead, enters in ((10.0, False), (50.0, True)):
        cx, cy = lead_in.x1 + nx / 10.0 * lead, lead_in.y1 + ny / 10.0 * lead
        a = np.linspace(0.0, TWO_PI, 2000)
        circle = shapely.LineString(np.column_stack([cx + lead * np.cos(a), cy + lead * np.sin(a)]))
        # the lead arcs are the quarter circles either side of the touching point
        near = circle.intersection(shapely.Point(lead_in.x1, lead_in.y1).buffer(lead * 1.42))
        assert near.intersects(forbidden) is enters


@pytest.mark.parametrize(
    ("kw", "error"),
    [
        ({"safe_z_mm": 5.0}, "both --safe-z"),
        ({"safe_z_mm": -5.0, "cut_z_mm": -3.0, "plunge_feed_mm_min": 10.0}, "above"),
        ({"safe_z_mm": 5.0, "cut_z_mm": -3.0}, "--plunge-feed"),
        ({"plunge_feed_mm_min": 10.0}, "Z moves"),
        ({"feed_mm_min": 0.0}, "feed_mm_min=0"),
        ({"lead_radius_mm": -1.0}, "lead_radius_mm=-1"),
    ],
)
def test_bad_machine_options_are_refused(kw: dict[str, float], error: str) -> None:
    d = load_example("popa-eccentric")
    args: dict[str, float] = {"feed_mm_min": 100.0, **kw}
    with pytest.raises(DesignError, match=error):
        write_gcode(d, tool_radius_mm=1.0, **args)  # type: ignore[arg-type]


def test_profile_command_writes_a_runnable_program(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "cam.ngc"
    args = ["profile", "-e", "popa-eccentric", "-o", str(out), "--cutter-radius", "6"]
    z = ["--safe-z", "10", "--cut-z", "-4", "--plunge-feed", "60"]
    assert main([*args, "--feed", "450", "--lead-radius", "3", *z]) == 0
    assert max(len(line) for line in capsys.readouterr().out.splitlines()) <= 80
    commands, moves = _run(out.read_text(encoding="utf-8"))
    assert commands[-1] == ("M", 30)
    cutting = [m for m in moves if m.g and m.xy]
    assert {m.feed for m in cutting} == {450.0} and {m.z for m in cutting} == {-4.0}
    lead_in = cutting[0]
    assert math.hypot(lead_in.x0 - lead_in.cx, lead_in.y0 - lead_in.cy) == pytest.approx(3.0)
    # bad machine options: one line, exit 2, nothing written
    for bad, message in (
        (["--cutter-radius", "6"], "--feed"),
        (["--cutter-radius", "6", "--feed", "100", "--safe-z", "1"], "--cut-z"),
        (["--cutter-radius", "6", "--feed", "100", "--plunge-feed", "5"], "Z moves"),
    ):
        nc = tmp_path / "bad.nc"
        assert main(["profile", "-e", "popa-eccentric", "-o", str(nc), *bad]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1 and not nc.exists()
    csv = tmp_path / "p.csv"
    assert main(["profile", "-e", "popa-eccentric", "-o", str(csv), "--feed", "100"]) == 2
    assert "only allowed for G-code" in capsys.readouterr().err and not csv.exists()
