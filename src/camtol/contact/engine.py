"""`follow`: the contact engine's entry point, dispatching on the follower type (THEORY §5)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from numpy.typing import ArrayLike

from camtol.contact.flat import Shape, follow_flat_oscillating, follow_flat_translating
from camtol.contact.result import FollowerMotion
from camtol.contact.roller import follow_roller_oscillating, follow_roller_translating
from camtol.exceptions import DesignError
from camtol.mechanisms.base import Mechanism

__all__ = ["FOLLOWERS", "follow"]

#: Exact-contact solvers by mechanism kind.
FOLLOWERS: dict[str, Callable[..., FollowerMotion]] = {
    "flat_translating": follow_flat_translating,
    "flat_oscillating": follow_flat_oscillating,
    "roller_translating": follow_roller_translating,
    "roller_oscillating": follow_roller_oscillating,
    # Cam B of a conjugate pair alone, and a conjugate pair seen as its cam A; the pair in
    # the measuring fixture is :func:`camtol.contact.fixture.simulate_fixture`.
    "conjugate_cam_b": follow_roller_oscillating,
    "conjugate": follow_roller_oscillating,
}


def follow(
    theta_rad: ArrayLike,
    shape: Shape,
    follower: Mechanism,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
    **options: Any,
) -> FollowerMotion:
    """Exact follower motion on a cam shape (THEORY §5).

    Parameters
    ----------
    theta_rad : array_like
        Cam angles. [rad]
    shape : AnalyticShape or PolygonShape
        The cam, in the cam frame. [mm]
    follower : Mechanism
        The actual follower; its dimensions define the contact (its profile parameters,
        e.g. r_b, are only used through ``reference``).
    reference : Mechanism, optional
        The follower that defines S = 0 (default: ``follower``); pass the nominal
        mechanism when simulating a perturbed follower.
    left_limit : array_like of bool, optional
        Rows taking one-sided (left) derivatives at profile boundaries.
    **options
        Passed to the follower's solver.

    Returns
    -------
    FollowerMotion

    Raises
    ------
    DesignError
        If the follower type has no exact-contact solver.
    """
    try:
        solver = FOLLOWERS[follower.kind]
    except KeyError:
        raise DesignError(
            f"follower type {follower.kind!r} has no exact-contact solver; available:"
            f" {', '.join(sorted(FOLLOWERS))}"
        ) from None
    return solver(theta_rad, shape, follower, reference=reference, left_limit=left_limit, **options)
