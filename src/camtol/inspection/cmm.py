"""Coordinate-measurement (CMM) scans of a cam: reading and stylus compensation.

A scan is a file of points measured around the cam (Chang & Wu 2011 used 3,600 points
per cam with a 2 mm probe ball, [CW11] §5): surface points, or stylus-ball centres that
are compensated by the ball radius along the local normal. Registration to the nominal
profile and the deviations are in :mod:`camtol.inspection.registration` and
:mod:`camtol.inspection.deviations`.

File form (read by :func:`camtol.tables.read_table`): a header line naming the columns
with their unit, ``x_mm, y_mm`` (optionally ``z_mm``; ``_um`` and ``_in`` are accepted, one
unit for all coordinates), optional ``bore`` (1 for a point measured on the bore, used by
the bore datum), ``keyway`` (1 for a point on the keyway, the angular datum) and ``cam``
(1 for cam A, 2 for cam B, for a file holding both cams of a conjugate pair); ``#``
comments; ``,``/``;``/blank separators. Other header names can be mapped onto these
with ``aliases`` (``{"X": "x_mm"}``). A header comment that states the
stylus radius (``# stylus_radius_mm = 1.5``, or camtol's own ``# stylus-ball centres:
inspect with --stylus-radius-mm 1.5``) is read by :func:`header_stylus_radius_mm`.

A DMIS output file (``.dmi``, ``.dmo``) is read by :mod:`camtol.inspection.dmis`.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from camtol.exceptions import InputFileError
from camtol.inspection.dmis import DMIS_SUFFIXES, read_dmis_points
from camtol.jet import FloatArray
from camtol.tables import Table, read_table

__all__ = [
    "CamLabel",
    "DMIS_SUFFIXES",
    "MIN_POINTS",
    "Scan",
    "check_coverage",
    "compensate_stylus",
    "header_stylus_radius_mm",
    "local_normals",
    "read_dmis_points",
    "read_scan",
]

CamLabel = Literal["A", "B"]

#: Fewest points accepted in a scan.
MIN_POINTS = 36
#: Largest gap in polar angle allowed between neighbouring scan points. [deg]
MAX_GAP_DEG = 20.0

_UNIT_MM = {"mm": 1.0, "um": 1e-3, "µm": 1e-3, "μm": 1e-3, "in": 25.4}
_COORD = re.compile(r"^([xyz])_(mm|um|µm|μm|in)$", re.IGNORECASE)
_CAM_CODES = {"A": 1, "B": 2}

_HEADER_STYLUS = (
    re.compile(r"stylus[ _-]?(?:ball[ _-]?)?radius(?:[ _-]?mm)?\s*[:=]\s*([0-9.eE+-]+)", re.I),
    re.compile(r"--stylus-radius-mm[ =]([0-9.eE+-]+)", re.I),
)


@dataclass(frozen=True)
class Scan:
    """Points measured on one cam, in the CMM frame.

    Attributes
    ----------
    source : str
        File name (or label) used in messages.
    x_mm, y_mm : ndarray
        Surface points (stylus-compensated when read from centres). [mm]
    bore : ndarray of bool
        Points flagged as measured on the bore (excluded from the profile).
    rows : ndarray of int
        Data-row index of each point in the file (0-based; file lines via
        :meth:`line_of`).
    stylus_radius_mm : float
        Stylus-ball radius the points were compensated by (0: surface points). [mm]
    """

    source: str
    x_mm: FloatArray
    y_mm: FloatArray
    bore: NDArray[np.bool_]
    rows: NDArray[np.intp]
    stylus_radius_mm: float = 0.0
    _table: Table | None = None
    _lines: NDArray[np.intp] | None = None
    keyway: NDArray[np.bool_] | None = None

    @property
    def feature(self) -> NDArray[np.bool_]:
        """Points on a datum feature (bore or keyway), not on the profile."""
        return self.bore if self.keyway is None else (self.bore | self.keyway)

    def keyway_point(self) -> tuple[float, float] | None:
        """Centroid of the points flagged keyway, or None. [mm]"""
        if self.keyway is None or not np.any(self.keyway):
            return None
        return float(np.mean(self.x_mm[self.keyway])), float(np.mean(self.y_mm[self.keyway]))

    @property
    def size(self) -> int:
        """Number of profile points (bore and keyway points excluded)."""
        return int(np.count_nonzero(~self.feature))

    def line_of(self, index: int) -> int:
        """File line (1-based) of point ``index``; 0 when unknown.

        Parameters
        ----------
        index : int
            Index into the scan's arrays.
        """
        if self._lines is not None:
            return int(self._lines[int(self.rows[index])])
        if self._table is None:
            return 0
        return self._table.line_of(int(self.rows[index]))

    def profile_points(self) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
        """Return the profile points (bore, keyway excluded) and their scan indices. [mm]"""
        idx = np.flatnonzero(~self.feature)
        return self.x_mm[idx], self.y_mm[idx], idx


def _coordinate_columns(table: Table) -> tuple[dict[str, str], float]:
    """Map x, y (z) to column names and return the common unit's scale to mm."""
    found: dict[str, tuple[str, str]] = {}
    for name in table.names:
        m = _COORD.match(name)
        if m:
            found[m.group(1).lower()] = (name, m.group(2).lower())
    bare = [n for n in table.names if n.lower() in ("x", "y", "z")]
    if "x" not in found or "y" not in found:
        if bare:
            raise InputFileError(
                f"{table.source}: column {bare[0]!r} has no unit; name the coordinates x_mm,"
                " y_mm (or _um, _in), or map them with a column mapping such as"
                f" {bare[0]}=x_mm"
            )
        raise InputFileError(
            f"{table.source}: a scan needs the columns x_mm, y_mm (optionally z_mm, bore, cam);"
            f" found: {', '.join(table.names)}"
        )
    units = {axis: unit for axis, (_, unit) in found.items()}
    scales = {_UNIT_MM[u] for u in units.values()}
    if len(scales) > 1:
        desc = ", ".join(f"{axis} in {u}" for axis, u in sorted(units.items()))
        raise InputFileError(
            f"{table.source}: mixed units ({desc}); give every coordinate in the same unit"
        )
    return {axis: name for axis, (name, _) in found.items()}, scales.pop()


