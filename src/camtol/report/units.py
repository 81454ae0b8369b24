"""Display units and number formatting shared by the terminal, the files and the plots.

The rule for display units (issue 13 item 7): a quantity whose unit is a length in µm
(``um``, ``um/s``, ``um/s2``, ``um/rad``, …) is shown in µm while its largest magnitude
is below 10 000, in mm from 10 000 µm, and in m from 10 000 000 µm, so a figure never
shows more than four digits before the decimal point. Units are spelled one way in
user-facing text (``µm/rad²``, ``m/s²``, ``°``) and ASCII in file column names and JSON
keys (``um_per_rad2``). Numbers in text carry five significant digits; JSON numbers are
rounded to ten significant digits at emission (no ``14.999999999999998``).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = [
    "JSON_SIGNIFICANT_DIGITS",
    "file_unit",
    "fmt",
    "json_number",
    "json_ready",
    "magnitude_unit",
    "pretty_unit",
]

#: Significant digits kept in JSON numbers.
JSON_SIGNIFICANT_DIGITS = 10

_SUPERSCRIPT = {"2": "²", "3": "³"}


def pretty_unit(unit: str) -> str:
    """ASCII unit -> display unit: ``um/rad2`` -> ``µm/rad²``, ``deg`` -> ``°``.

    Parameters
    ----------
    unit : str
        ASCII display unit (:func:`camtol.report.display.display_unit`: ``um``, ``deg``,
        ``mm/s2``, ``-``).

    Returns
    -------
    str
        The unit as users read it.
    """
    if unit == "deg":
        return "°"
    out = unit.replace("um", "µm").replace("deg", "°")
    for d, sup in _SUPERSCRIPT.items():
        out = out.replace(f"rad{d}", f"rad{sup}").replace(f"s{d}", f"s{sup}")
    return out


def file_unit(unit: str) -> str:
    """Display or ASCII unit -> column/key suffix: ``µm/rad²`` -> ``um_per_rad2``.

    Parameters
    ----------
    unit : str
        Unit in either spelling.

    Returns
    -------
    str
        ASCII snake_case suffix.
    """
    out = unit.replace("µ", "u").replace("°", "deg").replace("²", "2").replace("³", "3")
    return out.replace("/", "_per_")


def magnitude_unit(unit: str, largest: float) -> tuple[str, float]:
    """Choose the display unit of a µm-based quantity from its largest magnitude.

    Parameters
    ----------
    unit : str
        ASCII unit, e.g. ``um/s2``; units not starting with ``um`` are returned as is.
    largest : float
        Largest magnitude of the values, in ``unit``.

    Returns
    -------
    tuple of (str, float)
        The ASCII unit to show (``um…``, ``mm…`` or ``m…``) and the factor to multiply
        the values by.
    """
    if not unit.startswith("um") or not math.isfinite(largest):
        return unit, 1.0
    rest = unit[2:]
    if abs(largest) >= 1e7:
        return "m" + rest, 1e-6
    if abs(largest) >= 1e4:
        return "mm" + rest, 1e-3
    return unit, 1.0


def fmt(v: float, digits: int = 5) -> str:
    """Format a number with ``digits`` significant digits, no exponent for usual sizes.

    Parameters
    ----------
    v : float
        Value.
    digits : int
        Significant digits.

    Returns
    -------
    str
        E.g. ``42.303``, ``18966``, ``0.0012346``; ``inf``/``nan`` as such.
    """
    if v == 0 or not math.isfinite(v):
        return f"{v:g}"
    mag = math.floor(math.log10(abs(v)))
    if mag < -4:  # e.g. a numerically zero error on a dwell
        return f"{v:.{digits - 1}e}"
    if mag >= digits - 1:
        return f"{v:.0f}"
    return f"{v:.{digits - 1 - mag}f}"


def json_number(v: float) -> float | None:
    """Round a float to :data:`JSON_SIGNIFICANT_DIGITS`; None for inf or nan (strict JSON).

    Parameters
    ----------
    v : float
        Value.

    Returns
    -------
    float or None
        The rounded value, or None when not finite.
    """
    if not math.isfinite(v):
        return None
    if v == 0:
        return 0.0
    return float(f"{v:.{JSON_SIGNIFICANT_DIGITS}g}")


def json_ready(obj: Any) -> Any:
    """Return ``obj`` with every float rounded by :func:`json_number` (recursively).

    Parameters
    ----------
    obj : Any
        Nested dicts, lists, tuples, numbers, strings, None and numpy scalars.

    Returns
    -------
    Any
        Plain JSON-ready data (tuples become lists, numpy scalars Python numbers).
    """
    if isinstance(obj, dict):
        return {str(k): json_ready(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_ready(v) for v in obj]
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if hasattr(obj, "tolist") and getattr(obj, "ndim", 0) > 0:  # numpy array
        return json_ready(obj.tolist())
    if hasattr(obj, "item") and not isinstance(obj, (int, float)):  # numpy scalar
        obj = obj.item()
    if isinstance(obj, bool):
        return obj
    if isinstance(obj, int):
        return obj
    if isinstance(obj, float):
        return json_number(obj)
    return str(obj)
