"""The contact engine checks the analytic engine on one cam (THEORY §5; ``camtol verify``).

Three checks, each against exact contact geometry (no linearisation, no stepping):

1. Round trip: the profile synthesised by THEORY §2 is handed to the contact engine with
   the nominal follower; the follower's exact motion must reproduce S(θ) to 1e-9 (mm, or
   rad for an oscillating follower).
2. Polyline: the profile as exported (:func:`camtol.analysis.profile.profile_points`, its
   default chordal tolerance) is a polygon inscribed in the curve; the follower's motion
   on it must fall short of S(θ) by the chordal sag of each chord times the output's
   sensitivity to a normal profile error (THEORY §3), no more and no less.
3. Linearisation: every toleranced error source of the design is applied at its
   tolerance to the shape (Δr, Δn: an analytic profile with the error), to the follower
   (e, φ, f, l, r_f: :meth:`~camtol.mechanisms.base.Mechanism.perturbed` on the nominal
   profile, S measured from the nominal zero) or to the design (design-level sources of
   :mod:`camtol.design.sources`, e.g. the cam's angular phase), re-simulated exactly, and
   the exact ΔS is compared with the closed form ΔS_p of THEORY §3. Repeating at half the tolerance
   shows the difference is of second order (it falls by about 4).

A conjugate pair is verified through the measuring fixture with the same checks
(:mod:`camtol.pair.verify`); :func:`camtol.verify.verify` takes any design.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camtol.analysis.errors import error_analysis
from camtol.analysis.kinematics import analysis_grid
from camtol.contact.as_made import follow_as_made
from camtol.contact.engine import follow
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.design.sources import AsMade, apply_source, can_apply
from camtol.jet import FloatArray

__all__ = [
    "LinearisationCheck",
    "PolylineCheck",
    "ROUNDTRIP_LIMIT",
    "Verification",
    "linearisation_check",
    "polyline_check",
    "verify_cam",
]

#: Largest allowed round-trip error. [mm or rad]
ROUNDTRIP_LIMIT = 1e-9
#: Largest allowed |exact − linear| as a fraction of max |linear| at the tolerance.
LINEAR_FRACTION_LIMIT = 0.01
#: A difference below this fraction of max |linear| means "linear to rounding".
EXACT_FRACTION = 1e-8


@dataclass(frozen=True)
class LinearisationCheck:
    """Closed-form (linear) against exact ΔS for one error source at its tolerance.

    Attributes
    ----------
    key : str
        Tolerance key.
    deviation : float or None
        Δp applied (None for the fixture's combined cases). [mm, or rad]
    unit : str
        Unit of the three maxima (the ``analyze`` curves' unit: ``um`` or ``deg``).
    linear_max, exact_max : float
        max |ΔS| of the closed form and of the exact re-simulation. [unit]
    max_difference : float
        max |exact − linear|. [unit]
    half_difference : float
        The same at half the tolerance. [unit]
    exact_to_rounding : bool
        The closed form is exact for this source (difference at rounding level), so the
        halving test does not apply.
    ok : bool
        Difference within 1 % of ``linear_max`` and, unless exact, falling by 3-5 when the
        tolerance is halved (second order).
    """

    key: str
    deviation: float | None
    unit: str
    linear_max: float
    exact_max: float
    max_difference: float
    half_difference: float
    exact_to_rounding: bool
    ok: bool

    @property
    def halving_ratio(self) -> float:
        """max_difference / half_difference: 4 for a second-order difference."""
        return self.max_difference / self.half_difference if self.half_difference else math.inf


@dataclass(frozen=True)
class PolylineCheck:
    """The exported polyline against the analytic profile.

    Attributes
    ----------
    points : int
        Vertices of the exported profile.
    chordal_tolerance_mm : float
        Export tolerance. [mm]
    chordal_sag_max_mm : float
        Largest sag of a chord (distance of the curve from it at mid-chord). [mm]
    max_error : float
        Largest S − S_polyline over the chord midpoints. [mm or rad]
    expected_max_error : float
        Largest sag × (ΔS per unit normal error). [mm or rad]
    max_deviation_from_expected : float
        max over chords of |error − expected|. [mm or rad]
    ok : bool
        Every chord's error has the sign of its expected value and exceeds it by no more
        than 10 % (it may be smaller where the contact moves to a vertex).
    """

    points: int
    chordal_tolerance_mm: float
    chordal_sag_max_mm: float
    max_error: float
    expected_max_error: float
    max_deviation_from_expected: float
    ok: bool


@dataclass(frozen=True)
class Verification:
    """Result of :func:`verify`; :meth:`to_dict` gives the ``--json`` object.

    Attributes
    ----------
    design_name, follower : str
        Design name and follower kind.
    output_unit : str
        ``mm`` (translating) or ``rad`` (oscillating): unit of the round-trip errors.
    step_deg : float
        θ grid step. [deg]
    roundtrip_max_error : float
        max |S_contact − S| over the grid. [output unit]
    roundtrip_velocity_max_error : float
        The same for V (one-sided at boundaries). [output unit per rad]
    roundtrip_acceleration_max_error : float or None
        The same for A (None where A is not simulated: the fixture). [output unit per rad²]
    polyline : PolylineCheck or None
        The exported-polyline check (None if the export is unavailable).
    linearisation : dict of str to LinearisationCheck
        One entry per toleranced source.
    notes : tuple of str
        What was done differently (e.g. a source not re-simulated), in plain words.
    """

    design_name: str
    follower: str
    output_unit: str
    step_deg: float
    roundtrip_max_error: float
    roundtrip_velocity_max_error: float
    roundtrip_acceleration_max_error: float | None
    polyline: PolylineCheck | None
    linearisation: dict[str, LinearisationCheck]
    notes: tuple[str, ...] = ()
    extras: dict[str, Any] = field(default_factory=dict)

    @property
    def roundtrip_ok(self) -> bool:
        """Round trip within :data:`ROUNDTRIP_LIMIT`."""
        return self.roundtrip_max_error <= ROUNDTRIP_LIMIT

    @property
    def ok(self) -> bool:
        """Every check passed."""
        poly_b = self.extras.get("polyline_b")
        rt_f = float(self.extras.get("roundtrip_delta_f_max_mm", 0.0))
        return (
            self.roundtrip_ok
            and rt_f <= ROUNDTRIP_LIMIT
            and (self.polyline is None or self.polyline.ok)
            and (poly_b is None or bool(poly_b["ok"]))
            and all(c.ok for c in self.linearisation.values())
        )

    def to_dict(self) -> dict[str, Any]:
        """Return the JSON object of ``camtol verify --json`` (strict JSON values)."""
        out: dict[str, Any] = {
            "design": self.design_name,
            "follower": self.follower,
            "output_unit": self.output_unit,
            "step_deg": self.step_deg,
            "ok": self.ok,
            "roundtrip_max_error": self.roundtrip_max_error,
            "roundtrip_limit": ROUNDTRIP_LIMIT,
            "roundtrip_velocity_max_error": self.roundtrip_velocity_max_error,
            "roundtrip_acceleration_max_error": self.roundtrip_acceleration_max_error,
            "polyline": None if self.polyline is None else dataclasses.asdict(self.polyline),
            "linearisation": {
                k: {**dataclasses.asdict(c), "halving_ratio": c.halving_ratio}
                for k, c in self.linearisation.items()
            },
            "notes": list(self.notes),
        }
        out.update(self.extras)
        safe: dict[str, Any] = _json_safe(out)
        return safe


def _json_safe(x: Any) -> Any:
    """Replace non-finite floats by None so that the object is strict JSON."""
    if isinstance(x, dict):
        return {k: _json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json_safe(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# ---------------------------------------------------------------------------------------
def _nominal_shape(design: CamDesign) -> AnalyticShape:
    return AnalyticShape(design.mechanism, design.program)


def _exact_delta(
    design: CamDesign,
    key: str,
    deviation: float,
    theta: FloatArray,
    left: np.ndarray[Any, np.dtype[np.bool_]],
    nominal_lift: FloatArray,
) -> FloatArray:
    """Exact ΔS of one source at ``deviation`` (internal units)."""
    as_made = apply_source(AsMade(design.mechanism), key, deviation)
    res = follow_as_made(as_made, design.mechanism, design.program, theta, left_limit=left)
    return np.asarray(res.lift - nominal_lift)


def _scale(design: CamDesign) -> tuple[str, float]:
    if design.mechanism.output == "translating":
        return "um", 1e3
    return "deg", 180.0 / math.pi


def linearisation_check(
    design: CamDesign,
    tolerances: tuple[ResolvedTolerance, ...],
    theta: FloatArray,
    left: np.ndarray[Any, np.dtype[np.bool_]],
) -> tuple[dict[str, LinearisationCheck], list[str]]:
    """Re-simulate each toleranced source exactly and compare with its closed form.

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    tolerances : tuple of ResolvedTolerance
        The deviations to apply, one source at a time. [mm or rad]
    theta : ndarray
        Cam angles. [rad]
    left : ndarray of bool
        Rows taking left limits at segment boundaries.

    Returns
    -------
    (dict of str to LinearisationCheck, list of str)
        A check per source that can be re-simulated, and a note for each that cannot.
    """
    unit, scale = _scale(design)
    nominal = design.program.evaluate(theta, left_limit=left).lift
    checks: dict[str, LinearisationCheck] = {}
    notes: list[str] = []
    for tol in tolerances:
        key = tol.key
        if not can_apply(design.mechanism, key):
            notes.append(f"source {key!r} has no exact re-simulation; not checked")
            continue
        lin = error_analysis(design, (tol,), theta, left_limit=left).sources[key].delta_lift
        ex = _exact_delta(design, key, tol.deviation, theta, left, nominal)
        half_tol = dataclasses.replace(tol, deviation=0.5 * tol.deviation)
        lin_h = error_analysis(design, (half_tol,), theta, left_limit=left).sources[key]
        ex_h = _exact_delta(design, key, half_tol.deviation, theta, left, nominal)
        lin_max = float(np.max(np.abs(lin)))
        diff = float(np.max(np.abs(ex - lin)))
        diff_h = float(np.max(np.abs(ex_h - lin_h.delta_lift)))
        exact = diff <= EXACT_FRACTION * lin_max + 1e-14
        ratio = diff / diff_h if diff_h > 0 else math.inf
        ok = diff <= LINEAR_FRACTION_LIMIT * lin_max and (exact or 3.0 <= ratio <= 5.0)
        checks[key] = LinearisationCheck(
            key=key,
            deviation=tol.deviation,
            unit=unit,
            linear_max=lin_max * scale,
            exact_max=float(np.max(np.abs(ex))) * scale,
            max_difference=diff * scale,
            half_difference=diff_h * scale,
            exact_to_rounding=bool(exact),
            ok=bool(ok),
        )
    return checks, notes


def polyline_check(design: CamDesign) -> PolylineCheck:
    """Follow the exported polyline and compare its error with the chordal sag (check 2).

    Parameters
    ----------
    design : CamDesign
        A single-cam design.

    Returns
    -------
    PolylineCheck
    """
    from camtol.analysis.profile import DEFAULT_TOLERANCE_MM, profile_points

    curve = profile_points(design).profile
    poly = PolygonShape(np.column_stack([curve.x_mm, curve.y_mm]))
    t0 = curve.theta_rad
    t1 = np.append(t0[1:], t0[0] + 2.0 * math.pi)
    mid = 0.5 * (t0 + t1)
    shape = _nominal_shape(design)
    px, py = shape.jets(np.mod(mid, 2.0 * math.pi))
    x0, y0 = curve.x_mm, curve.y_mm
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    dx, dy = x1 - x0, y1 - y0
    # Signed sag: > 0 where the curve bulges out of the chord (convex: the polyline removes
    # material), < 0 in a concave stretch (the chord adds material). The profile runs
    # counterclockwise, so an outward bulge lies to the right of the chord.
    sag = -(dx * (py.v - y0) - dy * (px.v - x0)) / np.hypot(dx, dy)
    res = follow(poly, design.mechanism, mid)
    nominal = design.program.evaluate(mid).lift
    err = nominal - res.lift
    unit_n = ResolvedTolerance("n", 1.0, "mm", "unit normal error")
    sens = error_analysis(design, (unit_n,), mid).sources["n"].sensitivity
    # The polyline is the profile with a normal error of −sag at mid-chord, if the face or
    # roller touches the chord there. Where the curvature varies along a chord (e.g. a
    # spline's piecewise-constant jerk) it touches a vertex instead and the error is
    # smaller. So: the same sign as the prediction, and never more than 10 % beyond it.
    expected = sag * sens
    dev = float(np.max(np.abs(err - expected)))
    tiny = 1e-12 + 1e-9 * float(np.max(np.abs(expected)))
    ok = bool(
        np.all(err * np.sign(expected) >= -tiny)
        and np.all(np.abs(err) <= 1.1 * np.abs(expected) + tiny)
    )
    return PolylineCheck(
        points=int(curve.x_mm.size),
        chordal_tolerance_mm=DEFAULT_TOLERANCE_MM,
        chordal_sag_max_mm=float(np.max(np.abs(sag))),
        max_error=float(np.max(np.abs(err))),
        expected_max_error=float(np.max(np.abs(expected))),
        max_deviation_from_expected=dev,
        ok=ok,
    )


def verify_cam(design: CamDesign, *, step_deg: float = 0.1, polyline: bool = True) -> Verification:
    """Verify the analytic engine of a design with the contact engine (THEORY §5).

    Parameters
    ----------
    design : CamDesign
        A single-cam design (any follower type with an exact-contact solver).
    step_deg : float
        θ grid step; segment boundaries are included as left/right rows. [deg]
    polyline : bool
        Also check the exported polyline.

    Returns
    -------
    Verification

    Raises
    ------
    GeometryError, UndercutError
        If the design cannot produce its motion (as ``analyze`` would report).
    """
    from camtol.analysis.result import max_radius_mm

    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)
    motion = design.program.evaluate(theta, left_limit=left)
    res = follow(_nominal_shape(design), design.mechanism, theta, left_limit=left)
    tolerances = design.resolve_tolerances(max_radius_mm(design))
    checks, notes = linearisation_check(design, tolerances, theta, left)
    return Verification(
        design_name=design.name,
        follower=design.mechanism.kind,
        output_unit=design.mechanism.output_unit,
        step_deg=step_deg,
        roundtrip_max_error=float(np.max(np.abs(res.lift - motion.lift))),
        roundtrip_velocity_max_error=float(np.max(np.abs(res.velocity - motion.velocity))),
        roundtrip_acceleration_max_error=float(
            np.max(np.abs(res.acceleration - motion.acceleration))
        ),
        polyline=polyline_check(design) if polyline else None,
        linearisation=checks,
        notes=tuple(notes),
    )
