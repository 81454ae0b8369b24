r"""Normal contact force, camshaft torque and Hertz contact stress (THEORY §9.4, §9.5).

The train force Q (a force along the follower's motion, or a moment about its pivot)
becomes the normal force at the contact by virtual work: a normal displacement Δn of the
cam's profile moves the follower by ΔS_n = (∂S/∂n) Δn, the closed-form sensitivity of
THEORY §3 (1/cos φ for a translating follower, 1/(l cos φ) for an oscillating roller,
1/u for an oscillating face), so

.. math:: F_n = Q \, \frac{\partial S}{\partial n}, \qquad
          τ = Q \, V \quad \text{(power balance, friction neglected)}.

The Hertz stress of the line contact of a cylinder pair of width L, with the cam's
radius of curvature ρ at the contact (ρ < 0 where the cam is concave) and the roller's
radius r_f (a flat face: 1/r_f = 0), is

.. math:: \frac{1}{R} = \frac{1}{ρ} + \frac{1}{r_f}, \qquad
          p_{max} = \sqrt{\frac{F_n E^*}{π L R}}, \qquad
          \frac{1}{E^*} = \frac{1 - ν_1^2}{E_1} + \frac{1 - ν_2^2}{E_2}.

The geometry (∂S/∂n, ρ) is the design's: for an as-made cam it is taken at the nominal
profile (a cut polygon's facets are flat and its vertices sharp: not a Hertz contact).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camtol import jet
from camtol.design.cam_design import CamDesign
from camtol.dynamics.lift import CamLift
from camtol.dynamics.train import ContactMaterials, FollowerTrain
from camtol.jet import FloatArray
from camtol.mechanisms.elements import RollerGuide

__all__ = ["CamContact", "cam_contacts", "camshaft_torque_nm", "hertz_stress_mpa"]


@dataclass(frozen=True)
class CamContact:
    """The contact of one cam with its follower over the revolution.

    Attributes
    ----------
    label : str
        ``""`` for a design's only cam, ``"A"``/``"B"`` for a conjugate pair's.
    normal_force_n : ndarray
        Normal contact force F_n (negative: the follower would leave a force-closed cam;
        a cam of a conjugate pair carries max(F_n, 0)). [N]
    hertz_stress_mpa : ndarray or None
        Hertz contact stress (0 where F_n ≤ 0); None without a face width. [MPa]
    normal_factor : ndarray
        ∂S/∂n at the contact (THEORY §3). [mm/mm, or rad/mm]
    curvature_radius_mm : ndarray
        The cam's radius of curvature ρ at the contact (> 0 convex). [mm]
    roller_radius_mm : float or None
        The roller's radius; None for a flat face. [mm]
    """

    label: str
    normal_force_n: FloatArray
    hertz_stress_mpa: FloatArray | None
    normal_factor: FloatArray
    curvature_radius_mm: FloatArray
    roller_radius_mm: float | None


def hertz_stress_mpa(
    normal_force_n: FloatArray,
    curvature_radius_mm: FloatArray,
    roller_radius_mm: float | None,
    materials: ContactMaterials,
) -> FloatArray | None:
    """Return the Hertz line-contact stress p_max (THEORY §9.5).

    Parameters
    ----------
    normal_force_n : ndarray
        Normal force F_n; ≤ 0 gives 0 (no contact). [N]
    curvature_radius_mm : ndarray
        The cam's radius of curvature ρ at the contact (< 0 concave, inf flat). [mm]
    roller_radius_mm : float or None
        Roller radius r_f; None for a flat face. [mm]
    materials : ContactMaterials
        Face width and elastic constants; no face width gives None.

    Returns
    -------
    ndarray or None
        p_max. [MPa]

    Examples
    --------
    A flat face on a 30 mm radius, 1 kN over 10 mm, steel on steel (E* = 115.4 GPa):

    >>> m = ContactMaterials(face_width_mm=10.0)
    >>> round(float(hertz_stress_mpa(np.array([1000.0]), np.array([30.0]), None, m)[0]), 1)
    349.9
    """
    if materials.face_width_mm is None:
        return None
    inv_r = 1.0 / np.asarray(curvature_radius_mm, dtype=float)
    if roller_radius_mm is not None:
        inv_r = inv_r + 1.0 / roller_radius_mm
    f = np.maximum(np.asarray(normal_force_n, dtype=float), 0.0)
    curv = np.maximum(inv_r, 0.0)
    return np.asarray(
        np.sqrt(f * curv * materials.effective_modulus_mpa / (np.pi * materials.face_width_mm))
    )


def camshaft_torque_nm(
    train: FollowerTrain, train_force: FloatArray, velocity: FloatArray
) -> FloatArray:
    """Return the torque the camshaft delivers, τ = Q V (THEORY §9.4). [N·m]

    Parameters
    ----------
    train : FollowerTrain
        The train (its output fixes the unit).
    train_force : ndarray
        Q. [N, or N·m]
    velocity : ndarray
        V = dS/dθ of the cam as given. [mm/rad, or rad/rad]

    Returns
    -------
    ndarray
        τ > 0 drives the follower, τ < 0 is the follower driving the cam. [N·m]
    """
    return np.asarray(train_force * velocity * train.torque_factor)


def cam_contacts(
    design: CamDesign, lift: CamLift, train: FollowerTrain, train_force: FloatArray
) -> tuple[CamContact, ...]:
    """Return the contact force and stress of every cam of the design (THEORY §9.4, §9.5).

    Parameters
    ----------
    design : CamDesign
        The design (one cam, or the two cams of a conjugate pair).
    lift : CamLift
        The lift (its nominal S, V, A give the contact geometry).
    train : FollowerTrain
        The train (its materials; form-closed for a pair).
    train_force : ndarray
        Q over the grid. [N, or N·m]

    Returns
    -------
    tuple of CamContact
        In the design's order of cams.
    """
    theta = lift.theta_rad
    s, v, a = lift.nominal_lift, lift.nominal_velocity, lift.nominal_acceleration
    out = []
    for cam in design.cams():
        mech = cam.mechanism
        factor = np.asarray(jet.value(mech.error_sensitivities(theta, s, v)["n"]), dtype=float)
        factor = np.broadcast_to(factor, theta.shape)
        force = train_force * factor * train.force_to_newton
        if train.form_closed:
            force = np.maximum(force, 0.0)
        else:
            force = np.copysign(1.0, factor) * force  # pushing: Q > 0 is contact
        rho = np.asarray(mech.curvature_radius(theta, s, v, a), dtype=float)
        element = mech.contact_element()
        rf = element.roller_radius_mm if isinstance(element, RollerGuide) else None
        out.append(
            CamContact(
                label=cam.label,
                normal_force_n=np.asarray(force, dtype=float),
                hertz_stress_mpa=hertz_stress_mpa(force, rho, rf, train.materials),
                normal_factor=factor,
                curvature_radius_mm=rho,
                roller_radius_mm=rf,
            )
        )
    return tuple(out)
