"""The conjugate pair on the measuring fixture: forward and inverse analysis (THEORY §4.1-4.2).

The follower pivot O3 of a conjugate pair rides on a slider along the line of centres; an
indicator reads the centre-distance variation Δf = f* − f while the pair turns ([CW11]).
This module computes

* the per-angle geometric factors φ, α, λ of both cams (:func:`conjugate_factors`);
* the forward conjugate variation Δf_r, Δf_rf, Δf_l, Δf_η, Δf_est from known errors
  (THEORY §4.1, [CW11] eqs. 14-18, :func:`conjugate_variation`);
* the inverse analysis Δr_A,est (with master cam B) and Δr_B,est (with master cam A) from a
  measured Δf_mea(θ) (THEORY §4.2, [CW11] eqs. 19-21, :func:`inverse_estimate`).

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction
from camtol.jet import FloatArray
from camtol.mechanisms.conjugate import ConjugatePair
from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec
from camtol.pair.kinematics import conjugate_kinematics

__all__ = [
    "ConjugateFactors",
    "ConjugateVariation",
    "FixtureErrors",
    "InverseEstimate",
    "conjugate_factors",
    "conjugate_variation",
    "constant_parts",
    "df_sensitivities",
    "fixture_reading_um",
    "inverse_estimate",
]


@dataclass(frozen=True)
class ConjugateFactors:
    """Per-θ geometric factors of the pair entering THEORY §4 (all arrays over θ).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    arm_a_mm, arm_b_mm : float
        l_A, l_B. [mm]
    pressure_a_rad, pressure_b_rad : ndarray
        Signed φ_A, φ_B. [rad]
    centre_line_a_rad, centre_line_b_rad : ndarray
        α_A, α_B. [rad]
    shift_a_rad, shift_b_rad : ndarray
        λ_A, λ_B. [rad]
    """

    theta_rad: FloatArray
    arm_a_mm: float
    arm_b_mm: float
    pressure_a_rad: FloatArray
    pressure_b_rad: FloatArray
    centre_line_a_rad: FloatArray
    centre_line_b_rad: FloatArray
    shift_a_rad: FloatArray
    shift_b_rad: FloatArray

    def shift_rad(self, cam: str) -> FloatArray:
        """λ of cam ``"A"`` or ``"B"`` over θ. [rad]

        Parameters
        ----------
        cam : {"A", "B"}
            The cam's letter.

        Returns
        -------
        ndarray
        """
        return self.shift_a_rad if cam == "A" else self.shift_b_rad

    @property
    def denominator_mm(self) -> FloatArray:
        """D = l_A cos φ_A cos α_B + l_B cos φ_B cos α_A. [mm]"""
        return np.asarray(
            self.arm_a_mm * np.cos(self.pressure_a_rad) * np.cos(self.centre_line_b_rad)
            + self.arm_b_mm * np.cos(self.pressure_b_rad) * np.cos(self.centre_line_a_rad)
        )

    @property
    def gain_a(self) -> FloatArray:
        """∂Δf/∂Δr_A = l_B cos φ_B cos λ_A / D. [-]"""
        return np.asarray(
            self.arm_b_mm
            * np.cos(self.pressure_b_rad)
            * np.cos(self.shift_a_rad)
            / self.denominator_mm
        )

    @property
    def gain_b(self) -> FloatArray:
        """∂Δf/∂Δr_B = l_A cos φ_A cos λ_B / D. [-]"""
        return np.asarray(
            self.arm_a_mm
            * np.cos(self.pressure_a_rad)
            * np.cos(self.shift_b_rad)
            / self.denominator_mm
        )


def _pair(design: CamDesign) -> ConjugatePair:
    if not isinstance(design.mechanism, ConjugatePair):
        raise DesignError(
            f"follower.type={design.mechanism.kind!r}: the fixture analysis needs a conjugate"
            " design (follower.type='conjugate')"
        )
    return design.mechanism


def conjugate_factors(design: CamDesign, theta_rad: ArrayLike) -> ConjugateFactors:
    """Evaluate φ, α, λ of both cams over θ (THEORY §2.4, §2.5).

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    theta_rad : array_like
        Cam angles. [rad]

    Returns
    -------
    ConjugateFactors
        Both cams' angles on the grid.

    Raises
    ------
    GeometryError, UndercutError
        If either cam cannot work (with the cam angle).

    Notes
    -----
    Design first, then angles, as everywhere in camtol; the former order
    ``conjugate_factors(theta_rad, design)`` still works with a DeprecationWarning.
    """
    if isinstance(theta_rad, CamDesign) and not isinstance(design, CamDesign):
        import warnings

        warnings.warn(
            "conjugate_factors(design, theta) is deprecated; use conjugate_factors( theta, design)",
            DeprecationWarning,
            stacklevel=2,
        )
        design, theta_rad = theta_rad, design
    pair = _pair(design)
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    k = conjugate_kinematics(design, theta)
    return ConjugateFactors(
        theta_rad=theta,
        arm_a_mm=pair.arm_a_mm,
        arm_b_mm=pair.arm_b_mm,
        pressure_a_rad=k.a.pressure_angle_rad,
        pressure_b_rad=k.b.pressure_angle_rad,
        centre_line_a_rad=k.centre_line_angle_a_rad,
        centre_line_b_rad=k.centre_line_angle_b_rad,
        shift_a_rad=k.a.shift_angle_rad,
        shift_b_rad=k.b.shift_angle_rad,
    )


@dataclass(frozen=True)
class ConjugateVariation:
    """Centre-distance variation and its parts (THEORY §4.1). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_r_um, df_rf_um, df_l_um, df_eta_um : ndarray
        Δf caused by the profile errors, the roller radii, the arm lengths and η. [µm]
    """

    theta_rad: FloatArray
    df_r_um: FloatArray
    df_rf_um: FloatArray
    df_l_um: FloatArray
    df_eta_um: FloatArray

    @property
    def df_constant_um(self) -> FloatArray:
        """Δf_rf + Δf_l + Δf_η, the part not due to the profiles. [µm]"""
        return np.asarray(self.df_rf_um + self.df_l_um + self.df_eta_um)

    @property
    def df_est_um(self) -> FloatArray:
        """Δf_est = Δf_r + Δf_rf + Δf_l + Δf_η (CW11 eq. 18). [µm]"""
        return np.asarray(self.df_r_um + self.df_constant_um)


def constant_parts(
    fac: ConjugateFactors, errors: FixtureErrors
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Return the parts of Δf not due to the profiles (THEORY §4.1, CW11 eqs. 15-17).

    Parameters
    ----------
    fac : ConjugateFactors
        From :func:`conjugate_factors`.
    errors : FixtureErrors
        Constant errors of the follower.

    Returns
    -------
    df_rf_um, df_l_um, df_eta_um : ndarray
        Δf_rf, Δf_l, Δf_η over θ. [µm]
    """
    la, lb = fac.arm_a_mm, fac.arm_b_mm
    ca, cb = np.cos(fac.pressure_a_rad), np.cos(fac.pressure_b_rad)
    d = fac.denominator_mm
    df_rf = (errors.drr_c_mm * lb * cb + errors.drr_d_mm * la * ca) / d
    df_l = (
        errors.dl_a_mm * lb * cb * np.sin(fac.pressure_a_rad)
        + errors.dl_b_mm * la * ca * np.sin(fac.pressure_b_rad)
    ) / d
    df_eta = -errors.deta_rad * la * lb * ca * cb / d
    return np.asarray(df_rf * 1e3), np.asarray(df_l * 1e3), np.asarray(df_eta * 1e3)


