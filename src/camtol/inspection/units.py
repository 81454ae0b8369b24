"""Lengths as inspectors write them (``"22 um"``, ``"0.022 mm"``, ``22``) and their bounds.

Every inspection quantity of THEORY §4 (radial errors, tolerances, the follower's constant
errors, the measured centre-distance variation, indicator readings) is a small length in
µm. camtol refuses magnitudes beyond :data:`MAX_ERROR_UM` (10 mm): the linear theory of §4
is meaningless long before that, and such a value is a unit mistake (mm typed as µm, a
reading in nm) or a corrupted file, not a measurement.
"""

from __future__ import annotations

import math
import re

from camtol.exceptions import DesignError

__all__ = [
    "MAX_ANGLE_ERROR_DEG",
    "MAX_ERROR_UM",
    "check_length_um",
    "match_length_um",
    "parse_length_um",
]

#: Largest magnitude of an inspection length (error, tolerance, reading): 10 mm. [µm]
MAX_ERROR_UM = 10_000.0
#: Largest magnitude of the follower's arm-angle error Δη. [deg]
MAX_ANGLE_ERROR_DEG = 10.0

_UNITS_UM = {"um": 1.0, "µm": 1.0, "μm": 1.0, "mm": 1e3, "": 1.0}
_LENGTH = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([a-zA-Zµμ]*)\s*")


def _shown(text: object) -> str:
    r = repr(text)
    return r if len(r) <= 60 else r[:50] + "...'"


def check_length_um(value: float, *, field: str, shown: object = None) -> float:
    """Return a length after checking it is finite and within ±:data:`MAX_ERROR_UM`.

    Parameters
    ----------
    value : float
        The length. [µm]
    field : str
        Name of the input field as the user wrote it, for the message.
    shown : object, optional
        The value as the user wrote it (default: ``value``).

    Returns
    -------
    float
        ``value`` unchanged. [µm]

    Raises
    ------
    DesignError
        If it is not finite or beyond the bound.
    """
    given = value if shown is None else shown
    if not math.isfinite(value):
        raise DesignError(f"{field}={_shown(given)} is not allowed; give a finite length")
    if abs(value) > MAX_ERROR_UM:
        raise DesignError(
            f"{field}={_shown(given)} is not allowed; an inspection length must lie within"
            f" ±{MAX_ERROR_UM:g} µm (±{MAX_ERROR_UM / 1e3:g} mm): check the unit"
        )
    return value


def match_length_um(text: str) -> float | None:
    """Return the length a text gives in µm, or None when it is not a length.

    Parameters
    ----------
    text : str
        A number optionally followed by ``um``, ``µm`` or ``mm``.

    Returns
    -------
    float or None
        The length (not bound-checked: see :func:`check_length_um`). [µm]
    """
    m = _LENGTH.fullmatch(text)
    if not m or m.group(2) not in _UNITS_UM:
        return None
    return float(m.group(1)) * _UNITS_UM[m.group(2)]


def parse_length_um(text: str | float, *, field: str = "value") -> float:
    """Parse a length with an optional unit (``"22 um"``, ``"0.022mm"``, ``22``) into µm.

    Parameters
    ----------
    text : str or float
        A number followed by ``um``, ``µm`` or ``mm``, or a plain number (taken as µm).
    field : str
        Name of the input field, used in error messages.

    Returns
    -------
    float
        The length, finite and within ±:data:`MAX_ERROR_UM`. [µm]

    Raises
    ------
    DesignError
        If it is not a number followed by ``um``, ``µm`` or ``mm`` (``"1.2.3 um"``, ``"."``
        and ``".."`` included), or it is out of bounds.

    Examples
    --------
    >>> parse_length_um("0.022 mm")
    22.0
    """
    if isinstance(text, bool) or not isinstance(text, int | float | str):
        raise DesignError(
            f"{field}={_shown(text)} is not allowed; give a number with unit um or mm, e.g. '22 um'"
        )
    if isinstance(text, int | float):
        try:
            value = float(text)
        except OverflowError:  # an integer beyond the float range
            value = math.inf
    else:
        matched = match_length_um(text)
        if matched is None:
            raise DesignError(
                f"{field}={_shown(text)} is not allowed; give a number with unit um or mm,"
                " e.g. '22 um'"
            )
        value = matched
    return check_length_um(value, field=field, shown=text)
