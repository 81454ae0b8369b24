"""The contact engine: exact follower motion from any cam shape (THEORY §5).

Shapes (:mod:`~camtol.contact.shapes`): analytic profiles with radial or normal error
functions (:mod:`~camtol.contact.errors_profile`), and polygons with straight or
circular-arc edges (measured point clouds, exported polylines, cut cams). Followers:
flat faces (:mod:`~camtol.contact.flat`), rollers (:mod:`~camtol.contact.roller`) and the
conjugate measuring fixture (:mod:`~camtol.pair.contact_fixture`). :func:`follow` solves the
follower's contact element and returns a :class:`FollowerMotion` (the analytic engine's
:class:`~camtol.design.motion.MotionState` plus the contact point).

Examples
--------
>>> import numpy as np
>>> from camtol.config.design_file import load_example
>>> d = load_example("cw06-translating")
>>> theta = np.radians([0.0, 60.0, 150.0])
>>> res = follow(AnalyticShape(d.mechanism, d.program), d.mechanism, theta)
>>> bool(np.allclose(res.lift, d.program.evaluate(theta).lift, atol=1e-9))
True
"""

from __future__ import annotations

from typing import Any

from camtol import _compat
from camtol.contact.engine import follow
from camtol.contact.errors_profile import (
    CallableError,
    FourierError,
    ProfileError,
    TabulatedError,
)
from camtol.contact.result import FollowerMotion
from camtol.contact.shapes import AnalyticShape, PolygonShape, Support

__all__ = [
    "AnalyticShape",
    "CallableError",
    "FollowerMotion",
    "FourierError",
    "PolygonShape",
    "ProfileError",
    "Support",
    "TabulatedError",
    "follow",
]


def __getattr__(name: str) -> Any:
    """Return a name moved to :mod:`camtol.pair` (the fixture simulation), with a warning."""
    return _compat.moved_name(__name__, name)
