"""The lift that drives the follower train: the nominal cam, a cut cam, a scanned cam.

The dynamics of THEORY §9 take the cam's lift y = S(θ) over one revolution on a uniform
grid of N angles θ_j = 2πj/N. A :class:`CamLift` splits it in two parts that reach the
train differently (THEORY §9.6):

- the **smooth** part, whose acceleration A is known exactly (the design's program,
  THEORY §1; a CMM scan's follower motion after its stated Fourier low-pass, THEORY §5):
  it enters through the rigid-body load P + k_s S + M ω² A;
- the **rough** part ΔS, a lift error whose acceleration is unbounded (a cut polygon's
  vertices, THEORY §6.3): it enters only through the train's transfer function from lift
  to force, which a finite follower stiffness bounds. A rigid train cannot take it.

Sources: :func:`nominal_lift` (the design), :func:`cut_lift` (the polygon a flat or
cylindrical tool set every δ leaves, followed exactly by the contact engine, THEORY §5,
§6.3) and :func:`scan_lift` (a registered CMM scan, through
:func:`camtol.inspection.functional.functional_deviation`, exactly as ``camtol inspect``
computes the follower's motion on it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.design.motion import MotionProgram, SegmentProgram
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.jet import FloatArray

__all__ = ["CamLift", "LiftSource", "cut_lift", "dwell_intervals", "nominal_lift", "scan_lift"]

LiftSource = Literal["nominal", "cut", "scan"]
TWO_PI = 2.0 * math.pi
#: Finest grid of the dynamics (the FFT's size; 0.0001°). [angles]
MAX_ANGLES = 3_600_000


@dataclass(frozen=True)
class CamLift:
    """The lift over one revolution on a uniform grid, split as THEORY §9.6 says.

    Attributes
    ----------
    theta_rad : ndarray
        θ_j = 2πj/N, j = 0 .. N−1. [rad]
    lift, velocity : ndarray
        S and V of the cam as given (V one-sided where a polygon makes it jump). [mm or
        rad, per rad]
    smooth_lift, smooth_acceleration : ndarray
        S and A of the smooth part (lift = smooth_lift + rough_lift). [mm or rad, per rad²]
    rough_lift : ndarray or None
        The rough part ΔS (None: none). [mm or rad]
    nominal_lift, nominal_velocity, nominal_acceleration : ndarray
        The design's S, V, A: the contact geometry (∂S/∂n, ρ) is taken there. [per rad^k]
    source : {"nominal", "cut", "scan"}
        Where the lift comes from.
    description : str
        One line for reports, e.g. ``"cut with a flat tool every 2°"``.
    program : MotionProgram
        The design's program (exact values at any angle).
    dwells_rad : tuple of (float, float)
        Start and end of each dwell of the design's program. [rad]
    lift_error_max : float
        max |S − S_design|. [mm or rad]
    velocity_error_max : float
        max |V − V_design|. [mm/rad or rad/rad]
    """

    theta_rad: FloatArray
    lift: FloatArray
    velocity: FloatArray
    smooth_lift: FloatArray
    smooth_acceleration: FloatArray
    rough_lift: FloatArray | None
    nominal_lift: FloatArray
    nominal_velocity: FloatArray
    nominal_acceleration: FloatArray
    source: LiftSource
    description: str
    program: MotionProgram
    dwells_rad: tuple[tuple[float, float], ...]
    lift_error_max: float = 0.0
    velocity_error_max: float = 0.0

    @property
    def angles(self) -> int:
        """Number N of grid angles."""
        return int(self.theta_rad.size)

    @property
    def step_deg(self) -> float:
        """Grid step 360°/N. [deg]"""
        return 360.0 / self.angles

    @property
    def exact(self) -> bool:
        """True when the lift is the design's own (S, V, A exact at any angle)."""
        return self.source == "nominal"


def dwell_intervals(program: MotionProgram) -> tuple[tuple[float, float], ...]:
    """Return the dwells of a program as (start, end) cam angles (none for a lift table).

    Parameters
    ----------
    program : MotionProgram
        The design's program.

    Returns
    -------
    tuple of (float, float)
        Start and end of each dwell, in [0, 2π]. [rad]
    """
    if not isinstance(program, SegmentProgram):
        return ()
    return tuple((s.start_rad, s.end_rad) for s in program.segments if s.kind == "dwell")


def _grid(step_deg: float) -> FloatArray:
    n = check_step(step_deg, name="--step", min_points=16, max_points=MAX_ANGLES)
    return np.arange(n, dtype=float) * (TWO_PI / n)


def nominal_lift(design: CamDesign, step_deg: float) -> CamLift:
    """Return the design's lift on a grid of step ``step_deg`` (THEORY §1).

    Parameters
    ----------
    design : CamDesign
        The design.
    step_deg : float
        Grid step; must divide 360°. [deg]

    Returns
    -------
    CamLift
        S, V, A of the program, all smooth.
    """
    theta = _grid(step_deg)
    m = design.program.evaluate(theta)
    return CamLift(
        theta_rad=theta,
        lift=m.lift,
        velocity=m.velocity,
        smooth_lift=m.lift,
        smooth_acceleration=m.acceleration,
        rough_lift=None,
        nominal_lift=m.lift,
        nominal_velocity=m.velocity,
        nominal_acceleration=m.acceleration,
        source="nominal",
        description="nominal (the design's program)",
        program=design.program,
        dwells_rad=dwell_intervals(design.program),
    )


