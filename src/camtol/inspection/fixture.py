"""Conjugate-cam measuring fixture: variation, inverse analysis, acceptance (THEORY §4).

The follower pivot O3 of a conjugate pair rides on a slider along the line of centres; an
indicator reads the centre-distance variation Δf = f* − f while the pair turns ([CW11]).
This module computes

* the forward conjugate variation Δf_r, Δf_rf, Δf_l, Δf_η, Δf_est from known errors
  (THEORY §4.1, [CW11] eqs. 14-18);
* the inverse analysis Δr_A,est (with master cam B) and Δr_B,est (with master cam A) from a
  measured Δf_mea(θ) (THEORY §4.2, [CW11] eqs. 19-21);
* the four acceptance bands and a verdict per inspected cam with the cam-angle intervals
  where it fails, interval ends located to better than 0.01° (THEORY §4.3, [CW11]
  eqs. 22-31).

Error functions of θ (:class:`ErrorFunction`) are constants, formulas in θ evaluated by a
small safe expression evaluator (never ``eval``), or periodic tables (CSV of θ in degrees
and µm).

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import ast
import csv
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from camtol.design import CamDesign
from camtol.exceptions import DesignError, InputFileError
from camtol.extremes import Extreme, find_extremes
from camtol.jet import FloatArray
from camtol.mechanisms.conjugate import ConjugatePair, conjugate_kinematics

__all__ = [
    "AcceptanceBands",
    "CamVerdict",
    "ConjugateFactors",
    "ConjugateVariation",
    "ErrorFunction",
    "FixtureErrors",
    "FixtureInspection",
    "FixtureSpec",
    "InverseEstimate",
    "acceptance_bands",
    "conjugate_factors",
    "conjugate_variation",
    "failing_intervals",
    "merge_intervals",
    "fixture_spec_from_mapping",
    "inspect_conjugate",
    "inverse_estimate",
    "parse_error_function",
    "parse_length_um",
]

# ---------------------------------------------------------------------------------------
# Error functions of the cam angle
# ---------------------------------------------------------------------------------------

_FUNCTIONS: dict[str, Callable[[FloatArray], FloatArray]] = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "exp": np.exp,
    "sqrt": np.sqrt,
    "abs": np.abs,
}
_CONSTANTS: dict[str, float] = {"pi": math.pi}
_VARIABLES = ("theta", "theta_deg")
_BINOPS: dict[type[ast.operator], Callable[[FloatArray, FloatArray], FloatArray]] = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
    ast.Pow: np.power,
}


def _check_formula(node: ast.AST, text: str) -> None:
    """Reject anything but numbers, θ, pi, + − * / **, unary ±, and the allowed functions."""
    allowed = (
        f"numbers, the variables {', '.join(_VARIABLES)}, pi, + - * / ** and the functions"
        f" {', '.join(sorted(_FUNCTIONS))}"
    )
    for sub in ast.walk(node):
        ok = isinstance(
            sub,
            ast.Expression | ast.BinOp | ast.UnaryOp | ast.Load | ast.UAdd | ast.USub,
        ) or (isinstance(sub, ast.operator) and type(sub) in _BINOPS)
        if isinstance(sub, ast.Constant):
            ok = isinstance(sub.value, int | float) and not isinstance(sub.value, bool)
        elif isinstance(sub, ast.Name):
            ok = sub.id in _VARIABLES or sub.id in _CONSTANTS or sub.id in _FUNCTIONS
        elif isinstance(sub, ast.Call):
            ok = (
                isinstance(sub.func, ast.Name)
                and sub.func.id in _FUNCTIONS
                and len(sub.args) == 1
                and not sub.keywords
            )
        if not ok:
            raise DesignError(
                f"error function {text!r}: {type(sub).__name__} is not allowed; allowed: {allowed}"
            )


def _eval_formula(node: ast.AST, env: dict[str, FloatArray]) -> FloatArray:
    if isinstance(node, ast.Expression):
        return _eval_formula(node.body, env)
    if isinstance(node, ast.Constant):
        value = node.value
        assert isinstance(value, int | float)  # checked by _check_formula
        return np.asarray(float(value))
    if isinstance(node, ast.Name):
        if node.id in env:
            return env[node.id]
        return np.asarray(_CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        val = _eval_formula(node.operand, env)
        return np.asarray(-val if isinstance(node.op, ast.USub) else val)
    if isinstance(node, ast.BinOp):
        return np.asarray(
            _BINOPS[type(node.op)](_eval_formula(node.left, env), _eval_formula(node.right, env))
        )
    if isinstance(node, ast.Call):
        assert isinstance(node.func, ast.Name)
        return np.asarray(_FUNCTIONS[node.func.id](_eval_formula(node.args[0], env)))
    raise AssertionError("unreachable: formula was checked")  # pragma: no cover


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
    _tree: ast.Expression | None = field(default=None, repr=False, compare=False)
    _table_deg: FloatArray | None = field(default=None, repr=False, compare=False)
    _table_um: FloatArray | None = field(default=None, repr=False, compare=False)

    @classmethod
    def constant(cls, value_um: float) -> ErrorFunction:
        """Return the same error at every θ.

        Parameters
        ----------
        value_um : float
            The error. [µm]
        """
        if not math.isfinite(value_um):
            raise DesignError(f"error value {value_um!r} must be a finite number of µm")
        return cls(f"{value_um:g} µm", _constant_um=float(value_um))

    @classmethod
    def formula(cls, text: str) -> ErrorFunction:
        """Build a formula in ``theta`` (rad) or ``theta_deg`` (deg) giving µm.

        Parameters
        ----------
        text : str
            E.g. ``"18.5 + 3.5*sin(theta)"``. Allowed: numbers, ``theta``, ``theta_deg``,
            ``pi``, ``+ - * / **``, ``sin cos tan exp sqrt abs``. Nothing is ``eval``-ed.

        Raises
        ------
        DesignError
            On a syntax error or anything not allowed.
        """
        try:
            tree = ast.parse(text.strip(), mode="eval")
        except SyntaxError as exc:
            raise DesignError(
                f"error function {text!r} is not a valid formula: {exc.msg}"
            ) from None
        _check_formula(tree, text)
        return cls(f"{text.strip()} µm", _tree=tree)

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
            Errors at those angles. [µm]
        name : str
            Description (e.g. the file name).
        """
        t = np.mod(np.asarray(theta_deg, dtype=float), 360.0)
        v = np.asarray(values_um, dtype=float)
        if t.ndim != 1 or t.shape != v.shape or t.size < 2:
            raise InputFileError(f"{name}: need at least two rows of theta_deg and µm")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise InputFileError(f"{name}: theta_deg and µm must be finite numbers")
        order = np.argsort(t, kind="stable")
        t, v = t[order], v[order]
        if np.any(np.diff(t) <= 0):
            i = int(np.argmax(np.diff(t) <= 0))
            raise InputFileError(f"{name}: theta_deg={t[i]:g} appears twice (modulo 360)")
        return cls(f"table {name}", _table_deg=t, _table_um=v)

    @classmethod
    def from_csv(cls, path: str | Path) -> ErrorFunction:
        """Read a CSV table of ``theta_deg`` and µm (first two columns; header optional).

        Parameters
        ----------
        path : str or Path
            CSV file: angle [deg] and error [µm] per row; blank lines and lines starting
            with ``#`` are skipped.

        Returns
        -------
        ErrorFunction
            The tabulated error function.

        Raises
        ------
        InputFileError
            If the file cannot be read or a row is not two numbers (names file and line).
        """
        p = Path(path)
        from camtol.textfile import read_text

        lines = read_text(p, what="error table").splitlines()
        rows: list[tuple[float, float]] = []
        for lineno, row in enumerate(csv.reader(lines), start=1):
            if not row or not "".join(row).strip() or row[0].lstrip().startswith("#"):
                continue
            try:
                rows.append((float(row[0]), float(row[1])))
            except (ValueError, IndexError):
                if not rows and lineno == 1:
                    continue  # header
                raise InputFileError(
                    f"{p}, line {lineno}: expected two numbers 'theta_deg, um', got {row!r}"
                ) from None
        arr = np.asarray(rows, dtype=float).reshape(-1, 2)
        return cls.table(arr[:, 0], arr[:, 1], name=str(p))

    def __call__(self, theta_rad: ArrayLike) -> FloatArray:
        """Return the error at cam angles θ. [µm]"""
        theta = np.asarray(theta_rad, dtype=float)
        if self._constant_um is not None:
            return np.full(theta.shape, self._constant_um)
        if self._tree is not None:
            env = {"theta": theta, "theta_deg": np.degrees(theta)}
            with np.errstate(all="ignore"):
                out = np.broadcast_to(_eval_formula(self._tree, env), theta.shape).astype(float)
            if not np.all(np.isfinite(out)):
                i = int(np.argmax(~np.isfinite(out)))
                raise DesignError(
                    f"error function {self.description!r} is not finite at"
                    f" θ={math.degrees(float(theta.flat[i])):.2f}°"
                )
            return out
        assert self._table_deg is not None and self._table_um is not None
        return np.asarray(
            np.interp(np.degrees(theta), self._table_deg, self._table_um, period=360.0)
        )


