"""The fixture checked against the CMM: [CW11]'s validation loop (THEORY §4, §8.4).

With coordinate measurements of both cams of a conjugate pair:

1. **Predicted record.** The fixture's Δf(θ) predicted from the two measured profiles by
   the exact fixture simulation (the digital twin, :func:`~camtol.contact.simulate_fixture`,
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

import math
from dataclasses import dataclass

import numpy as np

from camtol.contact import AnalyticShape, Fixture, FourierError, simulate_fixture
from camtol.design import CamDesign
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.inspection.conjugate import (
    FixtureErrors,
    conjugate_factors,
    conjugate_variation,
    inverse_estimate,
)
from camtol.inspection.error_functions import ErrorFunction
from camtol.jet import FloatArray

__all__ = ["CmmFixtureComparison", "compare_cmm_fixture", "rms"]


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
