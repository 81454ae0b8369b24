"""The mechanism contract (contract.py) applied to the two flat-faced followers.

THEORY §2.1, §2.2, §2.5, §3.1, §3.2; the exact solver moves the face line itself.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from contract import Element, FArr, MechanismContract
from hypothesis import strategies as st

from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.mechanisms import FlatOscillating, FlatTranslating


def program(h: float, rise: float = 120.0, dwell: float = 60.0) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0, r(rise), "cycloidal", h),
            Segment("dwell", r(rise), r(rise + dwell)),
            Segment("return", r(rise + dwell), r(360), "cycloidal", h),
        )
    )


class TestFlatTranslatingContract(MechanismContract):
    designs = st.builds(
        lambda rb, e, phi, h: CamDesign("t", FlatTranslating(rb, e, math.radians(phi)), program(h)),
        rb=st.floats(30, 80),
        e=st.floats(-20, 20),
        phi=st.floats(-30, 30),
        h=st.floats(1, 15),
    )
    pressure_sign = 1.0

    def element(self, mech: Any, nominal: Any, theta: FArr, s: FArr) -> Element:
        # Reference point P = e·w + L·t on the face, L = L0 + S with the nominal L0 as the
        # follower's datum; the face turns about P when φ changes (THEORY §2.1).
        phi0, e0 = nominal.face_angle_rad, nominal.offset_mm
        phi, e = mech.face_angle_rad, mech.offset_mm
        big_l = nominal.base_radius_mm / math.cos(phi0) - e0 * math.tan(phi0) + s
        c, sn = np.cos(theta), np.sin(theta)
        px, py = -e * sn + big_l * c, e * c + big_l * sn
        nx, ny = np.cos(theta + phi), np.sin(theta + phi)
        return Element("face", nx, ny, px * nx + py * ny)

    def follower_velocity(self, mech: Any, theta: FArr, g: Any) -> tuple[FArr, FArr]:
        return np.cos(theta), np.sin(theta)

    def lambda_special(self, mech: Any, theta: FArr, lift: FArr, vel: FArr, g: Any) -> FArr:
        rad = np.hypot(g.contact_x, g.contact_y)
        return np.arcsin(vel * math.cos(mech.face_angle_rad) / rad)


class TestFlatOscillatingContract(MechanismContract):
    designs = st.builds(
        lambda rb, f, e, h: CamDesign("o", FlatOscillating(rb, f, e), program(math.radians(h))),
        rb=st.floats(30, 60),
        f=st.floats(70, 120),
        e=st.floats(-10, 20),
        h=st.floats(2, 15),
    )
    # φ > 0 for e > 0 (tan φ = e/u): the normal is turned counterclockwise from v̂.
    pressure_sign = 1.0

    def position(self, mech: Any, lift: FArr) -> FArr:
        return mech.initial_angle_rad + lift

    def element(self, mech: Any, nominal: Any, theta: FArr, s: FArr) -> Element:
        # face normal at ψ = θ + 90° − ξ, face at distance e from O3 = f·(cos θ, sin θ)
        f, e = mech.pivot_distance_mm, mech.face_offset_mm
        psi = theta + math.pi / 2 - s
        nx, ny = np.cos(psi), np.sin(psi)
        return Element("face", nx, ny, f * (np.cos(theta) * nx + np.sin(theta) * ny) + e)

    def follower_velocity(self, mech: Any, theta: FArr, g: Any) -> tuple[FArr, FArr]:
        f = mech.pivot_distance_mm
        dx = np.asarray(g.contact_x) - f * np.cos(theta)
        dy = np.asarray(g.contact_y) - f * np.sin(theta)
        return dy, -dx

    def lambda_special(self, mech: Any, theta: FArr, lift: FArr, vel: FArr, g: Any) -> FArr:
        rad = np.hypot(g.contact_x, g.contact_y)
        xi = mech.initial_angle_rad + lift
        return np.arcsin(mech.pivot_distance_mm * vel * np.cos(xi) / ((1 - vel) * rad))
