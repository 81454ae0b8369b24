"""Designs and independent closed forms shared by the dynamics tests (THEORY §9)."""

from __future__ import annotations

import math

import numpy as np

from camtol.config.design_file import design_from_mapping
from camtol.design.cam_design import CamDesign

H_MM = 10.0


def cycloidal_design(beta_deg: float, name: str = "cycloidal") -> CamDesign:
    """Rise of 10 mm over β, dwell to 180°, return over β, dwell: flat face, r_b 40 mm."""
    segs = [
        {"kind": "rise", "law": "cycloidal", "start_deg": 0, "end_deg": beta_deg, "lift_mm": H_MM},
        {"kind": "dwell", "start_deg": beta_deg, "end_deg": 180},
        {
            "kind": "return",
            "law": "cycloidal",
            "start_deg": 180,
            "end_deg": 180 + beta_deg,
            "lift_mm": H_MM,
        },
        {"kind": "dwell", "start_deg": 180 + beta_deg, "end_deg": 360},
    ]
    return design_from_mapping(
        {
            "name": name,
            "follower": {
                "type": "flat_translating",
                "base_radius_mm": 40.0,
                "offset_mm": 0.0,
                "face_angle_deg": 0.0,
            },
            "motion": {"segments": segs},
        }
    )


def cycloidal_lift(theta: float, beta_rad: float) -> tuple[float, float]:
    """y and dy/dθ of :func:`cycloidal_design`, written out independently of camtol."""
    t = theta % (2 * math.pi)
    if t < beta_rad:
        x = t / beta_rad
        return (
            H_MM * (x - math.sin(2 * math.pi * x) / (2 * math.pi)),
            H_MM * (1 - math.cos(2 * math.pi * x)) / beta_rad,
        )
    if t < math.pi:
        return H_MM, 0.0
    if t < math.pi + beta_rad:
        x = (t - math.pi) / beta_rad
        return (
            H_MM - H_MM * (x - math.sin(2 * math.pi * x) / (2 * math.pi)),
            -H_MM * (1 - math.cos(2 * math.pi * x)) / beta_rad,
        )
    return 0.0, 0.0


def residual_from_rest(h: float, r: float, kappa: float = 1.0) -> float:
    """THEORY §9.2: free-vibration amplitude after a cycloidal rise from rest.

    κ h |sin πr| / (π r |r² − 1|), r = T/T_n the rise's duration over the train's period.
    """
    if abs(r - 1.0) < 1e-12:
        return kappa * h / 2.0
    return kappa * h * abs(math.sin(math.pi * r)) / (math.pi * r * abs(r * r - 1.0))


def residual_periodic(
    h: float, beta_rad: float, omega: float, wn: float, kappa: float = 1.0
) -> float:
    """THEORY §9.2: undamped periodic amplitude in the dwell after the rise.

    Rise and return of the same cycloidal law and duration T = β/ω, the return starting at
    half a revolution: z = ẇ + iω_n w over one period, z₀ = e^{iω_n T_c}U/(1 − e^{iω_n T_c}).
    """
    t = beta_rad / omega
    om = 2 * math.pi / t
    u1 = -kappa * (2 * math.pi * h / t**2) * (np.exp(-1j * wn * t) - 1) * om / (wn**2 - om**2)
    t_r = math.pi / omega
    u2 = (
        kappa
        * (2 * math.pi * h / t**2)
        * np.exp(-1j * wn * t_r)
        * (np.exp(-1j * wn * t) - 1)
        * om
        / (wn**2 - om**2)
    )
    e = np.exp(1j * wn * 2 * math.pi / omega)
    z0 = (u1 + u2) * e / (1 - e)
    z_end = np.exp(1j * wn * t) * (z0 + u1)
    return float(abs(z_end) / wn)
