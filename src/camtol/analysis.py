"""`analyse`: everything the analytic engine says about a design, in display units.

Internal units are mm and rad (THEORY §0). Tables, files and the terminal use µm for
length errors of a translating follower, degrees for angles and for the output errors of
an oscillating follower; derivatives are per radian of cam angle, or per second when the
design gives a cam speed. :class:`Analysis` records the unit of every quantity.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import NoReturn

import numpy as np
from numpy.typing import NDArray

from camtol import iso286
from camtol.design import CamDesign, ResolvedTolerance
from camtol.engine import evaluate_engine
from camtol.errors import ErrorAnalysis, errors_from_sensitivities
from camtol.exceptions import GeometryError
from camtol.extremes import Extreme, find_extremes
from camtol.grid import check_step
from camtol.jet import FloatArray
from camtol.kinematics import Kinematics, analysis_grid, kinematics
from camtol.motion import LiftTable, MotionState
from camtol.summary import CamGeometry, MotionPeaks, cam_geometry, motion_peaks

__all__ = [
    "Analysis",
    "Curves",
    "DisplayUnits",
    "Quantity",
    "analyse",
    "analyze",
    "max_radius_mm",
]

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
    curves : Curves
        Every quantity on the grid in its display unit (a mapping computed when read).
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
    other_cams : tuple of (str, Kinematics)
        The kinematics of the design's further cams (cam B of a conjugate pair) on the
        same grid, by label; see :meth:`cam_kinematics`.
    geometry : tuple of CamGeometry
        Geometry figures of each cam of :meth:`CamDesign.cams` (one, or A and B): signed
        pressure-angle range against the limit, smallest convex and concave radii.
    motion : MotionPeaks or None
        Peak V, A, J of the nominal follower motion (per radian; SI at the design speed
        with :meth:`MotionPeaks.at_speed`).
    """

    design: CamDesign
    step_deg: float
    kinematics: Kinematics
    errors: ErrorAnalysis
    tolerances: tuple[ResolvedTolerance, ...]
    quantities: tuple[Quantity, ...]
    curves: Curves
    extremes: dict[str, tuple[Extreme, Extreme]]
    max_radius_mm: float
    travel: float
    accuracy: iso286.GradeBracket
    notes: tuple[str, ...] = ()
    other_cams: tuple[tuple[str, Kinematics], ...] = ()

    def cam_kinematics(self, label: str) -> Kinematics:
        """Kinematics of one cam of the design on the analysis grid (:meth:`CamDesign.cams`).

        Parameters
        ----------
        label : str
            ``""`` or the first cam's label for :attr:`kinematics`; ``"B"`` for cam B of a
            conjugate pair (in :attr:`other_cams`).

        Returns
        -------
        Kinematics
            That cam's kinematics (internal units).

        Raises
        ------
        KeyError
            If the design has no such cam.
        """
        for name, kin in self.other_cams:
            if name == label:
                return kin
        if label in ("", self.design.cams()[0].label):
            return self.kinematics
        raise KeyError(f"cam {label!r} is not a cam of design {self.design.name!r}")

    geometry: tuple[CamGeometry, ...] = ()
    motion: MotionPeaks | None = None

    @property
    def pressure_angle_exceeds_limit(self) -> bool:
        """True when any cam's max |φ| is beyond the design's pressure-angle limit."""
        return any(g.exceeds_pressure_angle_limit for g in self.geometry)

    @property
    def error_unit(self) -> str:
        """Display unit of ΔS: ``um`` (translating) or ``deg`` (oscillating)."""
        return DisplayUnits.of(self.design).lift

    @property
    def travel_unit(self) -> str:
        """Unit of :attr:`travel`: ``mm`` or ``deg``."""
        return "mm" if self.design.mechanism.output == "translating" else "deg"


