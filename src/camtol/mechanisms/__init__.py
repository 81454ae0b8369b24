"""Follower mechanisms: one module per follower type (THEORY §2, §3)."""

from __future__ import annotations

from camtol.mechanisms.base import ContactGeometry, ErrorSource, Mechanism, shift_angle
from camtol.mechanisms.flat_oscillating import FlatOscillating
from camtol.mechanisms.flat_translating import FlatTranslating
from camtol.mechanisms.roller_oscillating import RollerOscillating
from camtol.mechanisms.roller_translating import RollerTranslating

#: Follower types by the name used in design files.
MECHANISMS: dict[str, type[Mechanism]] = {
    FlatTranslating.kind: FlatTranslating,
    FlatOscillating.kind: FlatOscillating,
    RollerTranslating.kind: RollerTranslating,
    RollerOscillating.kind: RollerOscillating,
}
# The conjugate pair (camtol.mechanisms.conjugate.ConjugatePair, kind "conjugate") is not
# imported here: it builds on camtol.design and camtol.kinematics, which import this package.

__all__ = [
    "MECHANISMS",
    "ContactGeometry",
    "ErrorSource",
    "FlatOscillating",
    "FlatTranslating",
    "Mechanism",
    "RollerOscillating",
    "RollerTranslating",
    "shift_angle",
]
