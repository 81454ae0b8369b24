"""Both cams of a conjugate pair together (THEORY §2.4; [CW11] §2).

A conjugate design's cams A and B are analysed one by one like any cam
(:meth:`camtol.design.cam_design.CamDesign.cams`); what needs both at once lives here:
:func:`conjugate_kinematics` evaluates the pair on one grid (the measuring fixture of
THEORY §4 and the conjugate variation build on it). The pair itself is
:class:`camtol.mechanisms.conjugate.ConjugatePair`.

Argument order, as everywhere in camtol: the design first, then the angles, then
keyword-only options.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, in *Wide Spectra of Quality Control*, InTech, 2011,
   ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol import jet
from camtol.analysis.kinematics import Kinematics, kinematics
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError
from camtol.jet import FloatArray, JetLike
from camtol.mechanisms.conjugate import ConjugatePair

__all__ = [
    "ConjugateKinematics",
    "cam_design",
    "conjugate_kinematics",
    "is_pair",
    "require_pair",
]


@dataclass(frozen=True)
class ConjugateKinematics:
    """Both cams of a conjugate pair on one θ grid.

    Attributes
    ----------
    a, b : Kinematics
        Per-cam kinematics (contact points, radial dimension, signed φ, λ, ρ, ξ).
    centre_line_angle_a_rad, centre_line_angle_b_rad : ndarray
        α_A, α_B of THEORY §2.4. [rad]
    pitch_a_x_mm, pitch_a_y_mm, pitch_b_x_mm, pitch_b_y_mm : ndarray
        Roller centres C and D in the cam frame. [mm]
    """

    a: Kinematics
    b: Kinematics
    centre_line_angle_a_rad: FloatArray
    centre_line_angle_b_rad: FloatArray
    pitch_a_x_mm: FloatArray
    pitch_a_y_mm: FloatArray
    pitch_b_x_mm: FloatArray
    pitch_b_y_mm: FloatArray

    @property
    def theta_rad(self) -> FloatArray:
        """The grid. [rad]"""
        return self.a.theta_rad


def is_pair(design: CamDesign) -> bool:
    """Tell whether a design is a conjugate pair (its cams share one follower).

    Parameters
    ----------
    design : CamDesign
        Any design.

    Returns
    -------
    bool
    """
    return isinstance(design.mechanism, ConjugatePair)


def require_pair(design: CamDesign, who: str) -> ConjugatePair:
    """Return the pair's mechanism, or refuse a design that is not a conjugate pair.

    Parameters
    ----------
    design : CamDesign
        Any design.
    who : str
        Who needs the pair, for the message, e.g. "`camtol conjugate` needs".

    Returns
    -------
    ConjugatePair

    Raises
    ------
    DesignError
        Naming the design's follower type and the one needed.
    """
    mech = design.mechanism
    if not isinstance(mech, ConjugatePair):
        raise DesignError(
            f"follower.type={mech.kind!r}: {who} a conjugate design (follower.type = 'conjugate')"
        )
    return mech


def _pair(design: CamDesign) -> ConjugatePair:
    mech = design.mechanism
    if not isinstance(mech, ConjugatePair):
        raise DesignError(
            f"follower.type={mech.kind!r} is not a conjugate pair; this analysis needs"
            " follower.type='conjugate'"
        )
    return mech


def cam_design(design: CamDesign, cam: str) -> CamDesign:
    """Return the single-contact design of cam ``"A"`` or ``"B"`` of a conjugate design.

    Shorthand for the matching entry of :meth:`camtol.design.cam_design.CamDesign.cams`.

    Parameters
    ----------
    design : CamDesign
        Design whose mechanism is a :class:`ConjugatePair`.
    cam : {"A", "B"}
        Which cam.

    Returns
    -------
    CamDesign
        That cam's single-contact design.
    """
    _pair(design)
    for c in design.cams():
        if c.label == cam:
            return c.design
    raise DesignError(f"cam={cam!r} is not a cam of a conjugate pair; allowed: A, B")


def conjugate_kinematics(
    design: CamDesign,
    theta_rad: ArrayLike,
    *,
    left_limit: ArrayLike | None = None,
    check: bool = True,
) -> ConjugateKinematics:
    """Evaluate both cams of a conjugate design over θ (THEORY §2.4).

    Parameters
    ----------
    design : CamDesign
        Design whose mechanism is a :class:`ConjugatePair`.
    theta_rad : array_like
        Cam angles from the line of centres. [rad]
    left_limit : array_like of bool, optional
        Rows that take the left limit at segment boundaries.
    check : bool
        Raise on undercut, V ≥ 1 or |φ| ≥ 90° of either cam (with the cam angle).

    Raises
    ------
    GeometryError, UndercutError
        As :func:`camtol.analysis.kinematics.kinematics`, for cam A or cam B.
    """
    _pair(design)
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    kins = []
    geometry = []
    for cam in design.cams():
        try:
            kins.append(kinematics(cam.design, theta, left_limit=left_limit, check=check))
        except GeometryError as exc:  # name the cam (same class: UndercutError stays one)
            raise type(exc)(f"cam {cam.label}: {exc}") from None
        geometry.append(cam.mechanism.contact(theta, kins[-1].lift, kins[-1].velocity))
    kin_a, kin_b = kins
    ga, gb = geometry

    def v(x: JetLike) -> FloatArray:
        return np.asarray(jet.value(x), dtype=float)

    return ConjugateKinematics(
        a=kin_a,
        b=kin_b,
        centre_line_angle_a_rad=v(ga.extras["centre_line_angle"]),
        centre_line_angle_b_rad=v(gb.extras["centre_line_angle"]),
        pitch_a_x_mm=v(ga.extras["pitch_x"]),
        pitch_a_y_mm=v(ga.extras["pitch_y"]),
        pitch_b_x_mm=v(gb.extras["pitch_x"]),
        pitch_b_y_mm=v(gb.extras["pitch_y"]),
    )