@dataclass(frozen=True)
class DisplayUnits:
    """Display units of the output errors and the factors from internal units.

    Attributes
    ----------
    lift, velocity, acceleration : str
        Unit keys of ΔS, ΔV, ΔA: ``um``, ``um/rad`` or ``um/s``, ``um/rad2`` or
        ``um/s2`` for a translating follower; ``deg...`` for an oscillating one.
    lift_scale, velocity_scale, acceleration_scale : float
        Factors from the internal unit (mm or rad, per rad^k of cam angle) to those
        units; with a cam speed ω they include ω and ω².
    """

    lift: str
    velocity: str
    acceleration: str
    lift_scale: float
    velocity_scale: float
    acceleration_scale: float

    @classmethod
    def of(cls, design: CamDesign) -> DisplayUnits:
        """Return the display units of a design's output errors.

        Parameters
        ----------
        design : CamDesign
            The design (its follower's output and its cam speed).

        Returns
        -------
        DisplayUnits
            µm or ° for ΔS; per rad, or per s when the design gives a speed.
        """
        if design.mechanism.output == "translating":
            unit, scale = "um", 1e3
        else:
            unit, scale = "deg", 180.0 / math.pi
        omega = design.omega_rad_s
        if omega is None:
            return cls(unit, f"{unit}/rad", f"{unit}/rad2", scale, scale, scale)
        return cls(unit, f"{unit}/s", f"{unit}/s2", scale, scale * omega, scale * omega**2)


def max_radius_mm(design: CamDesign, *, step_deg: float = DEFAULT_STEP_DEG) -> float:
    """Maximum radial dimension |O2A| of the theoretical profile (THEORY §3.6). [mm]

    Sampled every ``step_deg`` and refined like every extreme of :func:`analyse`
    (:func:`~camtol.extremes.find_extremes`), so both give the same value.

    Parameters
    ----------
    design : CamDesign
        The design.
    step_deg : float
        Sampling step; the refinement locates the maximum to step/1000 or better. [deg]

    Returns
    -------
    float
        Largest radial dimension of the profile. [mm]
    """
    design = design.cams()[0].design  # the first cam's (cam A's: the tolerances' cam)
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    r = kinematics(design, theta, left_limit=left, check=False).radius_mm
    return _refined_max_radius(design, theta, r, step_deg)


def _refined_max_radius(
    design: CamDesign, theta_rad: FloatArray, radius_mm: FloatArray, step_deg: float
) -> float:
    def radius(t: FloatArray) -> dict[str, FloatArray]:
        return {"radius": kinematics(design, t, check=False).radius_mm}

    top = find_extremes(theta_rad, {"radius": radius_mm}, radius, step_deg=step_deg)["radius"][0]
    return max(top.value, float(np.nanmax(radius_mm)))


def _quantities(
    design: CamDesign, tolerances: tuple[ResolvedTolerance, ...]
) -> tuple[Quantity, ...]:
    units = DisplayUnits.of(design)
    unit, vunit, aunit = units.lift, units.velocity, units.acceleration
    mech = design.mechanism
    q = [
        Quantity("pressure_angle", "pressure angle φ", "deg"),
        Quantity("shift_angle", "shift angle λ", "deg"),
        Quantity("radius", "radial dimension |O2A|", "mm"),
        Quantity("curvature_radius", "radius of curvature ρ", "mm"),
    ]
    if mech.has_face:
        q.append(Quantity("face_contact", "contact on face u", "mm"))
    factor_unit = "-" if mech.output == "translating" else "deg/mm"
    q.append(Quantity("radial_factor", mech.radial_factor_label, factor_unit))
    for t in tolerances:
        q.append(Quantity(f"dS_{t.key}", f"ΔS_{t.key} ({t.display})", unit))
    q += [
        Quantity("dS_worst", "ΔS worst case", unit),
        Quantity("dS_rms", "ΔS RMS", unit),
        Quantity("dV_worst", "ΔV worst case", vunit),
        Quantity("dA_worst", "ΔA worst case", aunit),
    ]
    return tuple(q)