_UNITS_UM = {"um": 1.0, "µm": 1.0, "μm": 1.0, "mm": 1e3, "": 1.0}


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
        The length. [µm]

    Raises
    ------
    DesignError
        If it is not a number followed by ``um``, ``µm`` or ``mm``.
    """
    if isinstance(text, int | float):
        value = float(text)
    else:
        m = re.fullmatch(r"\s*([-+]?[0-9.]+(?:[eE][-+]?\d+)?)\s*([a-zA-Zµμ]*)\s*", text)
        if not m or m.group(2) not in _UNITS_UM:
            raise DesignError(
                f"{field}={text!r} is not allowed; give a number with unit um or mm, e.g. '22 um'"
            )
        value = float(m.group(1)) * _UNITS_UM[m.group(2)]
    if not math.isfinite(value):
        raise DesignError(f"{field}={text!r} must be finite")
    return value


def parse_error_function(spec: str | float, *, field: str = "error") -> ErrorFunction:
    """Build an :class:`ErrorFunction` from a number (µm), a length, a CSV path or a formula.

    Parameters
    ----------
    spec : str or float
        ``22`` or ``"22 um"`` (constant); ``"path.csv"`` (table of theta_deg, µm);
        otherwise a formula in ``theta``/``theta_deg`` giving µm.
    field : str
        Name used in error messages.
    """
    if isinstance(spec, int | float) and not isinstance(spec, bool):
        return ErrorFunction.constant(float(spec))
    if not isinstance(spec, str):
        raise DesignError(f"{field}={spec!r} must be a number of µm, a formula or a CSV path")
    s = spec.strip()
    if s.lower().endswith(".csv"):
        return ErrorFunction.from_csv(s)
    try:
        return ErrorFunction.constant(parse_length_um(s, field=field))
    except DesignError:
        pass
    try:
        return ErrorFunction.formula(s)
    except DesignError as exc:
        raise DesignError(
            f"{field}: {exc}; allowed: a length ('22 um', '0.022 mm'), a CSV file"
            " (theta_deg, um) or a formula in theta [rad] or theta_deg giving µm"
            " ('18.5 + 3.5*sin(theta)')"
        ) from None


# ---------------------------------------------------------------------------------------
# The pair's factors and the forward variation (THEORY §4.1)
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FixtureErrors:
    """The constant errors of the follower (THEORY §4.1).

    Attributes
    ----------
    dl_a_mm, dl_b_mm : float
        Arm-length errors Δl_A, Δl_B. [mm]
    drr_c_mm, drr_d_mm : float
        Roller-radius errors Δr_rC, Δr_rD. [mm]
    deta_rad : float
        Arm-angle error Δη (> 0: arms opened wider). [rad]
    """

    dl_a_mm: float = 0.0
    dl_b_mm: float = 0.0
    drr_c_mm: float = 0.0
    drr_d_mm: float = 0.0
    deta_rad: float = 0.0


@dataclass(frozen=True)
class ConjugateFactors:
    """Per-θ geometric factors of the pair entering THEORY §4 (all arrays over θ).

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    arm_a_mm, arm_b_mm : float
        l_A, l_B. [mm]
    pressure_a_rad, pressure_b_rad : ndarray
        Signed φ_A, φ_B. [rad]
    centre_line_a_rad, centre_line_b_rad : ndarray
        α_A, α_B. [rad]
    shift_a_rad, shift_b_rad : ndarray
        λ_A, λ_B. [rad]
    """

    theta_rad: FloatArray
    arm_a_mm: float
    arm_b_mm: float
    pressure_a_rad: FloatArray
    pressure_b_rad: FloatArray
    centre_line_a_rad: FloatArray
    centre_line_b_rad: FloatArray
    shift_a_rad: FloatArray
    shift_b_rad: FloatArray

    @property
    def denominator_mm(self) -> FloatArray:
        """D = l_A cos φ_A cos α_B + l_B cos φ_B cos α_A. [mm]"""
        return np.asarray(
            self.arm_a_mm * np.cos(self.pressure_a_rad) * np.cos(self.centre_line_b_rad)
            + self.arm_b_mm * np.cos(self.pressure_b_rad) * np.cos(self.centre_line_a_rad)
        )

    @property
    def gain_a(self) -> FloatArray:
        """∂Δf/∂Δr_A = l_B cos φ_B cos λ_A / D. [-]"""
        return np.asarray(
            self.arm_b_mm
            * np.cos(self.pressure_b_rad)
            * np.cos(self.shift_a_rad)
            / self.denominator_mm
        )

    @property
    def gain_b(self) -> FloatArray:
        """∂Δf/∂Δr_B = l_A cos φ_A cos λ_B / D. [-]"""
        return np.asarray(
            self.arm_a_mm
            * np.cos(self.pressure_a_rad)
            * np.cos(self.shift_b_rad)
            / self.denominator_mm
        )


def _pair(design: CamDesign) -> ConjugatePair:
    if not isinstance(design.mechanism, ConjugatePair):
        raise DesignError(
            f"follower.type={design.mechanism.kind!r}: the fixture analysis needs a conjugate"
            " design (follower.type='conjugate')"
        )
    return design.mechanism


def conjugate_factors(theta_rad: ArrayLike, design: CamDesign) -> ConjugateFactors:
    """Evaluate φ, α, λ of both cams over θ (THEORY §2.4, §2.5).

    Parameters
    ----------
    theta_rad : array_like
        Cam angles. [rad]
    design : CamDesign
        A conjugate design.

    Raises
    ------
    GeometryError, UndercutError
        If either cam cannot work (with the cam angle).
    """
    pair = _pair(design)
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    k = conjugate_kinematics(design, theta)
    return ConjugateFactors(
        theta_rad=theta,
        arm_a_mm=pair.arm_a_mm,
        arm_b_mm=pair.arm_b_mm,
        pressure_a_rad=k.a.pressure_angle_rad,
        pressure_b_rad=k.b.pressure_angle_rad,
        centre_line_a_rad=k.centre_line_angle_a_rad,
        centre_line_b_rad=k.centre_line_angle_b_rad,
        shift_a_rad=k.a.shift_angle_rad,
        shift_b_rad=k.b.shift_angle_rad,
    )


@dataclass(frozen=True)
class ConjugateVariation:
    """Centre-distance variation and its parts (THEORY §4.1). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_r_um, df_rf_um, df_l_um, df_eta_um : ndarray
        Δf caused by the profile errors, the roller radii, the arm lengths and η. [µm]
    """

    theta_rad: FloatArray
    df_r_um: FloatArray
    df_rf_um: FloatArray
    df_l_um: FloatArray
    df_eta_um: FloatArray

    @property
    def df_constant_um(self) -> FloatArray:
        """Δf_rf + Δf_l + Δf_η, the part not due to the profiles. [µm]"""
        return np.asarray(self.df_rf_um + self.df_l_um + self.df_eta_um)

    @property
    def df_est_um(self) -> FloatArray:
        """Δf_est = Δf_r + Δf_rf + Δf_l + Δf_η (CW11 eq. 18). [µm]"""
        return np.asarray(self.df_r_um + self.df_constant_um)


def _constant_parts(
    fac: ConjugateFactors, errors: FixtureErrors
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Δf_rf, Δf_l, Δf_η in µm (CW11 eqs. 15-17)."""
    la, lb = fac.arm_a_mm, fac.arm_b_mm
    ca, cb = np.cos(fac.pressure_a_rad), np.cos(fac.pressure_b_rad)
    d = fac.denominator_mm
    df_rf = (errors.drr_c_mm * lb * cb + errors.drr_d_mm * la * ca) / d
    df_l = (
        errors.dl_a_mm * lb * cb * np.sin(fac.pressure_a_rad)
        + errors.dl_b_mm * la * ca * np.sin(fac.pressure_b_rad)
    ) / d
    df_eta = -errors.deta_rad * la * lb * ca * cb / d
    return np.asarray(df_rf * 1e3), np.asarray(df_l * 1e3), np.asarray(df_eta * 1e3)