def _flag_column(table: Any, name: str, meaning: str) -> NDArray[np.bool_]:
    """Read a 0/1 flag column of a point file (all False when absent; other values refused)."""
    if name not in table:
        return np.zeros(table.rows, dtype=bool)
    v = table.column(name)
    bad = (v != 0) & (v != 1)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise InputFileError(
            f"{table.source}, line {table.line_of(i)}: column {name!r}={v[i]:g} is not"
            f" allowed; give {meaning}"
        )
    return np.asarray(v == 1)


def read_scan(
    path: str | Path,
    *,
    cam: CamLabel | None = None,
    stylus_radius_mm: float = 0.0,
    aliases: Mapping[str, str] | None = None,
) -> Scan:
    """Read a CMM point file (see the module notes for the form).

    Parameters
    ----------
    path : str or Path
        The file.
    cam : {"A", "B"}, optional
        For a file with a ``cam`` column: the cam whose points to take (required then).
    stylus_radius_mm : float
        > 0 when the points are stylus-ball centres: each is moved inwards by this radius
        along the local normal (:func:`compensate_stylus`). [mm]
    aliases : mapping of str to str, optional
        Header names to rename, e.g. ``{"X": "x_mm", "Y": "y_mm"}``.

    Returns
    -------
    Scan

    Raises
    ------
    InputFileError
        Naming the file (and the line where it applies): missing or unit-less coordinate
        columns, mixed units, non-numbers or NaN, duplicate points, a bad ``cam`` or
        ``bore`` value, too few points; for DMIS (``.dmi``, ``.dmo``): no measured point,
        an unknown unit, a malformed point, or ``aliases`` given.
    """
    if not (math.isfinite(stylus_radius_mm) and stylus_radius_mm >= 0):
        raise InputFileError(
            f"stylus radius {stylus_radius_mm!r} mm is not allowed; give a number ≥ 0 mm"
        )
    if Path(path).suffix.lower() in DMIS_SUFFIXES:
        if aliases:
            raise InputFileError(
                f"{path}: --columns maps CSV column names; a DMIS file has none (leave it out)"
            )
        x, y, bore, lines = read_dmis_points(path)
        source = str(path)
        rows = np.arange(x.size, dtype=np.intp)
        _check_duplicates(source, x, y, lambda i: int(lines[i]))
        n_profile = int(np.count_nonzero(~bore))
        if n_profile < MIN_POINTS:
            raise InputFileError(
                f"{source}: {n_profile} profile point(s); a scan needs at least"
                f" {MIN_POINTS} points round the cam"
            )
        scan = Scan(source, x, y, bore, rows, 0.0, None, lines)
        return compensate_stylus(scan, stylus_radius_mm) if stylus_radius_mm > 0 else scan
    table = read_table(
        path,
        optional=("x_mm", "y_mm", "z_mm", "bore", "keyway", "cam"),
        aliases=aliases,
        what="CMM scan",
    )
    cols, scale = _coordinate_columns(table)
    x = table.column(cols["x"]) * scale
    y = table.column(cols["y"]) * scale
    rows = np.arange(table.rows, dtype=np.intp)
    bore = _flag_column(table, "bore", "1 for a bore point, 0 for a profile point")
    keyway = _flag_column(table, "keyway", "1 for a keyway point, 0 otherwise") & ~bore
    if "cam" in table:
        c = table.column("cam")
        bad = (c != 1) & (c != 2)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise InputFileError(
                f"{table.source}, line {table.line_of(i)}: column 'cam'={c[i]:g} is not"
                " allowed; give 1 for cam A, 2 for cam B"
            )
        if cam is None:
            if np.any(c != c[0]):
                raise InputFileError(
                    f"{table.source}: the file holds points of both cams (column 'cam');"
                    " choose one with --cam A or --cam B"
                )
        else:
            keep = (c == _CAM_CODES[cam]) | bore | keyway
            x, y, bore, rows, keyway = x[keep], y[keep], bore[keep], rows[keep], keyway[keep]
    _check_duplicates(table.source, x, y, lambda i: table.line_of(int(rows[i])))
    n_profile = int(np.count_nonzero(~(bore | keyway)))
    if n_profile < MIN_POINTS:
        raise InputFileError(
            f"{table.source}: {n_profile} profile point(s); a scan needs at least"
            f" {MIN_POINTS} points round the cam"
        )
    scan = Scan(table.source, x, y, bore, rows, 0.0, table, None, keyway)
    if stylus_radius_mm > 0:
        scan = compensate_stylus(scan, stylus_radius_mm)
    return scan


