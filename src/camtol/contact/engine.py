"""`follow`: the contact engine's entry point (THEORY §5).

The follower says what it presents to the cam
(:meth:`~camtol.mechanisms.base.Mechanism.contact_element`: a roller on a line or a
circle, a translating or an oscillating flat face); the engine solves each kind of element
exactly. There is no table of follower types: a new follower class that returns one of
these elements works here unchanged.

Argument order, as everywhere in camtol: what is evaluated first (the shape and the
follower; elsewhere the design), then the cam angles, then keyword-only options.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camtol.contact.flat import Shape, follow_flat_oscillating, follow_flat_translating
from camtol.contact.result import FollowerMotion
from camtol.contact.roller import follow_roller
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.mechanisms.base import Mechanism
from camtol.mechanisms.elements import OscillatingFace, RollerGuide, TranslatingFace

__all__ = ["follow"]


def follow(
    shape: Shape,
    follower: Mechanism,
    theta_rad: ArrayLike,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
    **options: Any,
) -> FollowerMotion:
    """Exact follower motion on a cam shape (THEORY §5).

    Parameters
    ----------
    shape : AnalyticShape or PolygonShape
        The cam, in the cam frame. [mm]
    follower : Mechanism
        The actual follower; its dimensions define the contact (its profile parameters,
        e.g. r_b, are only used through ``reference``).
    theta_rad : array_like
        Cam angles. [rad]
    reference : Mechanism, optional
        The follower that defines S = 0 (default: ``follower``); pass the nominal
        mechanism when simulating a perturbed follower
        (:meth:`~camtol.mechanisms.base.Mechanism.perturbed`).
    left_limit : array_like of bool, optional
        Rows taking one-sided (left) derivatives at profile boundaries.
    **options
        Passed to the element's solver (e.g. ``initial_rad`` for an oscillating face).

    Returns
    -------
    FollowerMotion

    Raises
    ------
    DesignError
        If the follower type has no exact-contact solver.

    Notes
    -----
    The former order ``follow(theta_rad, shape, follower)`` is still accepted, with a
    :class:`DeprecationWarning`, while the code built on it moves to the one order.
    """
    if isinstance(follower, AnalyticShape | PolygonShape):  # the former order
        warnings.warn(
            "follow(theta, shape, follower) is deprecated; use follow(shape, follower, theta)",
            DeprecationWarning,
            stacklevel=2,
        )
        old_theta: Any = shape
        shape, follower = follower, theta_rad  # type: ignore[assignment]
        theta_rad = np.asarray(old_theta, dtype=float)
    element = follower.contact_element()
    if isinstance(element, RollerGuide):
        return follow_roller(
            shape, follower, theta_rad, reference=reference, left_limit=left_limit, **options
        )
    if isinstance(element, TranslatingFace):
        return follow_flat_translating(
            shape, follower, theta_rad, reference=reference, left_limit=left_limit
        )
    assert isinstance(element, OscillatingFace)
    return follow_flat_oscillating(
        shape, follower, theta_rad, reference=reference, left_limit=left_limit, **options
    )
