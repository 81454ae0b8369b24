"""`analyse`: everything the analytic engine says about a design, in internal units.

Every result is in the internal units of THEORY §0: lengths in mm, angles in rad,
derivatives per radian of cam angle (``mm/rad``, ``rad/rad2``). :class:`Analysis`
records the unit of every quantity (:attr:`Quantity.unit`). Display units (µm, degrees,
per second at the design's cam speed) are the report layer's business
(:mod:`camtol.report.display`), so nothing here is scaled for a reader.

Why one module: it is :func:`analyse` and the result it returns. :class:`Analysis`,
:class:`Quantity` and :class:`Curves` are the shape of that result; the extremes search
(which reads :class:`Curves`' stored arrays to search a source's sensitivity, not its
product) and the loop that confirms the tolerances at the refined radius are the steps that
fill it, and :func:`max_radius_mm` is that same refined radius without an analysis.
"""

from __future__ import annotations

import contextlib
import functools
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, replace
from typing import NoReturn

import numpy as np

from camtol import iso286
from camtol.analysis.engine import evaluate_engine, shared_dwells
from camtol.analysis.errors import ErrorAnalysis, errors_from_sensitivities
from camtol.analysis.extremes import Extreme, find_extremes, overflow_error, scaled_extremes
from camtol.analysis.kinematics import Kinematics, analysis_grid, kinematics
from camtol.analysis.summary import (
    CamGeometry,
    LiftTablePrecision,
    MotionPeaks,
    cam_geometry,
    lift_table_precision,
    motion_peaks,
)
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.design.motion import MotionState
from camtol.grid import check_step
from camtol.jet import FloatArray

__all__ = [
    "Analysis",
    "Curves",
    "Quantity",
    "analyse",
    "analyze",
    "max_radius_mm",
]

#: Default analysis grid step. [deg]
DEFAULT_STEP_DEG = 0.1
#: Degrees per radian, for the ISO 286 angle table (which is in degrees). [deg/rad]
_DEG_PER_RAD = 180.0 / math.pi


@dataclass(frozen=True)
class Quantity:
    """A reported quantity: key, label (with symbol) and internal unit.

    Attributes
    ----------
    key : str
        Key in :attr:`Analysis.curves` and :attr:`Analysis.extremes`, e.g. ``"dS_worst"``.
    label : str
        Name with its symbol, e.g. ``"ΔS worst case"``.
    unit : str
        ASCII internal unit (THEORY §0): ``mm``, ``rad``, ``-``, ``rad/mm``; the output
        errors in ``mm`` (translating follower) or ``rad`` (oscillating), their
        derivatives per radian of cam angle (``mm/rad``, ``rad/rad2``).
    """

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
        Reported quantities, in report order, with their internal units.
    curves : Curves
        Every quantity on the grid in its internal unit (a mapping computed when read).
    extremes : dict of str to (Extreme, Extreme)
        Global (max, min) of every quantity of :attr:`quantities`, in its internal unit.
    max_radius_mm : float
        Maximum radial dimension of the profile. [mm]
    travel : float
        Total follower travel. [mm, or rad for an oscillating follower: :attr:`travel_unit`]
    accuracy : iso286.GradeBracket or None
        IT grades of the travel that bracket max |ΔS_worst| (THEORY §3.6); None when the
        design tolerances nothing (ΔS is then zero by construction: not an accuracy).
    notes : tuple of str
        Further caveats in words (none today; the report adds those of
        :attr:`lift_table`, see :func:`camtol.report.display.analysis_notes`).
    other_cams : tuple of (str, Kinematics)
        The kinematics of the design's further cams (cam B of a conjugate pair) on the
        same grid, by label; see :meth:`cam_kinematics`.
    geometry : tuple of CamGeometry
        Geometry figures of each cam of :meth:`CamDesign.cams` (one, or A and B): signed
        pressure-angle range against the limit, smallest convex and concave radii.
    motion : MotionPeaks or None
        Peak V, A, J of the nominal follower motion (per radian; SI at the design speed
        with :meth:`MotionPeaks.at_speed`).
    lift_table : LiftTablePrecision or None
        For a motion given as a lift table: how its precision limits V, A and J.
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
    accuracy: iso286.GradeBracket | None
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
    lift_table: LiftTablePrecision | None = None

    @property
    def pressure_angle_exceeds_limit(self) -> bool:
        """True when any cam's max |φ| is beyond the design's pressure-angle limit."""
        return any(g.exceeds_pressure_angle_limit for g in self.geometry)

    @property
    def travel_unit(self) -> str:
        """Internal unit of :attr:`travel` and of ΔS: ``mm`` or ``rad`` (oscillating)."""
        return self.design.mechanism.output_unit


