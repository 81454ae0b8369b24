"""Designs and shapes shared by the contact-engine tests (not a test module)."""

from __future__ import annotations

import math

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.mechanisms import FlatOscillating, FlatTranslating, RollerOscillating, RollerTranslating
from camtol.mechanisms.conjugate import ConjugatePair

r = math.radians


def program(
    h: float,
    rise_deg: float = 120.0,
    dwell1_deg: float = 40.0,
    ret_deg: float = 120.0,
    law: str = "cycloidal",
    law_ret: str | None = None,
) -> SegmentProgram:
    """Rise, dwell, return, dwell covering 360° (h in mm or rad)."""
    a = rise_deg
    b = a + dwell1_deg
    c = b + ret_deg
    segs = [
        Segment("rise", 0.0, r(a), law, h),
        Segment("dwell", r(a), r(b)),
        Segment("return", r(b), r(c), law_ret or law, h),
    ]
    if c < 360.0 - 1e-9:
        segs.append(Segment("dwell", r(c), 2 * math.pi))
    return SegmentProgram(tuple(segs))


def cw06_translating() -> CamDesign:
    """THEORY §8.1 without tolerances."""
    return CamDesign(
        "cw06-translating",
        FlatTranslating(40.0, 10.0, r(15.0)),
        program(22.0, 120.0, 70.0, 100.0),
    )


def cw06_oscillating() -> CamDesign:
    """THEORY §8.2 without tolerances."""
    return CamDesign(
        "cw06-oscillating", FlatOscillating(40.0, 80.0, 16.0), program(r(15.0), 120, 40, 120)
    )


def roller_translating() -> CamDesign:
    """An offset translating roller follower design."""
    return CamDesign(
        "roller-translating", RollerTranslating(40.0, 10.0, 6.0), program(18.0, 130, 50, 110)
    )


def roller_oscillating() -> CamDesign:
    """The single oscillating roller cam (cam A) of THEORY §8.3."""
    return CamDesign(
        "roller-oscillating", RollerOscillating(60.0, 16.0, 120.0, 66.0), program(r(30.0))
    )


def conjugate_pair() -> ConjugatePair:
    """The conjugate pair of THEORY §8.3."""
    return ConjugatePair(60.0, 16.0, 120.0, 66.0, 66.0, r(100.0))


def star_polygon(rng: np.random.Generator, m: int, r0: float, amp: float) -> np.ndarray:
    """A non-convex star-shaped polygon (counterclockwise), radii r0 ± amp."""
    t = np.sort(rng.uniform(0, 2 * math.pi, m))
    rad = r0 + amp * rng.uniform(-1, 1, m)
    return np.column_stack([rad * np.cos(t), rad * np.sin(t)])
