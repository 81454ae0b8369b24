"""A cutting-step study: one cam cut at several steps and followed exactly (THEORY §6.3).

:func:`cut_study` is what ``camtol cut`` computes, for the Python API too: the cam chosen
by its letter, every cutting step simulated (:func:`~camtol.manufacturing.cutting.simulate_cut`),
the coarsest of those steps meeting a lift tolerance or an acceleration budget (chosen
among the steps the user listed, judged on the same simulations as the table, so the
recommendation is always a row of it), and, when asked, the lift errors of every step on
one common reading grid for a CSV.

A lift tolerance is in the follower's own unit and says so: µm for a translating
follower, degrees for an oscillating one (``lift_tolerance_unit``); the other unit is
refused rather than converted, because a tolerance typed in µm for an arm angle (or in
degrees for a slide) is a mistake, not a request.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.jet import FloatArray
from camtol.manufacturing.cutting import (
    CutResult,
    ToolKind,
    max_abs_acceleration,
    simulate_cut,
)

__all__ = ["CutStudy", "CutStudyInputs", "cut_study"]


@dataclass(frozen=True)
class CutStudyInputs:
    """What a cutting-step study is asked (``camtol cut``'s options).

    Attributes
    ----------
    cut_steps_deg : tuple of float
        Cutting steps δ; each must divide 360. [deg]
    tool : {"flat", "cylinder"}
        Flat tool (half-planes) or cylindrical tool (disks).
    tool_radius_mm : float, optional
        Radius of a cylindrical tool (wire EDM: wire radius + spark gap). [mm]
    read_step_deg : float, optional
        Step at which the cut cam is followed (default: from the cutting step). [deg]
    cam : str
        The cam's letter (``A``; ``B`` of a conjugate pair).
    lift_tolerance : float, optional
        Largest lift error for the coarsest-step search, in ``lift_tolerance_unit``.
    lift_tolerance_unit : {"um", "deg"}, optional
        The unit the tolerance was given in: ``"um"`` (translating follower, lift in
        µm) or ``"deg"`` (oscillating follower, arm angle in degrees); None takes the
        follower's own. A unit that does not fit the follower is refused.
    accel_budget_pct : float, optional
        Largest acceleration error for that search, in % of the nominal peak. [%]
    curves : bool
        Also give every step's lift error on one common reading grid.
    """

    cut_steps_deg: tuple[float, ...]
    tool: ToolKind = "flat"
    tool_radius_mm: float | None = None
    read_step_deg: float | None = None
    cam: str = "A"
    lift_tolerance: float | None = None
    accel_budget_pct: float | None = None
    curves: bool = False
    lift_tolerance_unit: str | None = None

    def __post_init__(self) -> None:
        for s in self.cut_steps_deg:
            check_step(s, name="--cut-step", min_points=3)
        if self.tool == "cylinder" and self.tool_radius_mm is None:
            raise DesignError(
                "--tool cylinder needs --tool-radius MM (wire EDM: wire radius + spark gap)"
            )
        if self.tool == "flat" and self.tool_radius_mm is not None:
            raise DesignError("--tool-radius is only allowed with --tool cylinder")
        if self.read_step_deg is not None:
            check_step(self.read_step_deg, name="--read-step", min_points=3)
            finest = min(self.cut_steps_deg)
            if self.read_step_deg > finest * (1 + 1e-9):
                raise DesignError(
                    f"--read-step={self.read_step_deg:g} is not allowed; it must not be coarser"
                    f" than the finest cutting step {finest:g}°"
                )

    @property
    def has_criteria(self) -> bool:
        """Whether a coarsest step was asked for (a lift tolerance or an acceleration budget)."""
        return self.lift_tolerance is not None or self.accel_budget_pct is not None


@dataclass(frozen=True)
class CutStudy:
    """The result of :func:`cut_study`.

    Attributes
    ----------
    design_name : str
        The design's name.
    cam : str or None
        The cam's label in a design with several cams (``A``, ``B``), else None.
    inputs : CutStudyInputs
        What was asked.
    results : tuple of CutResult
        One per cutting step, in the order asked.
    coarsest_cut_step_deg : float or None
        The coarsest of the listed cutting steps meeting the criteria (None: none does,
        or none asked). [deg]
    curves_theta_deg : ndarray or None
        The common reading grid of :attr:`curves_lift_error`. [deg]
    curves_lift_error : tuple of ndarray
        Each step's lift error on that grid, in the display unit of
        :attr:`~camtol.manufacturing.cutting.CutResult.lift_error_unit`.
    """

    design_name: str
    cam: str | None
    inputs: CutStudyInputs
    results: tuple[CutResult, ...]
    coarsest_cut_step_deg: float | None
    curves_theta_deg: FloatArray | None = None
    curves_lift_error: tuple[FloatArray, ...] = ()


def _check_tolerance_unit(inputs: CutStudyInputs, oscillating: bool) -> None:
    """Refuse a lift tolerance in the other follower kind's unit (µm vs degrees)."""
    unit = inputs.lift_tolerance_unit
    if inputs.lift_tolerance is None or unit is None:
        return
    if unit not in ("um", "deg"):
        raise DesignError(f"lift_tolerance_unit={unit!r} is not allowed; allowed: um, deg")
    if oscillating and unit == "um":
        raise DesignError(
            f"--lift-tolerance-um={inputs.lift_tolerance:g} is not allowed: the follower"
            " oscillates and its lift is an arm angle; give --lift-tolerance-deg DEG"
        )
    if not oscillating and unit == "deg":
        raise DesignError(
            f"--lift-tolerance-deg={inputs.lift_tolerance:g} is not allowed: the follower"
            " translates and its lift is a length; give --lift-tolerance-um UM"
        )


def cut_study(design: CamDesign, inputs: CutStudyInputs) -> CutStudy:
    """Cut one cam of a design at each step and follow it exactly (THEORY §6.3).

    Parameters
    ----------
    design : CamDesign
        Any design; ``inputs.cam`` picks the cam of a conjugate pair.
    inputs : CutStudyInputs
        Steps, tool, reading step and criteria.

    Returns
    -------
    CutStudy

    Raises
    ------
    DesignError
        A cam the design does not have, or a lift tolerance in the other follower
        kind's unit.
    GeometryError, UndercutError
        A tool that cannot cut the profile.
    """
    one = design.cam(inputs.cam)
    cam = one.design
    _check_tolerance_unit(inputs, cam.mechanism.output == "oscillating")
    radius = inputs.tool_radius_mm or 0.0
    results = tuple(
        simulate_cut(
            cam, s, tool=inputs.tool, tool_radius_mm=radius, read_step_deg=inputs.read_step_deg
        )
        for s in inputs.cut_steps_deg
    )
    coarsest = None
    if inputs.has_criteria:
        tol = None
        if inputs.lift_tolerance is not None:
            oscillating = results[0].oscillating
            tol = (
                math.radians(inputs.lift_tolerance) if oscillating else inputs.lift_tolerance * 1e-3
            )
        a_max = max_abs_acceleration(cam)
        good = [r.cut.cut_step_deg for r in results if r.meets(a_max, tol, inputs.accel_budget_pct)]
        coarsest = max(good) if good else None
    theta = None
    errors: tuple[FloatArray, ...] = ()
    if inputs.curves:
        common = inputs.read_step_deg or min(r.read_step_deg for r in results)
        again = [
            simulate_cut(cam, s, tool=inputs.tool, tool_radius_mm=radius, read_step_deg=common)
            for s in inputs.cut_steps_deg
        ]
        theta = np.degrees(again[0].theta_rad)
        errors = tuple(r.lift_error_display for r in again)
    return CutStudy(design.name, one.label or None, inputs, results, coarsest, theta, errors)
