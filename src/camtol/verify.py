"""`camtol verify`: the contact engine checks the analytic engine (THEORY §5).

Three checks, each against exact contact geometry (no linearisation, no stepping):

1. Round trip: the profile synthesised by THEORY §2 is handed to the contact engine with
   the nominal follower; the follower's exact motion must reproduce S(θ) to 1e-9 (mm, or
   rad for an oscillating follower).
2. Polyline: the profile as exported (:func:`camtol.profile.profile_points`, its
   default chordal tolerance) is a polygon inscribed in the curve; the follower's motion
   on it must fall short of S(θ) by the chordal sag of each chord times the output's
   sensitivity to a normal profile error (THEORY §3), no more and no less.
3. Linearisation: every toleranced error source of the design is applied at its
   tolerance to the shape (Δr, Δn: an analytic profile with the error), to the follower
   (e, φ, f, l, r_f: :meth:`~camtol.mechanisms.base.Mechanism.perturbed` on the nominal
   profile, S measured from the nominal zero) or to the design (design-level sources of
   :mod:`camtol.sources`, e.g. the cam's angular phase), re-simulated exactly, and the exact ΔS is
   compared with the closed form ΔS_p of THEORY §3. Repeating at half the tolerance
   shows the difference is of second order (it falls by about 4).

For conjugate designs the measuring fixture (THEORY §4, §5) stands in for the follower:
see :mod:`camtol.contact.fixture`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.contact.engine import follow
from camtol.contact.errors_profile import CallableError, FourierError, ProfileError
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.design import CamDesign, ResolvedTolerance
from camtol.errors import error_analysis
from camtol.jet import FloatArray, Jet
from camtol.kinematics import analysis_grid, kinematics
from camtol.sources import DESIGN_SOURCES

if TYPE_CHECKING:
    from camtol.inspection.conjugate import FixtureErrors

__all__ = [
    "LinearisationCheck",
    "PolylineCheck",
    "ROUNDTRIP_LIMIT",
    "Verification",
    "verify",
    "verify_conjugate",
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


def _exactly_simulable(design: CamDesign, key: str) -> bool:
    """Tell whether ``key`` can be re-simulated exactly (profile, parameter, design)."""
    if key in ("r", "n") or key in DESIGN_SOURCES:
        return True
    return any(s.key == key and s.parameter is not None for s in design.mechanism.sources)


def _exact_delta(
    design: CamDesign,
    key: str,
    deviation: float,
    theta: FloatArray,
    left: np.ndarray[Any, np.dtype[np.bool_]],
    nominal_lift: FloatArray,
) -> FloatArray:
    """Exact ΔS of one source at ``deviation`` (internal units)."""
    mech = design.mechanism
    dsrc = DESIGN_SOURCES.get(key)
    if dsrc is not None:
        lift = dsrc.exact_lift(mech, design.program, theta, deviation, left_limit=left)
        return np.asarray(lift - nominal_lift)
    if key in ("r", "n"):
        err = FourierError(deviation)
        shape = AnalyticShape(
            mech,
            design.program,
            radial_error=err if key == "r" else None,
            normal_error=err if key == "n" else None,
        )
        res = follow(shape, mech, theta, left_limit=left)
    else:
        res = follow(
            _nominal_shape(design),
            mech.perturbed(key, deviation),
            theta,
            reference=mech,
            left_limit=left,
        )
    return np.asarray(res.lift - nominal_lift)


def _scale(design: CamDesign) -> tuple[str, float]:
    if design.mechanism.output == "translating":
        return "um", 1e3
    return "deg", 180.0 / math.pi


def _linearisation(
    design: CamDesign,
    tolerances: tuple[ResolvedTolerance, ...],
    theta: FloatArray,
    left: np.ndarray[Any, np.dtype[np.bool_]],
) -> tuple[dict[str, LinearisationCheck], list[str]]:
    unit, scale = _scale(design)
    nominal = design.program.evaluate(theta, left_limit=left).lift
    checks: dict[str, LinearisationCheck] = {}
    notes: list[str] = []
    for tol in tolerances:
        key = tol.key
        if not _exactly_simulable(design, key):
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


def _polyline(design: CamDesign) -> PolylineCheck:
    from camtol.profile import DEFAULT_TOLERANCE_MM, profile_points

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


def verify(design: CamDesign, *, step_deg: float = 0.1, polyline: bool = True) -> Verification:
    """Verify the analytic engine of a design with the contact engine (THEORY §5).

    Parameters
    ----------
    design : CamDesign
        The design (any follower type with an exact-contact solver; conjugate pairs are
        checked through the measuring fixture).
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
    if len(design.cams()) > 1:  # both cams together: through the measuring fixture
        return verify_conjugate(design, step_deg=step_deg, polyline=polyline)
    from camtol.analysis import max_radius_mm

    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    kinematics(design, theta, left_limit=left, check=True)
    motion = design.program.evaluate(theta, left_limit=left)
    res = follow(_nominal_shape(design), design.mechanism, theta, left_limit=left)
    tolerances = design.resolve_tolerances(max_radius_mm(design))
    checks, notes = _linearisation(design, tolerances, theta, left)
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
        polyline=_polyline(design) if polyline else None,
        linearisation=checks,
        notes=tuple(notes),
    )


