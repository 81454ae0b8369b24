r"""CNC output: the cutter-centre path as G-code, lines or biarcs within a tolerance (THEORY §6).

The path is the profile offset outward by the tool radius R (for wire EDM: wire radius +
spark gap), an exact curve of θ (:func:`camtol.manufacturing.toolpath.profile_path`). It is
written in absolute millimetres in the cam frame of THEORY §0 (origin at the cam pivot),
counterclockwise around the cam as θ grows, either

- as ``G01`` lines whose vertices lie on the path and whose chords deviate from it by
  less than the tolerance (sagitta plan h ≈ Δs²/(8ρ), then verified and bisected), or
- as ``G02``/``G03`` arcs fitted by *biarcs*: between two points of the path with their
  unit tangents T0, T1, two circular arcs meeting with a common tangent at
  J = (P0 + d T0 + P1 − d T1)/2, with the equal tangent lengths d solving
  |P1 − P0 − d(T0 + T1)| = 2d. Every block starts with the tangent the previous one ended
  with, so the program is tangent-continuous; intervals whose fit deviates from the path
  by more than the tolerance are bisected. Far fewer blocks than lines (what commercial
  cam software exports).

:func:`read_gcode` reads such a program back (G00/G01/G02/G03 with X, Y, I, J), and
:func:`path_deviation` measures the distance from the analytic path of points sampled
*along* every block (between the block ends, not only at them), the check the tests use.

Why one module: it is the G-code program of the cutter path, both ways. The fit makes the
:class:`GcodePath` blocks :func:`write_gcode` prints, :func:`read_gcode` reads exactly that
dialect back into the same blocks, and :func:`path_deviation` measures them against the same
analytic path, so the writer's tolerance is checked on what it wrote.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from camtol.analysis.profile import MAX_TOOL_RADIUS_MM
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError, InputFileError
from camtol.jet import FloatArray
from camtol.manufacturing.toolpath import PathSample, check_gouge, profile_path, single_cams

__all__ = [
    "GCODE_MODES",
    "GcodeMode",
    "GcodePath",
    "GcodeProgram",
    "path_deviation",
    "read_gcode",
    "write_gcode",
]

GcodeMode = Literal["arcs", "lines"]
GCODE_MODES: tuple[str, ...] = get_args(GcodeMode)
TWO_PI = 2.0 * math.pi
#: Fraction of the tolerance the fit itself may use (the rest covers rounding). [-]
_FIT_SHARE = 0.8
#: Interior points per interval at which the fit is verified. [-]
_CHECKS = 9
#: Largest feed (mm/min) or lead radius (mm) accepted: far above any machine, so only a
#: mistyped exponent is refused.
MAX_FEED_OR_LEAD = 1e6


@dataclass(frozen=True)
class GcodePath:
    """One closed contour as blocks (arrays, one entry per block).

    Attributes
    ----------
    label : str
        "" for a single cam, "A"/"B" for the cams of a conjugate pair.
    x0_mm, y0_mm, x1_mm, y1_mm : ndarray
        Block start and end points. [mm]
    centre_x_mm, centre_y_mm : ndarray
        Arc centres (NaN for a line). [mm]
    ccw : ndarray of bool
        True for G03 (counterclockwise arc); False for G02 or a line.
    is_arc : ndarray of bool
        True for an arc block.
    """

    label: str
    x0_mm: FloatArray
    y0_mm: FloatArray
    x1_mm: FloatArray
    y1_mm: FloatArray
    centre_x_mm: FloatArray
    centre_y_mm: FloatArray
    ccw: np.ndarray
    is_arc: np.ndarray

    @property
    def blocks(self) -> int:
        """Number of motion blocks."""
        return int(self.x0_mm.size)


@dataclass(frozen=True)
class GcodeProgram:
    """A G-code program of the cutter-centre path and what it was built from.

    Attributes
    ----------
    text : str
        The program.
    paths : tuple of GcodePath
        The contours as fitted (before rounding to the written decimals).
    mode : {"arcs", "lines"}
        Biarcs (G02/G03) or chords (G01).
    tolerance_mm : float
        Largest allowed distance from the analytic cutter path. [mm]
    tool_radius_mm : float
        Offset of the path from the profile (tool radius; wire radius + spark gap). [mm]
    max_fit_deviation_mm : float
        Largest deviation found by the fit's verification. [mm]
    feed_mm_min : float
        Cutting feed. [mm/min]
    lead_radius_mm : float
        Radius of the lead-in and lead-out arcs. [mm]
    safe_z_mm, cut_z_mm, plunge_feed_mm_min : float or None
        The Z moves (None for a 2D contour). [mm, mm, mm/min]
    """

    text: str
    paths: tuple[GcodePath, ...]
    mode: str
    tolerance_mm: float
    tool_radius_mm: float
    max_fit_deviation_mm: float
    feed_mm_min: float = 0.0
    lead_radius_mm: float = 0.0
    safe_z_mm: float | None = None
    cut_z_mm: float | None = None
    plunge_feed_mm_min: float | None = None

    @property
    def blocks(self) -> int:
        """Motion blocks in all contours."""
        return sum(p.blocks for p in self.paths)


# ---------------------------------------------------------------------------------------
# Fitting
# ---------------------------------------------------------------------------------------
def _initial_knots(design: CamDesign, r: float, tol: float, mode: str) -> FloatArray:
    """Knots from the sagitta rule on a 0.1° grid (biarcs: a coarser start)."""
    theta = np.linspace(0.0, TWO_PI, 3600, endpoint=False)
    p = profile_path(design, theta, offset_mm=r)
    arc = 2.0 * np.sqrt(2.0 * np.abs(p.rho_mm) * tol * _FIT_SHARE)  # Δs with Δs²/(8ρ) = tol
    if mode == "arcs":
        arc = arc * 8.0  # a biarc's error is third order: start coarse, bisect as needed
    dtheta = np.clip(arc / p.speed_mm, math.radians(0.01), math.radians(5.0))
    cum = np.concatenate([[0.0], np.cumsum(0.1 * math.pi / 180.0 / dtheta)])
    n = max(8, math.ceil(cum[-1]))
    knots = np.interp(np.linspace(0.0, cum[-1], n + 1)[:-1], cum, np.append(theta, TWO_PI))
    bounds = np.mod(np.asarray(design.program.boundaries_rad, dtype=float), TWO_PI)
    return np.unique(np.concatenate([knots, bounds]))


def _biarcs(p0: PathSample, p1: PathSample) -> tuple[FloatArray, ...]:
    """Biarc through (P0, T0) and (P1, T1): join point and both arcs' signed radii/centres."""
    vx, vy = p1.x_mm - p0.x_mm, p1.y_mm - p0.y_mm
    tx, ty = p0.tx + p1.tx, p0.ty + p1.ty
    vt = vx * tx + vy * ty
    vv = vx * vx + vy * vy
    c = 1.0 - (p0.tx * p1.tx + p0.ty * p1.ty)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(
            c > 1e-12,
            (-vt + np.sqrt(vt * vt + 2.0 * c * vv)) / (2.0 * c),
            vv / (4.0 * (vx * p0.tx + vy * p0.ty)),
        )
    jx = 0.5 * (p0.x_mm + d * p0.tx + p1.x_mm - d * p1.tx)
    jy = 0.5 * (p0.y_mm + d * p0.ty + p1.y_mm - d * p1.ty)
    return (
        jx,
        jy,
        *_arc_through(p0.x_mm, p0.y_mm, p0.tx, p0.ty, jx, jy),
        *_arc_through(p1.x_mm, p1.y_mm, p1.tx, p1.ty, jx, jy),
    )


