"""Contact points turned into the cam frame when first read (analysis.state.ContactPoints)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from camtol.analysis.engine import evaluate_engine
from camtol.analysis.kinematics import ContactPoints, analysis_grid
from camtol.analysis.result import analyse
from camtol.config.design_file import example_names, load_example

RNG = np.random.default_rng(11)


def _frame_points(n: int) -> ContactPoints:
    xa, ya, xq, yq = RNG.uniform(-60.0, 60.0, (4, n))
    return ContactPoints(xa, ya, xq, yq, turn_rad=RNG.uniform(0.0, 2.0 * np.pi, n))


def test_the_turn_is_the_rotation_by_theta_bit_for_bit_and_kept() -> None:
    p = _frame_points(1_000)
    assert p.turn_rad is not None
    c, s = np.cos(p.turn_rad), np.sin(p.turn_rad)
    xa, ya, xq, yq = p.cam_frame
    # The same elementwise formula as the mechanisms' own turn: equal, not merely close.
    np.testing.assert_array_equal(xa, c * p.contact_x_mm - s * p.contact_y_mm)
    np.testing.assert_array_equal(ya, s * p.contact_x_mm + c * p.contact_y_mm)
    np.testing.assert_array_equal(xq, c * p.centre_x_mm - s * p.centre_y_mm)
    np.testing.assert_array_equal(yq, s * p.centre_x_mm + c * p.centre_y_mm)
    assert p.cam_frame[0] is xa  # computed once


def test_points_already_in_the_cam_frame_are_returned_as_they_are() -> None:
    xa, ya, xq, yq = RNG.uniform(-60.0, 60.0, (4, 10))
    p = ContactPoints(xa, ya, xq, yq)
    assert all(a is b for a, b in zip(p.cam_frame, (xa, ya, xq, yq), strict=True))


@pytest.mark.parametrize("other_turned", [True, False])
def test_joined_points_are_the_rows_of_both(other_turned: bool) -> None:
    a = _frame_points(7)
    b = _frame_points(5) if other_turned else ContactPoints(*RNG.uniform(-1.0, 1.0, (4, 5)))
    j = a.joined(b)
    assert (j.turn_rad is not None) == other_turned  # two deferred turns stay deferred
    for got, first, second in zip(j.cam_frame, a.cam_frame, b.cam_frame, strict=True):
        np.testing.assert_array_equal(got, np.concatenate([first, second]))


def test_stored_rows_are_spread_over_the_rows_that_repeat_them() -> None:
    rows = np.array([True, False, False, True, True, False, True])
    xa, ya, xq = RNG.uniform(-60.0, 60.0, (3, 4))
    yq = np.broadcast_to(0.0, (4,))  # a constant stays a constant
    turn = RNG.uniform(0.0, 2.0 * np.pi, rows.size)
    p = ContactPoints(xa, ya, xq, yq, turn_rad=turn, rows=rows)
    index = [0, 0, 0, 1, 2, 2, 3]
    full = ContactPoints(xa[index], ya[index], xq[index], np.zeros(rows.size), turn_rad=turn)
    for got, want in zip(p.cam_frame, full.cam_frame, strict=True):
        np.testing.assert_array_equal(got, want)
    j = p.joined(_frame_points(3))
    assert j.rows is None and j.turn_rad is not None
    for got, first in zip(j.cam_frame, full.cam_frame, strict=True):
        np.testing.assert_array_equal(got[: rows.size], first)


@pytest.mark.parametrize("name", example_names())
def test_dwells_store_their_points_once_and_read_the_same(name: str) -> None:
    """A dwell's points are stored once; read, they are those of every row, bit for bit."""
    for cam in load_example(name).cams():
        theta, left = analysis_grid(0.1, cam.design.program.boundaries_rad)
        stored, _ = evaluate_engine(cam.design, theta, left, check=False, sensitivities=False)
        # Chunks shorter than 1024 rows are evaluated row by row, dwells included.
        every, _ = evaluate_engine(cam.design, theta, left, check=False, chunk=1_000)
        assert every.contact_points.rows is None
        rows = stored.contact_points.rows
        if rows is not None:  # the cam dwells (popa-eccentric has no dwell)
            assert stored.contact_points.contact_x_mm.size == np.count_nonzero(rows) < rows.size
        else:
            assert stored.contact_points.contact_x_mm.size == theta.size
        for got, want in zip(
            stored.contact_points.cam_frame, every.contact_points.cam_frame, strict=True
        ):
            np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("name", example_names())
def test_analyse_leaves_the_profile_unturned_until_it_is_read(name: str) -> None:
    """The analysis never reads the profile points, so it never pays for their turn."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pressure-angle warnings of demonstration designs
        a = analyse(load_example(name), step_deg=1.0)
    kins = [a.kinematics, *(k for _, k in a.other_cams)]
    for kin in kins:
        assert "cam_frame" not in vars(kin.contact_points)  # not turned yet
        x = kin.contact_x_mm
        assert x.shape == kin.theta_rad.shape and np.all(np.isfinite(x))
        assert "cam_frame" in vars(kin.contact_points)
        # |O2A| is the same in either frame.
        np.testing.assert_allclose(
            np.hypot(kin.contact_x_mm, kin.contact_y_mm), kin.radius_mm, rtol=1e-13
        )
