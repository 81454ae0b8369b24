"""Contact points turned into the cam frame when first read (camtol.kinematics.ContactPoints)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from camtol.analysis import analyse
from camtol.config import example_names, load_example
from camtol.kinematics import ContactPoints

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