class Curves(Mapping[str, FloatArray]):
    """Every reported quantity on the grid in its display unit, computed when read.

    Nothing is stored but references to the internal-unit results, so a fine grid costs
    no second copy of every curve; each look-up returns a new array (or the kinematics'
    own array when no conversion is needed).
    """

    def __init__(
        self, design: CamDesign, kin: Kinematics, err: ErrorAnalysis, radial: FloatArray
    ) -> None:
        self._design, self._kin, self._err, self._radial = design, kin, err, radial
        keys = ["pressure_angle", "shift_angle", "radius", "curvature_radius", "radial_factor"]
        if kin.face_contact_mm is not None:
            keys.append("face_contact")
        for key in err.sources:
            keys += [f"dS_{key}", f"dV_{key}", f"dA_{key}"]
        keys += ["dS_worst", "dS_rms", "dV_worst", "dV_rms", "dA_worst", "dA_rms"]
        self._keys = tuple(keys)

    def internal(self, key: str) -> tuple[FloatArray, float]:
        """(internal-unit array, factor to the display unit) of a quantity.

        Parameters
        ----------
        key : str
            Quantity key, e.g. ``"dS_worst"``.

        Returns
        -------
        tuple of (ndarray, float)
            The curve is ``array * factor``; for a source's ΔS, ΔV, ΔA the array is its
            sensitivity and the factor includes the deviation (it may be negative).
        """
        return self._array(key), self.factor(key)

    def factor(self, key: str) -> float:
        """Factor from the internal array of :meth:`internal` to the display unit.

        Parameters
        ----------
        key : str
            Quantity key.

        Returns
        -------
        float
            Display value = internal value × factor. [display unit per internal unit]
        """
        if key not in self._keys:
            raise KeyError(key)
        deg = 180.0 / math.pi
        if key in ("pressure_angle", "shift_angle"):
            return deg
        if key in ("radius", "curvature_radius", "face_contact"):
            return 1.0
        if key == "radial_factor":
            return 1.0 if self._design.mechanism.output == "translating" else deg
        u = DisplayUnits.of(self._design)
        scale, vscale, ascale = u.lift_scale, u.velocity_scale, u.acceleration_scale
        prefix, name = key.split("_", 1)
        factor = (scale, vscale, ascale)["SVA".index(prefix[1])]
        if name in ("worst", "rms"):
            return factor
        return factor * self._err.sources[name].deviation

    def _array(self, key: str) -> FloatArray:
        if key not in self._keys:
            raise KeyError(key)
        kin, err = self._kin, self._err
        fixed = {
            "pressure_angle": kin.pressure_angle_rad,
            "shift_angle": kin.shift_angle_rad,
            "radius": kin.radius_mm,
            "curvature_radius": kin.curvature_radius_mm,
            "face_contact": kin.face_contact_mm,
            "radial_factor": self._radial,
        }
        if key in fixed:
            out = fixed[key]
            assert out is not None
            return out
        prefix, name = key.split("_", 1)
        order = "SVA".index(prefix[1])
        if name == "worst":
            return err.worst(order)
        if name == "rms":
            return err.rms(order)
        src = err.sources[name]
        return np.asarray((src.sensitivity, src.sensitivity_d1, src.sensitivity_d2)[order])

    def __getitem__(self, key: str) -> FloatArray:
        array, factor = self.internal(key)
        return array if factor == 1.0 else np.asarray(array * factor)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys)

    def __len__(self) -> int:
        return len(self._keys)


def _extremes(
    curves: Curves,
    quantities: tuple[Quantity, ...],
    evaluate: Callable[[FloatArray], Curves],
    theta_rad: FloatArray,
    step_deg: float,
) -> dict[str, tuple[Extreme, Extreme]]:
    """Extremes of the display curves, found on the internal arrays and then converted.

    Raises
    ------
    DesignError
        A quantity is NaN or infinite somewhere (found by the same search: a quantity
        whose max and min are finite is finite everywhere), naming the first such
        quantity in report order and where.
    """
    keys = [q.key for q in quantities]
    labels = {q.key: q.label for q in quantities}
    factors = {k: curves.factor(k) for k in keys}

    def values(c: Curves) -> dict[str, FloatArray]:
        return {k: c._array(k) if factors[k] != 0.0 else c[k] for k in keys}

    class _Lazy(Mapping[str, FloatArray]):  # one curve at a time, never all at once
        def __getitem__(self, key: str) -> FloatArray:
            return curves._array(key) if factors[key] != 0.0 else curves[key]

        def __iter__(self) -> Iterator[str]:
            return iter(keys)

        def __len__(self) -> int:
            return len(keys)

    def nonfinite(key: str, i: int) -> None:
        _not_finite(labels[key], float(curves[key][i]), float(theta_rad[i]))

    found = find_extremes(
        theta_rad,
        _Lazy(),
        lambda t: values(evaluate(t)),
        step_deg=step_deg,
        on_nonfinite=nonfinite,
    )
    out = {}
    for key, (hi, lo) in found.items():
        f = factors[key]
        if f == 0.0:
            out[key] = (hi, lo)
            continue
        if f < 0.0:
            hi, lo = lo, hi
        for e in (hi, lo):  # finite internal values may still overflow the display unit
            if not math.isfinite(e.value * f):
                _not_finite(labels[key], e.value * f, math.radians(e.theta_deg))
        out[key] = (
            dataclasses.replace(hi, kind="max", value=hi.value * f),
            dataclasses.replace(lo, kind="min", value=lo.value * f),
        )
    return out


