"""Tolerance band: lower and upper limit curves of the output error ΔS(θ) (issue 11).

A motion spec need not be one number on max_θ |ΔS|: a designer may allow more error in a
dwell than on a rise, or more above the nominal than below it. A band gives, at every
cam angle θ, lower(θ) ≤ ΔS(θ) ≤ upper(θ). It is read from a CSV file by the shared table
reader :func:`camtol.tables.read_table` (docs/tolerancing.md, docs/file-formats.md):

- columns ``theta_deg, lower_um, upper_um`` for a translating follower (ΔS a lift error),
  ``theta_deg, lower_deg, upper_deg`` for an oscillating one (ΔS a swing error);
- at least two rows, angles strictly increasing within [0, 360);
- the curve is periodic over 360° and interpolated linearly (:func:`numpy.interp` with
  ``period=360``) onto the analysis grid;
- lower(θ) < 0 < upper(θ) at every angle: the nominal motion (ΔS = 0, a perfectly made
  mechanism) must lie strictly inside the band. A band that excludes it cannot be met by
  any tolerance, however fine: the problem is then the nominal motion, not the
  tolerances; and the allocation divides by upper(θ) and −lower(θ)
  (:func:`camtol.tolerancing.allocate`). Linear interpolation between rows that satisfy
  it keeps it at every angle in between.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camtol.exceptions import DesignError, InputFileError
from camtol.jet import FloatArray
from camtol.mechanisms.base import OutputKind
from camtol.tables import read_table

__all__ = ["ToleranceBand", "band_curves", "band_label", "read_band_csv"]

#: Display unit and factor to internal units (mm or rad) per follower output.
_UNITS: dict[str, tuple[str, float]] = {
    "translating": ("um", 1e-3),
    "oscillating": ("deg", math.pi / 180.0),
}


@dataclass(frozen=True)
class ToleranceBand:
    """Lower and upper limit curves of ΔS over one revolution (periodic, linear).

    Attributes
    ----------
    theta_deg : ndarray
        Cam angles of the rows, strictly increasing in [0, 360). [deg]
    lower, upper : ndarray
        Limits of ΔS at those angles, lower < 0 < upper. [mm, or rad for an oscillating
        follower]
    source : str
        Where the band came from (the file name), for messages and reports.
    """

    theta_deg: FloatArray
    lower: FloatArray
    upper: FloatArray
    source: str

    def on_grid(self, theta_rad: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Interpolate the band onto cam angles (periodic over 360°, linear).

        Parameters
        ----------
        theta_rad : ndarray
            Cam angles, any values (taken modulo 2π). [rad]

        Returns
        -------
        (ndarray, ndarray)
            lower(θ) and upper(θ), the shape of ``theta_rad``. [mm or rad]
        """
        t = np.degrees(np.asarray(theta_rad, dtype=float))
        lo = np.interp(t, self.theta_deg, self.lower, period=360.0)
        hi = np.interp(t, self.theta_deg, self.upper, period=360.0)
        return np.asarray(lo), np.asarray(hi)


