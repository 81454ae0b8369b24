"""The ``[inspection]`` table of a design file, validated (THEORY §4, §8.3).

A strict table of fields (:mod:`camtol.config.fields`: a string is not a number, a
boolean is not a length; every
length within ±10 mm, Δη within ±10°) turns the table into the frozen
:class:`camtol.pair.fixture_spec.FixtureSpec` on the design. Messages name the field as
the user wrote it (``inspection.tolerance_a_um``), its value and what is allowed. The
table's fields are listed in :mod:`camtol.pair.fixture_spec`.

The CMM profile zone (ISO 1101, issue 31; :mod:`camtol.inspection.zone`) is stated in the
same table, for any design: ``profile_tolerance_um`` (t), or ``profile_tolerance``
(a grade), with an optional ``profile_offset_um`` (UZ), or ``limits_um = [lo, hi]``; for
a conjugate pair per cam with ``_a``/``_b`` (``profile_tolerance_a_um``, ...). A table
with no fixture key (``tolerance_a_um``, ``dl_a_um``, ...) becomes a
:class:`~camtol.inspection.zone.ZoneTable`; otherwise the fixture's
:class:`FixtureSpec` carries the zones beside its own radial bands, which keep their
meaning ([CW11] §4.3) and are never the CMM zone.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from camtol.config.fields import AnyOf, Field, ListOf, Number, Table, Text
from camtol.exceptions import DesignError, FieldErrors
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.units import MAX_ANGLE_ERROR_DEG, MAX_ERROR_UM
from camtol.inspection.zone import ZoneSpec, ZoneTable
from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec

__all__ = ["fixture_spec_from_mapping"]


_LENGTH_BOUND = f"a number of µm within ±{MAX_ERROR_UM:g}"
_FUNCTION = "a number of µm, a length ('22 um', '0.022 mm'), a formula in theta or a CSV path"
#: What each field allows, for messages.
_ALLOWED: dict[str, str] = {
    "tolerance_a_um": "[lower, upper] in µm with lower < upper, e.g. [-22, 22]",
    "tolerance_b_um": "[lower, upper] in µm with lower < upper, e.g. [-22, 22]",
    "dl_a_um": _LENGTH_BOUND,
    "dl_b_um": _LENGTH_BOUND,
    "drr_c_um": _LENGTH_BOUND,
    "drr_d_um": _LENGTH_BOUND,
    "deta_deg": f"a number of degrees within ±{MAX_ANGLE_ERROR_DEG:g}",
    "master_a_um": _FUNCTION,
    "master_b_um": _FUNCTION,
    "df_mea_um": _FUNCTION,
}
_ZONE_ALLOWED = {
    "profile_tolerance{c}_um": "the zone width t > 0 in µm (ISO 1101: ±t/2 about the nominal)",
    "profile_tolerance{c}": "an IT grade such as 'IT7' (t = that grade at the largest radius)",
    "profile_offset{c}_um": "the zone offset UZ in µm (> 0 outwards), |UZ| < t/2",
    "limits{c}_um": "[lower, upper] in µm with lower < upper, e.g. [-15, 15]",
}
for _c in ("", "_a", "_b"):
    _ALLOWED.update({k.format(c=_c): v for k, v in _ZONE_ALLOWED.items()})
#: Keys of the measuring fixture (a table without any is a zone-only table).
_FIXTURE_KEYS = frozenset(
    ("tolerance_a_um", "tolerance_b_um", "dl_a_um", "dl_b_um", "drr_c_um", "drr_d_um")
    + ("deta_deg", "master_a_um", "master_b_um", "df_mea_um")
)


_REAL = Number(finite=False)  # types only here: the values are checked below
_REALS = ListOf(_REAL)
_FUNCTION_KIND = AnyOf((_REAL, Text()))

#: Strict types of the ``[inspection]`` table (values checked further below).
_INSPECTION = Table(
    {
        "tolerance_a_um": Field(_REALS, None),
        "tolerance_b_um": Field(_REALS, None),
        **{
            name.format(c=c): Field(kind, None)
            for c in ("", "_a", "_b")
            for name, kind in (
                ("profile_tolerance{c}_um", _REAL),
                ("profile_tolerance{c}", Text()),
                ("profile_offset{c}_um", _REAL),
                ("limits{c}_um", _REALS),
            )
        },
        "dl_a_um": Field(_REAL, 0.0),
        "dl_b_um": Field(_REAL, 0.0),
        "drr_c_um": Field(_REAL, 0.0),
        "drr_d_um": Field(_REAL, 0.0),
        "deta_deg": Field(_REAL, 0.0),
        "master_a_um": Field(_FUNCTION_KIND, 0.0),
        "master_b_um": Field(_FUNCTION_KIND, 0.0),
        "df_mea_um": Field(_FUNCTION_KIND, None),
    }
)


def _shown(value: object) -> str:
    r = repr(value)
    return r if len(r) <= 60 else r[:50] + "..."


def _validation_message(exc: FieldErrors, raw: Mapping[str, Any], prefix: str) -> str:
    problem = exc.problems[0]
    key = str(problem.loc[0]) if problem.loc else ""
    if problem.kind == "unknown":
        return f"{prefix}{key} is not a known field; allowed: {', '.join(_ALLOWED)}"
    if problem.kind == "missing":
        return f"{prefix}{key} is missing; give {_ALLOWED.get(key, 'a value')}"
    return (
        f"{prefix}{key}={_shown(raw.get(key))} is not allowed; give"
        f" {_ALLOWED.get(key, 'a valid value')}"
    )


def _band(value: list[float] | None, key: str, prefix: str, given: object) -> tuple[float, float]:
    """Return (lower, upper) of a tolerance band; ``given`` is the value as written."""
    if value is None or len(value) != 2:
        raise DesignError(f"{prefix}{key}={_shown(given)} is not allowed; give {_ALLOWED[key]}")
    lo, hi = float(value[0]), float(value[1])
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise DesignError(f"{prefix}{key}={_shown(given)} is not allowed; give {_ALLOWED[key]}")
    if max(abs(lo), abs(hi)) > MAX_ERROR_UM:
        raise DesignError(
            f"{prefix}{key}={_shown(given)} is not allowed; give limits within"
            f" ±{MAX_ERROR_UM:g} µm (check the unit)"
        )
    return lo, hi


def _bounded(value: float, key: str, bound: float, unit: str, prefix: str) -> float:
    if not (math.isfinite(value) and abs(value) <= bound):
        raise DesignError(
            f"{prefix}{key}={_shown(value)} is not allowed; give {_ALLOWED[key]}"
            f" (a larger {unit} is a unit mistake)"
        )
    return float(value)


def _function(value: Any, base_dir: Path | None) -> Any:
    """Return the value with a relative CSV path made absolute (against ``base_dir``)."""
    if isinstance(value, str) and value.strip().lower().endswith(".csv") and base_dir is not None:
        path = Path(value.strip())
        return str(path if path.is_absolute() else base_dir / path)
    return value


def fixture_spec_from_mapping(
    raw: Mapping[str, Any], *, base_dir: Path | None = None, prefix: str = "inspection."
) -> FixtureSpec | ZoneTable:
    """Validate a design file's ``[inspection]`` table into a :class:`FixtureSpec`.

    Parameters
    ----------
    raw : mapping
        The table (see the module docstring); only ``tolerance_a_um`` is required.
    base_dir : Path, optional
        Directory for relative CSV paths (the design file's directory).
    prefix : str
        How the table is named in messages.

    Returns
    -------
    FixtureSpec or ZoneTable
        The typed, frozen spec (with the CMM zones, if any); a
        :class:`~camtol.inspection.zone.ZoneTable` for a table that states only zones.

    Raises
    ------
    DesignError
        Naming the field as written (``inspection.tolerance_a_um``), the value and what is
        allowed.
    InputFileError
        When a CSV table it names cannot be read (naming file, line and column).
    """
    if not isinstance(raw, Mapping):
        raise DesignError(f"{prefix.rstrip('.')}={_shown(raw)} is not allowed; give a table")
    try:
        m = _INSPECTION.validate(raw)
    except FieldErrors as exc:
        raise DesignError(_validation_message(exc, raw, prefix)) from None
    zones = _zones(m, raw, prefix)
    if not _FIXTURE_KEYS.intersection(raw):
        if not zones:
            raise DesignError(
                f"{prefix.rstrip('.')} states nothing; give {prefix}profile_tolerance_um"
                " (the CMM zone) or the fixture's inputs (tolerance_a_um, ...)"
            )
        return ZoneTable(zones, table=tuple(dict(raw).items()))
    if m["tolerance_a_um"] is None:
        raise DesignError(f"{prefix}tolerance_a_um is missing; give {_ALLOWED['tolerance_a_um']}")
    tol_a = _band(m["tolerance_a_um"], "tolerance_a_um", prefix, raw.get("tolerance_a_um"))
    tol_b = (
        tol_a
        if m["tolerance_b_um"] is None
        else _band(m["tolerance_b_um"], "tolerance_b_um", prefix, raw.get("tolerance_b_um"))
    )
    lengths = {
        k: _bounded(m[k], k, MAX_ERROR_UM, "length", prefix)
        for k in ("dl_a_um", "dl_b_um", "drr_c_um", "drr_d_um")
    }
    deta = _bounded(m["deta_deg"], "deta_deg", MAX_ANGLE_ERROR_DEG, "angle", prefix)
    errors = FixtureErrors(
        dl_a_mm=lengths["dl_a_um"] * 1e-3,
        dl_b_mm=lengths["dl_b_um"] * 1e-3,
        drr_c_mm=lengths["drr_c_um"] * 1e-3,
        drr_d_mm=lengths["drr_d_um"] * 1e-3,
        deta_rad=math.radians(deta),
    )
    given = {k: _function(v, base_dir) if k.endswith("_um") else v for k, v in raw.items()}
    functions = {
        k: parse_error_function(given[k], field=f"{prefix}{k}")
        for k in ("master_a_um", "master_b_um", "df_mea_um")
        if k in given
    }
    zero = ErrorFunction.constant(0.0)
    return FixtureSpec(
        errors,
        tol_a,
        tol_b,
        functions.get("master_a_um", zero),
        functions.get("master_b_um", zero),
        functions.get("df_mea_um"),
        table=tuple(given.items()),
        profile_zones=ZoneTable(zones, table=()) if zones else None,
    )


def _zones(m: Mapping[str, Any], raw: Mapping[str, Any], prefix: str) -> dict[str, ZoneSpec]:
    """Return the CMM profile zone of each cam the table states one for (ISO 1101).

    Unsuffixed keys state the zone of a single cam, or of both cams of a pair; ``_a`` /
    ``_b`` keys state one cam's (and win over the unsuffixed ones for that cam).
    """
    out: dict[str, ZoneSpec] = {}
    for suffix, cams in (("", ("A", "B")), ("_a", ("A",)), ("_b", ("B",))):
        width = m[f"profile_tolerance{suffix}_um"]
        grade = m[f"profile_tolerance{suffix}"]
        offset = m[f"profile_offset{suffix}_um"]
        limits = m[f"limits{suffix}_um"]
        names = {
            "width": f"{prefix}profile_tolerance{suffix}_um",
            "grade": f"{prefix}profile_tolerance{suffix}",
            "offset": f"{prefix}profile_offset{suffix}_um",
            "limits": f"{prefix}limits{suffix}_um",
        }
        if width is None and grade is None and limits is None:
            if offset is not None:
                raise DesignError(
                    f"{names['offset']}={offset!r} needs the zone width: give"
                    f" {names['width']} (or {names['grade']}) as well"
                )
            continue
        if width is not None and grade is not None:
            raise DesignError(
                f"{names['grade']}={grade!r} and {names['width']}={width!r} both state t;"
                " give one of them"
            )
        if limits is not None and (width is not None or grade is not None or offset is not None):
            other = names["width"] if width is not None else names["grade"]
            if width is None and grade is None:
                other = names["offset"]
            raise DesignError(
                f"{names['limits']} and {other} both state the zone; give either"
                " profile_tolerance_um (with profile_offset_um) or limits_um"
            )
        spec: ZoneSpec
        if limits is not None:
            lo, hi = _band(limits, f"limits{suffix}_um", prefix, raw.get(f"limits{suffix}_um"))
            spec = ZoneSpec(names["limits"], limits_um=(lo, hi))
        else:
            if grade is not None:
                from camtol import iso286
                from camtol.exceptions import ToleranceGradeError

                try:
                    grade = iso286.parse_grade(grade)
                except ToleranceGradeError:
                    raise DesignError(
                        f"{names['grade']}={_shown(grade)} is not allowed; give"
                        f" {_ALLOWED[f'profile_tolerance{suffix}']}"
                    ) from None
            if width is not None and not (math.isfinite(width) and 0 < width <= MAX_ERROR_UM):
                raise DesignError(
                    f"{names['width']}={_shown(width)} is not allowed; give"
                    f" {_ALLOWED[f'profile_tolerance{suffix}_um']}, at most {MAX_ERROR_UM:g}"
                )
            off = 0.0 if offset is None else float(offset)
            if width is not None and not (math.isfinite(off) and abs(off) < 0.5 * width):
                raise DesignError(
                    f"{names['offset']}={_shown(offset)} is not allowed; give"
                    f" {_ALLOWED[f'profile_offset{suffix}_um']} (t/2 = {0.5 * width:g} µm)"
                )
            if not math.isfinite(off) or abs(off) > MAX_ERROR_UM:
                raise DesignError(
                    f"{names['offset']}={_shown(offset)} is not allowed; give"
                    f" {_ALLOWED[f'profile_offset{suffix}_um']}"
                )
            key = names["grade"] if grade is not None else names["width"]
            spec = ZoneSpec(key, width_um=width, grade=grade, offset_um=off)
        for cam in cams:
            out[cam] = spec
    return out