def _arc_through(
    x: FloatArray, y: FloatArray, tx: FloatArray, ty: FloatArray, qx: FloatArray, qy: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Circle tangent to T at (x, y) through Q: centre and signed radius (> 0 turns left)."""
    nx, ny = -ty, tx
    ex, ey = qx - x, qy - y
    with np.errstate(divide="ignore", invalid="ignore"):
        r = (ex * ex + ey * ey) / (2.0 * (ex * nx + ey * ny))
    return x + r * nx, y + r * ny, r


def _dist_to_arc(
    px: FloatArray,
    py: FloatArray,
    ax: FloatArray,
    ay: FloatArray,
    bx: FloatArray,
    by: FloatArray,
    cx: FloatArray,
    cy: FloatArray,
    r: FloatArray,
) -> FloatArray:
    """Distance from P to the arc (or segment when |r| is huge) from A to B."""
    # Segment distance (used where the arc is nearly straight, and as the end distance).
    sx, sy = bx - ax, by - ay
    ll = sx * sx + sy * sy
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.clip(((px - ax) * sx + (py - ay) * sy) / ll, 0.0, 1.0)
    seg = np.hypot(px - ax - u * sx, py - ay - u * sy)
    straight = ~np.isfinite(r) | (np.abs(r) > 1e7)
    with np.errstate(invalid="ignore"):
        rad = np.abs(np.hypot(px - cx, py - cy) - np.abs(r))
        # On the arc's sweep when P lies on the same side of chord AB as the arc's middle.
        side_p = sx * (py - ay) - sy * (px - ax)
        mid_side = -np.sign(r) * ll  # the arc bulges to the right of AB when turning left
        on = side_p * mid_side >= 0
    ends = np.minimum(np.hypot(px - ax, py - ay), np.hypot(px - bx, py - by))
    return np.where(straight, seg, np.where(on, rad, ends))


def _fit(design: CamDesign, r: float, tol: float, mode: str, label: str) -> tuple[GcodePath, float]:
    knots = _initial_knots(design, r, tol, mode)
    frac = np.arange(1, _CHECKS + 1) / (_CHECKS + 1)
    for _ in range(40):
        t1 = np.append(knots[1:], knots[0] + TWO_PI)
        p0 = profile_path(design, knots, offset_mm=r)
        p1 = profile_path(design, np.mod(t1, TWO_PI), offset_mm=r)
        tm = (knots[:, None] + frac[None, :] * (t1 - knots)[:, None]).ravel()
        pm = profile_path(design, np.mod(tm, TWO_PI), offset_mm=r)
        qx = pm.x_mm.reshape(-1, _CHECKS)
        qy = pm.y_mm.reshape(-1, _CHECKS)
        if mode == "lines":
            nan = np.full(knots.size, np.nan)
            ends = [a[:, None] for a in (p0.x_mm, p0.y_mm, p1.x_mm, p1.y_mm)]
            none = nan[:, None]
            dev = _dist_to_arc(qx, qy, ends[0], ends[1], ends[2], ends[3], none, none, none)
            worst = dev.max(axis=1)
        else:
            jx, jy, c1x, c1y, r1, c2x, c2y, r2 = _biarcs(p0, p1)
            a1 = [a[:, None] for a in (p0.x_mm, p0.y_mm, jx, jy, c1x, c1y, r1)]
            d1 = _dist_to_arc(qx, qy, a1[0], a1[1], a1[2], a1[3], a1[4], a1[5], a1[6])
            a2 = [a[:, None] for a in (jx, jy, p1.x_mm, p1.y_mm, c2x, c2y, r2)]
            d2 = _dist_to_arc(qx, qy, a2[0], a2[1], a2[2], a2[3], a2[4], a2[5], a2[6])
            worst = np.minimum(d1, d2).max(axis=1)
        bad = np.flatnonzero(~(worst <= _FIT_SHARE * tol))
        if bad.size == 0:
            break
        knots = np.sort(np.concatenate([knots, 0.5 * (knots[bad] + t1[bad])]))
    else:
        raise GeometryError(f"the cutter path could not be fitted within {tol * 1e3:g} µm")
    if mode == "lines":
        nan = np.full(knots.size, np.nan)
        path = GcodePath(label, p0.x_mm, p0.y_mm, p1.x_mm, p1.y_mm, nan, nan,
                         np.zeros(knots.size, bool), np.zeros(knots.size, bool))  # fmt: skip
        return path, float(worst.max())
    # Interleave the two arcs of every biarc: P0 -> J on circle 1, J -> P1 on circle 2 (both
    # radii signed for travel in the direction of growing θ, > 0 turning left).
    n = knots.size
    x0 = np.empty(2 * n)
    y0, x1, y1, cx, cy = (np.empty(2 * n) for _ in range(5))
    rr = np.empty(2 * n)
    x0[0::2], y0[0::2], x1[0::2], y1[0::2] = p0.x_mm, p0.y_mm, jx, jy
    x0[1::2], y0[1::2], x1[1::2], y1[1::2] = jx, jy, p1.x_mm, p1.y_mm
    cx[0::2], cy[0::2], rr[0::2] = c1x, c1y, r1
    cx[1::2], cy[1::2], rr[1::2] = c2x, c2y, r2
    is_arc = np.isfinite(rr) & (np.abs(rr) <= 1e7)
    cx, cy = np.where(is_arc, cx, np.nan), np.where(is_arc, cy, np.nan)
    path = GcodePath(label, x0, y0, x1, y1, cx, cy, is_arc & (rr > 0), is_arc)
    return path, float(worst.max())


# ---------------------------------------------------------------------------------------
# Writing and reading
# ---------------------------------------------------------------------------------------
def _decimals(tol: float) -> int:
    """Decimals so that rounding moves a point by at most 2 % of the tolerance."""
    return max(3, min(8, math.ceil(-math.log10(0.02 * tol / math.sqrt(2.0)))))


def _lead_arcs(
    design: CamDesign, r: float, lead_mm: float
) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float], bool]:
    """Lead-in start, lead-out end, common centre, and ccw, of the 90° lead arcs at θ = 0.

    Both arcs lie on one circle of radius ``lead_mm`` tangent to the cutter path at its start
    P0, on the outer side (centre C = P0 + ρ_l N0): the lead-in runs a quarter turn onto P0
    arriving along the path's tangent T0, the lead-out a quarter turn off it, so the tool
    enters and leaves the contour tangentially and never dwells on it. Refused when the
    circle would cross into the cam (a concave start tighter than the lead radius).
    """
    p = profile_path(design, np.array([0.0]), offset_mm=r)
    px, py = float(p.x_mm[0]), float(p.y_mm[0])
    nx, ny = float(p.normal_x[0]), float(p.normal_y[0])  # outward (away from the cam)
    tx, ty = float(p.tx[0]), float(p.ty[0])  # direction of travel (θ growing)
    cx, cy = px + lead_mm * nx, py + lead_mm * ny
    ccw = (ny * tx - nx * ty) > 0.0  # ccw about C moves along rot90(−N0) at P0
    start = (cx - lead_mm * tx, cy - lead_mm * ty)
    end = (cx + lead_mm * tx, cy + lead_mm * ty)
    # The arcs must stay outside the cutter path (else the tool cuts into the cam).
    theta = np.linspace(0.0, TWO_PI, 7200, endpoint=False)
    ring = profile_path(design, theta, offset_mm=r)
    phi = np.linspace(0.02, 0.5 * math.pi, 64)  # from near P0 out to each arc's far end
    rad = -np.array([nx, ny])
    tan = np.array([tx, ty])
    pts = [
        np.column_stack(
            [
                cx + lead_mm * (rad[0] * np.cos(phi) + s * tan[0] * np.sin(phi)),
                cy + lead_mm * (rad[1] * np.cos(phi) + s * tan[1] * np.sin(phi)),
            ]
        )
        for s in (-1.0, 1.0)
    ]
    q = np.concatenate(pts)
    dx = ring.x_mm[None, :] - q[:, :1]
    dy = ring.y_mm[None, :] - q[:, 1:]
    ang = np.arctan2(dy, dx)
    winding = np.sum(np.mod(np.diff(ang, append=ang[:, :1], axis=1) + math.pi, TWO_PI) - math.pi, 1)
    if np.any(np.abs(winding) > math.pi):
        raise GeometryError(
            f"lead radius {lead_mm:g} mm is not allowed: the lead-in/lead-out arcs at θ=0°"
            " would cut into the cam (the cutter path curves back there); give a smaller"
            " --lead-radius"
        )
    return start, end, (cx, cy), bool(ccw)


def write_gcode(
    design: CamDesign,
    *,
    feed_mm_min: float,
    tool_radius_mm: float | None = None,
    tolerance_mm: float = 1e-3,
    mode: GcodeMode = "arcs",
    wire_radius_mm: float | None = None,
    spark_gap_mm: float = 0.0,
    lead_radius_mm: float | None = None,
    safe_z_mm: float | None = None,
    cut_z_mm: float | None = None,
    plunge_feed_mm_min: float | None = None,
) -> GcodeProgram:
    """Build the G-code program of the cutter-centre path (THEORY §6).

    The program a machine runs: a header stating the units (G21), plane (G17), absolute
    mode (G90), cutter compensation off (G40, the path is already the cutter centre) and
    feed per minute (G94), the tool, the tolerance and the frame; per cam a rapid to the
    lead-in start, a 90° lead-in arc onto the contour at θ = 0 with the feed, the closed
    contour, a 90° lead-out arc off it; ``M30`` at the end. By default a 2D contour with no
    Z words (the header says so: the machinist sets the depth); with ``safe_z_mm`` and
    ``cut_z_mm`` the program retracts to the safe height, rapids over the start, plunges at
    ``plunge_feed_mm_min`` and retracts after the lead-out.

    Parameters
    ----------
    design : CamDesign
        The design (both cams of a conjugate pair, one contour each).
    feed_mm_min : float
        Cutting feed rate, on the lead-in block (modal for the contour). [mm/min]
    tool_radius_mm : float, optional
        Cutter radius R (milling, grinding). Give this or ``wire_radius_mm``. [mm]
    tolerance_mm : float
        Largest distance of the program from the analytic cutter path, 1e-6..1. [mm]
    mode : {"arcs", "lines"}
        ``"arcs"``: G02/G03 biarcs, tangent-continuous; ``"lines"``: G01 chords.
    wire_radius_mm : float, optional
        Wire-EDM contour: wire radius; the offset is wire radius + spark gap. [mm]
    spark_gap_mm : float
        Wire-EDM spark gap (overcut per side). [mm]
    lead_radius_mm : float, optional
        Radius of the lead-in and lead-out arcs (default: the tool offset, at least
        1 mm). [mm]
    safe_z_mm, cut_z_mm : float, optional
        Retract height and cutting depth, given together for a program with Z moves; the
        safe height must lie above the cutting depth. [mm]
    plunge_feed_mm_min : float, optional
        Feed of the plunge to ``cut_z_mm`` (required with Z moves). [mm/min]

    Returns
    -------
    GcodeProgram

    Raises
    ------
    DesignError
        Missing or conflicting tool or Z options, values out of range.
    UndercutError
        The tool radius exceeds a concave radius of curvature (it would gouge; says where).
    GeometryError
        Lead arcs that would cut into the cam.
    """
    from camtol._version import __version__

    if (tool_radius_mm is None) == (wire_radius_mm is None):
        raise DesignError("give exactly one of a tool radius or a wire radius (wire EDM)")
    if mode not in GCODE_MODES:
        raise DesignError(f"mode={mode!r} is unknown; allowed: {', '.join(GCODE_MODES)}")
    if not (math.isfinite(tolerance_mm) and 1e-6 <= tolerance_mm <= 1.0):
        raise DesignError(
            f"tolerance_mm={tolerance_mm:g} is not allowed; the G-code tolerance must lie"
            " between 1e-6 mm (1 nm) and 1 mm"
        )
    for name, val in (
        ("tool_radius_mm", tool_radius_mm),
        ("wire_radius_mm", wire_radius_mm),
        ("spark_gap_mm", spark_gap_mm),
    ):
        if val is not None and not (math.isfinite(val) and val >= 0):
            raise DesignError(f"{name}={val:g} is not allowed; give a length ≥ 0")
    for name, val in (
        ("feed_mm_min", feed_mm_min),
        ("plunge_feed_mm_min", plunge_feed_mm_min),
        ("lead_radius_mm", lead_radius_mm),
    ):
        if val is not None and not (math.isfinite(val) and 0 < val <= MAX_FEED_OR_LEAD):
            raise DesignError(
                f"{name}={val:g} is not allowed; give a positive value up to"
                f" {MAX_FEED_OR_LEAD:g} (mm/min or mm)"
            )
    if (safe_z_mm is None) != (cut_z_mm is None):
        raise DesignError("Z moves need both --safe-z MM and --cut-z MM (or neither: 2D)")
    with_z = safe_z_mm is not None and cut_z_mm is not None
    if with_z:
        assert safe_z_mm is not None and cut_z_mm is not None
        if not (math.isfinite(safe_z_mm) and math.isfinite(cut_z_mm) and safe_z_mm > cut_z_mm):
            raise DesignError(
                f"--safe-z={safe_z_mm:g} is not allowed; the safe height must lie above the"
                f" cutting depth --cut-z={cut_z_mm:g} mm"
            )
        if plunge_feed_mm_min is None:
            raise DesignError("a program with Z moves needs --plunge-feed MM_PER_MIN")
    elif plunge_feed_mm_min is not None:
        raise DesignError("--plunge-feed is for a program with Z moves: give --safe-z and --cut-z")
    offset = (tool_radius_mm or 0.0) + (wire_radius_mm or 0.0) + spark_gap_mm
    if offset > MAX_TOOL_RADIUS_MM:
        raise DesignError(
            f"tool offset {offset:g} mm is not allowed (tool_radius_mm, or wire_radius_mm +"
            f" spark_gap_mm); give at most {MAX_TOOL_RADIUS_MM:g} mm"
        )
    if wire_radius_mm is not None:
        r = wire_radius_mm + spark_gap_mm
        tool = (
            f"wire EDM: wire radius {wire_radius_mm:g} mm + spark gap {spark_gap_mm:g} mm"
            f" = offset {r:g} mm"
        )
    else:
        assert tool_radius_mm is not None
        r = tool_radius_mm
        tool = f"cylindrical cutter, radius {r:g} mm"
    lead = lead_radius_mm if lead_radius_mm is not None else max(r, 1.0)
    paths, leads, worst = [], [], 0.0
    for label, cam in single_cams(design):
        check_gouge(cam, r)
        path, dev = _fit(cam, r, tolerance_mm, mode, label)
        paths.append(path)
        leads.append(_lead_arcs(cam, r, lead))
        worst = max(worst, dev)
    k = _decimals(tolerance_mm)
    kind = "G02/G03 biarcs, tangent-continuous" if mode == "arcs" else "G01 chords"
    name = design.name.replace("(", "[").replace(")", "]")
    lines = [
        "%",
        f"(camtol {__version__}: cutter-centre path of a disk cam)",
        f"(design: {name})",
        f"(tool: {tool})",
        f"(cutter compensation: off; the path is the cutter centre, offset {r:g} mm)",
        f"(tolerance: {tolerance_mm * 1e3:g} um from the analytic cutter path; {kind})",
        f"(fit: max deviation {worst * 1e3:.4g} um before rounding to {k} decimals)",
        "(coordinates: absolute mm, cam frame X-Y of camtol THEORY 0, origin at the cam pivot)",
        "(contour: counterclockwise around the cam)",
        f"(lead-in, lead-out: 90-degree arcs of radius {lead:g} mm tangent at theta = 0)",
        f"(feed: {feed_mm_min:g} mm/min)",
    ]
    if with_z:
        lines.append(
            f"(Z moves: safe height {safe_z_mm:g} mm, cutting depth {cut_z_mm:g} mm,"
            f" plunge feed {plunge_feed_mm_min:g} mm/min)"
        )
    else:
        lines.append("(2D contour: no Z words; set the cutting depth before cycle start)")
    lines += [
        "G21 (millimetres)",
        "G17 (XY plane)",
        "G90 (absolute coordinates)",
        "G40 (cutter compensation off)",
        "G94 (feed per minute)",
    ]

    def xy(x: float, y: float) -> str:
        return f"X{x:.{k}f} Y{y:.{k}f}"

    for i, (path, (start, end, centre, ccw)) in enumerate(zip(paths, leads, strict=True)):
        if path.label:
            lines.append(f"(cam {path.label})")
        if with_z:
            lines.append(f"G00 Z{safe_z_mm:.{k}f}")
        lines.append(f"G00 {xy(*start)} (lead-in start)")
        if with_z:
            lines.append(f"G01 Z{cut_z_mm:.{k}f} F{plunge_feed_mm_min:g} (plunge)")
        g = "G03" if ccw else "G02"
        p0 = (float(path.x0_mm[0]), float(path.y0_mm[0]))
        ci, cj = centre[0] - start[0], centre[1] - start[1]
        lines.append(f"{g} {xy(*p0)} I{ci:.{k}f} J{cj:.{k}f} F{feed_mm_min:g} (lead-in)")
        for j in range(path.blocks):
            to = xy(path.x1_mm[j], path.y1_mm[j])
            if path.is_arc[j]:
                ci = path.centre_x_mm[j] - path.x0_mm[j]
                cj = path.centre_y_mm[j] - path.y0_mm[j]
                lines.append(f"{'G03' if path.ccw[j] else 'G02'} {to} I{ci:.{k}f} J{cj:.{k}f}")
            else:
                lines.append(f"G01 {to}")
        ci, cj = centre[0] - p0[0], centre[1] - p0[1]
        lines.append(f"{g} {xy(*end)} I{ci:.{k}f} J{cj:.{k}f} (lead-out)")
        if with_z:
            lines.append(f"G00 Z{safe_z_mm:.{k}f} (retract)")
        if i + 1 < len(paths):
            lines.append(f"M00 (cam {paths[i + 1].label} next: set it up, then cycle start)")
    lines += ["M30 (end of program)", "%"]
    return GcodeProgram(
        "\n".join(lines) + "\n",
        tuple(paths),
        mode,
        tolerance_mm,
        r,
        worst,
        feed_mm_min=feed_mm_min,
        lead_radius_mm=lead,
        safe_z_mm=safe_z_mm,
        cut_z_mm=cut_z_mm,
        plunge_feed_mm_min=plunge_feed_mm_min,
    )


_WORD = re.compile(r"([A-Z])\s*([-+]?\d*\.?\d+(?:[eE][-+]?\d+)?)")


def read_gcode(text: str) -> list[GcodePath]:
    """Read contours back from G-code (G00 rapid starts a contour; G01/G02/G03 cut).

    Only what :func:`write_gcode` writes is understood: absolute XY, arc centres by I, J
    relative to the block start, comments in parentheses or after ``;``. Blocks marked
    ``(lead-in)`` or ``(lead-out)`` move the tool but are not part of the contour; Z-only
    blocks (retract, plunge) are skipped.

    Parameters
    ----------
    text : str
        The program.

    Returns
    -------
    list of GcodePath
        One per contour. The arc centre is taken as the block start + (I, J), as a
        controller does. [mm]

    Raises
    ------
    InputFileError
        A motion block without coordinates, or G91 (incremental) mode.
    """
    paths: list[GcodePath] = []
    cur: list[tuple[float, float, float, float, float, float, bool, bool]] = []
    x = y = math.nan
    motion = 0

    def close() -> None:
        if cur:
            a = np.array(cur, dtype=float)
            paths.append(
                GcodePath(
                    "",
                    a[:, 0],
                    a[:, 1],
                    a[:, 2],
                    a[:, 3],
                    a[:, 4],
                    a[:, 5],
                    a[:, 6].astype(bool),
                    a[:, 7].astype(bool),
                )  # fmt: skip
            )
            cur.clear()

    for lineno, raw in enumerate(text.splitlines(), start=1):
        lead = "(lead-in)" in raw or "(lead-out)" in raw
        line = re.sub(r"\(.*?\)", "", raw).split(";")[0].upper()
        words = dict(_WORD.findall(line))
        gs = [int(float(v)) for k, v in _WORD.findall(line) if k == "G"]
        if 91 in gs:
            raise InputFileError(f"G-code line {lineno}: G91 (incremental) is not supported")
        for g in gs:
            if g in (0, 1, 2, 3):
                motion = g
        if "X" not in words and "Y" not in words:
            continue
        nx = float(words.get("X", x))
        ny = float(words.get("Y", y))
        if motion == 0:
            close()
        elif math.isnan(x):
            raise InputFileError(f"G-code line {lineno}: a cutting move before any position")
        elif lead:
            pass
        elif motion == 1:
            cur.append((x, y, nx, ny, math.nan, math.nan, False, False))
        else:
            ci, cj = float(words.get("I", 0.0)), float(words.get("J", 0.0))
            cur.append((x, y, nx, ny, x + ci, y + cj, motion == 3, True))
        x, y = nx, ny
    close()
    return paths


def _sample_blocks(path: GcodePath, per_block: int) -> tuple[FloatArray, FloatArray]:
    """Points along every block, including its interior."""
    u = np.linspace(0.0, 1.0, per_block + 1)[None, :]
    x0, y0 = path.x0_mm[:, None], path.y0_mm[:, None]
    x1, y1 = path.x1_mm[:, None], path.y1_mm[:, None]
    lx, ly = x0 + u * (x1 - x0), y0 + u * (y1 - y0)
    cx, cy = path.centre_x_mm[:, None], path.centre_y_mm[:, None]
    r = np.hypot(x0 - cx, y0 - cy)  # radius from the start, as a controller takes it
    a0 = np.arctan2(y0 - cy, x0 - cx)
    a1 = np.arctan2(y1 - cy, x1 - cx)
    ccw = path.ccw[:, None]
    sweep = np.where(ccw, np.mod(a1 - a0, TWO_PI), -np.mod(a0 - a1, TWO_PI))
    ang = a0 + u * sweep
    ax, ay = cx + r * np.cos(ang), cy + r * np.sin(ang)
    arc = path.is_arc[:, None]
    return np.where(arc, ax, lx).ravel(), np.where(arc, ay, ly).ravel()


def path_deviation(
    path: GcodePath, design: CamDesign, tool_radius_mm: float, *, per_block: int = 16
) -> float:
    """Largest distance from the analytic cutter path of points along every block. [mm]

    The analytic path is sampled every 0.002° and the distance of each block point to
    that dense polyline is taken (the polyline's own chord error is below 1e-7 mm for any
    cam of radius under 1 m).

    Parameters
    ----------
    path : GcodePath
        A contour, e.g. from :func:`read_gcode`.
    design : CamDesign
        A single-cam design.
    tool_radius_mm : float
        Offset of the path. [mm]
    per_block : int
        Points per block (both ends included).

    Returns
    -------
    float
        max distance. [mm]
    """
    from scipy.spatial import cKDTree

    theta = np.linspace(0.0, TWO_PI, 180_000, endpoint=False)
    ref = profile_path(design, theta, offset_mm=tool_radius_mm)
    rx, ry = ref.x_mm, ref.y_mm
    px, py = _sample_blocks(path, per_block)
    _, i = cKDTree(np.column_stack([rx, ry])).query(np.column_stack([px, py]))
    best = np.full(px.size, np.inf)
    for j in (i - 1, i):
        a, b = np.mod(j, rx.size), np.mod(j + 1, rx.size)
        sx, sy = rx[b] - rx[a], ry[b] - ry[a]
        u = np.clip(((px - rx[a]) * sx + (py - ry[a]) * sy) / (sx * sx + sy * sy), 0.0, 1.0)
        best = np.minimum(best, np.hypot(px - rx[a] - u * sx, py - ry[a] - u * sy))
    return float(best.max())