def read_band_csv(path: str | Path, output: OutputKind) -> ToleranceBand:
    """Read a band file (see the module docstring for its form).

    Parameters
    ----------
    path : str or Path
        CSV (or whitespace-separated) file read by :func:`camtol.tables.read_table`.
    output : {"translating", "oscillating"}
        The design's follower output: it fixes the unit of the limits (µm or deg).

    Returns
    -------
    ToleranceBand
        The band in internal units.

    Raises
    ------
    InputFileError
        The file is unreadable or malformed, the limits are in the other output's unit,
        fewer than two rows, angles not strictly increasing within [0, 360), or a row
        with lower ≥ 0 or upper ≤ 0 (each naming the file, line and column or angle).
    """
    p = Path(path)
    unit, factor = _UNITS[output]
    other = "deg" if unit == "um" else "um"
    want = ("theta_deg", f"lower_{unit}", f"upper_{unit}")
    others = (f"lower_{other}", f"upper_{other}")
    # Only these columns are read (others may hold notes); the missing ones are told below.
    tab = read_table(p, optional=want + others, ignore_other_columns=True, what="tolerance band")
    if any(n in tab for n in others) and not all(n in tab for n in want[1:]):
        what = "a lift (translating follower)" if unit == "um" else "a swing (oscillating follower)"
        raise InputFileError(
            f"{p}: the band is given in {other}, but this design's output is {what};"
            f" give the columns {', '.join(want)}"
        )
    if not all(c in tab for c in want):
        # Read again requiring them: the reader's message names the columns it found.
        read_table(p, required=want, ignore_other_columns=True, what="tolerance band")
        raise InputFileError(f"{p}: the tolerance band needs the columns {', '.join(want)}")
    theta = np.array(tab.column("theta_deg"), dtype=float)
    lower = np.array(tab.column(want[1]), dtype=float)
    upper = np.array(tab.column(want[2]), dtype=float)
    if theta.size < 2:
        raise InputFileError(
            f"{p}: the tolerance band has {theta.size} row; give at least 2 (the curve is"
            " interpolated periodically over 360°)"
        )
    out = (theta < 0) | (theta >= 360)
    if np.any(out):
        i = int(np.argmax(out))
        raise InputFileError(
            f"{p}, line {tab.line_of(i)}, column theta_deg: {theta[i]:g} is not allowed;"
            " angles lie in [0, 360)"
        )
    back = np.diff(theta) <= 0
    if np.any(back):
        i = int(np.argmax(back)) + 1
        raise InputFileError(
            f"{p}, line {tab.line_of(i)}, column theta_deg: {theta[i]:g} does not follow"
            f" {theta[i - 1]:g}; angles must be strictly increasing"
        )
    for col, values, bad, allowed in (
        (want[1], lower, lower >= 0, "< 0"),
        (want[2], upper, upper <= 0, "> 0"),
    ):
        if np.any(bad):
            i = int(np.argmax(bad))
            raise InputFileError(
                f"{p}, line {tab.line_of(i)}, column {col}: {values[i]:g} at theta_deg="
                f"{theta[i]:g} is not allowed; it must be {allowed} (the band must contain"
                " the nominal motion, ΔS = 0)"
            )
    return ToleranceBand(theta, lower * factor, upper * factor, p.name)


def band_curves(
    band: ToleranceBand | tuple[FloatArray, FloatArray],
    theta_rad: FloatArray,
    *,
    require_nominal: bool = True,
) -> tuple[FloatArray, FloatArray]:
    """Lower and upper curves of a band on an analysis grid, checked.

    Parameters
    ----------
    band : ToleranceBand or (ndarray, ndarray)
        A band, or its two curves already on the grid. [mm or rad]
    theta_rad : ndarray
        The grid. [rad]
    require_nominal : bool
        Require lower < 0 < upper at every grid angle (allocation needs it).

    Returns
    -------
    (ndarray, ndarray)
        lower(θ), upper(θ) on the grid. [mm or rad]

    Raises
    ------
    DesignError
        Curves of the wrong length, not finite, or (``require_nominal``) not containing
        ΔS = 0 at some angle (naming the angle).
    """
    if isinstance(band, ToleranceBand):
        lo, hi = band.on_grid(theta_rad)
    else:
        lo, hi = (np.asarray(b, dtype=float) for b in band)
    n = np.shape(theta_rad)
    if lo.shape != n or hi.shape != n:
        raise DesignError(
            f"band: the curves need {int(np.size(theta_rad))} values (one per grid angle)"
        )
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise DesignError("band: every value of the lower and upper curves must be finite")
    if require_nominal:
        bad = (lo >= 0) | (hi <= 0)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise DesignError(
                f"band at theta={math.degrees(float(np.asarray(theta_rad)[i])):.2f}°: lower"
                f"={lo[i]:g}, upper={hi[i]:g} is not allowed; need lower < 0 < upper at every"
                " angle (the band must contain the nominal motion, ΔS = 0)"
            )
    return lo, hi


def band_label(band: ToleranceBand | tuple[FloatArray, FloatArray]) -> str:
    """Return a short description of a band: its file name, or a phrase for arrays.

    Parameters
    ----------
    band : ToleranceBand or (ndarray, ndarray)
        The band.

    Returns
    -------
    str
        ``band.csv`` (the file's name) or ``curves given in Python``.
    """
    return band.source if isinstance(band, ToleranceBand) else "curves given in Python"
