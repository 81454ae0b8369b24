"""`analyse`: everything the analytic engine says about a design, in display units.

Internal units are mm and rad (THEORY §0). Tables, files and the terminal use µm for
length errors of a translating follower, degrees for angles and for the output errors of
an oscillating follower; derivatives are per radian of cam angle, or per second when the
design gives a cam speed. :class:`Analysis` records the unit of every quantity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from camtol import iso286
from camtol.design import CamDesign, ResolvedTolerance
from camtol.errors import ErrorAnalysis, error_analysis
from camtol.extremes import Extreme, find_extremes
from camtol.grid import check_step
from camtol.jet import FloatArray
from camtol.kinematics import Kinematics, analysis_grid, kinematics
from camtol.motion import LiftTable

__all__ = ["Analysis", "Quantity", "analyse", "max_radius_mm"]

#: Default analysis grid step. [deg]
DEFAULT_STEP_DEG = 0.1


@dataclass(frozen=True)
class Quantity:
    """A reported quantity: key, label (with symbol) and display unit."""

    key: str
    label: str
    unit: str


@dataclass(frozen=True)
class Analysis:
    """Result of :func:`analyse`.

    Attributes
    ----------
    design : CamDesign
        The analysed design.
    step_deg : float
        Grid step. [deg]
    kinematics : Kinematics
        Analytic-engine kinematics on the grid.
    errors : ErrorAnalysis
        Per-source and combined errors (internal units).
    tolerances : tuple of ResolvedTolerance
        Deviations used, with how each was obtained.
    quantities : tuple of Quantity
        Reported quantities, in report order.
    curves : dict of str to ndarray
        Every quantity on the grid in its display unit.
    extremes : dict of str to (Extreme, Extreme)
        Global (max, min) of every quantity.
    max_radius_mm : float
        Maximum radial dimension of the profile. [mm]
    travel : float
        Total follower travel. [mm, or deg for an oscillating follower]
    accuracy : iso286.GradeBracket
        IT grades of the travel that bracket max |ΔS_worst| (THEORY §3.6).
    notes : tuple of str
        What the user must know to trust the numbers (e.g. a lift table's precision).
    """

    design: CamDesign
    step_deg: float
    kinematics: Kinematics
    errors: ErrorAnalysis
    tolerances: tuple[ResolvedTolerance, ...]
    quantities: tuple[Quantity, ...]
    curves: dict[str, FloatArray]
    extremes: dict[str, tuple[Extreme, Extreme]]
    max_radius_mm: float
    travel: float
    accuracy: iso286.GradeBracket
    notes: tuple[str, ...] = ()

    @property
    def error_unit(self) -> str:
        """Display unit of ΔS: ``um`` (translating) or ``deg`` (oscillating)."""
        return _units(self.design)[0]

    @property
    def travel_unit(self) -> str:
        """Unit of :attr:`travel`: ``mm`` or ``deg``."""
        return "mm" if self.design.mechanism.output == "translating" else "deg"


def _units(design: CamDesign) -> tuple[str, float, str, str, float, float]:
    """(ΔS unit, scale from internal, ΔV unit, ΔA unit, ΔV scale, ΔA scale)."""
    if design.mechanism.output == "translating":
        unit, scale = "um", 1e3
    else:
        unit, scale = "deg", 180.0 / math.pi
    omega = design.omega_rad_s
    if omega is None:
        return unit, scale, f"{unit}/rad", f"{unit}/rad2", scale, scale
    return unit, scale, f"{unit}/s", f"{unit}/s2", scale * omega, scale * omega**2


def max_radius_mm(design: CamDesign, *, step_deg: float = 0.01) -> float:
    """Maximum radial dimension |O2A| of the theoretical profile (THEORY §3.6). [mm]

    Sampled every ``step_deg`` and refined on a fine grid around the best sample.

    Parameters
    ----------
    design : CamDesign
        The design.
    step_deg : float
        Sampling step of the first pass; the refinement spans ±``step_deg`` around the
        largest sample. [deg]

    Returns
    -------
    float
        Largest radial dimension of the profile. [mm]
    """
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    kin = kinematics(design, theta, left_limit=left, check=False)
    i = int(np.nanargmax(kin.radius_mm))
    fine = theta[i] + np.linspace(-1, 1, 2001) * math.radians(step_deg)
    r = kinematics(design, fine, check=False).radius_mm
    return float(max(np.nanmax(r), kin.radius_mm[i]))


def _quantities(
    design: CamDesign, tolerances: tuple[ResolvedTolerance, ...]
) -> tuple[Quantity, ...]:
    unit, _, vunit, aunit, _, _ = _units(design)
    mech = design.mechanism
    q = [
        Quantity("pressure_angle", "pressure angle φ", "deg"),
        Quantity("shift_angle", "shift angle λ", "deg"),
        Quantity("radius", "radial dimension |O2A|", "mm"),
        Quantity("curvature_radius", "radius of curvature ρ", "mm"),
    ]
    if mech.kind.startswith("flat"):
        q.append(Quantity("face_contact", "contact on face u", "mm"))
    if mech.output == "translating":
        q.append(Quantity("radial_factor", "ΔS_r/Δr = cos λ / cos φ", "-"))
    elif mech.kind.startswith("flat"):
        q.append(Quantity("radial_factor", "ΔS_r/Δr = cos λ / u", "deg/mm"))
    else:  # oscillating roller (THEORY §3.3)
        q.append(Quantity("radial_factor", "ΔS_r/Δr = cos λ / (l cos φ)", "deg/mm"))
    for t in tolerances:
        q.append(Quantity(f"dS_{t.key}", f"ΔS_{t.key} ({t.display})", unit))
    q += [
        Quantity("dS_worst", "ΔS worst case", unit),
        Quantity("dS_rms", "ΔS RMS", unit),
        Quantity("dV_worst", "ΔV worst case", vunit),
        Quantity("dA_worst", "ΔA worst case", aunit),
    ]
    return tuple(q)


def _evaluate(
    design: CamDesign,
    tolerances: tuple[ResolvedTolerance, ...],
    theta_rad: FloatArray,
    left_limit: NDArray[np.bool_] | None = None,
    *,
    check: bool = True,
) -> tuple[Kinematics, ErrorAnalysis, dict[str, FloatArray]]:
    kin = kinematics(design, theta_rad, left_limit=left_limit, check=check)
    err = error_analysis(design, tolerances, theta_rad, left_limit=left_limit)
    unit, scale, _, _, vscale, ascale = _units(design)
    deg = 180.0 / math.pi
    radial = (
        err.sources["r"].sensitivity
        if "r" in err.sources
        else _radial_sensitivity(design, theta_rad, left_limit)
    )
    curves: dict[str, FloatArray] = {
        "pressure_angle": kin.pressure_angle_rad * deg,
        "shift_angle": kin.shift_angle_rad * deg,
        "radius": kin.radius_mm,
        "curvature_radius": kin.curvature_radius_mm,
        "radial_factor": radial if design.mechanism.output == "translating" else radial * deg,
    }
    if kin.face_contact_mm is not None:
        curves["face_contact"] = kin.face_contact_mm
    for key, src in err.sources.items():
        curves[f"dS_{key}"] = src.delta_lift * scale
        curves[f"dV_{key}"] = src.delta_velocity * vscale
        curves[f"dA_{key}"] = src.delta_acceleration * ascale
    curves["dS_worst"] = err.worst_lift * scale
    curves["dS_rms"] = err.rms_lift * scale
    curves["dV_worst"] = err.worst_velocity * vscale
    curves["dV_rms"] = err.rms_velocity * vscale
    curves["dA_worst"] = err.worst_acceleration * ascale
    curves["dA_rms"] = err.rms_acceleration * ascale
    return kin, err, curves


def _radial_sensitivity(
    design: CamDesign, theta_rad: FloatArray, left_limit: NDArray[np.bool_] | None
) -> FloatArray:
    unit_r = ResolvedTolerance("r", 1.0, "mm", "unit")
    e = error_analysis(design, (unit_r,), theta_rad, left_limit=left_limit)
    return e.sources["r"].sensitivity


def analyse(design: CamDesign, *, step_deg: float = DEFAULT_STEP_DEG) -> Analysis:
    """Analyse a design: kinematics, per-source errors, worst case, RMS and extremes.

    Parameters
    ----------
    design : CamDesign
        The design.
    step_deg : float
        Grid step; 360/step must be a whole number. [deg]

    Returns
    -------
    Analysis

    Raises
    ------
    DesignError
        Bad step, or a tolerance that cannot be resolved.
    GeometryError, UndercutError
        The design cannot produce its motion.
    """
    check_step(step_deg, name="step_deg")
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    # Check the geometry first so an invalid design fails before anything else.
    kinematics(design, theta, left_limit=left, check=True)
    rmax = max_radius_mm(design)
    tolerances = design.resolve_tolerances(rmax)
    kin, err, curves = _evaluate(design, tolerances, theta, left, check=False)  # checked above
    quantities = _quantities(design, tolerances)
    keys = [q.key for q in quantities]

    def evaluate(t: FloatArray) -> dict[str, FloatArray]:
        return {
            k: v for k, v in _evaluate(design, tolerances, t, check=False)[2].items() if k in keys
        }

    extremes = find_extremes(theta, {k: curves[k] for k in keys}, evaluate, step_deg=step_deg)
    if design.mechanism.output == "translating":
        travel = design.program.total_travel
        accuracy = iso286.grade_of_deviation(extremes["dS_worst"][0].value, travel)
    else:
        travel = math.degrees(design.program.total_travel)
        accuracy = iso286.grade_of_angle_deviation(extremes["dS_worst"][0].value, travel)
    return Analysis(
        design,
        step_deg,
        kin,
        err,
        tolerances,
        quantities,
        curves,
        extremes,
        rmax,
        travel,
        accuracy,
        _notes(design, kin),
    )


def _notes(design: CamDesign, kin: Kinematics) -> tuple[str, ...]:
    """Caveats on the numbers: a lift table's derivatives depend on its precision."""
    program = design.program
    if not isinstance(program, LiftTable):
        return ()
    oscillating = design.mechanism.output == "oscillating"
    unit, scale = ("°", 180.0 / math.pi) if oscillating else (" mm", 1.0)
    step = math.degrees(program.step_rad)
    notes = [
        f"the motion is a lift table every {step:g}°: V, A and J are the derivatives of a"
        " periodic cubic spline through it and depend on the table's precision"
        " (THEORY §1, §6.1); J jumps at every tabulated angle"
    ]
    bound = program.acceleration_noise_bound
    if bound is not None and program.resolution is not None:
        a_max = float(np.max(np.abs(kin.acceleration)))
        notes.append(
            f"the table is rounded to {program.resolution * scale:g}{unit}: rounding alone can"
            f" change the spline's A by up to 6Q/Δθ² = {bound * scale:.4g}{unit}/rad²"
            " (alternating ±Q/2; 3× the second-difference bound 2Q/Δθ² of [CDH] eq. 10.4),"
            f" against max |A| = {a_max * scale:.4g}{unit}/rad²"
            + (
                "; ΔV and ΔA are NOT reliable at this precision: tabulate with more decimals"
                if bound > 0.05 * a_max
                else ""
            )
        )
    return tuple(notes)
