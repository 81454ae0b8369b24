"""What a follower presents to the contact engine and to the drawing (THEORY §5).

Each follower class returns one contact element from
:meth:`~camtol.mechanisms.base.Mechanism.contact_element`; the contact engine
(:func:`camtol.contact.engine.follow`) solves each kind of element exactly, so the engine
needs no table of follower types. :class:`Outline` is the follower drawn at one angle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from camtol import jet
from camtol.jet import JetLike

__all__ = [
    "ContactElement",
    "OscillatingFace",
    "Outline",
    "RollerGuide",
    "Segment2",
    "TranslatingFace",
    "face_segment",
    "point",
]


@dataclass(frozen=True)
class RollerGuide:
    """How a roller follower's centre moves, for the contact engine (THEORY §5).

    Attributes
    ----------
    path : {"line", "circle"}
        The roller centre runs on a line (translating: C = e·w + x·t) or on a circle about
        the pivot O3 = f·(cos θ, sin θ) (oscillating: arm angle x = γ).
    roller_radius_mm : float
        Roller radius r_f. [mm]
    offset_mm : float
        Line: offset e. [mm]
    pivot_mm, arm_mm : float
        Circle: centre distance f and arm length l. [mm]
    side : {-1, +1}
        Circle: −1 for an arm at θ + 180° − γ (cam A), +1 at θ + 180° + γ (cam B).
    sign, shift : float
        The follower's absolute output is sign·x + shift. [mm or rad]
    zero : float
        Absolute output at S = 0 (s0, or ξ0). [mm or rad]
    """

    path: Literal["line", "circle"]
    roller_radius_mm: float
    offset_mm: float = 0.0
    pivot_mm: float = 0.0
    arm_mm: float = 0.0
    side: int = -1
    sign: float = 1.0
    shift: float = 0.0
    zero: float = 0.0


@dataclass(frozen=True)
class TranslatingFace:
    """A translating flat face, for the contact engine (THEORY §2.1, §5).

    Attributes
    ----------
    face_angle_rad : float
        Obliquity φ. [rad]
    offset_mm : float
        Offset e. [mm]
    zero : float
        L at S = 0: r_b sec φ − e tan φ. [mm]
    """

    face_angle_rad: float
    offset_mm: float
    zero: float


@dataclass(frozen=True)
class OscillatingFace:
    """An oscillating flat face, for the contact engine (THEORY §2.2, §5).

    Attributes
    ----------
    pivot_distance_mm : float
        f. [mm]
    face_offset_mm : float
        e. [mm]
    zero : float
        ξ0 at S = 0. [rad]
    """

    pivot_distance_mm: float
    face_offset_mm: float
    zero: float


#: What a follower presents to the contact engine: the engine solves each kind exactly.
ContactElement = RollerGuide | TranslatingFace | OscillatingFace


#: A line segment ((x0, y0), (x1, y1)) of a drawing. [mm]
Segment2 = tuple[tuple[float, float], tuple[float, float]]


@dataclass(frozen=True)
class Outline:
    """The follower drawn at one cam angle (cam frame), for the report's cam drawing.

    Attributes
    ----------
    circles : tuple of (x, y, r)
        Rollers. [mm]
    segments : tuple of ((x0, y0), (x1, y1))
        Faces, stems and arms. [mm]
    guides : tuple of ((x0, y0), (x1, y1))
        Construction lines (e.g. a translating follower's line of motion). [mm]
    pivots : tuple of (x, y)
        Follower pivots O3. [mm]
    labels : tuple of (text, x, y)
        Named points (e.g. the face reference point P). [mm]
    """

    circles: tuple[tuple[float, float, float], ...] = ()
    segments: tuple[Segment2, ...] = ()
    guides: tuple[Segment2, ...] = ()
    pivots: tuple[tuple[float, float], ...] = ()
    labels: tuple[tuple[str, float, float], ...] = ()


def point(x: JetLike) -> float:
    """Return the first value of an array or jet as a float (drawing helpers).

    Parameters
    ----------
    x : JetLike
        An array or jet of one angle. [any unit]

    Returns
    -------
    float
        Its first value. [same unit]
    """
    return float(np.asarray(jet.value(x), dtype=float).ravel()[0])


def face_segment(
    a: tuple[float, float], p: tuple[float, float], d: tuple[float, float], scale_mm: float
) -> Segment2:
    """Return a face along direction d through contact point a, covering p, ±0.3·scale.

    Parameters
    ----------
    a, p : tuple of float
        Contact point and face reference point. [mm]
    d : tuple of float
        Unit direction along the face. [-]
    scale_mm : float
        Drawing scale (the base radius). [mm]

    Returns
    -------
    Segment2
        End points. [mm]
    """
    s = (0.0, (p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1])
    lo, hi = min(s) - 0.3 * scale_mm, max(s) + 0.3 * scale_mm
    return ((a[0] + lo * d[0], a[1] + lo * d[1]), (a[0] + hi * d[0], a[1] + hi * d[1]))