# ---------------------------------------------------------------------------------------
# Conjugate designs: the measuring fixture stands in for the follower (THEORY §4, §5)
# ---------------------------------------------------------------------------------------
def _fixture_inputs(
    design: CamDesign, max_radius: float
) -> tuple[dict[str, tuple[ProfileError | None, ProfileError | None, FixtureErrors]], str]:
    """Error cases to re-simulate: key → (Δr_A, Δr_B, constant errors), and their origin."""
    from camtol.inspection.conjugate import FixtureErrors

    spec = design.inspection
    if spec is not None:
        ma, mb = spec.master_a, spec.master_b
        err_a: ProfileError = CallableError(lambda t: np.asarray(ma(t)) * 1e-3)
        err_b: ProfileError = CallableError(lambda t: np.asarray(mb(t)) * 1e-3)
        e = spec.errors
        origin = "the design's [inspection] errors (master cams and constant errors)"
    else:
        tol = {t.key: t.deviation for t in design.resolve_tolerances(max_radius)}
        dr = tol.get("r", 0.0)
        err_a = err_b = FourierError(dr)
        e = FixtureErrors(
            dl_a_mm=tol.get("l", 0.0),
            dl_b_mm=tol.get("l", 0.0),
            drr_c_mm=tol.get("rf", 0.0),
            drr_d_mm=tol.get("rf", 0.0),
        )
        origin = "the design's tolerances applied to both cams and both arms"
    none = FixtureErrors()
    cases: dict[str, tuple[ProfileError | None, ProfileError | None, FixtureErrors]] = {
        "r_a": (err_a, None, none),
        "r_b": (None, err_b, none),
        "rf": (None, None, FixtureErrors(drr_c_mm=e.drr_c_mm, drr_d_mm=e.drr_d_mm)),
        "l": (None, None, FixtureErrors(dl_a_mm=e.dl_a_mm, dl_b_mm=e.dl_b_mm)),
        "eta": (None, None, FixtureErrors(deta_rad=e.deta_rad)),
        "all": (err_a, err_b, e),
    }
    return cases, origin


class _Scaled:
    """A profile error multiplied by a constant."""

    def __init__(self, err: ProfileError, factor: float) -> None:
        self.err, self.factor = err, factor

    def __call__(self, theta_rad: FloatArray) -> Jet:
        return self.err(theta_rad) * self.factor


def _scaled_errors(e: FixtureErrors, k: float) -> FixtureErrors:
    return dataclasses.replace(
        e,
        dl_a_mm=e.dl_a_mm * k,
        dl_b_mm=e.dl_b_mm * k,
        drr_c_mm=e.drr_c_mm * k,
        drr_d_mm=e.drr_d_mm * k,
        deta_rad=e.deta_rad * k,
    )