def conjugate_variation(
    factors: ConjugateFactors,
    dr_a: ErrorFunction | ArrayLike,
    dr_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> ConjugateVariation:
    r"""Forward centre-distance variation from known errors (THEORY §4.1, CW11 eqs. 14-18).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    dr_a, dr_b : ErrorFunction or array_like
        Radial errors Δr_A(θ), Δr_B(θ) of the profile points in contact at θ. [µm]
    errors : FixtureErrors
        Constant errors.

    Returns
    -------
    ConjugateVariation

    Notes
    -----
    With D = l_A cos φ_A cos α_B + l_B cos φ_B cos α_A:

    .. math::

        Δf_r &= [Δr_A l_B \cos φ_B \cos λ_A + Δr_B l_A \cos φ_A \cos λ_B] / D \\
        Δf_{rf} &= [Δr_{rC} l_B \cos φ_B + Δr_{rD} l_A \cos φ_A] / D \\
        Δf_l &= [Δl_A l_B \cos φ_B \sin φ_A + Δl_B l_A \cos φ_A \sin φ_B] / D \\
        Δf_η &= -Δη\, l_A l_B \cos φ_A \cos φ_B / D

    Derivation (implicit differentiation of both contact constraints, as in
    :func:`~camtol.mechanisms.roller_oscillating.oscillating_roller_sensitivities`):
    cam A: l_A cos φ_A Δξ + cos α_A Δf − sin φ_A Δl_A = Δn_A + Δr_rC; cam B:
    −l_B cos φ_B Δξ + cos α_B Δf − sin φ_B Δl_B + l_B cos φ_B Δη = Δn_B + Δr_rD, with
    Δn = Δr cos λ; eliminating Δξ gives the forms above (THEORY's signs confirmed; checked
    against an exact 4×4 re-solution of the perturbed fixture in the tests).
    """
    theta = factors.theta_rad
    ra = dr_a(theta) if isinstance(dr_a, ErrorFunction) else np.asarray(dr_a, dtype=float)
    rb = dr_b(theta) if isinstance(dr_b, ErrorFunction) else np.asarray(dr_b, dtype=float)
    df_r = ra * factors.gain_a + rb * factors.gain_b
    rf, ll, eta = _constant_parts(factors, errors)
    return ConjugateVariation(theta, np.asarray(df_r), rf, ll, eta)


# ---------------------------------------------------------------------------------------
# Inverse analysis and acceptance (THEORY §4.2, §4.3)
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class InverseEstimate:
    """Profile errors estimated from a measured Δf (THEORY §4.2). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_mea_um : ndarray
        Measured centre-distance variation. [µm]
    df_r_um : ndarray
        Δf_r = Δf_mea − (Δf_rf + Δf_l + Δf_η) (CW11 eq. 19). [µm]
    dr_a_est_um : ndarray
        Δr_A,est with master cam B (CW11 eq. 20). [µm]
    dr_b_est_um : ndarray
        Δr_B,est with master cam A (CW11 eq. 21). [µm]
    """

    theta_rad: FloatArray
    df_mea_um: FloatArray
    df_r_um: FloatArray
    dr_a_est_um: FloatArray
    dr_b_est_um: FloatArray


def inverse_estimate(
    factors: ConjugateFactors,
    df_mea: ErrorFunction | ArrayLike,
    master_a: ErrorFunction | ArrayLike,
    master_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> InverseEstimate:
    r"""Profile errors from a measured centre-distance variation (THEORY §4.2, CW11 eqs. 19-21).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    df_mea : ErrorFunction or array_like
        Measured Δf_mea(θ). [µm]
    master_a, master_b : ErrorFunction or array_like
        Known radial errors of the master cams A_(m) and B_(m). [µm]
    errors : FixtureErrors
        Constant errors of the follower.

    Notes
    -----
    .. math::

        Δf_r &= Δf_{mea} - (Δf_{rf} + Δf_l + Δf_η) \\
        Δr_{A,est} &= [D Δf_r - Δr_{B,mea} l_A \cos φ_A \cos λ_B] / (l_B \cos φ_B \cos λ_A) \\
        Δr_{B,est} &= [D Δf_r - Δr_{A,mea} l_B \cos φ_B \cos λ_A] / (l_A \cos φ_A \cos λ_B)

    Put back into :func:`conjugate_variation` (with the master's error for the other cam)
    the estimate returns Δf_mea exactly.
    """
    theta = factors.theta_rad

    def ev(x: ErrorFunction | ArrayLike) -> FloatArray:
        return x(theta) if isinstance(x, ErrorFunction) else np.asarray(x, dtype=float)

    mea = np.broadcast_to(ev(df_mea), theta.shape).astype(float)
    rf, ll, eta = _constant_parts(factors, errors)
    df_r = mea - (rf + ll + eta)
    ga, gb = factors.gain_a, factors.gain_b
    dr_a = (df_r - ev(master_b) * gb) / ga
    dr_b = (df_r - ev(master_a) * ga) / gb
    return InverseEstimate(theta, mea, np.asarray(df_r), np.asarray(dr_a), np.asarray(dr_b))


@dataclass(frozen=True)
class AcceptanceBands:
    """The four acceptance bands of THEORY §4.3 (CW11 eqs. 22-31). [µm]

    Attributes
    ----------
    theta_rad : ndarray
        Cam angles. [rad]
    df_a_upper_um, df_a_lower_um : ndarray
        Δf_A(u),est, Δf_A(l),est: inspecting cam A with master B. [µm]
    df_b_upper_um, df_b_lower_um : ndarray
        Δf_B(u),est, Δf_B(l),est: inspecting cam B with master A. [µm]
    """

    theta_rad: FloatArray
    df_a_upper_um: FloatArray
    df_a_lower_um: FloatArray
    df_b_upper_um: FloatArray
    df_b_lower_um: FloatArray


def acceptance_bands(
    factors: ConjugateFactors,
    tolerance_a_um: tuple[float, float],
    tolerance_b_um: tuple[float, float],
    master_a: ErrorFunction | ArrayLike,
    master_b: ErrorFunction | ArrayLike,
    errors: FixtureErrors,
) -> AcceptanceBands:
    """Compute the acceptance bands of Δf for each inspected cam (THEORY §4.3).

    Parameters
    ----------
    factors : ConjugateFactors
        From :func:`conjugate_factors`.
    tolerance_a_um, tolerance_b_um : tuple of float
        Radial tolerances (lower, upper) of cams A and B, e.g. (−22, 22). [µm]
    master_a, master_b : ErrorFunction or array_like
        Known errors of the master cams. [µm]
    errors : FixtureErrors
        Constant errors.

    Notes
    -----
    Δf_A(u),est = Δf_r(Δr_A = Δr_A(u), Δr_B = Δr_B(m),mea) + Δf_rf + Δf_l + Δf_η and
    likewise for the lower limit and for cam B with master A.
    """

    def est(ra: ErrorFunction | ArrayLike, rb: ErrorFunction | ArrayLike) -> FloatArray:
        return conjugate_variation(factors, ra, rb, errors).df_est_um

    n = factors.theta_rad.shape
    lo_a, hi_a = (np.full(n, float(v)) for v in tolerance_a_um)
    lo_b, hi_b = (np.full(n, float(v)) for v in tolerance_b_um)
    return AcceptanceBands(
        factors.theta_rad,
        est(hi_a, master_b),
        est(lo_a, master_b),
        est(master_a, hi_b),
        est(master_a, lo_b),
    )


@dataclass(frozen=True)
class CamVerdict:
    """Acceptance of one inspected cam (THEORY §4.3).

    Attributes
    ----------
    cam : str
        ``"A"`` or ``"B"``.
    passed : bool
        True when Δf_lower ≤ Δf_mea ≤ Δf_upper at every θ (a necessary condition).
    failing_intervals_deg : list of (float, float)
        Cam-angle intervals (start, end) where it fails, ends located to < 0.01°; an
        interval that wraps through 0° has end < start. [deg]
    min_margin_um : float
        Smallest margin min(Δf_mea − lower, upper − Δf_mea) over θ (< 0: fails). [µm]
    """

    cam: str
    passed: bool
    failing_intervals_deg: list[tuple[float, float]]
    min_margin_um: float


def merge_intervals(
    intervals: Sequence[tuple[float, float]], gap_deg: float
) -> list[tuple[float, float]]:
    """Join failing intervals separated by less than ``gap_deg``.

    A noisy measured record crosses a band edge many times; the exact intervals are then
    many slivers. Joining them across short gaps gives the stretches an inspector acts on.

    Parameters
    ----------
    intervals : sequence of (float, float)
        Sorted, non-overlapping cam-angle intervals. [deg]
    gap_deg : float
        Gaps shorter than this are closed. [deg]

    Returns
    -------
    list of (float, float)
        The joined intervals. [deg]
    """
    out: list[tuple[float, float]] = []
    for a, b in intervals:
        if out and a - out[-1][1] < gap_deg:
            out[-1] = (out[-1][0], b)
        else:
            out.append((a, b))
    return out


def failing_intervals(
    theta_rad: FloatArray,
    margin: Callable[[FloatArray], FloatArray],
    *,
    tol_deg: float = 1e-4,
) -> list[tuple[float, float]]:
    """Intervals of θ over a revolution where ``margin(θ) < 0``, ends refined by bisection.

    Parameters
    ----------
    theta_rad : ndarray
        Uniform grid over [0, 2π) (without the end point). [rad]
    margin : callable
        Continuous function of θ (rad) evaluated vectorised; < 0 means failing.
    tol_deg : float
        Bisection tolerance of the interval ends. [deg]

    Returns
    -------
    list of (float, float)
        (start, end) in degrees in [0, 360); a wrapping interval has end < start; the whole
        revolution is (0.0, 360.0).
    """
    theta = np.asarray(theta_rad, dtype=float)
    fail = margin(theta) < 0
    if not np.any(fail):
        return []
    if np.all(fail):
        return [(0.0, 360.0)]
    n = theta.size
    nxt = np.roll(np.arange(n), -1)
    t_next = np.where(nxt == 0, theta[0] + 2 * math.pi, theta[nxt])
    starts_i = np.flatnonzero(~fail & fail[nxt])  # pass → fail between i and i+1
    ends_i = np.flatnonzero(fail & ~fail[nxt])  # fail → pass between i and i+1

    def refine(idx: np.ndarray, fail_on_left: bool) -> FloatArray:
        lo, hi = theta[idx].copy(), t_next[idx].copy()
        tol = math.radians(tol_deg)
        while np.any(hi - lo > tol):
            mid = 0.5 * (lo + hi)
            f_mid = margin(np.mod(mid, 2 * math.pi)) < 0
            left_side = f_mid if fail_on_left else ~f_mid
            lo = np.where(left_side, mid, lo)
            hi = np.where(left_side, hi, mid)
        return np.asarray(np.mod(np.degrees(0.5 * (lo + hi)), 360.0))

    starts = refine(starts_i, fail_on_left=False)
    ends = refine(ends_i, fail_on_left=True)
    s_order, e_order = np.argsort(starts_i), np.argsort(ends_i)
    starts, ends = starts[s_order], ends[e_order]
    if ends_i.min() < starts_i.min():  # the first end belongs to an interval wrapping 0°
        ends = np.roll(ends, -1)
    return [(float(s), float(e)) for s, e in zip(starts, ends, strict=True)]


# ---------------------------------------------------------------------------------------
# The whole fixture analysis
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FixtureSpec:
    """Inputs of a fixture analysis (THEORY §4, §8.3).

    Attributes
    ----------
    errors : FixtureErrors
        Constant errors of the follower.
    tolerance_a_um, tolerance_b_um : tuple of float
        Radial tolerances (lower, upper) of cams A and B. [µm]
    master_a, master_b : ErrorFunction
        Known radial errors of the master cams. [µm]
    df_mea : ErrorFunction or None
        Measured centre-distance variation; None when there is no record. [µm]
    """

    errors: FixtureErrors
    tolerance_a_um: tuple[float, float]
    tolerance_b_um: tuple[float, float]
    master_a: ErrorFunction
    master_b: ErrorFunction
    df_mea: ErrorFunction | None = None

    def __post_init__(self) -> None:
        for cam, (lo, hi) in (("a", self.tolerance_a_um), ("b", self.tolerance_b_um)):
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise DesignError(
                    f"fixture.tolerance_{cam}_um=[{lo:g}, {hi:g}] is not allowed; give"
                    " [lower, upper] with lower < upper"
                )


@dataclass(frozen=True)
class FixtureInspection:
    """Result of :func:`inspect_conjugate` on a θ grid.

    Attributes
    ----------
    theta_rad : ndarray
        Uniform grid over [0, 2π). [rad]
    factors : ConjugateFactors
        Geometry of the pair.
    variation : ConjugateVariation
        Forward variation; Δf_r from the measurement (eq. 19) when there is one, otherwise
        from the master cams' errors (the master pair on the fixture). [µm]
    estimate : InverseEstimate or None
        Δr_A,est and Δr_B,est (None without a measurement). [µm]
    bands : AcceptanceBands
        The four bands. [µm]
    verdicts : dict of str to CamVerdict or None
        ``"A"``, ``"B"``; empty without a measurement.
    extremes : dict of str to (Extreme, Extreme)
        Global (max, min) of every curve of :func:`fixture_curves`, refined to step/1000;
        a value held over an angle range is reported as that range. [µm]
    """

    theta_rad: FloatArray
    factors: ConjugateFactors
    variation: ConjugateVariation
    estimate: InverseEstimate | None
    bands: AcceptanceBands
    verdicts: dict[str, CamVerdict]
    extremes: dict[str, tuple[Extreme, Extreme]]

    @property
    def passed(self) -> bool | None:
        """True if both inspected cams pass, False if one fails, None without a record."""
        if not self.verdicts:
            return None
        return all(v.passed for v in self.verdicts.values())


def inspect_conjugate(
    design: CamDesign, spec: FixtureSpec, *, step_deg: float = 0.1
) -> FixtureInspection:
    """Run the whole fixture analysis of THEORY §4 on a conjugate design.

    Parameters
    ----------
    design : CamDesign
        A conjugate design (mechanism :class:`~camtol.mechanisms.conjugate.ConjugatePair`).
    spec : FixtureSpec
        Errors, tolerances, master cams and the measured Δf.
    step_deg : float
        Grid step; 360 must be a whole multiple of it. Failing-interval ends are refined by
        bisection on the continuous functions to 1e-4° regardless. [deg]

    Returns
    -------
    FixtureInspection
    """
    n = int(round(360.0 / step_deg))
    if n < 4 or abs(n * step_deg - 360.0) > 1e-9:
        raise DesignError(f"step_deg={step_deg:g} is not allowed; 360 must be a multiple of it")
    theta: FloatArray = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    from camtol.validity import check_design_geometry

    _pair(design)
    check_design_geometry(design)  # both cams, whatever the grid (issue 9)
    fac, variation, est, bands = _fixture_parts(design, spec, theta)

    def evaluate(t: FloatArray) -> dict[str, FloatArray]:
        _, var_t, est_t, bands_t = _fixture_parts(design, spec, t)
        return fixture_curves(var_t, est_t, bands_t)

    extremes = find_extremes(
        theta, fixture_curves(variation, est, bands), evaluate, step_deg=step_deg
    )
    if spec.df_mea is None or est is None:
        return FixtureInspection(theta, fac, variation, None, bands, {}, extremes)
    df_mea = spec.df_mea

    def margin_fn(cam: str) -> Callable[[FloatArray], FloatArray]:
        def margin(t: FloatArray) -> FloatArray:
            f = conjugate_factors(t, design)
            b = acceptance_bands(
                f,
                spec.tolerance_a_um,
                spec.tolerance_b_um,
                spec.master_a,
                spec.master_b,
                spec.errors,
            )
            mea = df_mea(t)
            up, lo = (
                (b.df_a_upper_um, b.df_a_lower_um)
                if cam == "A"
                else (b.df_b_upper_um, b.df_b_lower_um)
            )
            return np.asarray(np.minimum(mea - lo, up - mea))

        return margin

    verdicts = {}
    for cam, (up, lo) in (
        ("A", (bands.df_a_upper_um, bands.df_a_lower_um)),
        ("B", (bands.df_b_upper_um, bands.df_b_lower_um)),
    ):
        m = np.minimum(est.df_mea_um - lo, up - est.df_mea_um)
        intervals = failing_intervals(theta, margin_fn(cam))
        verdicts[cam] = CamVerdict(cam, not intervals, intervals, float(m.min()))
    return FixtureInspection(theta, fac, variation, est, bands, verdicts, extremes)


def _fixture_parts(
    design: CamDesign, spec: FixtureSpec, theta: FloatArray
) -> tuple[ConjugateFactors, ConjugateVariation, InverseEstimate | None, AcceptanceBands]:
    """Geometry, variation, estimate (with a measurement) and bands at the angles."""
    fac = conjugate_factors(theta, design)
    bands = acceptance_bands(
        fac, spec.tolerance_a_um, spec.tolerance_b_um, spec.master_a, spec.master_b, spec.errors
    )
    if spec.df_mea is None:
        return fac, conjugate_variation(fac, spec.master_a, spec.master_b, spec.errors), None, bands
    est = inverse_estimate(fac, spec.df_mea, spec.master_a, spec.master_b, spec.errors)
    rf, ll, eta = _constant_parts(fac, spec.errors)
    return fac, ConjugateVariation(theta, est.df_r_um, rf, ll, eta), est, bands


def fixture_curves(
    variation: ConjugateVariation, estimate: InverseEstimate | None, bands: AcceptanceBands
) -> dict[str, FloatArray]:
    """Collect the fixture's curves by name (µm); the estimates only with a measurement."""
    out = {
        "df_r": variation.df_r_um,
        "df_rf": variation.df_rf_um,
        "df_l": variation.df_l_um,
        "df_eta": variation.df_eta_um,
        "df_est": variation.df_est_um,
    }
    if estimate is not None:
        out |= {
            "df_mea": estimate.df_mea_um,
            "dr_A_est": estimate.dr_a_est_um,
            "dr_B_est": estimate.dr_b_est_um,
        }
    out |= {
        "df_A_upper": bands.df_a_upper_um,
        "df_A_lower": bands.df_a_lower_um,
        "df_B_upper": bands.df_b_upper_um,
        "df_B_lower": bands.df_b_lower_um,
    }
    return {k: np.asarray(v, dtype=float) for k, v in out.items()}


_SPEC_KEYS = (
    "tolerance_a_um",
    "tolerance_b_um",
    "dl_a_um",
    "dl_b_um",
    "drr_c_um",
    "drr_d_um",
    "deta_deg",
    "master_a_um",
    "master_b_um",
    "df_mea_um",
)


def _function_field(raw: Mapping[str, Any], key: str, base_dir: Path | None) -> ErrorFunction:
    value = raw.get(key, 0.0)
    if isinstance(value, str) and value.strip().lower().endswith(".csv") and base_dir is not None:
        path = Path(value.strip())
        value = str(path if path.is_absolute() else base_dir / path)
    return parse_error_function(value, field=f"inspection.{key}")


def _number_field(raw: Mapping[str, Any], key: str) -> float:
    value = raw.get(key, 0.0)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise DesignError(f"inspection.{key}={value!r} must be a finite number")
    return float(value)


def _band_field(raw: Mapping[str, Any], key: str, default: Any = None) -> tuple[float, float]:
    value = raw.get(key, default)
    ok = (
        isinstance(value, list | tuple)
        and len(value) == 2
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
    )
    if not ok:
        raise DesignError(
            f"inspection.{key}={value!r} is not allowed; give [lower, upper] in µm, e.g. [-22, 22]"
        )
    return float(value[0]), float(value[1])


def fixture_spec_from_mapping(
    raw: Mapping[str, Any], *, base_dir: Path | None = None
) -> FixtureSpec:
    """Build a :class:`FixtureSpec` from a design file's ``[inspection]`` table.

    Parameters
    ----------
    raw : mapping
        Keys (all optional except ``tolerance_a_um``)::

            tolerance_a_um = [-22, 22]      # radial tolerance of cam A [µm]
            tolerance_b_um = [-22, 22]      # of cam B (default: as cam A) [µm]
            dl_a_um = 19                    # arm-length errors [µm]
            dl_b_um = 19
            drr_c_um = 11                   # roller-radius errors [µm]
            drr_d_um = 11
            deta_deg = 0.022                # arm-angle error [deg]
            master_a_um = "18.5 + 3.5*sin(theta)"   # master cams' known errors:
            master_b_um = "17.5 + 4.5*cos(2*theta)" #   number, formula or CSV path
            df_mea_um = 22                  # measured Δf: number, formula or CSV path

    base_dir : Path, optional
        Directory for relative CSV paths.

    Raises
    ------
    DesignError
        Naming the field, the value and what is allowed.
    """
    unknown = sorted(set(raw) - set(_SPEC_KEYS))
    if unknown:
        raise DesignError(
            f"inspection.{unknown[0]} is not a known field; allowed: {', '.join(_SPEC_KEYS)}"
        )
    tol_a = _band_field(raw, "tolerance_a_um")
    tol_b = _band_field(raw, "tolerance_b_um", list(tol_a))
    errors = FixtureErrors(
        dl_a_mm=_number_field(raw, "dl_a_um") * 1e-3,
        dl_b_mm=_number_field(raw, "dl_b_um") * 1e-3,
        drr_c_mm=_number_field(raw, "drr_c_um") * 1e-3,
        drr_d_mm=_number_field(raw, "drr_d_um") * 1e-3,
        deta_rad=math.radians(_number_field(raw, "deta_deg")),
    )
    df_mea = _function_field(raw, "df_mea_um", base_dir) if "df_mea_um" in raw else None
    return FixtureSpec(
        errors,
        tol_a,
        tol_b,
        _function_field(raw, "master_a_um", base_dir),
        _function_field(raw, "master_b_um", base_dir),
        df_mea,
    )