def header_stylus_radius_mm(path: str | Path) -> float | None:
    """Return the stylus radius a scan's header comments state, or None. [mm]

    Recognised in the ``#`` comment lines before the first data line:
    ``stylus_radius_mm = R``, ``stylus radius: R`` and camtol's own
    ``--stylus-radius-mm R`` (:func:`camtol.inspection.twin.scan_csv_text`).

    Parameters
    ----------
    path : str or Path
        The CSV scan (a DMIS file has no such comment: None).
    """
    if Path(path).suffix.lower() in DMIS_SUFFIXES:
        return None
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = [fh.readline() for _ in range(50)]
    except OSError:
        return None
    for line in head:
        text = line.strip()
        if text and not text.startswith("#"):
            break  # the header comments end at the first other line
        for pattern in _HEADER_STYLUS:
            m = pattern.search(text)
            if m:
                try:
                    value = float(m.group(1))
                except ValueError:
                    continue
                if math.isfinite(value) and value >= 0:
                    return value
    return None


def _check_duplicates(source: str, x: FloatArray, y: FloatArray, line_of: Any) -> None:
    """Refuse a point given twice, naming both lines (``line_of(i)``: point i's line)."""
    order = np.lexsort((y, x))
    same = (np.diff(x[order]) == 0) & (np.diff(y[order]) == 0)
    if np.any(same):
        k = int(np.argmax(same))
        i, j = sorted((int(order[k]), int(order[k + 1])))
        raise InputFileError(
            f"{source}, line {line_of(j)}: duplicate point ({x[j]:g}, {y[j]:g}) mm, same as"
            f" line {line_of(i)}; every point once"
        )


