"""Errors as functions of the cam angle: constants, formulas and periodic tables (THEORY §4).

The master cams' known radial errors Δr_A(m)(θ), Δr_B(m)(θ) and the measured
centre-distance variation Δf_mea(θ) of the conjugate fixture are error functions: a
constant, a formula in θ (:class:`~camtol.inspection.formula.Formula`, never ``eval``-ed),
or a table of θ and µm interpolated linearly and periodically over 360°, read from a CSV
file by the shared reader :func:`camtol.tables.read_table`.

Every value of an error function is finite and within ±
:data:`~camtol.inspection.units.MAX_ERROR_UM`; a formula is checked on a 0.1° grid when
it is built, so a bad one is refused where it is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import DesignError, InputFileError
from camtol.inspection.formula import Formula
from camtol.inspection.units import (
    MAX_ERROR_UM,
    check_length_um,
    match_length_um,
    parse_length_um,
)
from camtol.jet import FloatArray
from camtol.tables import read_table

__all__ = ["ErrorFunction", "parse_error_function"]

#: Grid on which a formula is checked when it is built. [rad]
_CHECK_THETA = np.linspace(0.0, 2 * math.pi, 3600, endpoint=False)


def _check_values(values: FloatArray, theta_rad: FloatArray, what: str) -> None:
    """Refuse non-finite values and values beyond ±MAX_ERROR_UM, naming the angle."""
    bad = ~np.isfinite(values)
    if np.any(bad):
        i = int(np.argmax(bad))
        at_deg = math.degrees(float(theta_rad.flat[i]))
        raise DesignError(f"error function {what!r} is not finite at θ={at_deg:.2f}°")
    big = np.abs(values) > MAX_ERROR_UM
    if np.any(big):
        i = int(np.argmax(big))
        raise DesignError(
            f"error function {what!r} reaches {float(values.flat[i]):.4g} µm at"
            f" θ={math.degrees(float(theta_rad.flat[i])):.2f}°; allowed: within"
            f" ±{MAX_ERROR_UM:g} µm (check the unit)"
        )


@dataclass(frozen=True)
class ErrorFunction:
    """An error as a function of the cam angle: constant, formula or periodic table. [µm]

    Build with :meth:`constant`, :meth:`formula`, :meth:`table` or :meth:`from_csv`, or
    :func:`parse_error_function`. Calling it with θ in radians returns µm.

    Attributes
    ----------
    description : str
        What it is, e.g. ``"18.5 + 3.5*sin(theta) µm"``.
    """

    description: str
    _constant_um: float | None = None
    _formula: Formula | None = field(default=None, repr=False, compare=False)
    _table_deg: FloatArray | None = field(default=None, repr=False, compare=False)
    _table_um: FloatArray | None = field(default=None, repr=False, compare=False)

    @classmethod
    def constant(cls, value_um: float) -> ErrorFunction:
        """Return the same error at every θ.

        Parameters
        ----------
        value_um : float
            The error, finite and within ±10 mm. [µm]

        Returns
        -------
        ErrorFunction
            The constant function.
        """
        if not math.isfinite(value_um):
            raise DesignError(f"error value {value_um!r} must be a finite number of µm")
        check_length_um(float(value_um), field="error value")
        return cls(f"{value_um:g} µm", _constant_um=float(value_um))

    @classmethod
    def formula(cls, text: str) -> ErrorFunction:
        """Build a formula in ``theta`` (rad) or ``theta_deg`` (deg) giving µm.

        Parameters
        ----------
        text : str
            E.g. ``"18.5 + 3.5*sin(theta)"``. Allowed: numbers, ``theta``, ``theta_deg``,
            ``pi``, ``+ - * / **``, ``sin cos tan exp sqrt abs``; bounded in size
            (:mod:`camtol.inspection.formula`). Nothing is ``eval``-ed.

        Returns
        -------
        ErrorFunction
            The formula, checked finite and within bounds on a 0.1° grid.

        Raises
        ------
        DesignError
            On a syntax error, anything not allowed, a formula too large, or values that
            are not finite or beyond ±10 mm on the check grid.
        """
        f = Formula.parse(text)
        out = cls(f"{f.text} µm", _formula=f)
        out(_CHECK_THETA)
        return out

    @classmethod
    def table(
        cls, theta_deg: ArrayLike, values_um: ArrayLike, *, name: str = "table"
    ) -> ErrorFunction:
        """Build a table of θ and error, interpolated linearly and periodically over 360°.

        Parameters
        ----------
        theta_deg : array_like
            Cam angles, any order, distinct modulo 360. [deg]
        values_um : array_like
            Errors at those angles, within ±10 mm. [µm]
        name : str
            Description (e.g. the file name).

        Returns
        -------
        ErrorFunction
            The tabulated function.
        """
        t = np.mod(np.asarray(theta_deg, dtype=float), 360.0)
        v = np.asarray(values_um, dtype=float)
        if t.ndim != 1 or t.shape != v.shape or t.size < 2:
            raise InputFileError(f"{name}: need at least two rows of theta_deg and µm")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise InputFileError(f"{name}: theta_deg and µm must be finite numbers")
        big = np.abs(v) > MAX_ERROR_UM
        if np.any(big):
            i = int(np.argmax(big))
            raise InputFileError(
                f"{name}: the error {v[i]:.4g} µm at theta_deg={t[i]:g} is not allowed; give"
                f" errors within ±{MAX_ERROR_UM:g} µm (check the unit)"
            )
        order = np.argsort(t, kind="stable")
        t, v = t[order], v[order]
        if np.any(np.diff(t) <= 0):
            i = int(np.argmax(np.diff(t) <= 0))
            raise InputFileError(f"{name}: theta_deg={t[i]:g} appears twice (modulo 360)")
        return cls(f"table {name}", _table_deg=t, _table_um=v)

    @classmethod
    def from_csv(cls, path: str | Path) -> ErrorFunction:
        """Read a CSV table of ``theta_deg`` and an error column in µm.

        Parameters
        ----------
        path : str or Path
            Table read by :func:`camtol.tables.read_table` (``#`` comments, ``,``/``;``/
            blanks, BOM, CRLF): a header naming ``theta_deg`` and one error column whose
            name ends in ``um`` (``um``, ``dr_um``, ``df_um``), or no header and the two
            columns in that order.

        Returns
        -------
        ErrorFunction
            The tabulated error function.

        Raises
        ------
        InputFileError
            If the file cannot be read, has no such columns, or a cell is not a finite
            number (naming file, line and column).
        """
        p = Path(path)
        tab = read_table(
            p,
            required=("theta_deg",),
            default_names=("theta_deg", "error_um"),
            what="error table (theta_deg, µm)",
        )
        value_cols = [n for n in tab.names if n != "theta_deg" and n.lower().endswith("um")]
        if not value_cols:
            raise InputFileError(
                f"{p}: the error table needs a column in µm besides theta_deg (a name ending in"
                f" 'um', e.g. dr_um); found: {', '.join(tab.names)}"
            )
        return cls.table(tab.column("theta_deg"), tab.column(value_cols[0]), name=str(p))

    def __call__(self, theta_rad: ArrayLike) -> FloatArray:
        """Return the error at cam angles θ. [µm]"""
        theta = np.asarray(theta_rad, dtype=float)
        if self._constant_um is not None:
            return np.full(theta.shape, self._constant_um)
        if self._formula is not None:
            out = self._formula(theta)
            _check_values(out, theta, self.description)
            return out
        assert self._table_deg is not None and self._table_um is not None
        return np.asarray(
            np.interp(np.degrees(theta), self._table_deg, self._table_um, period=360.0)
        )


def parse_error_function(spec: str | float, *, field: str = "error") -> ErrorFunction:
    """Build an :class:`ErrorFunction` from a number (µm), a length, a CSV path or a formula.

    Parameters
    ----------
    spec : str or float
        ``22`` or ``"22 um"`` (constant); ``"path.csv"`` (table of theta_deg, µm);
        otherwise a formula in ``theta``/``theta_deg`` giving µm.
    field : str
        Name used in error messages, as the user wrote it (``inspection.master_a_um``,
        ``--df-mea``).

    Returns
    -------
    ErrorFunction
        The error function.

    Raises
    ------
    DesignError, InputFileError
        Naming the field, the value and what is allowed (or the file, line and column).
    """
    if isinstance(spec, int | float) and not isinstance(spec, bool):
        return ErrorFunction.constant(parse_length_um(spec, field=field))
    if not isinstance(spec, str):
        raise DesignError(f"{field}={spec!r} must be a number of µm, a formula or a CSV path")
    s = spec.strip()
    if s.lower().endswith(".csv"):
        return ErrorFunction.from_csv(s)
    value = match_length_um(s)
    if value is not None:  # a length: bounds are checked, it is never taken as a formula
        return ErrorFunction.constant(check_length_um(value, field=field, shown=spec))
    try:
        return ErrorFunction.formula(s)
    except DesignError as exc:
        raise DesignError(
            f"{field}: {exc}; allowed: a length ('22 um', '0.022 mm'), a CSV file"
            " (theta_deg, um) or a formula in theta [rad] or theta_deg giving µm"
            " ('18.5 + 3.5*sin(theta)')"
        ) from None
