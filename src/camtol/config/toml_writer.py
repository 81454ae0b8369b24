"""A small TOML writer for camtol's own files (design files written back, ``dump_design``).

Writes strings, booleans, integers, floats (shortest round-trip ``repr``; ``inf`` and
``nan`` as TOML spells them), arrays and tables. Top-level scalars first, then one
``[table]`` per mapping; mappings inside arrays and deeper mappings become inline tables.
Only what camtol writes is supported: keys are bare when they can be, quoted otherwise.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["dumps", "value"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else _string(k)


def _string(s: str) -> str:
    # JSON's escapes are valid TOML basic-string escapes; DEL must be escaped in TOML.
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def value(x: Any) -> str:
    """Return the TOML text of one value (scalar, array or inline table).

    Parameters
    ----------
    x : str, bool, int, float, sequence or mapping
        The value.

    Returns
    -------
    str
        Its TOML representation.

    Raises
    ------
    TypeError
        For a type TOML cannot hold (e.g. None).
    """
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(x, str):
        return _string(x)
    if isinstance(x, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {value(v)}" for k, v in x.items()) + " }"
    if isinstance(x, Sequence):
        return "[" + ", ".join(value(v) for v in x) + "]"
    raise TypeError(f"TOML cannot hold {type(x).__name__} values")


def _entry(k: str, v: Any) -> str:
    """``key = value``; long arrays and arrays of tables one item (or 8 numbers) per line."""
    if isinstance(v, Sequence) and not isinstance(v, str) and v:
        if any(isinstance(x, Mapping) for x in v):
            rows = [value(x) for x in v]
        elif len(v) > 8:
            rows = [", ".join(value(x) for x in v[i : i + 8]) for i in range(0, len(v), 8)]
        else:
            rows = []
        if rows:
            return f"{_key(k)} = [\n" + "".join(f"  {r},\n" for r in rows) + "]"
    return f"{_key(k)} = {value(v)}"


def dumps(doc: Mapping[str, Any]) -> str:
    """Return a TOML document: scalars and arrays first, then one table per mapping.

    Parameters
    ----------
    doc : mapping
        Top-level keys; mapping values become ``[tables]`` (their own mapping values are
        inline tables). None values are left out.

    Returns
    -------
    str
        The document, ending with a newline.
    """
    lines: list[str] = []
    tables: list[tuple[str, Mapping[str, Any]]] = []
    for k, v in doc.items():
        if v is None:
            continue
        if isinstance(v, Mapping):
            tables.append((k, v))
        else:
            lines.append(_entry(k, v))
    for name, table in tables:
        lines.append("")
        lines.append(f"[{_key(name)}]")
        for k, v in table.items():
            if v is not None:
                lines.append(_entry(k, v))
    return "\n".join(lines) + "\n"
