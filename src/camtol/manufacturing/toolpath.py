"""Cutter paths of a design's cams: the profile's offset by the tool radius (THEORY §6.3).

The offset curves themselves are the analytic engine's (:mod:`camtol.analysis.offset`);
this module adds what a tool needs: every cam of a design (:func:`single_cams`) and the
gouge check of a round tool against the profile's concave stretches (:func:`check_gouge`).
"""

from __future__ import annotations

import math

from camtol.analysis.offset import PathSample, profile_path, smallest_concave_radius
from camtol.design.cam_design import CamDesign
from camtol.exceptions import UndercutError

__all__ = [
    "PathSample",
    "check_gouge",
    "profile_path",
    "single_cams",
    "smallest_concave_radius",
]


def single_cams(design: CamDesign) -> list[tuple[str, CamDesign]]:
    """Return the single cams of a design: itself, or cams A and B of a conjugate pair.

    Parameters
    ----------
    design : CamDesign
        Any design.

    Returns
    -------
    list of (str, CamDesign)
        (label, design of one cam with its own follower); the label is "" for a single
        cam, "A" and "B" for a conjugate pair.
    """
    return [(cam.label, cam.design) for cam in design.cams()]


def check_gouge(design: CamDesign, tool_radius_mm: float, *, step_deg: float = 0.05) -> None:
    """Raise if a tool of this radius cannot follow the profile (concave ρ smaller than R).

    Parameters
    ----------
    design : CamDesign
        A single-cam design.
    tool_radius_mm : float
        Tool radius R (wire radius + spark gap for wire EDM). [mm]
    step_deg : float
        Angular step of the check. [deg]

    Raises
    ------
    UndercutError
        Naming the smallest concave radius of curvature, the cam angle where it occurs,
        and the largest tool radius that cuts the profile without gouging.
    """
    tight = smallest_concave_radius(design, step_deg=step_deg) if tool_radius_mm > 0 else None
    if tight is not None and tight[0] < tool_radius_mm:
        rho, at = tight
        if math.isinf(tool_radius_mm):
            raise UndercutError(
                f"a flat tool cannot cut this profile: it is concave (radius of curvature"
                f" {rho:.4g} mm) at θ={at:.2f}° and the tool would gouge there; use a"
                f" cylindrical tool of radius at most {rho:.4g} mm"
            )
        raise UndercutError(
            f"tool radius {tool_radius_mm:g} mm is larger than the concave radius of curvature"
            f" {rho:.4g} mm of the profile at θ={at:.2f}°: the tool would gouge there; use a"
            f" tool radius of at most {rho:.4g} mm"
        )
