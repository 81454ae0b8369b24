"""Follower mechanisms: one module per follower type (THEORY §2, §3).

A follower type is one class: its parameters (:mod:`camtol.mechanisms.spec`), synthesis,
sensitivities, :meth:`~camtol.mechanisms.base.Mechanism.perturbed`, contact element and
drawing. Importing this package registers the built-in types in :data:`MECHANISMS`, the
one registry (``follower.type`` → class) from which the design-file schema is derived.
"""

from __future__ import annotations

from camtol.mechanisms.base import (
    FOLLOWER_TYPES,
    ContactGeometry,
    ErrorSource,
    Mechanism,
    register_follower,
    shift_angle,
)
from camtol.mechanisms.conjugate import ConjugatePair
from camtol.mechanisms.flat_oscillating import FlatOscillating
from camtol.mechanisms.flat_translating import FlatTranslating
from camtol.mechanisms.roller_oscillating import RollerOscillating
from camtol.mechanisms.roller_translating import RollerTranslating
from camtol.mechanisms.spec import Parameter

#: Follower types by the name used in design files (``follower.type``); the registry
#: filled by :func:`~camtol.mechanisms.base.register_follower`.
MECHANISMS: dict[str, type[Mechanism]] = FOLLOWER_TYPES

__all__ = [
    "MECHANISMS",
    "ConjugatePair",
    "ContactGeometry",
    "ErrorSource",
    "FlatOscillating",
    "FlatTranslating",
    "Mechanism",
    "Parameter",
    "RollerOscillating",
    "RollerTranslating",
    "register_follower",
    "shift_angle",
]
