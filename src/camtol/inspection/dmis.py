"""DMIS output: the measured points of a CMM's DMIS results file (ANSI/DMIS 105.2, ISO 22093).

Measuring machines report results in DMIS (Dimensional Measuring Interface Standard). A
``.dmi``/``.dmo`` output file states the length unit (``UNITS/MM,ANGDEC``; ``MM``, ``CM``,
``M``/``METER``, ``INCH`` or ``FEET``) and, for each measured point feature, its actual
(``FA``) values::

    UNITS/MM,ANGDEC
    F(P1)=FEAT/POINT,CART,40.0,0.0,0.0,1,0,0       $$ nominal: ignored
    FA(P1)=FEAT/POINT,CART,40.0012,0.0003,0.0,1,0,0

Statements continue over lines that end in ``$``; ``$$`` starts a comment. camtol reads
``FA(label)=FEAT/POINT,CART,x,y,z[,i,j,k]`` in the unit of the last ``UNITS`` before it
(z and the vector are not used: a disk cam is planar; an actual point is already
probe-compensated) and flags a point whose label starts with ``BORE`` as a bore point.
:func:`camtol.inspection.cmm.read_scan` reads a file with one of :data:`DMIS_SUFFIXES`
through :func:`read_dmis_points`.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from camtol.exceptions import InputFileError
from camtol.jet import FloatArray

__all__ = ["DMIS_SUFFIXES", "DMIS_UNITS_MM", "read_dmis_points"]

#: File suffixes read as DMIS output.
DMIS_SUFFIXES = (".dmi", ".dmo")
#: DMIS length units (the UNITS statement) and their size. [mm]
DMIS_UNITS_MM = {"MM": 1.0, "CM": 10.0, "M": 1000.0, "METER": 1000.0, "INCH": 25.4, "FEET": 304.8}
_DMIS_UNITS = DMIS_UNITS_MM
_DMIS_FA = re.compile(r"^FA\(([^)]*)\)\s*=\s*FEAT/POINT\s*,(.*)$", re.IGNORECASE)
_DMIS_UNITS_RE = re.compile(r"^UNITS\s*/\s*([A-Z]+)", re.IGNORECASE)


def read_dmis_points(
    path: str | Path,
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_], NDArray[np.intp]]:
    """Read the measured points of a DMIS output file (see the module notes).

    Parameters
    ----------
    path : str or Path
        The ``.dmi``/``.dmo`` file.

    Returns
    -------
    x_mm, y_mm : ndarray
        The points in mm (z and the vector i, j, k are not used: a planar cam). [mm]
    bore : ndarray of bool
        Points whose label starts with ``BORE``.
    lines : ndarray of int
        The file line (1-based) of each point's statement.

    Raises
    ------
    InputFileError
        Unreadable file, an unknown unit, a malformed ``FA(...)=FEAT/POINT`` statement,
        a point before any ``UNITS`` statement, or no measured point at all.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8-sig", errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{source}: cannot read the DMIS file ({exc})") from None
    statements: list[tuple[int, str]] = []
    pending, start = "", 0
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("$$", 1)[0].strip()
        if not line and not pending:
            continue
        if not pending:
            start = lineno
        if line.endswith("$"):  # continued on the next line
            pending += line[:-1]
            continue
        statements.append((start, pending + line))
        pending = ""
    if pending:
        statements.append((start, pending))
    scale: float | None = None
    xs: list[float] = []
    ys: list[float] = []
    bores: list[bool] = []
    lines: list[int] = []
    for lineno, st in statements:
        m = _DMIS_UNITS_RE.match(st)
        if m:
            unit = m.group(1).upper()
            if unit not in _DMIS_UNITS:
                raise InputFileError(
                    f"{source}, line {lineno}: UNITS/{m.group(1)} is not a known length unit;"
                    f" allowed: {', '.join(_DMIS_UNITS)}"
                )
            scale = _DMIS_UNITS[unit]
            continue
        m = _DMIS_FA.match(st)
        if not m:
            continue
        fields = [f.strip() for f in m.group(2).split(",")]
        try:
            if fields[0].upper() != "CART" or len(fields) not in (4, 7):
                raise ValueError
            x, y, _z = (float(v) for v in fields[1:4])
            if not (math.isfinite(x) and math.isfinite(y)):
                raise ValueError
        except ValueError:
            raise InputFileError(
                f"{source}, line {lineno}: {st[:60]!r} is not a measured point; allowed"
                " FA(label)=FEAT/POINT,CART,x,y,z[,i,j,k]"
            ) from None
        if scale is None:
            raise InputFileError(
                f"{source}, line {lineno}: a point before any UNITS statement; give"
                " UNITS/MM,ANGDEC (or INCH, CM, M, FEET) first"
            )
        xs.append(x * scale)
        ys.append(y * scale)
        bores.append(m.group(1).strip().upper().startswith("BORE"))
        lines.append(lineno)
    if not xs:
        raise InputFileError(
            f"{source}: no measured point (FA(label)=FEAT/POINT,CART,x,y,z,i,j,k) in the DMIS file"
        )
    return (
        np.asarray(xs, dtype=float),
        np.asarray(ys, dtype=float),
        np.asarray(bores, dtype=bool),
        np.asarray(lines, dtype=np.intp),
    )
