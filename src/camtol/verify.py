"""`camtol verify`: the contact engine checks the analytic engine, for any design (THEORY §5).

A single cam is checked by :func:`camtol.contact.verification.verify_cam` (round trip,
exported polyline, the linearisation of every toleranced source); a conjugate pair
through the simulated measuring fixture by :func:`camtol.pair.verify.verify_pair`. Both
return one :class:`~camtol.contact.verification.Verification`.
"""

from __future__ import annotations

from camtol.contact.verification import (
    ROUNDTRIP_LIMIT,
    LinearisationCheck,
    PolylineCheck,
    Verification,
    verify_cam,
)
from camtol.design.cam_design import CamDesign
from camtol.pair.kinematics import is_pair
from camtol.pair.verify import verify_pair

__all__ = [
    "LinearisationCheck",
    "PolylineCheck",
    "ROUNDTRIP_LIMIT",
    "Verification",
    "verify",
    "verify_cam",
    "verify_conjugate",
    "verify_pair",
]

#: The former name of :func:`verify_pair`.
verify_conjugate = verify_pair


def verify(design: CamDesign, *, step_deg: float = 0.1, polyline: bool = True) -> Verification:
    """Verify a design's analytic results with the exact contact engine (THEORY §5).

    Parameters
    ----------
    design : CamDesign
        Any design; a conjugate pair is checked through the measuring fixture.
    step_deg : float
        θ grid step; segment boundaries are included as left/right rows. [deg]
    polyline : bool
        Also check the exported polyline(s).

    Returns
    -------
    Verification

    Raises
    ------
    GeometryError, UndercutError
        If the design cannot produce its motion (as ``analyze`` would report).
    """
    if is_pair(design):  # both cams together, through the measuring fixture
        return verify_pair(design, step_deg=step_deg, polyline=polyline)
    return verify_cam(design, step_deg=step_deg, polyline=polyline)
