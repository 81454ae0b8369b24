"""The output guard: no NaN or infinity ever reaches a file or the JSON camtol prints.

Every writer (CSV curves, profile CSV/DXF/SVG, HTML report, figures, ``--json``) passes
its numbers through :func:`require_finite_columns` or :func:`json_text` first. A
non-finite value is an :class:`~camtol.exceptions.OutputError` naming the quantity (column
or JSON key) and, for curves, the cam angle where it first occurs; nothing is written.
"""

from __future__ import annotations

import json
import math
from collections.abc import Collection, Mapping
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import OutputError

__all__ = [
    "json_text",
    "require_finite",
    "require_finite_columns",
    "require_finite_json",
    "require_no_nan_json",
]


def require_finite(
    name: str, values: ArrayLike, *, theta_deg: ArrayLike | None = None, where: str = ""
) -> None:
    """Raise unless every value is finite.

    Parameters
    ----------
    name : str
        Quantity as the output names it (column, layer or key).
    values : array_like
        The numbers.
    theta_deg : array_like, optional
        Cam angles of the values (same shape), to name where the first bad one is. [deg]
    where : str
        Output described in the message, e.g. ``"--curves"``.

    Raises
    ------
    OutputError
        A value is NaN or infinite.
    """
    v = np.asarray(values)
    if v.dtype.kind not in "fc":
        return
    ok = np.isfinite(v)
    if bool(np.all(ok)):
        return
    i = int(np.argmax(~ok.ravel()))
    bad = v.ravel()[i].item()
    at = ""
    if theta_deg is not None:
        t = np.broadcast_to(np.asarray(theta_deg, dtype=float), v.shape).ravel()
        at = f" at θ={float(t[i]):.6g}°"
    out = f" in {where}" if where else ""
    raise OutputError(
        f"{name} is {bad!r}{at}{out}: the result is not a finite number there (the design"
        " is outside the range where the computation holds); nothing was written"
    )


def require_finite_columns(
    columns: Mapping[str, ArrayLike],
    *,
    angle: str = "theta_deg",
    optional: Collection[str] = (),
    where: str = "",
) -> None:
    """Raise unless every column is finite (``optional`` columns may be entirely NaN).

    Parameters
    ----------
    columns : mapping of str to array_like
        Columns keyed by their name in the file.
    angle : str
        Name of the cam-angle column used to say where a bad value is. [deg]
    optional : collection of str
        Columns that may be absent as a whole (all NaN, written as empty cells), such as
        the estimates of an inspection without measurement.
    where : str
        Output described in the message.

    Raises
    ------
    OutputError
        A value is NaN or infinite (first column in order, first angle).
    """
    theta = columns.get(angle)
    for name, values in columns.items():
        v = np.asarray(values)
        if name in optional and v.dtype.kind == "f" and bool(np.all(np.isnan(v))):
            continue
        require_finite(name, v, theta_deg=theta, where=where)


def require_finite_json(doc: Any, path: str = "") -> None:
    """Raise if a float anywhere in a JSON-like document is NaN or infinite.

    Parameters
    ----------
    doc : object
        Nested dicts, lists, tuples and scalars (numpy scalars included).
    path : str
        Key path of ``doc`` (used in the message).

    Raises
    ------
    OutputError
        Naming the key path, e.g. ``extremes.dS_worst.max.value``.
    """
    if isinstance(doc, Mapping):
        for k, v in doc.items():
            require_finite_json(v, f"{path}.{k}" if path else str(k))
    elif isinstance(doc, (list, tuple)):
        for i, v in enumerate(doc):
            require_finite_json(v, f"{path}[{i}]")
    elif isinstance(doc, np.ndarray):
        require_finite(path or "value", doc, where="the JSON output")
    elif isinstance(doc, (float, np.floating)) and not math.isfinite(float(doc)):
        raise OutputError(
            f"{path or 'value'} is {float(doc)!r} in the JSON output: the result is not a"
            " finite number (the design is outside the range where the computation holds)"
        )


def require_no_nan_json(doc: Any, path: str = "") -> None:
    """Raise if a float anywhere in a JSON-like document is NaN (infinities pass).

    The JSON emitter writes an infinity as null ("none", e.g. no concave stretch); a NaN
    is a failed computation and must never be printed.

    Parameters
    ----------
    doc : object
        Nested dicts, lists, tuples and scalars (numpy scalars and arrays included).
    path : str
        Key path of ``doc`` (used in the message).

    Raises
    ------
    OutputError
        Naming the key path of the first NaN.
    """
    found = _nan_path(doc)
    if found is None:
        return
    keys, array = found
    where = path
    for key in reversed(keys):
        where = (
            f"{where}[{key}]" if isinstance(key, int) else (f"{where}.{key}" if where else str(key))
        )
    if array:
        raise OutputError(f"{where or 'value'} holds NaN in the JSON output; nothing was printed")
    raise OutputError(
        f"{where or 'value'} is nan in the JSON output: the result is not a number (the"
        " design is outside the range where the computation holds); nothing was printed"
    )


def _nan_path(doc: Any) -> tuple[list[Any], bool] | None:
    """Keys to the first NaN in ``doc``, innermost first, and whether it is in an array.

    The keys are collected only on the way back from a NaN: a document of 10,000 parts
    is checked without formatting 70,000 key paths (``records stats --json``).
    """
    if isinstance(doc, float):
        return ([], False) if doc != doc else None
    if isinstance(doc, Mapping):
        items: Any = doc.items()
    elif isinstance(doc, (list, tuple)):
        items = enumerate(doc)
    elif isinstance(doc, np.ndarray):
        return ([], True) if doc.dtype.kind in "fc" and np.any(np.isnan(doc)) else None
    elif isinstance(doc, np.floating):
        return ([], False) if math.isnan(float(doc)) else None
    else:
        return None
    for key, value in items:
        if isinstance(value, (str, int)):  # the common leaves (bool is an int)
            continue
        found = _nan_path(value)
        if found is not None:
            found[0].append(key)
            return found
    return None


def _default(o: Any) -> Any:
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def json_text(doc: Any) -> str:
    """Serialise a document as strict JSON (never a bare ``NaN``); indent 2.

    Parameters
    ----------
    doc : object
        Nested dicts, lists and scalars.

    Returns
    -------
    str
        The JSON text.

    Raises
    ------
    OutputError
        A number is NaN or infinite (named by its key path).
    """
    require_finite_json(doc)
    return json.dumps(doc, indent=2, default=_default, allow_nan=False)