def cut_lift(
    design: CamDesign,
    step_deg: float,
    cut_step_deg: float,
    *,
    tool: Literal["flat", "cylinder"] = "flat",
    tool_radius_mm: float = 0.0,
) -> CamLift:
    """Return the lift of the cam a tool set every ``cut_step_deg`` leaves (THEORY §6.3).

    The cut cam is followed exactly by the contact engine (THEORY §5) at every grid
    angle (:func:`camtol.manufacturing.cutting.simulate_cut`); its error against the
    design is the rough part of the lift (THEORY §9.6).

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    step_deg : float
        Grid step; must divide 360° and not exceed a tenth of the cutting step, so that
        the kinks of the cut lift are resolved. [deg]
    cut_step_deg : float
        Cutting step δ; must divide 360°. [deg]
    tool : {"flat", "cylinder"}
        Tool kind.
    tool_radius_mm : float
        Cylinder radius (ignored for a flat tool). [mm]

    Returns
    -------
    CamLift

    Raises
    ------
    DesignError
        A grid coarser than δ/10, or what :func:`~camtol.manufacturing.cutting.cut_cam`
        refuses.
    """
    from camtol.manufacturing.cutting import simulate_cut

    theta = _grid(step_deg)
    if step_deg > cut_step_deg / 10.0 * (1 + 1e-9):
        raise DesignError(
            f"--step={step_deg:g} is not allowed with --cut-step={cut_step_deg:g}: the grid"
            f" must be at least ten times finer than the cutting step (--step"
            f" {cut_step_deg / 10.0:g} or finer) to resolve the cut cam's kinks"
        )
    cut = simulate_cut(
        design, cut_step_deg, tool=tool, tool_radius_mm=tool_radius_mm, read_step_deg=step_deg
    )
    m = design.program.evaluate(theta)
    rough = np.asarray(cut.lift_error, dtype=float)
    dv = np.asarray(cut.velocity_error, dtype=float)
    what = "a flat tool" if tool == "flat" else f"a cylindrical tool R = {tool_radius_mm:g} mm"
    return CamLift(
        theta_rad=theta,
        lift=m.lift + rough,
        velocity=m.velocity + dv,
        smooth_lift=m.lift,
        smooth_acceleration=m.acceleration,
        rough_lift=rough,
        nominal_lift=m.lift,
        nominal_velocity=m.velocity,
        nominal_acceleration=m.acceleration,
        source="cut",
        description=f"cut with {what} every {cut_step_deg:g}°",
        program=design.program,
        dwells_rad=dwell_intervals(design.program),
        lift_error_max=float(np.max(np.abs(rough))),
        velocity_error_max=float(np.max(np.abs(dv))),
    )


def scan_lift(
    design: CamDesign,
    step_deg: float,
    deviation_source: object,
    *,
    harmonics: int,
    source_name: str = "scan",
) -> CamLift:
    """Return the lift of a scanned cam: its follower motion as ``camtol inspect`` finds it.

    The scan's normal deviation Δn is smoothed by the least-squares Fourier series up to
    ``harmonics`` (the stated low-pass of :mod:`camtol.inspection.functional`) and the
    follower is moved over the smoothed cam exactly (THEORY §5): S, V and A of the
    measured cam are exact and smooth, so the whole lift is the smooth part.

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    step_deg : float
        Grid step; must divide 360°. [deg]
    deviation_source : CmmInspection or FourierError
        A registered scan (:func:`camtol.inspection.deviations.inspect_scan`) or the
        normal error Δn(t) itself. [mm]
    harmonics : int
        Fourier cut-off of the smoothing of a scan.
    source_name : str
        The scan's name, for the description.

    Returns
    -------
    CamLift
    """
    from camtol.inspection.deviations import cam_profile
    from camtol.inspection.functional import functional_deviation

    theta = _grid(step_deg)
    profile = cam_profile(design, "A")
    func = functional_deviation(
        profile,
        deviation_source,  # type: ignore[arg-type]
        step_deg=step_deg,
        harmonics=harmonics,
    )
    m = design.program.evaluate(theta)
    ds, dv, da = func.ds_measured, func.dv_measured, func.da_measured
    return CamLift(
        theta_rad=theta,
        lift=m.lift + ds,
        velocity=m.velocity + dv,
        smooth_lift=m.lift + ds,
        smooth_acceleration=m.acceleration + da,
        rough_lift=None,
        nominal_lift=m.lift,
        nominal_velocity=m.velocity,
        nominal_acceleration=m.acceleration,
        source="scan",
        description=f"CMM scan {source_name} (Δn smoothed to {func.harmonics} harmonics)",
        program=design.program,
        dwells_rad=dwell_intervals(design.program),
        lift_error_max=float(np.max(np.abs(ds))),
        velocity_error_max=float(np.max(np.abs(dv))),
    )
