"""Follower mechanisms: one module per follower type (THEORY §2, §3)."""

from __future__ import annotations

from camtol.mechanisms.base import ContactGeometry, ErrorSource, Mechanism, shift_angle
from camtol.mechanisms.flat_oscillating import FlatOscillating
from camtol.mechanisms.flat_translating import FlatTranslating

#: Follower types by the name used in design files.
MECHANISMS: dict[str, type[Mechanism]] = {
    FlatTranslating.kind: FlatTranslating,
    FlatOscillating.kind: FlatOscillating,
}

__all__ = [
    "MECHANISMS",
    "ContactGeometry",
    "ErrorSource",
    "FlatOscillating",
    "FlatTranslating",
    "Mechanism",
    "shift_angle",
]
