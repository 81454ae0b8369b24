"""The fixture checked against the CMM: [CW11]'s validation loop (THEORY §4, §8.4).

With coordinate measurements of both cams of a conjugate pair:

1. **Predicted record.** The fixture's Δf(θ) predicted from the two measured profiles by
   the exact fixture simulation (the digital twin, :func:`~camtol.pair.simulate_fixture`,
   with the follower's actual constants), and by the linear eqs. 14-18 (Δf_est), each
   compared with the measured Δf_mea: rms of the difference and relative deviation
   rms(diff)/rms(Δf_mea), as [CW11] Table 4.
2. **Estimates against the CMM.** Each cam's radial error estimated from the fixture
   record with the *other* cam's CMM error as its master (eqs. 19-21: A with Δr_B,CMM,
   B with Δr_A,CMM, as the experiment does), compared with its own CMM error: rms of the
   difference against the rms of the error ([CW11] reports 4.68 and 4.69 µm against
   146.13 and 109.5 µm, and 2.75 µm for Δf_est − Δf_mea).

The CMM error enters as the smoothed normal error Δn(t) of each scan
(:func:`~camtol.inspection.functional.fourier_fit`); the papers' radial error at the
profile point in contact at θ is Δr(θ) = Δn(θ)/cos λ(θ) (THEORY §2.5).

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from camtol.contact import AnalyticShape, FourierError
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.inspection.cmm import read_scan
from camtol.inspection.deviations import inspect_scan
from camtol.inspection.error_functions import ErrorFunction
from camtol.inspection.functional import DEFAULT_HARMONICS, fourier_fit
from camtol.inspection.registration import Datum
from camtol.jet import FloatArray
from camtol.pair.contact_fixture import Fixture, simulate_fixture
from camtol.pair.fixture_spec import FixtureSpec
from camtol.pair.variation import (
    FixtureErrors,
    conjugate_factors,
    conjugate_variation,
    inverse_estimate,
)

__all__ = ["CmmFixtureComparison", "compare_cmm_fixture", "masters_from_scans", "rms"]


def rms(x: FloatArray) -> float:
    """Root mean square over a uniform grid. [unit of x]

    Parameters
    ----------
    x : ndarray
        Values.
    """
    return float(np.sqrt(np.mean(np.square(x))))


@dataclass(frozen=True)
class CmmFixtureComparison:
    """Fixture record and CMM profiles compared (see the module notes). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Uniform cam-angle grid. [rad]
    dr_a_cmm_um, dr_b_cmm_um : ndarray
        Radial errors of cams A and B from the CMM, Δn/cos λ. [µm]
    df_mea_um : ndarray or None
        The measured (or given) Δf_mea. [µm]
    df_twin_um : ndarray
        Δf predicted from the two CMM profiles by the exact fixture simulation. [µm]
    df_est_um : ndarray
        Δf_est from eqs. 14-18 with the CMM errors and the fixture constants. [µm]
    dr_a_est_um, dr_b_est_um : ndarray or None
        Estimates from Δf_mea, A with B's CMM error as master and B with A's. [µm]
    """

    theta_rad: FloatArray
    dr_a_cmm_um: FloatArray
    dr_b_cmm_um: FloatArray
    df_mea_um: FloatArray | None
    df_twin_um: FloatArray
    df_est_um: FloatArray
    dr_a_est_um: FloatArray | None
    dr_b_est_um: FloatArray | None

    def summary(self) -> dict[str, float]:
        """Return the rms figures of [CW11] Table 4 (µm; relative deviations as fractions)."""
        out = {
            "rms_dr_A_cmm_um": rms(self.dr_a_cmm_um),
            "rms_dr_B_cmm_um": rms(self.dr_b_cmm_um),
            "rms_df_twin_um": rms(self.df_twin_um),
            "rms_df_est_um": rms(self.df_est_um),
            "rms_df_est_minus_twin_um": rms(self.df_est_um - self.df_twin_um),
        }
        if self.df_mea_um is not None:
            mea = rms(self.df_mea_um)
            d_est = rms(self.df_est_um - self.df_mea_um)
            d_twin = rms(self.df_twin_um - self.df_mea_um)
            out |= {
                "rms_df_mea_um": mea,
                "rms_df_est_minus_mea_um": d_est,
                "relative_deviation_df_est": d_est / mea if mea > 0 else math.nan,
                "rms_df_twin_minus_mea_um": d_twin,
                "relative_deviation_df_twin": d_twin / mea if mea > 0 else math.nan,
            }
        if self.dr_a_est_um is not None and self.dr_b_est_um is not None:
            out |= {
                "rms_dr_A_est_minus_cmm_um": rms(self.dr_a_est_um - self.dr_a_cmm_um),
                "rms_dr_B_est_minus_cmm_um": rms(self.dr_b_est_um - self.dr_b_cmm_um),
            }
        return out


def compare_cmm_fixture(
    design: CamDesign,
    normal_a: FourierError,
    normal_b: FourierError,
    errors: FixtureErrors,
    *,
    df_mea: ErrorFunction | None = None,
    step_deg: float = 0.1,
) -> CmmFixtureComparison:
    """Compare the fixture with the CMM profiles of both cams (see the module notes).

    Parameters
    ----------
    design : CamDesign
        The conjugate design.
    normal_a, normal_b : FourierError
        Smoothed normal errors Δn(t) of cams A and B from their scans. [mm]
    errors : FixtureErrors
        The fixture follower's constant errors (arm lengths, roller radii, η).
    df_mea : ErrorFunction, optional
        The measured centre-distance variation (e.g. a processed indicator record). [µm]
    step_deg : float
        Uniform grid step; 360 must be a multiple of it. [deg]

    Returns
    -------
    CmmFixtureComparison

    Raises
    ------
    DesignError
        If the design is not a conjugate pair.
    """
    from camtol.mechanisms.conjugate import ConjugatePair

    pair = design.mechanism
    if not isinstance(pair, ConjugatePair):
        raise DesignError(
            f"follower.type={pair.kind!r}: the CMM-fixture comparison needs a conjugate design"
        )
    n = check_step(step_deg, name="--step", min_points=4)
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    fac = conjugate_factors(design, theta)
    dr_a = normal_a(theta).v / np.cos(fac.shift_a_rad) * 1e3
    dr_b = normal_b(theta).v / np.cos(fac.shift_b_rad) * 1e3
    twin = simulate_fixture(
        theta,
        AnalyticShape(pair.cam_a, design.program, normal_error=normal_a),
        AnalyticShape(pair.cam_b, design.program, normal_error=normal_b),
        Fixture.of(pair, errors),
        initial_angle_rad=pair.initial_angle_rad,
    )
    df_twin = twin.extras["delta_f_mm"] * 1e3
    df_est = conjugate_variation(fac, dr_a, dr_b, errors).df_est_um
    mea = est_a = est_b = None
    if df_mea is not None:
        mea = np.asarray(df_mea(theta), dtype=float)
        inv = inverse_estimate(fac, mea, dr_a, dr_b, errors)
        est_a, est_b = inv.dr_a_est_um, inv.dr_b_est_um
    return CmmFixtureComparison(theta, dr_a, dr_b, mea, df_twin, df_est, est_a, est_b)


def masters_from_scans(
    design: CamDesign,
    spec: FixtureSpec,
    scans: dict[str, str],
    *,
    stylus_radius_mm: float,
    datum: Datum,
    keep_masters: tuple[bool, bool],
    step_deg: float,
) -> tuple[FixtureSpec, CmmFixtureComparison]:
    """Both cams' CMM scans as the fixture's masters, and the fixture compared with them.

    Each scan is registered (:func:`camtol.inspection.deviations.inspect_scan`, against
    the cam's radial band of the ``[inspection]`` table) and its Δn smoothed
    (:func:`camtol.inspection.functional.fourier_fit`); the CMM radial errors
    Δr = Δn / cos λ become the master cams' errors (unless kept: the paper estimates A
    with B's CMM error and B with A's), and the fixture is compared with the CMM profiles
    (:func:`compare_cmm_fixture`; [CW11]'s validation loop, issue 12 item 5).

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    spec : FixtureSpec
        The fixture's inputs so far.
    scans : dict of str to str
        CMM scan file of each cam, by letter (``{"A": ..., "B": ...}``).
    stylus_radius_mm : float
        Stylus radius of the scans (0: surface points). [mm]
    datum : Datum
        Registration of the scans.
    keep_masters : (bool, bool)
        Keep the spec's master of cam A, of cam B (given explicitly).
    step_deg : float
        Grid of the comparison. [deg]

    Returns
    -------
    (FixtureSpec, CmmFixtureComparison)
        The spec with the masters replaced, and the comparison.
    """
    normals = []
    for cam in design.cams():
        path = scans[cam.letter]
        scan = read_scan(path, cam=cam.letter, stylus_radius_mm=stylus_radius_mm)  # type: ignore[arg-type]
        insp = inspect_scan(
            design,
            scan,
            cam=cam.letter,  # type: ignore[arg-type]
            datum=datum,
            tolerance_um=cam.inspection_band_um,
            tolerance_kind="radial",
        )
        kept = insp.kept
        normals.append(
            fourier_fit(insp.param_rad[kept], insp.dn_um[kept] * 1e-3, DEFAULT_HARMONICS)
        )
    comp = compare_cmm_fixture(
        design, normals[0], normals[1], spec.errors, df_mea=spec.df_mea, step_deg=step_deg
    )
    deg = np.degrees(comp.theta_rad)
    cmm_a, cmm_b = scans["A"], scans["B"]
    spec = dataclasses.replace(
        spec,
        master_a=spec.master_a
        if keep_masters[0]
        else ErrorFunction.table(deg, comp.dr_a_cmm_um, name=f"CMM {cmm_a}"),
        master_b=spec.master_b
        if keep_masters[1]
        else ErrorFunction.table(deg, comp.dr_b_cmm_um, name=f"CMM {cmm_b}"),
    )
    return spec, comp
