r"""Numeric tables as camtol writes them to CSV: one format for every command.

Ten significant digits (``.10g``; profile coordinates twelve), one header row of names
with units, ``\n`` line ends; a negative zero is written as ``0``: a velocity of ``-0``
in a dwell or a deviation of ``-0`` µm reads as a sign where there is none.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["csv_text"]


def csv_text(
    header: Sequence[str],
    data: ArrayLike,
    *,
    comment: str | None = None,
    blank_nonfinite: bool = False,
    digits: int = 10,
) -> str:
    """Return the CSV text of a numeric table.

    Parameters
    ----------
    header : sequence of str
        Column names, with their units (e.g. ``theta_deg``).
    data : array_like
        Rows × columns of numbers.
    comment : str, optional
        A first line, written as ``# comment``.
    blank_nonfinite : bool
        Write NaN and ±inf as empty fields (a value that does not apply to the row);
        otherwise callers check that every value is finite before writing.
    digits : int
        Significant digits.

    Returns
    -------
    str
    """
    rows = np.asarray(data, dtype=float) + 0.0  # -0.0 + 0.0 is +0.0 in IEEE arithmetic
    buf = io.StringIO()
    if comment is not None:
        buf.write(f"# {comment}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    spec = f".{int(digits)}g"
    if blank_nonfinite:
        w.writerows(
            [[format(x, spec) if math.isfinite(x) else "" for x in r] for r in rows.tolist()]
        )
    else:
        w.writerows([[format(x, spec) for x in r] for r in rows.tolist()])
    return buf.getvalue()
