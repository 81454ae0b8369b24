"""One dynamics study from its inputs: what ``camtol dynamics`` computes (THEORY §9).

:class:`DynamicsInputs` holds what the command line gives (speed, train overrides, grid,
the as-made cam: a cutting step or a CMM scan); :func:`run_dynamics` builds the train and
the lift, solves the periodic steady state, the contact forces, torque and stress, the
residual vibration, the jump speed and, above it, the separations.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.dynamics.jump import Separation, jump_speed_rpm, separations
from camtol.dynamics.lift import CamLift, cut_lift, nominal_lift, scan_lift
from camtol.dynamics.steady import (
    DwellVibration,
    SteadyState,
    as_made_bound,
    check_rpm,
    residual_vibration,
    steady_state,
)
from camtol.dynamics.stress import CamContact, cam_contacts, camshaft_torque_nm
from camtol.dynamics.train import FollowerTrain, follower_train
from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = ["DEFAULT_STEP_DEG", "DynamicsInputs", "DynamicsResult", "run_dynamics", "study_lift"]

#: Grid step of a study of the nominal cam or a scan. [deg]
DEFAULT_STEP_DEG = 0.1


@dataclass(frozen=True)
class DynamicsInputs:
    """What one dynamics study needs besides the design.

    Attributes
    ----------
    rpm : float or None
        Cam speed (None: the design's ``operation.speed_rpm``). [rpm]
    overrides : mapping of str to object
        ``[dynamics]`` fields given on the command line (file units), overriding the
        table's.
    step_deg : float or None
        Grid step (None: 0.1°, or δ/20 and at most 0.1° with a cutting step). [deg]
    cut_step_deg : float or None
        The as-made cam cut every δ (THEORY §6.3). [deg]
    tool : {"flat", "cylinder"}
        The cutting tool.
    tool_radius_mm : float
        Cylinder radius. [mm]
    points_path : str or None
        The as-made cam as a CMM scan, registered as ``camtol inspect`` does.
    stylus_radius_mm : float
        Stylus-ball radius of the scan (0: surface points). [mm]
    harmonics : int
        Fourier cut-off of the scan's smoothing (THEORY §9.6).
    revolutions : int
        Revolutions integrated above the jump speed.
    """

    rpm: float | None = None
    overrides: Mapping[str, Any] = field(default_factory=dict)
    step_deg: float | None = None
    cut_step_deg: float | None = None
    tool: Literal["flat", "cylinder"] = "flat"
    tool_radius_mm: float = 0.0
    points_path: str | None = None
    stylus_radius_mm: float = 0.0
    harmonics: int = 100
    revolutions: int = 3

    def __post_init__(self) -> None:
        if self.cut_step_deg is not None and self.points_path is not None:
            raise DesignError("--cut-step and --points are two as-made cams: give one of them")


@dataclass(frozen=True)
class DynamicsResult:
    """A design's follower at speed: forces, torque, stress, vibration, jump (THEORY §9).

    Attributes
    ----------
    design_name : str
        The design.
    train : FollowerTrain
        The follower train.
    lift : CamLift
        The lift that drove it (nominal or as made).
    steady : SteadyState
        The periodic motion with contact kept.
    contacts : tuple of CamContact
        Normal force and stress of each cam.
    torque_nm : ndarray
        Camshaft torque over the grid. [N·m]
    residual : tuple of DwellVibration
        Residual vibration per dwell.
    jump_speed_rpm : float or None
        Lowest speed at which the follower leaves the cam (None: form-closed, or none
        found). [rpm]
    separations : tuple of Separation
        Flights at this speed (none below the jump speed).
    as_made_bound : float or None
        Bound on the change of the train force that the as-made lift error can cause
        (THEORY §9.6; None for the nominal cam or a rigid train). [N, or N·m]
    """

    design_name: str
    train: FollowerTrain
    lift: CamLift
    steady: SteadyState
    contacts: tuple[CamContact, ...]
    torque_nm: FloatArray
    residual: tuple[DwellVibration, ...]
    jump_speed_rpm: float | None
    separations: tuple[Separation, ...]
    as_made_bound: float | None = None

    @property
    def rpm(self) -> float:
        """Cam speed. [rpm]"""
        return self.steady.rpm

    @property
    def oscillating(self) -> bool:
        """True when the lift is an angle."""
        return self.train.output == "oscillating"

    @property
    def contact_force_n(self) -> FloatArray:
        """The normal force the cams carry (a pair: the one cam that carries it). [N]"""
        return np.asarray(np.sum([c.normal_force_n for c in self.contacts], axis=0))

    @property
    def hertz_stress_mpa(self) -> FloatArray | None:
        """Hertz stress at the loaded contact (None without a face width). [MPa]"""
        parts = [c.hertz_stress_mpa for c in self.contacts]
        if any(p is None for p in parts):
            return None
        return np.asarray(np.max([p for p in parts if p is not None], axis=0))

    @property
    def residual_vibration(self) -> float | None:
        """Largest residual vibration over the dwells (None: no dwell). [mm, or rad]"""
        if not self.residual:
            return None
        return max(r.amplitude for r in self.residual)


def _default_step(inputs: DynamicsInputs) -> float:
    if inputs.step_deg is not None:
        return inputs.step_deg
    if inputs.cut_step_deg is not None:
        from camtol.manufacturing.cutting import default_read_step_deg

        return default_read_step_deg(inputs.cut_step_deg)
    return DEFAULT_STEP_DEG


def study_lift(design: CamDesign, inputs: DynamicsInputs) -> CamLift:
    """Return the lift the inputs name: the design's, a cut cam's or a scanned cam's.

    Parameters
    ----------
    design : CamDesign
        A single-cam design for an as-made cam.
    inputs : DynamicsInputs
        The study's inputs.

    Returns
    -------
    CamLift
    """
    step = _default_step(inputs)
    as_made = inputs.cut_step_deg is not None or inputs.points_path is not None
    if as_made and len(design.cams()) > 1:
        raise DesignError(
            "--cut-step/--points: the as-made dynamics of a conjugate pair need both cams"
            " as made; give a single-cam design"
        )
    if inputs.cut_step_deg is not None:
        return cut_lift(
            design,
            step,
            inputs.cut_step_deg,
            tool=inputs.tool,
            tool_radius_mm=inputs.tool_radius_mm,
        )
    if inputs.points_path is not None:
        from camtol.inspection.cmm import read_scan
        from camtol.inspection.deviations import cam_profile, inspect_scan, profile_tolerance

        scan = read_scan(inputs.points_path, stylus_radius_mm=inputs.stylus_radius_mm)
        profile = cam_profile(design, "A")
        # the scan's verdict is not used here: a design without a profile tolerance gets
        # a nominal band, which also keeps inspect's check that it is a scan of this cam
        tol = None if profile_tolerance(design, "A") is not None else (-1.0, 1.0)
        insp = inspect_scan(design, scan, tolerance_um=tol, profile=profile)
        return scan_lift(
            design, step, insp, harmonics=inputs.harmonics, source_name=Path(scan.source).name
        )
    return nominal_lift(design, step)


def run_dynamics(design: CamDesign, inputs: DynamicsInputs) -> DynamicsResult:
    """Study a design's follower at speed, nominal or as made (THEORY §9).

    Parameters
    ----------
    design : CamDesign
        The design; its ``[dynamics]`` table (with ``inputs.overrides``) gives the train.
    inputs : DynamicsInputs
        Speed, grid and the as-made cam.

    Returns
    -------
    DynamicsResult

    Raises
    ------
    DesignError
        No speed (neither ``rpm`` nor ``operation.speed_rpm``), a train field missing or
        out of range, a table that does not apply to the design, a grid that does not
        resolve the train's resonance at this speed, or a rigid train on a cut cam.
    """
    from camtol.analysis.validity import check_design_geometry
    from camtol.pair.kinematics import is_pair

    if inputs.rpm is None and design.speed_rpm is None:
        raise DesignError(
            "--rpm is missing: give the cam speed, or operation.speed_rpm in the design"
        )
    speed = inputs.rpm if inputs.rpm is not None else design.speed_rpm
    rpm = check_rpm(speed if speed is not None else math.nan)
    pair = is_pair(design)
    train = follower_train(design, inputs.overrides, form_closed=pair)
    check_design_geometry(design)
    lift = study_lift(design, inputs)
    steady = steady_state(train, lift, rpm)
    contacts = cam_contacts(design, lift, train, steady.train_force)
    torque = camshaft_torque_nm(train, steady.train_force, lift.velocity)
    try:
        jump = jump_speed_rpm(train, lift)
    except DesignError as exc:  # below the speeds searched: the study at rpm still stands
        import warnings

        warnings.warn(f"jump speed not found: {exc}", stacklevel=2)
        jump = None
    seps = separations(train, lift, steady, revolutions=inputs.revolutions)
    return DynamicsResult(
        design_name=design.name,
        train=train,
        lift=lift,
        steady=steady,
        contacts=contacts,
        torque_nm=torque,
        residual=residual_vibration(train, lift, steady),
        jump_speed_rpm=None if jump is None or not math.isfinite(jump) else jump,
        separations=seps,
        as_made_bound=as_made_bound(train, lift, rpm),
    )
