r"""Cutting simulation: the cam a tool set at discrete cam angles leaves (THEORY §6.3, §5).

The tool is set at the cam angles θ_k = kδ, touching the design profile at A_k with
outward normal N_k:

- **flat tool** (shaper, face of a grinding wheel; Popa's "by cutting"): each setting
  removes the half-plane beyond the tangent line, so the cam is the intersection of the
  half-planes {X : N_k·X ≤ N_k·A_k}, a polygon whose vertices are the intersections of
  consecutive lines. It needs a convex profile.
- **cylindrical tool** of radius R (end mill, grinding wheel, wire-EDM wire with R = wire
  radius + spark gap): each setting removes the disk of radius R centred on the cutter
  path C_k = A_k + R N_k (for a roller follower, the pitch curve offset by R − r_f); the cam
  is the blank minus the disks, a polygon of concave circular arcs joined at the cusps
  P_k, the inner intersections of consecutive tool circles. R must not exceed any concave
  radius of curvature of the profile (the tool would gouge) and consecutive disks must
  overlap.

The follower's motion on the cut cam is then computed exactly with the contact engine
(:func:`camtol.contact.follow`, THEORY §5) at a reading step finer than the cuts (default
δ/20, never coarser than 0.1°: at Popa's reading step of 1° the cut vertices can coincide
with the readings and hide the error). The scallop (cusp) height is the distance of each
cusp from the design profile; for a flat tool it follows the rule

.. math:: h ≈ \frac{ρ δ_n^2}{8}

with ρ the profile's radius of curvature and δ_n the angle between the normals of
consecutive cuts (δ_n = δ for a translating flat-faced follower). On Popa's eccentric
circle (r = 30 mm) the flat-tool lift error midway between cuts is exactly
r(sec(δ/2) − 1): 4.57 µm at δ = 2°, 28.6 µm at 5° (27.4 µm where a 1° reading grid
falls, 0.5° from the midpoint), 114.6 µm at 10°. A cylindrical tool leaves
h ≈ (ρδ_n²/8)(1 + ρ/R) on a convex profile.

References
----------
.. [Pop] D. Popa, "The influence of cams external groove in cam-follower mechanism
   functioning", University of Pitesti.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np

from camtol.analysis.profile import MAX_TOOL_RADIUS_MM
from camtol.contact import PolygonShape, follow
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError
from camtol.grid import check_step
from camtol.jet import FloatArray
from camtol.manufacturing.toolpath import check_gouge, profile_path

__all__ = [
    "CANDIDATE_STEPS_DEG",
    "TOOLS",
    "CutCam",
    "CutResult",
    "ToolKind",
    "coarsest_cut_step",
    "cut_cam",
    "default_read_step_deg",
    "max_abs_acceleration",
    "simulate_cut",
]

ToolKind = Literal["flat", "cylinder"]
TOOLS: tuple[str, ...] = get_args(ToolKind)
TWO_PI = 2.0 * math.pi
#: Cut steps tried by :func:`coarsest_cut_step`: divisors of 360° from 0.25° to 30°. [deg]
CANDIDATE_STEPS_DEG: tuple[float, ...] = (
    0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 9.0, 10.0, 12.0, 15.0, 20.0, 30.0
)  # fmt: skip


@dataclass(frozen=True)
class CutCam:
    """The cam left by a tool set at the angles kδ.

    Attributes
    ----------
    cut_step_deg : float
        Cutting step δ. [deg]
    tool : {"flat", "cylinder"}
        Tool kind.
    tool_radius_mm : float
        Cylinder radius R (0 for a flat tool). [mm]
    shape : PolygonShape
        The cut cam (straight edges for a flat tool, concave arcs for a cylinder). [mm]
    cut_theta_rad : ndarray
        Cam angles of the cuts. [rad]
    cusp_x_mm, cusp_y_mm : ndarray
        Cusp k between cuts k and k+1 (the polygon's vertices). [mm]
    normal_turn_rad : ndarray
        Angle δ_n between the profile normals of cuts k and k+1. [rad]
    """

    cut_step_deg: float
    tool: str
    tool_radius_mm: float
    shape: PolygonShape
    cut_theta_rad: FloatArray
    cusp_x_mm: FloatArray
    cusp_y_mm: FloatArray
    normal_turn_rad: FloatArray


@dataclass(frozen=True)
class CutResult:
    """The follower's exact motion on a cut cam against the design (THEORY §6.3).

    Attributes
    ----------
    cut : CutCam
        The cut cam.
    read_step_deg : float
        Reading step. [deg]
    theta_rad : ndarray
        Reading angles. [rad]
    lift_error : ndarray
        S_cut − S_design at the readings. [mm, or rad for an oscillating follower]
    velocity_error, acceleration_error : ndarray
        Exact one-sided V and A on the cut cam minus the design's (the follower's
        velocity jumps at every vertex of a polygon). [per rad^k]
    central_acceleration_error : ndarray
        Second differences of the read lift minus the design's A. [per rad²]
    scallop_height_mm : ndarray
        Distance of each cusp outside the design profile. [mm]
    rule_mm : ndarray
        ρ δ_n²/8 at each cusp (ρ of the profile at the cusp's foot point). [mm]
    oscillating : bool
        True when the lift is an angle (errors in rad internally, deg in reports).
    velocity_jump : ndarray
        The follower's velocity jump V(θ⁺) − V(θ⁻) at each change of the contact feature
        between consecutive readings (a cusp or vertex passed): an acceleration impulse of
        that size. Estimated from the one-sided values either side, V_k+1 − V_k −
        (A_k + A_k+1)h/2, exact to O(h²). [per rad]
    jump_theta_rad : ndarray
        Where each jump happens (midway between the two readings). [rad]
    """

    cut: CutCam
    read_step_deg: float
    theta_rad: FloatArray
    lift_error: FloatArray
    velocity_error: FloatArray
    acceleration_error: FloatArray
    central_acceleration_error: FloatArray
    scallop_height_mm: FloatArray
    rule_mm: FloatArray
    oscillating: bool
    velocity_jump: FloatArray = field(default_factory=lambda: np.zeros(0))
    jump_theta_rad: FloatArray = field(default_factory=lambda: np.zeros(0))

    @property
    def max_velocity_jump(self) -> float:
        """Largest |velocity jump| at a cusp (0 when the contact never switches). [per rad]"""
        return float(np.max(np.abs(self.velocity_jump))) if self.velocity_jump.size else 0.0

    def meets(
        self, a_max: float, lift_tolerance: float | None, accel_budget_pct: float | None
    ) -> bool:
        """Whether this cut meets a lift tolerance and/or a second-difference A budget.

        Parameters
        ----------
        a_max : float
            The design's max |A|, the reference of the budget. [per rad²]
        lift_tolerance : float, optional
            Largest |lift error|. [mm, or rad for an oscillating follower]
        accel_budget_pct : float, optional
            Largest |A_central − A| in percent of ``a_max``. [%]

        Returns
        -------
        bool
        """
        good = True
        if lift_tolerance is not None:
            good &= float(np.max(np.abs(self.lift_error))) <= lift_tolerance
        if accel_budget_pct is not None:
            worst = float(np.max(np.abs(self.central_acceleration_error)))
            good &= worst <= accel_budget_pct / 100.0 * a_max
        return good

    @property
    def lift_error_display(self) -> FloatArray:
        """Lift error in µm (translating) or degrees (oscillating). [um or deg]"""
        return self.lift_error * (180.0 / math.pi if self.oscillating else 1e3)

    @property
    def lift_error_unit(self) -> str:
        """``"um"`` or ``"deg"``."""
        return "deg" if self.oscillating else "um"


def max_abs_acceleration(design: CamDesign) -> float:
    """Return the design's max |A| on a 0.1° grid, the reference of an acceleration budget.

    Parameters
    ----------
    design : CamDesign
        A single-cam design.

    Returns
    -------
    float
        max |A|. [mm/rad², or rad/rad² for an oscillating follower]
    """
    fine = np.linspace(0.0, TWO_PI, 3600, endpoint=False)
    return float(np.max(np.abs(design.program.evaluate(fine).acceleration)))


def default_read_step_deg(cut_step_deg: float) -> float:
    """Default reading step: δ/20, never coarser than 0.1°. [deg]

    Parameters
    ----------
    cut_step_deg : float
        Cutting step δ. [deg]

    Returns
    -------
    float
        min(δ/20, 0.1). [deg]
    """
    return min(cut_step_deg / 20.0, 0.1)


def _check_tool(tool: str, tool_radius_mm: float) -> None:
    if tool not in TOOLS:
        raise DesignError(f"tool={tool!r} is unknown; allowed: {', '.join(TOOLS)}")
    if tool == "cylinder" and not (0 < tool_radius_mm <= MAX_TOOL_RADIUS_MM):
        raise DesignError(
            f"tool_radius_mm={tool_radius_mm:g} is not allowed; a cylindrical tool needs a"
            f" positive radius of at most {MAX_TOOL_RADIUS_MM:g} mm (wire EDM: wire radius +"
            " spark gap)"
        )


def cut_cam(
    design: CamDesign,
    cut_step_deg: float,
    *,
    tool: ToolKind = "flat",
    tool_radius_mm: float = 0.0,
) -> CutCam:
    """Build the cam a tool set every ``cut_step_deg`` leaves (THEORY §6.3).

    Parameters
    ----------
    design : CamDesign
        A single-cam design (cams A and B of a conjugate pair are cut one at a time).
    cut_step_deg : float
        Cutting step δ; must divide 360°. [deg]
    tool : {"flat", "cylinder"}
        Tool kind.
    tool_radius_mm : float
        Cylinder radius R (wire radius + spark gap for wire EDM); ignored for a flat
        tool. [mm]

    Returns
    -------
    CutCam

    Raises
    ------
    DesignError
        A step that does not divide 360°, an unknown tool, or a non-positive radius.
    UndercutError
        The tool radius exceeds a concave radius of curvature (it would gouge; the
        message says where), or a flat tool meets a concave profile.
    GeometryError
        Consecutive tool positions leave material between them (disks do not overlap).
    """
    n = check_step(cut_step_deg, name="--cut-step", min_points=3)
    _check_tool(tool, tool_radius_mm)
    step = TWO_PI / n
    theta = np.arange(n, dtype=float) * step
    p = profile_path(design, theta)
    nx, ny = p.normal_x, p.normal_y
    turn = np.mod(np.arctan2(np.roll(ny, -1), np.roll(nx, -1)) - np.arctan2(ny, nx), TWO_PI)
    if tool == "flat":
        check_gouge(design, math.inf)  # a flat tool is an infinite radius
        if np.any(turn >= math.pi) or abs(float(np.sum(turn)) - TWO_PI) > 1e-6:
            raise GeometryError(
                f"a flat tool at {cut_step_deg:g}° steps cannot cut this profile: the normals of"
                " consecutive cuts do not turn steadily (use a finer step)"
            )
        h = nx * p.x_mm + ny * p.y_mm
        nx1, ny1, h1 = np.roll(nx, -1), np.roll(ny, -1), np.roll(h, -1)
        det = nx * ny1 - ny * nx1
        vx = (h * ny1 - ny * h1) / det
        vy = (nx * h1 - h * nx1) / det
        shape = PolygonShape(np.column_stack([vx, vy]))
        return CutCam(cut_step_deg, tool, 0.0, shape, theta, vx, vy, turn)
    r = float(tool_radius_mm)
    check_gouge(design, r)
    c = profile_path(design, theta, offset_mm=r)
    cx, cy = c.x_mm, c.y_mm
    dx, dy = np.roll(cx, -1) - cx, np.roll(cy, -1) - cy
    d = np.hypot(dx, dy)
    if np.any(d >= 2.0 * r):
        k = int(np.argmax(d))
        raise GeometryError(
            f"tool radius {r:g} mm is too small for a {cut_step_deg:g}° cutting step: the tool"
            f" positions at θ={math.degrees(theta[k]):.2f}° and the next are {d[k]:.4g} mm"
            f" apart, so material is left between them (need a radius above {d[k] / 2:.4g} mm"
            " or a finer step)"
        )
    a = np.sqrt(r * r - 0.25 * d * d)
    # Inner intersection: on the left of the travel direction (the cam's side).
    px = cx + 0.5 * dx - a * dy / d
    py = cy + 0.5 * dy + a * dx / d
    # Edge i runs from cusp i to cusp i+1 along tool circle i+1, clockwise about its centre.
    cx1, cy1 = np.roll(cx, -1), np.roll(cy, -1)
    a0 = np.arctan2(py - cy1, px - cx1)
    a1 = np.arctan2(np.roll(py, -1) - cy1, np.roll(px, -1) - cx1)
    sweep = np.mod(a1 - a0 + math.pi, TWO_PI) - math.pi
    shape = PolygonShape(np.column_stack([px, py]), np.tan(sweep / 4.0))
    return CutCam(cut_step_deg, tool, r, shape, theta, px, py, turn)


def _scallops(design: CamDesign, cut: CutCam) -> tuple[FloatArray, FloatArray]:
    """Distance of each cusp outside the profile, and ρ δ_n²/8 there. [mm]"""
    step = TWO_PI / cut.cut_theta_rad.size
    t = cut.cut_theta_rad + 0.5 * step
    x, y = cut.cusp_x_mm, cut.cusp_y_mm
    for _ in range(30):  # Newton on (P(t) − X)·P'(t) = 0 within the cut interval
        p = profile_path(design, t)
        ex, ey = p.x_mm - x, p.y_mm - y
        f = (ex * p.tx + ey * p.ty) * p.speed_mm
        # d/dt of (P − X)·P' = |P'|² + (P − X)·P''; P'' = s' T + s²/ρ N (N inward-left).
        fp = p.speed_mm**2 - (ex * p.normal_x + ey * p.normal_y) * p.speed_mm**2 / p.rho_mm
        dt = np.clip(-f / fp, -0.5 * step, 0.5 * step)
        t = np.clip(t + dt, cut.cut_theta_rad, cut.cut_theta_rad + step)
        if np.max(np.abs(dt)) < 1e-14:
            break
    p = profile_path(design, t)
    dist = -((p.x_mm - x) * p.normal_x + (p.y_mm - y) * p.normal_y)
    rule = np.abs(p.rho_mm) * cut.normal_turn_rad**2 / 8.0
    return dist, rule


def simulate_cut(
    design: CamDesign,
    cut_step_deg: float,
    *,
    tool: ToolKind = "flat",
    tool_radius_mm: float = 0.0,
    read_step_deg: float | None = None,
) -> CutResult:
    """Cut the cam and follow it exactly; errors against the design (THEORY §6.3, §5).

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    cut_step_deg : float
        Cutting step δ; must divide 360°. [deg]
    tool : {"flat", "cylinder"}
        Tool kind.
    tool_radius_mm : float
        Cylinder radius (wire radius + spark gap for wire EDM). [mm]
    read_step_deg : float, optional
        Reading step; must divide 360° and not exceed δ (default
        :func:`default_read_step_deg`). [deg]

    Returns
    -------
    CutResult

    Raises
    ------
    DesignError, UndercutError, GeometryError
        As :func:`cut_cam`, or a reading step coarser than the cutting step.

    Examples
    --------
    >>> from camtol.config.design_file import load_example
    >>> res = simulate_cut(load_example("popa-eccentric"), 2.0)
    >>> round(float(res.lift_error.max()) * 1e3, 2)  # µm: 30 (sec 1° − 1) mm
    4.57
    """
    read = default_read_step_deg(cut_step_deg) if read_step_deg is None else read_step_deg
    m = check_step(read, name="--read-step", min_points=3)
    cut = cut_cam(design, cut_step_deg, tool=tool, tool_radius_mm=tool_radius_mm)
    if read > cut_step_deg * (1 + 1e-9):
        raise DesignError(
            f"--read-step={read:g} is not allowed; it must not be coarser than the cutting"
            f" step {cut_step_deg:g}° (the readings would miss the cusps)"
        )
    h = TWO_PI / m
    theta = np.arange(m, dtype=float) * h
    nominal = design.program.evaluate(theta)
    motion = follow(cut.shape, design.mechanism, theta)
    err = motion.lift - nominal.lift
    s = motion.lift
    # Across a cusp the velocity jumps by ΔV, so the second difference there reads
    # ΔV/h: it grows as the reading step shrinks (the "A error" of a kink, not of the
    # curve). The jumps are reported with their size beside it.
    a_central = (np.roll(s, 1) + np.roll(s, -1) - 2.0 * s) / h**2
    v, a = motion.velocity, motion.acceleration
    switch = np.flatnonzero(motion.feature != np.roll(motion.feature, -1))
    nxt = (switch + 1) % m
    jump = v[nxt] - v[switch] - 0.5 * (a[switch] + a[nxt]) * h
    scallop, rule = _scallops(design, cut)
    return CutResult(
        cut=cut,
        read_step_deg=360.0 / m,
        theta_rad=theta,
        lift_error=err,
        velocity_error=motion.velocity - nominal.velocity,
        acceleration_error=motion.acceleration - nominal.acceleration,
        central_acceleration_error=a_central - nominal.acceleration,
        scallop_height_mm=scallop,
        rule_mm=rule,
        oscillating=design.mechanism.output == "oscillating",
        velocity_jump=jump,
        jump_theta_rad=theta[switch] + 0.5 * h,
    )


def coarsest_cut_step(
    design: CamDesign,
    *,
    tool: ToolKind = "flat",
    tool_radius_mm: float = 0.0,
    lift_tolerance: float | None = None,
    accel_budget_pct: float | None = None,
    candidates: Sequence[float] = CANDIDATE_STEPS_DEG,
) -> float | None:
    """Coarsest cutting step whose exact simulation meets a lift tolerance and/or A budget.

    Bisection over the sorted candidate steps (the errors grow with δ); each candidate is
    simulated exactly at its default reading step.

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    tool : {"flat", "cylinder"}
        Tool kind.
    tool_radius_mm : float
        Cylinder radius. [mm]
    lift_tolerance : float, optional
        Largest |lift error|. [mm, or rad for an oscillating follower]
    accel_budget_pct : float, optional
        Largest |A_central − A| in percent of the design's max |A|. [%]
    candidates : sequence of float
        Steps to try; each must divide 360°. [deg]

    Returns
    -------
    float or None
        The coarsest candidate meeting every given criterion, or None if even the finest
        fails. [deg]

    Raises
    ------
    DesignError
        If neither criterion is given or a value is not positive.
    """
    if lift_tolerance is None and accel_budget_pct is None:
        raise DesignError("give a lift tolerance or an acceleration budget to choose a step")
    for name, val in (("lift tolerance", lift_tolerance), ("accel_budget_pct", accel_budget_pct)):
        if val is not None and not (math.isfinite(val) and val > 0):
            raise DesignError(f"{name}={val:g} is not allowed; give a positive value")
    a_max = max_abs_acceleration(design)

    def ok(step: float) -> bool:
        try:
            r = simulate_cut(design, step, tool=tool, tool_radius_mm=tool_radius_mm)
        except GeometryError:
            return False
        return r.meets(a_max, lift_tolerance, accel_budget_pct)

    steps = sorted(float(c) for c in candidates)
    lo, hi, best = 0, len(steps) - 1, None
    while lo <= hi:
        mid = (lo + hi) // 2
        if ok(steps[mid]):
            best, lo = steps[mid], mid + 1
        else:
            hi = mid - 1
    return best
