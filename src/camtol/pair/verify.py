"""A conjugate pair verified through the simulated measuring fixture (THEORY §4, §5).

The fixture (pivot free along the line of centres; :mod:`camtol.pair.contact_fixture`)
stands in for the double-roller follower: the nominal cams A and B give ξ − ξ0 = S(θ) and
Δf = 0, and each error of the pair (the cams' radial errors, the rollers, the arms, η)
re-simulated exactly is compared with the forward analysis of THEORY §4.1. The checks
and their result type are those of a single cam (:mod:`camtol.contact.verification`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from camtol.analysis.kinematics import analysis_grid
from camtol.contact.errors_profile import CallableError, FourierError, ProfileError
from camtol.contact.shapes import AnalyticShape
from camtol.contact.verification import (
    EXACT_FRACTION,
    LINEAR_FRACTION_LIMIT,
    LinearisationCheck,
    Verification,
    polyline_check,
)
from camtol.design.cam_design import CamDesign
from camtol.jet import FloatArray, Jet
from camtol.pair.fixture_spec import FixtureErrors

__all__ = ["verify_pair"]


# ---------------------------------------------------------------------------------------
# Conjugate designs: the measuring fixture stands in for the follower (THEORY §4, §5)
# ---------------------------------------------------------------------------------------
def _fixture_inputs(
    design: CamDesign, max_radius: float
) -> tuple[dict[str, tuple[ProfileError | None, ProfileError | None, FixtureErrors]], str]:
    """Error cases to re-simulate: key → (Δr_A, Δr_B, constant errors), and their origin."""
    from camtol.pair.fixture_spec import fixture_spec

    spec = fixture_spec(design)
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


def verify_pair(design: CamDesign, *, step_deg: float = 0.1, polyline: bool = True) -> Verification:
    """Verify a conjugate design through the simulated measuring fixture (THEORY §4, §5).

    Round trip: the nominal cams A and B in the nominal fixture give ξ − ξ0 = S(θ) and
    Δf = 0. Linearisation: the forward analysis of THEORY §4.1 (Δf_r, Δf_rf, Δf_l, Δf_η;
    :func:`camtol.pair.variation.conjugate_variation`) against the exact fixture with
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
    from camtol.analysis.result import max_radius_mm
    from camtol.mechanisms.conjugate import ConjugatePair
    from camtol.pair.contact_fixture import Fixture, simulate_fixture
    from camtol.pair.variation import conjugate_factors, conjugate_variation

    pair = design.mechanism
    assert isinstance(pair, ConjugatePair)
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)
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
        poly_a = polyline_check(cam_a)
        poly_b = polyline_check(cam_b)
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
