"""Popa's eccentric circle cam (THEORY §6.2, §8.5): the built-in example ``popa-eccentric``."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from numpy.testing import assert_allclose

from camtol.analysis.kinematics import kinematics
from camtol.config.design_file import load_example
from camtol.contact import PolygonShape, follow

R_MM, R0_MM = 30.0, 25.0
E_MM = R_MM - R0_MM


def test_popa_formula_chain_reduces_to_e_one_minus_cos() -> None:
    # Popa's chain (THEORY §6.2), written symbolically: the circle's centre O1 turns with
    # the cam at distance e from the pivot; the flat face (normal along the follower axis)
    # touches the circle where the radius O1T is parallel to the axis, so the face stands
    # at the height of O1 plus r; the lift is that height minus the lowest one, r0 = r − e.
    phi, r, r0 = sp.symbols("phi r r0", positive=True)
    e = r - r0  # eq. (1): eccentricity
    centre_height = -e * sp.cos(phi)  # eq. (2)-(3): O1 projected on the axis, s = 0 at φ = 0
    t_height = centre_height + r  # eq. (4): tangent point T on the face
    s = sp.simplify(t_height - r0)  # eq. (5): lift above the base circle
    assert sp.simplify(s - e * (1 - sp.cos(phi))) == 0
    assert sp.simplify(sp.diff(s, phi) - e * sp.sin(phi)) == 0  # eq. (6)
    assert sp.simplify(sp.diff(s, phi, 2) - e * sp.cos(phi)) == 0  # eq. (7)


def test_example_program_is_exactly_e_one_minus_cos() -> None:
    d = load_example("popa-eccentric")
    theta = np.linspace(0.0, 2.0 * math.pi, 7201)
    m = d.program.evaluate(theta)
    # Simple-harmonic rise and return of h = 2e over 180° each are e(1 − cos θ) exactly:
    # agreement to rounding (1e-12 mm) is the claim.
    assert_allclose(m.lift, E_MM * (1 - np.cos(theta)), atol=1e-12)
    assert_allclose(m.velocity, E_MM * np.sin(theta), atol=1e-12)
    assert_allclose(m.acceleration, E_MM * np.cos(theta), atol=1e-12)
    assert_allclose(m.jerk, -E_MM * np.sin(theta), atol=1e-12)


def test_synthesised_profile_is_the_eccentric_circle() -> None:
    d = load_example("popa-eccentric")
    theta = np.linspace(0.0, 2.0 * math.pi, 721)
    k = kinematics(d, theta)
    # The profile through the instant centre (THEORY §2.1) is the circle r = 30 mm centred
    # 5 mm from the pivot, opposite the reference radial.
    assert_allclose(np.hypot(k.contact_x_mm + E_MM, k.contact_y_mm), R_MM, atol=1e-11)
    assert_allclose(k.curvature_radius_mm, R_MM, atol=1e-9)


def test_contact_engine_on_the_true_circle_gives_popas_lift() -> None:
    # The circle as a polygon of four convex arcs (exact geometry, no sampling).
    ang = np.radians([0.0, 90.0, 180.0, 270.0])
    verts = np.column_stack([-E_MM + R_MM * np.cos(ang), R_MM * np.sin(ang)])
    circle = PolygonShape(verts, np.full(4, math.tan(math.pi / 8)))
    d = load_example("popa-eccentric")
    theta = np.linspace(0.0, 2.0 * math.pi, 3601)
    res = follow(circle, d.mechanism, theta)
    assert_allclose(res.lift, E_MM * (1 - np.cos(theta)), atol=1e-12)
    assert_allclose(res.acceleration, E_MM * np.cos(theta), atol=1e-11)