def max_radius_mm(design: CamDesign, *, step_deg: float = DEFAULT_STEP_DEG) -> float:
    """Maximum radial dimension |O2A| of the theoretical profile (THEORY §3.6). [mm]

    Sampled every ``step_deg`` and refined like every extreme of :func:`analyse`
    (:func:`~camtol.analysis.extremes.find_extremes`), so both give the same value.

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
    def radius(t: FloatArray, names: frozenset[str]) -> dict[str, FloatArray]:
        return {"radius": kinematics(design, t, check=False).radius_mm}

    top = find_extremes(theta_rad, {"radius": radius_mm}, radius, step_deg=step_deg)["radius"][0]
    return max(top.value, float(np.nanmax(radius_mm)))


def _quantities(
    design: CamDesign, tolerances: tuple[ResolvedTolerance, ...]
) -> tuple[Quantity, ...]:
    out = design.mechanism.output_unit
    mech = design.mechanism
    q = [
        Quantity("pressure_angle", "pressure angle φ", "rad"),
        Quantity("shift_angle", "shift angle λ", "rad"),
        Quantity("radius", "radial dimension |O2A|", "mm"),
        Quantity("curvature_radius", "radius of curvature ρ", "mm"),
    ]
    if mech.has_face:
        q.append(Quantity("face_contact", "contact on face u", "mm"))
    q.append(Quantity("radial_factor", mech.radial_factor_label, _radial_factor_unit(design)))
    for t in tolerances:
        q.append(Quantity(f"dS_{t.key}", f"ΔS_{t.key} ({t.display})", out))
    q += [
        Quantity("dS_worst", "ΔS worst case", out),
        Quantity("dS_rms", "ΔS RMS", out),
        Quantity("dV_worst", "ΔV worst case", f"{out}/rad"),
        Quantity("dA_worst", "ΔA worst case", f"{out}/rad2"),
    ]
    return tuple(q)


def _radial_factor_unit(design: CamDesign) -> str:
    """Return the internal unit of ΔS_r/Δr: ``-`` (translating) or ``rad/mm``."""
    return "-" if design.mechanism.output == "translating" else "rad/mm"


#: Internal unit of each fixed (non-error) curve; ``radial_factor`` depends on the output.
_FIXED_UNITS = {
    "pressure_angle": "rad",
    "shift_angle": "rad",
    "radius": "mm",
    "curvature_radius": "mm",
    "face_contact": "mm",
}


class Curves(Mapping[str, FloatArray]):
    """Every reported quantity on the grid in its internal unit, computed when read.

    Nothing is stored but references to the internal results, so a fine grid costs no
    second copy of every curve: a look-up returns the kinematics' or the error
    analysis' own array, or (a source's ΔS, ΔV, ΔA: its sensitivity × its deviation) a
    new one. :meth:`scaled` gives a curve times a factor in one multiplication (what a
    display conversion needs, without an intermediate copy).

    Keys: ``pressure_angle``, ``shift_angle``, ``radius``, ``curvature_radius``,
    ``radial_factor``, ``face_contact`` (flat face), then ``dS_<source>``,
    ``dV_<source>``, ``dA_<source>`` for every source and ``dS_worst``, ``dS_rms``,
    ``dV_worst``, ``dV_rms``, ``dA_worst``, ``dA_rms``; :meth:`unit` gives each unit.
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

    def unit(self, key: str) -> str:
        """Return the internal unit of a curve (as :attr:`Quantity.unit`).

        Parameters
        ----------
        key : str
            Curve key, e.g. ``"dV_phi"``.

        Returns
        -------
        str
            ASCII unit: ``mm``, ``rad``, ``-``, ``rad/mm``; ``mm``/``rad`` for ΔS,
            per ``rad`` for ΔV and per ``rad2`` for ΔA (of cam angle).

        Raises
        ------
        KeyError
            If there is no such curve.
        """
        if key not in self._keys:
            raise KeyError(key)
        if key in _FIXED_UNITS:
            return _FIXED_UNITS[key]
        if key == "radial_factor":
            return _radial_factor_unit(self._design)
        out = self._design.mechanism.output_unit
        return (out, f"{out}/rad", f"{out}/rad2")["SVA".index(key[1])]

    def scaled(self, key: str, factor: float) -> FloatArray:
        """Return a curve times a factor, computed in one multiplication.

        Parameters
        ----------
        key : str
            Curve key.
        factor : float
            Factor applied to the internal-unit curve (e.g. to a display unit).

        Returns
        -------
        ndarray
            ``curves[key] * factor``; the stored array itself when that factor is 1 (do
            not modify it). A source's curve is its sensitivity × (deviation × factor).

        Raises
        ------
        KeyError
            If there is no such curve.
        """
        base, deviation = self._base(key)
        f = factor * deviation if deviation is not None else factor
        return base if f == 1.0 else np.asarray(base * f)

    def _deviation(self, key: str) -> float | None:
        """Return the source's deviation of a source's curve, else None (nothing computed)."""
        if key not in self._keys:
            raise KeyError(key)
        name = key.split("_", 1)[1] if key[:3] in ("dS_", "dV_", "dA_") else ""
        src = self._err.sources.get(name) if name not in ("worst", "rms") else None
        return None if src is None else src.deviation

    def _base(self, key: str, out: FloatArray | None = None) -> tuple[FloatArray, float | None]:
        """Return (stored array, the source's deviation or None); the curve is their product.

        A worst case or RMS is computed into ``out`` when given (a scan's reused array).
        """
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
            return out, None
        prefix, name = key.split("_", 1)
        order = "SVA".index(prefix[1])
        if name == "worst":
            return err.worst(order, out=out), None
        if name == "rms":
            return err.rms(order, out=out), None
        src = err.sources[name]
        sens = (src.sensitivity, src.sensitivity_d1, src.sensitivity_d2)[order]
        return np.asarray(sens), src.deviation

    def __getitem__(self, key: str) -> FloatArray:
        return self.scaled(key, 1.0)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys)

    def __len__(self) -> int:
        return len(self._keys)