def conjugate_variation(
    factors: ConjugateFactors,
    dr_a: ErrorFunction | ArrayLike,
    dr_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> ConjugateVariation:
    r"""Forward centre-distance variation from known errors (THEORY §4.1, CW11 eqs. 14-18).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    dr_a, dr_b : ErrorFunction or array_like
        Radial errors Δr_A(θ), Δr_B(θ) of the profile points in contact at θ. [µm]
    errors : FixtureErrors
        Constant errors.

    Returns
    -------
    ConjugateVariation

    Notes
    -----
    With D = l_A cos φ_A cos α_B + l_B cos φ_B cos α_A:

    .. math::

        Δf_r &= [Δr_A l_B \cos φ_B \cos λ_A + Δr_B l_A \cos φ_A \cos λ_B] / D \\
        Δf_{rf} &= [Δr_{rC} l_B \cos φ_B + Δr_{rD} l_A \cos φ_A] / D \\
        Δf_l &= [Δl_A l_B \cos φ_B \sin φ_A + Δl_B l_A \cos φ_A \sin φ_B] / D \\
        Δf_η &= -Δη\, l_A l_B \cos φ_A \cos φ_B / D

    Derivation (implicit differentiation of both contact constraints, as in
    :func:`~camtol.mechanisms.roller_oscillating.oscillating_roller_sensitivities`):
    cam A: l_A cos φ_A Δξ + cos α_A Δf − sin φ_A Δl_A = Δn_A + Δr_rC; cam B:
    −l_B cos φ_B Δξ + cos α_B Δf − sin φ_B Δl_B + l_B cos φ_B Δη = Δn_B + Δr_rD, with
    Δn = Δr cos λ; eliminating Δξ gives the forms above (THEORY's signs confirmed; checked
    against an exact 4×4 re-solution of the perturbed fixture in the tests).
    """
    theta = factors.theta_rad
    ra = dr_a(theta) if isinstance(dr_a, ErrorFunction) else np.asarray(dr_a, dtype=float)
    rb = dr_b(theta) if isinstance(dr_b, ErrorFunction) else np.asarray(dr_b, dtype=float)
    df_r = ra * factors.gain_a + rb * factors.gain_b
    rf, ll, eta = constant_parts(factors, errors)
    return ConjugateVariation(theta, np.asarray(df_r), rf, ll, eta)


@dataclass(frozen=True)
class InverseEstimate:
    """Profile errors estimated from a measured Δf (THEORY §4.2). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_mea_um : ndarray
        Measured centre-distance variation. [µm]
    df_r_um : ndarray
        Δf_r = Δf_mea − (Δf_rf + Δf_l + Δf_η) (CW11 eq. 19). [µm]
    dr_a_est_um : ndarray
        Δr_A,est with master cam B (CW11 eq. 20). [µm]
    dr_b_est_um : ndarray
        Δr_B,est with master cam A (CW11 eq. 21). [µm]
    """

    theta_rad: FloatArray
    df_mea_um: FloatArray
    df_r_um: FloatArray
    dr_a_est_um: FloatArray
    dr_b_est_um: FloatArray


def inverse_estimate(
    factors: ConjugateFactors,
    df_mea: ErrorFunction | ArrayLike,
    master_a: ErrorFunction | ArrayLike,
    master_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> InverseEstimate:
    r"""Profile errors from a measured centre-distance variation (THEORY §4.2, CW11 eqs. 19-21).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    df_mea : ErrorFunction or array_like
        Measured Δf_mea(θ). [µm]
    master_a, master_b : ErrorFunction or array_like
        Known radial errors of the master cams A_(m) and B_(m). [µm]
    errors : FixtureErrors
        Constant errors of the follower.

    Notes
    -----
    .. math::

        Δf_r &= Δf_{mea} - (Δf_{rf} + Δf_l + Δf_η) \\
        Δr_{A,est} &= [D Δf_r - Δr_{B,mea} l_A \cos φ_A \cos λ_B] / (l_B \cos φ_B \cos λ_A) \\
        Δr_{B,est} &= [D Δf_r - Δr_{A,mea} l_B \cos φ_B \cos λ_A] / (l_A \cos φ_A \cos λ_B)

    Put back into :func:`conjugate_variation` (with the master's error for the other cam)
    the estimate returns Δf_mea exactly.
    """
    theta = factors.theta_rad

    def ev(x: ErrorFunction | ArrayLike) -> FloatArray:
        return x(theta) if isinstance(x, ErrorFunction) else np.asarray(x, dtype=float)

    mea = np.broadcast_to(ev(df_mea), theta.shape).astype(float)
    rf, ll, eta = constant_parts(factors, errors)
    df_r = mea - (rf + ll + eta)
    ga, gb = factors.gain_a, factors.gain_b
    dr_a = (df_r - ev(master_b) * gb) / ga
    dr_b = (df_r - ev(master_a) * ga) / gb
    return InverseEstimate(theta, mea, np.asarray(df_r), np.asarray(dr_a), np.asarray(dr_b))


def df_sensitivities(factors: ConjugateFactors) -> dict[str, FloatArray]:
    """Δf per unit error of each of the pair's sources (THEORY §4.1, linear).

    The same forms as :func:`conjugate_variation` with one error at a time: a radial error
    of a cam enters through its gain, a normal error through the gain over cos λ (Δr =
    Δn / cos λ), a roller, an arm and η through :func:`constant_parts`. The centre
    distance f of the machine does not change f* − f (it is what f* is compared with).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.

    Returns
    -------
    dict of str to ndarray
        By the pair's source key (``r_a``, ``n_a``, ``rf_c``, ``l_a``, ``eta``, ... and
        ``f``): ∂Δf/∂p over θ. [mm per mm, or mm per rad for ``eta``]
    """
    zero = np.zeros_like(factors.theta_rad)

    def constant(**unit: float) -> FloatArray:
        rf, ll, eta = constant_parts(factors, FixtureErrors(**unit))
        return np.asarray((rf + ll + eta) * 1e-3)

    return {
        "r_a": factors.gain_a,
        "r_b": factors.gain_b,
        "n_a": np.asarray(factors.gain_a / np.cos(factors.shift_a_rad)),
        "n_b": np.asarray(factors.gain_b / np.cos(factors.shift_b_rad)),
        "rf_c": constant(drr_c_mm=1.0),
        "rf_d": constant(drr_d_mm=1.0),
        "l_a": constant(dl_a_mm=1.0),
        "l_b": constant(dl_b_mm=1.0),
        "eta": constant(deta_rad=1.0),
        "f": zero,
    }


def fixture_reading_um(
    factors: ConjugateFactors, spec: FixtureSpec, cam: str, dr_um: ArrayLike
) -> FloatArray:
    """Δf the fixture reads on cam ``cam`` of radial error Δr against the other cam's master.

    Cam A is measured against master cam B and cam B against master A (THEORY §4.3),
    with the fixture's own constant errors: Δf_mea = Δf_r(Δr, master) + Δf_rf + Δf_l + Δf_η
    (:func:`conjugate_variation`).

    Parameters
    ----------
    factors : ConjugateFactors
        The pair's geometry on the grid.
    spec : FixtureSpec
        The masters' known errors and the fixture's constant errors.
    cam : {"A", "B"}
        The inspected cam.
    dr_um : array_like
        Its radial error over the grid (last axis; several cams as rows). [µm]

    Returns
    -------
    ndarray
        The reading, shaped as ``dr_um``. [µm]
    """
    if cam == "A":
        return conjugate_variation(factors, dr_um, spec.master_b, spec.errors).df_est_um
    return conjugate_variation(factors, spec.master_a, dr_um, spec.errors).df_est_um
