"""The ``[inspection]`` table of a design file, validated (THEORY §4, §8.3).

A strict pydantic model (a string is not a number, a boolean is not a length; every
length within ±10 mm, Δη within ±10°) turns the table into the frozen
:class:`camtol.pair.fixture_spec.FixtureSpec` on the design. Messages name the field as
the user wrote it (``inspection.tolerance_a_um``), its value and what is allowed. The
table's fields are listed in :mod:`camtol.pair.fixture_spec`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, ValidationError

from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.units import MAX_ANGLE_ERROR_DEG, MAX_ERROR_UM
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


class _InspectionSchema(BaseModel):
    """Strict types of the ``[inspection]`` table (values checked further below)."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    tolerance_a_um: list[float]
    tolerance_b_um: list[float] | None = None
    dl_a_um: float = 0.0
    dl_b_um: float = 0.0
    drr_c_um: float = 0.0
    drr_d_um: float = 0.0
    deta_deg: float = 0.0
    master_a_um: float | str = 0.0
    master_b_um: float | str = 0.0
    df_mea_um: float | str | None = None


def _shown(value: object) -> str:
    r = repr(value)
    return r if len(r) <= 60 else r[:50] + "..."


def _validation_message(exc: ValidationError, raw: Mapping[str, Any], prefix: str) -> str:
    err = exc.errors()[0]
    key = str(err["loc"][0]) if err["loc"] else ""
    if err["type"] == "extra_forbidden":
        return f"{prefix}{key} is not a known field; allowed: {', '.join(_ALLOWED)}"
    if err["type"] == "missing":
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
) -> FixtureSpec:
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
    FixtureSpec
        The typed, frozen spec.

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
        m = _InspectionSchema.model_validate(dict(raw))
    except ValidationError as exc:
        raise DesignError(_validation_message(exc, raw, prefix)) from None
    tol_a = _band(m.tolerance_a_um, "tolerance_a_um", prefix, raw.get("tolerance_a_um"))
    tol_b = (
        tol_a
        if m.tolerance_b_um is None
        else _band(m.tolerance_b_um, "tolerance_b_um", prefix, raw.get("tolerance_b_um"))
    )
    lengths = {
        k: _bounded(getattr(m, k), k, MAX_ERROR_UM, "length", prefix)
        for k in ("dl_a_um", "dl_b_um", "drr_c_um", "drr_d_um")
    }
    deta = _bounded(m.deta_deg, "deta_deg", MAX_ANGLE_ERROR_DEG, "angle", prefix)
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
    )
