"""The cam and its follower at one cam angle, as data for a drawing (THEORY §0, §2).

:func:`cam_drawing` computes what :func:`camtol.report.plots.cam_plot` draws: for every cam
of the design (:meth:`~camtol.design.cam_design.CamDesign.cams`) its profile, the
contact point A, the instant centre Q and the follower's outline
(:meth:`~camtol.mechanisms.base.Mechanism.outline`). The report only draws it.

Argument order, as everywhere in camtol: the design first, then the angle, then
keyword-only options.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camtol import jet
from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.design.cam_design import CamDesign
from camtol.jet import FloatArray
from camtol.mechanisms.elements import Outline

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis.result import Analysis

__all__ = ["CamDrawing", "CamView", "analysis_drawing", "cam_drawing"]


@dataclass(frozen=True)
class CamView:
    """One cam of a drawing (cam frame X-Y of THEORY §0).

    Attributes
    ----------
    label : str
        ``""``, or ``"A"``/``"B"`` for the cams of a conjugate pair.
    profile_x_mm, profile_y_mm : ndarray
        The closed profile. [mm]
    contact_x_mm, contact_y_mm : float
        Contact point A at the drawing's angle. [mm]
    centre_x_mm, centre_y_mm : float
        Instant centre Q = I23 at that angle. [mm]
    outline : Outline
        The follower at that angle. [mm]
    pitch_x_mm, pitch_y_mm : ndarray or None
        The pitch curve (roller-centre path) of a roller follower, else None. [mm]
    """

    label: str
    profile_x_mm: FloatArray
    profile_y_mm: FloatArray
    contact_x_mm: float
    contact_y_mm: float
    centre_x_mm: float
    centre_y_mm: float
    outline: Outline
    pitch_x_mm: FloatArray | None = None
    pitch_y_mm: FloatArray | None = None


@dataclass(frozen=True)
class CamDrawing:
    """Everything a drawing of the cam and follower at one angle needs.

    Attributes
    ----------
    design_name : str
        Name of the design.
    theta_deg : float
        Cam angle of the drawing, as asked. [deg]
    base_radius_mm : float
        Radius of the base circle: the smallest radial dimension of the first cam. [mm]
    cams : tuple of CamView
        Every cam of the design.
    """

    design_name: str
    theta_deg: float
    base_radius_mm: float
    cams: tuple[CamView, ...]


def cam_drawing(design: CamDesign, theta_deg: float, *, step_deg: float = 0.25) -> CamDrawing:
    """Compute the drawing of the design's cams and follower at cam angle ``theta_deg``.

    Parameters
    ----------
    design : CamDesign
        Any design (both cams of a conjugate pair are drawn).
    theta_deg : float
        Cam angle at which the follower stands. [deg]
    step_deg : float
        Angle step of the drawn profile. [deg]

    Returns
    -------
    CamDrawing
        Profiles, contact points, instant centres and follower outlines. [mm]
    """
    theta_rad = math.radians(float(theta_deg) % 360.0)
    grid, left = analysis_grid(step_deg, design.program.boundaries_rad)
    here = np.array([theta_rad])
    views = []
    scale = math.nan
    for cam in design.cams():
        k = kinematics(cam.design, grid, left_limit=left, check=False)
        if math.isnan(scale):
            scale = float(np.nanmin(k.radius_mm))
        k0 = kinematics(cam.design, here, check=False)
        outline = cam.mechanism.outline(theta_rad, float(k0.lift[0]), float(k0.velocity[0]), scale)
        g = cam.mechanism.contact(k.theta_rad, k.lift, k.velocity)
        pitch = (
            (
                np.asarray(jet.value(g.extras["pitch_x"]), dtype=float),
                np.asarray(jet.value(g.extras["pitch_y"]), dtype=float),
            )
            if "pitch_x" in g.extras
            else (None, None)
        )
        views.append(
            CamView(
                cam.label,
                k.contact_x_mm,
                k.contact_y_mm,
                float(k0.contact_x_mm[0]),
                float(k0.contact_y_mm[0]),
                float(k0.centre_x_mm[0]),
                float(k0.centre_y_mm[0]),
                outline,
                *pitch,
            )
        )
    return CamDrawing(design.name, float(theta_deg), scale, tuple(views))


def analysis_drawing(analysis: Analysis, theta_deg: float | None = None) -> CamDrawing:
    """Compute the drawing of an analysed design, by default where ΔS_worst is largest.

    Parameters
    ----------
    analysis : Analysis
        From :func:`camtol.analysis.result.analyze`.
    theta_deg : float, optional
        Cam angle; default: the angle of the largest worst-case ΔS, rounded to 0.01°. [deg]

    Returns
    -------
    CamDrawing
        As :func:`cam_drawing`.
    """
    if theta_deg is None:
        theta_deg = round(analysis.extremes["dS_worst"][0].theta_deg, 2)
    return cam_drawing(analysis.design, theta_deg)
