"""What a follower type declares about itself: file parameters and the registry.

A follower type is one class (:class:`camtol.mechanisms.base.Mechanism` subclass) that
states its design-file fields here, as :class:`Parameter` objects, and registers itself
with :func:`register_follower`. The design-file schema (:mod:`camtol.config.design_file`), the
writer of design files and every table of types derive from :data:`FOLLOWER_TYPES`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

__all__ = [
    "LENGTH_RANGE_MM",
    "OFFSET_RANGE_MM",
    "Parameter",
    "length",
    "offset",
]


#: Plausible range of a length in a design file (STYLE: bounds stated in the schema). [mm]
LENGTH_RANGE_MM: tuple[float, float] = (1e-3, 1e5)
#: Plausible range of a signed offset. [mm]
OFFSET_RANGE_MM: tuple[float, float] = (-1e5, 1e5)


@dataclass(frozen=True)
class Parameter:
    """A follower dimension as written in the ``[follower]`` table of a design file.

    The design-file schema (:mod:`camtol.config.design_file`) is derived from these declarations, so
    a follower type states its fields, units, bounds and defaults once, here.

    Attributes
    ----------
    name : str
        Field name in the file, with its unit suffix (``"arm_a_mm"``, ``"face_angle_deg"``).
    attribute : str
        The mechanism's dataclass field it sets (``"face_angle_rad"``).
    description : str
        What it is, e.g. ``"arm length l_A = |O3C|"``.
    minimum, maximum : float
        Allowed range in the file unit; ``exclusive`` says whether the ends are excluded.
    default : float or None
        Value when the field is omitted; ``required`` fields have none.
    required : bool
        The file must give it.
    exclusive : bool
        The range is open (minimum < x < maximum) rather than closed.
    """

    name: str
    attribute: str
    description: str
    minimum: float
    maximum: float
    default: float | None = None
    required: bool = True
    exclusive: bool = False

    @property
    def unit(self) -> Literal["mm", "deg"]:
        """File unit, from the name's suffix: ``"mm"`` or ``"deg"``."""
        return "deg" if self.name.endswith("_deg") else "mm"

    def to_internal(self, value: float | None) -> float | None:
        """File value → the mechanism field's unit (degrees → radians; None stays None).

        Parameters
        ----------
        value : float or None
            Value in the file unit. [mm or deg]

        Returns
        -------
        float or None
            Value in the internal unit. [mm or rad]
        """
        if value is None:
            return None
        return math.radians(value) if self.unit == "deg" else float(value)

    def describe_range(self) -> str:
        """Describe the allowed range, e.g. ``"0.001 ≤ x ≤ 1e+05 mm"``."""
        op = "<" if self.exclusive else "≤"
        return f"{self.minimum:g} {op} x {op} {self.maximum:g} {self.unit}"


def length(
    name: str, description: str, *, default: float | None = None, optional: bool = False
) -> Parameter:
    """Declare a positive length in the plausible range :data:`LENGTH_RANGE_MM`.

    Parameters
    ----------
    name : str
        File field name ending in ``_mm``; also the dataclass field.
    description : str
        What it is.
    default : float, optional
        Makes the field optional. [mm]
    optional : bool
        The field may be omitted without a default (the mechanism gets None).

    Returns
    -------
    Parameter
        The declaration.
    """
    lo, hi = LENGTH_RANGE_MM
    return Parameter(name, name, description, lo, hi, default, default is None and not optional)


def offset(name: str, description: str, *, default: float = 0.0) -> Parameter:
    """Declare a signed offset in :data:`OFFSET_RANGE_MM` (optional, default 0).

    Parameters
    ----------
    name : str
        File field name ending in ``_mm``; also the dataclass field.
    description : str
        What it is.
    default : float
        Value when omitted. [mm]

    Returns
    -------
    Parameter
        The declaration.
    """
    lo, hi = OFFSET_RANGE_MM
    return Parameter(name, name, description, lo, hi, default, False)