def analyze(design: CamDesign, *, step_deg: float = DEFAULT_STEP_DEG) -> Analysis:
    """Analyze a design: kinematics, per-source errors, worst case, RMS and extremes.

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
    # The numbers are those of the design's first cam (cam A of a conjugate pair, whose
    # further cams are in other_cams); the Analysis keeps the design itself. Every cam is
    # checked (issue 9 item 3): a further cam that cannot work fails the analysis too.
    from camtol.validity import check_design_geometry

    # The geometry first (every cam, independent of the grid: issue 9), so an invalid
    # design fails before anything else; then one evaluation of the engine on the grid.
    check_design_geometry(design)
    cams = design.cams()
    cam = cams[0].design
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    kin, sens = evaluate_engine(cam, theta, left, check=False)
    motion = MotionState(kin.lift, kin.velocity, kin.acceleration, kin.jerk)  # every cam's
    others = tuple((c.label, _checked(c.label, c.design, theta, left, motion)) for c in cams[1:])
    # Tolerances from the grid's largest radius, confirmed below with the refined one.
    tolerances = cam.resolve_tolerances(float(np.nanmax(kin.radius_mm)))
    while True:
        err = errors_from_sensitivities(theta, left, sens, tolerances)
        curves = Curves(cam, kin, err, sens["r"].v)
        quantities = _quantities(cam, tolerances)

        def evaluate(t: FloatArray, tols: tuple[ResolvedTolerance, ...] = tolerances) -> Curves:
            k, s = evaluate_engine(cam, t, check=False)
            e = errors_from_sensitivities(t, k.left_limit, s, tols)
            return Curves(cam, k, e, s["r"].v)

        extremes = _extremes(curves, quantities, evaluate, theta, step_deg)
        rmax = max(extremes["radius"][0].value, float(np.nanmax(kin.radius_mm)))
        final = cam.resolve_tolerances(rmax)
        if [t.deviation for t in final] == [t.deviation for t in tolerances]:
            tolerances = final
            break
        tolerances = final  # the refined radius moved an IT grade to another size band
    # Every curve is finite: the extremes' search checked it (same deviations).
    quantities = _quantities(cam, tolerances)
    err = errors_from_sensitivities(theta, left, sens, tolerances)
    curves = Curves(cam, kin, err, sens["r"].v)
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
        others,
        _geometry(design, kin, others),
        motion_peaks(kin, output=design.mechanism.output, omega_rad_s=design.omega_rad_s),
    )


def _geometry(
    design: CamDesign, kin: Kinematics, other_cams: tuple[tuple[str, Kinematics], ...]
) -> tuple[CamGeometry, ...]:
    """Geometry figures of every cam of the design on the analysis grid (THEORY §2)."""
    kins = dict(other_cams)
    return tuple(
        cam_geometry(
            cam.label,
            cam.mechanism,
            kin if i == 0 else kins[cam.label],  # the analysis kinematics: the first cam's
            pressure_angle_limit_deg=design.pressure_angle_limit_deg,
        )
        for i, cam in enumerate(design.cams())
    )


def _checked(
    label: str,
    design: CamDesign,
    theta_rad: FloatArray,
    left_limit: NDArray[np.bool_],
    motion: MotionState,
) -> Kinematics:
    """Kinematics of one further cam on the analysis grid, checked, the cam named."""
    try:
        return kinematics(design, theta_rad, left_limit=left_limit, check=True, motion=motion)
    except GeometryError as exc:  # same class (UndercutError stays one), cam named
        raise type(exc)(f"cam {label}: {exc}") from None


def _not_finite(label: str, value: float, theta_rad: float) -> NoReturn:
    """Raise the DesignError of a quantity that is not finite (overflow), and where."""
    from camtol.exceptions import DesignError

    raise DesignError(
        f"{label} is {value!r} at θ={math.degrees(theta_rad):.6g}°:"
        " the computation overflows; a dimension or tolerance of the design is far"
        " outside a plausible range"
    )


#: British spelling, kept as an alias of :func:`analyze` (the one spelling of the API and
#: of the ``camtol analyze`` command).
analyse = analyze


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