def verify_conjugate(
    design: CamDesign, *, step_deg: float = 0.1, polyline: bool = True
) -> Verification:
    """Verify a conjugate design through the simulated measuring fixture (THEORY §4, §5).

    Round trip: the nominal cams A and B in the nominal fixture give ξ − ξ0 = S(θ) and
    Δf = 0. Linearisation: the forward analysis of THEORY §4.1 (Δf_r, Δf_rf, Δf_l, Δf_η;
    :func:`camtol.inspection.conjugate.conjugate_variation`) against the exact fixture with
    the errors applied to the shapes and to the follower: each part alone (``r_a``,
    ``r_b``, ``rf``, ``l``, ``eta``) and all together (``all``, Δf_est), in µm of Δf.
    The errors are the design's ``[inspection]`` master-cam functions and constant errors
    when given, else its tolerances on both cams and arms. Polyline: each cam's exported
    profile with its own roller (cam A in ``polyline``, cam B in ``extras``).

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    step_deg : float
        θ grid step. [deg]
    polyline : bool
        Also check the exported polylines.
    """
    from camtol.analysis import max_radius_mm
    from camtol.conjugate import conjugate_kinematics
    from camtol.contact.fixture import Fixture, simulate_fixture
    from camtol.inspection.conjugate import conjugate_factors, conjugate_variation
    from camtol.mechanisms.conjugate import ConjugatePair

    pair = design.mechanism
    assert isinstance(pair, ConjugatePair)
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    conjugate_kinematics(design, theta, left_limit=left, check=True)
    shape_a = AnalyticShape(pair.cam_a, design.program)
    shape_b = AnalyticShape(pair.cam_b, design.program)
    xi0 = pair.initial_angle_rad
    motion = design.program.evaluate(theta, left_limit=left)
    nominal = simulate_fixture(
        theta, shape_a, shape_b, Fixture.of(pair), initial_angle_rad=xi0, left_limit=left
    )
    cases, origin = _fixture_inputs(design, max_radius_mm(design))
    factors = conjugate_factors(design, theta)
    checks: dict[str, LinearisationCheck] = {}
    for key, (ea, eb, const) in cases.items():
        lin, ex = [], []
        for k in (1.0, 0.5):
            sa = shape_a.with_errors(radial_error=_Scaled(ea, k)) if ea is not None else shape_a
            sb = shape_b.with_errors(radial_error=_Scaled(eb, k)) if eb is not None else shape_b
            errs = _scaled_errors(const, k)
            var = conjugate_variation(
                factors,
                ea(theta).v * 1e3 * k if ea is not None else np.zeros_like(theta),
                eb(theta).v * 1e3 * k if eb is not None else np.zeros_like(theta),
                errs,
            )
            res = simulate_fixture(
                theta, sa, sb, Fixture.of(pair, errs), initial_angle_rad=xi0, left_limit=left
            )
            lin.append(np.asarray(var.df_est_um))
            ex.append(np.asarray(res.extras["delta_f_mm"]) * 1e3)
        lin_max = float(np.max(np.abs(lin[0])))
        if lin_max == 0.0:
            continue
        diff = float(np.max(np.abs(ex[0] - lin[0])))
        diff_h = float(np.max(np.abs(ex[1] - lin[1])))
        exact = diff <= EXACT_FRACTION * lin_max + 1e-11
        ratio = diff / diff_h if diff_h > 0 else math.inf
        ok = diff <= LINEAR_FRACTION_LIMIT * lin_max and (exact or 3.0 <= ratio <= 5.0)
        checks[key] = LinearisationCheck(
            key=key,
            deviation=None,
            unit="um",
            linear_max=lin_max,
            exact_max=float(np.max(np.abs(ex[0]))),
            max_difference=diff,
            half_difference=diff_h,
            exact_to_rounding=bool(exact),
            ok=bool(ok),
        )
    extras: dict[str, Any] = {
        "roundtrip_delta_f_max_mm": float(np.max(np.abs(nominal.extras["delta_f_mm"]))),
        "linearisation_quantity": "centre-distance variation Δf of the measuring fixture",
        "linearisation_errors": origin,
    }
    poly_a = None
    if polyline:
        cam_a, cam_b = (c.design for c in design.cams())
        poly_a = _polyline(cam_a)
        poly_b = _polyline(cam_b)
        extras["polyline_b"] = dataclasses.asdict(poly_b)
    rt = float(np.max(np.abs(nominal.lift - motion.lift)))
    return Verification(
        design_name=design.name,
        follower=pair.kind,
        output_unit="rad",
        step_deg=step_deg,
        roundtrip_max_error=rt,
        roundtrip_velocity_max_error=float(np.max(np.abs(nominal.velocity - motion.velocity))),
        roundtrip_acceleration_max_error=None,
        polyline=poly_a,
        linearisation=checks,
        notes=(
            "conjugate design: the measuring fixture (pivot free along the line of centres)"
            " stands in for the follower; linearisation compares Δf in µm",
        ),
        extras=extras,
    )