def check_coverage(
    source: str, x_mm: FloatArray, y_mm: FloatArray, *, max_gap_deg: float = MAX_GAP_DEG
) -> None:
    """Refuse points that do not go round the cam (largest polar gap > ``max_gap_deg``).

    Parameters
    ----------
    source : str
        File name for the message.
    x_mm, y_mm : ndarray
        Points about the cam centre. [mm]
    max_gap_deg : float
        Largest gap allowed between neighbouring polar angles. [deg]

    Raises
    ------
    InputFileError
        Naming the gap's angles.
    """
    phi = np.sort(np.mod(np.degrees(np.arctan2(y_mm, x_mm)), 360.0))
    gaps = np.diff(np.append(phi, phi[0] + 360.0))
    k = int(np.argmax(gaps))
    if gaps[k] > max_gap_deg:
        raise InputFileError(
            f"{source}: the points do not go round the cam: no point between polar angles"
            f" {phi[k]:.1f}° and {np.mod(phi[k] + gaps[k], 360.0):.1f}° (a gap of"
            f" {gaps[k]:.1f}°, at most {max_gap_deg:g}° allowed)"
        )


def local_normals(
    x_mm: FloatArray, y_mm: FloatArray, *, span: int | None = None
) -> tuple[FloatArray, FloatArray]:
    """Outward unit normals of a closed scan, from the circle through each point's neighbours.

    The points are ordered by polar angle about their centroid; the normal at p_i is that of
    the circle through p_{i−k}, p_i, p_{i+k} (exact on a circle for any spacing), oriented
    outwards (the counterclockwise chord p_{i+k} − p_{i−k} turned clockwise), and the
    turned chord itself where the three are collinear; the median over the spans k − 1,
    k and k + 1, so that one outlying neighbour does not tilt it.

    Parameters
    ----------
    x_mm, y_mm : ndarray
        Points round the cam, any frame. [mm]
    span : int, optional
        Neighbour offset k (default: the points in about 1° of polar angle, at least 1).

    Returns
    -------
    nx, ny : ndarray
        Outward unit normals, in the input order.
    """
    n = x_mm.size
    k = max(1, round(n / 360)) if span is None else span
    # Ordered about the points' centroid: inside the cam whatever the CMM frame's origin.
    order = np.argsort(np.arctan2(y_mm - np.mean(y_mm), x_mm - np.mean(x_mm)), kind="stable")
    px, py = x_mm[order], y_mm[order]
    # Three spans k − 1, k, k + 1 and the median normal: a single outlier among the
    # neighbours spoils only one of them.
    spans = sorted({max(1, k - 1), k, k + 1}) if span is None else [k]
    cands = [_circle_normal(px, py, kk) for kk in spans]
    nx, ny = cands[len(cands) // 2]
    if len(cands) == 3:
        ref_x, ref_y = nx, ny
        ang = np.stack(
            [np.arctan2(ref_x * cy - ref_y * cx, ref_x * cx + ref_y * cy) for cx, cy in cands]
        )
        med = np.median(ang, axis=0)
        c, s_ = np.cos(med), np.sin(med)
        nx, ny = c * ref_x - s_ * ref_y, s_ * ref_x + c * ref_y
    out_x, out_y = np.empty(n), np.empty(n)
    out_x[order], out_y[order] = nx, ny
    return out_x, out_y


def _circle_normal(px: FloatArray, py: FloatArray, k: int) -> tuple[FloatArray, FloatArray]:
    """Outward normals of ordered points from the circle through p_{i−k}, p_i, p_{i+k}."""
    ax, ay = np.roll(px, k) - px, np.roll(py, k) - py
    bx, by = np.roll(px, -k) - px, np.roll(py, -k) - py
    tx, ty = bx - ax, by - ay
    chord = np.hypot(tx, ty)
    ntx, nty = ty / chord, -tx / chord
    d = 2.0 * (ax * by - ay * bx)
    a2, b2 = ax * ax + ay * ay, bx * bx + by * by
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (by * a2 - ay * b2) / d
        uy = (ax * b2 - bx * a2) / d
        ru = np.hypot(ux, uy)
        cx, cy = -ux / ru, -uy / ru
    sign = np.sign(cx * ntx + cy * nty)
    ok = np.isfinite(cx) & np.isfinite(cy) & (np.abs(d) > 1e-12 * (a2 + b2)) & (sign != 0)
    return np.where(ok, sign * cx, ntx), np.where(ok, sign * cy, nty)


def compensate_stylus(scan: Scan, radius_mm: float) -> Scan:
    """Turn stylus-ball centres into surface points: p − r·n along the local normal.

    The ball touches the cam's outer surface, so its centre lies r outside the surface
    along the outward normal; the normal is estimated from the scan itself
    (:func:`local_normals`), which is exact on a circle.

    Parameters
    ----------
    scan : Scan
        Stylus centres (bore points are compensated inwards towards the bore's centre
        side as well: a bore is probed from inside, its surface lies r further out).
    radius_mm : float
        Stylus-ball radius. [mm]

    Returns
    -------
    Scan
        The surface points, ``stylus_radius_mm`` set.
    """
    x, y = scan.x_mm.copy(), scan.y_mm.copy()
    prof = np.flatnonzero(~scan.feature)
    nx, ny = local_normals(x[prof], y[prof])
    x[prof] -= radius_mm * nx
    y[prof] -= radius_mm * ny
    bore = np.flatnonzero(scan.bore)
    if bore.size >= 3:
        cx, cy, _ = fit_circle(x[bore], y[bore])
        dx, dy = x[bore] - cx, y[bore] - cy
        r = np.hypot(dx, dy)
        x[bore] += radius_mm * dx / r
        y[bore] += radius_mm * dy / r
    return Scan(
        scan.source, x, y, scan.bore, scan.rows, radius_mm, scan._table, scan._lines, scan.keyway
    )


def fit_circle(x_mm: FloatArray, y_mm: FloatArray) -> tuple[float, float, float]:
    """Least-squares circle (algebraic Kåsa fit) through points: centre and radius. [mm]

    Parameters
    ----------
    x_mm, y_mm : ndarray
        At least 3 points not on a line. [mm]

    Raises
    ------
    InputFileError
        If the points do not define a circle.
    """
    mx, my = float(np.mean(x_mm)), float(np.mean(y_mm))
    u, v = x_mm - mx, y_mm - my
    a = np.stack([u, v, np.ones_like(u)], axis=1)
    b = u * u + v * v
    sol, *_ = np.linalg.lstsq(a, b, rcond=None)
    cx, cy = 0.5 * sol[0], 0.5 * sol[1]
    r2 = sol[2] + cx * cx + cy * cy
    if not (np.all(np.isfinite(sol)) and r2 > 0):
        raise InputFileError("the bore points do not lie on a circle")
    return float(cx + mx), float(cy + my), float(math.sqrt(r2))