class _LazyCurves(Mapping[str, FloatArray]):
    """Curves read one at a time, each computed when read (never all at once).

    A module-level class: one defined inside :func:`_extremes` is a new class object per
    call, and a class is always in a reference cycle, so its closure (the curves, hence
    every result array) outlived the analysis until the garbage collector ran.
    """

    def __init__(self, keys: list[str], read: Callable[[str], FloatArray]) -> None:
        self._keys, self._read = keys, read

    def __getitem__(self, key: str) -> FloatArray:
        return self._read(key)

    def __iter__(self) -> Iterator[str]:
        return iter(self._keys)

    def __len__(self) -> int:
        return len(self._keys)


def _extremes(
    curves: Curves,
    quantities: tuple[Quantity, ...],
    evaluate: Callable[[FloatArray, bool], Curves],
    theta_rad: FloatArray,
    step_deg: float,
) -> dict[str, tuple[Extreme, Extreme]]:
    """Extremes of the curves (internal units).

    A source's ΔS, ΔV, ΔA are its sensitivity × its deviation: the search runs on the
    sensitivity (no product array) and the extremes are then multiplied by the
    deviation, max and min swapped when it is negative.

    Raises
    ------
    DesignError
        A quantity is NaN or infinite somewhere (found by the same search: a quantity
        whose max and min are finite is finite everywhere), naming the first such
        quantity in report order and where.
    """
    labels = {q.key: q.label for q in quantities}
    factors = {q.key: curves._deviation(q.key) for q in quantities}  # a deviation, or None
    # Quantities searched on the same stored array (the radial factor is ΔS_r's
    # sensitivity) are searched once: the later takes the first one's extremes.
    keys: list[str] = []
    same: dict[str, str] = {}
    stored: dict[int, tuple[str, FloatArray]] = {}  # the array too: its id stays its own
    for q in quantities:
        if q.key.endswith(("_worst", "_rms")) or factors[q.key] == 0.0:  # computed curves
            keys.append(q.key)
            continue
        array = curves._base(q.key)[0]
        first = stored.setdefault(id(array), (q.key, array))[0]
        if first == q.key:
            keys.append(q.key)
        else:
            same[q.key] = first

    def pick(c: Curves, key: str, out: FloatArray | None = None) -> FloatArray:
        return c[key] if factors[key] == 0.0 else c._base(key, out)[0]

    # The search reads one curve at a time and is done with it before the next: the
    # computed ones (worst case, RMS) share one array instead of a fresh one each.
    scratch = np.empty(theta_rad.shape)

    def nonfinite(key: str, i: int) -> None:
        _not_finite(labels[key], float(curves[key][i]), float(theta_rad[i]))

    def values(t: FloatArray, names: frozenset[str]) -> dict[str, FloatArray]:
        # The sensitivities' θ-derivatives only when a ΔV or ΔA is among the quantities
        # refined (a kink of the worst-case ΔS, the usual second call, needs values).
        c = evaluate(t, any(k[:3] in ("dV_", "dA_") for k in names))
        return {k: pick(c, k) for k in names}

    lazy = _LazyCurves(keys, lambda key: pick(curves, key, scratch))
    found = find_extremes(theta_rad, lazy, values, step_deg=step_deg, on_nonfinite=nonfinite)
    for key, first in same.items():
        hi, lo = found[first]
        found[key] = (replace(hi, quantity=key), replace(lo, quantity=key))
    found = {q.key: found[q.key] for q in quantities}  # in report order
    # A source's extremes are its sensitivity's × its deviation (finite sensitivities × a
    # deviation may still overflow: scaled_extremes says where).
    out = {}
    for key, pair in found.items():
        f = factors[key]
        out[key] = pair if f is None or f == 0.0 else scaled_extremes(pair, f, labels[key])
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
    from camtol.analysis.validity import check_design_geometry

    # The geometry first (every cam, independent of the grid: issue 9), so an invalid
    # design fails before anything else; then one evaluation of the engine on the grid.
    check_design_geometry(design)
    cams = design.cams()
    cam = cams[0].design
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    # Only what the analysis reports: the toleranced sources with their derivatives (ΔS,
    # ΔV, ΔA), and the radial factor ∂S/∂r, a value (no tolerances: values alone).
    engine = functools.partial(
        evaluate_engine,
        cam,
        check=False,
        sources={"r", *(t.key for t in cam.tolerances)},
        derivatives=bool(cam.tolerances),
    )
    # Further cams share cam A's motion, and so its dwells (found once); the geometry
    # check above checked them as it did cam A, on a grid refined at each criterion's
    # worst point (any grid passes).
    with shared_dwells() if len(cams) > 1 else contextlib.nullcontext():
        kin, sens = engine(theta, left)
        motion = MotionState(kin.lift, kin.velocity, kin.acceleration, kin.jerk)  # every cam's
        others = tuple(
            (c.label, kinematics(c.design, theta, left_limit=left, check=False, motion=motion))
            for c in cams[1:]
        )
    # Tolerances from the grid's largest radius, confirmed below with the refined one.
    tolerances = cam.resolve_tolerances(float(np.nanmax(kin.radius_mm)))
    while True:
        err = errors_from_sensitivities(theta, left, sens, tolerances)
        curves = Curves(cam, kin, err, sens["r"].v)
        quantities = _quantities(cam, tolerances)

        def evaluate(
            t: FloatArray, derivatives: bool, tols: tuple[ResolvedTolerance, ...] = tolerances
        ) -> Curves:
            k, s = engine(t, derivatives=derivatives and bool(cam.tolerances))
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
    travel = design.program.total_travel  # [mm or rad]
    worst = extremes["dS_worst"][0].value  # [mm or rad]
    # ISO 286 tabulates µm against mm, and angles in degrees (THEORY §3.6).
    accuracy: iso286.GradeBracket | None
    if not tolerances:  # nothing toleranced: a zero ΔS says nothing of the output
        accuracy = None
    elif design.mechanism.output == "translating":
        accuracy = iso286.grade_of_deviation(worst * 1e3, travel)
    else:
        accuracy = iso286.grade_of_angle_deviation(worst * _DEG_PER_RAD, math.degrees(travel))
    return Analysis(
        design=design,
        step_deg=step_deg,
        kinematics=kin,
        errors=err,
        tolerances=tolerances,
        quantities=quantities,
        curves=curves,
        extremes=extremes,
        max_radius_mm=rmax,
        travel=travel,
        accuracy=accuracy,
        other_cams=others,
        geometry=_geometry(design, kin, others),
        motion=motion_peaks(kin, output=design.mechanism.output, omega_rad_s=design.omega_rad_s),
        lift_table=lift_table_precision(design.program, kin, output=design.mechanism.output),
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


def _not_finite(label: str, value: float, theta_rad: float) -> NoReturn:
    """Raise the DesignError of a quantity that is not finite (overflow), and where."""
    raise overflow_error(label, value, math.degrees(theta_rad))


#: British spelling, kept as an alias of :func:`analyze` (the one spelling of the API and
#: of the ``camtol analyze`` command).
analyse = analyze
