"""The ``[dynamics]`` table of a design file, validated (docs/file-formats.md, THEORY §9.1).

A strict table of fields (:mod:`camtol.config.fields`: a string is not a number, a
boolean is not a mass) with the
bounds of every field, then the checks that need the design: the follower's output picks
the field names (``mass_kg`` or ``inertia_kg_mm2`` ...), a conjugate pair takes no spring
and no train stiffness, gravity only for a translating follower. The result is the
design's :class:`~camtol.dynamics.train.DynamicsTable`, which keeps the table as written
(numbers as floats, however spelt) for the design's identity. Messages name the field,
the value and what is allowed.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from camtol.config.fields import Field, Flag, Number, Table, describe_problems
from camtol.design.cam_design import CamDesign
from camtol.dynamics.train import DynamicsTable, check_applicable
from camtol.exceptions import ConfigError, FieldErrors

__all__ = ["parse_dynamics"]


def _positive(unit: str) -> Field:
    return Field(Number(0.0, exclusive_minimum=True, unit=unit), None)


def _nonnegative(unit: str) -> Field:
    return Field(Number(0.0, unit=unit), None)


_POISSON = Field(Number(0.0, 0.5, exclusive_maximum=True), None)

#: Fields of the ``[dynamics]`` table (THEORY §9.1), all optional, in file units.
DYNAMICS_TABLE = Table(
    {
        "mass_kg": _positive("kg"),
        "spring_rate_n_per_mm": _positive("N/mm"),
        "preload_n": _nonnegative("N"),
        "follower_stiffness_n_per_mm": _positive("N/mm"),
        "inertia_kg_mm2": _positive("kg·mm²"),
        "spring_rate_nm_per_rad": _positive("N·m/rad"),
        "preload_nm": _nonnegative("N·m"),
        "follower_stiffness_nm_per_rad": _positive("N·m/rad"),
        "damping_ratio": Field(Number(0.0, 2.0, exclusive_maximum=True), None),
        "face_width_mm": _positive("mm"),
        "youngs_modulus_cam_gpa": _positive("GPa"),
        "youngs_modulus_follower_gpa": _positive("GPa"),
        "poisson_ratio_cam": _POISSON,
        "poisson_ratio_follower": _POISSON,
        "gravity": Field(Flag(), False),
        "gravity_angle_deg": Field(Number(-180.0, 180.0, unit="deg"), None),
    }
)


def parse_dynamics(raw: Mapping[str, Any], design: CamDesign) -> DynamicsTable:
    """Parse a ``[dynamics]`` table for a design.

    Parameters
    ----------
    raw : mapping
        The table as read from TOML.
    design : CamDesign
        The design (its follower's output, whether it is a conjugate pair).

    Returns
    -------
    DynamicsTable

    Raises
    ------
    ConfigError
        One line naming the field, the value and what is allowed.
    """
    from camtol.pair.kinematics import is_pair

    try:
        table = DYNAMICS_TABLE.validate(raw)
    except FieldErrors as exc:
        problem = exc.problems[0]
        if problem.kind == "unknown":
            raise ConfigError(
                f"dynamics.{problem.loc[0]} is not a field of the [dynamics] table;"
                f" allowed: {problem.allowed}"
            ) from None
        raise ConfigError(describe_problems(exc.problems[:1], "dynamics")) from None
    values = {k: v for k, v in table.items() if v is not None and v is not False}
    if table["gravity_angle_deg"] is not None and not table["gravity"]:
        raise ConfigError(
            f"dynamics.gravity_angle_deg={table['gravity_angle_deg']:g} needs gravity = true"
        )
    try:
        check_applicable(values, design, form_closed=is_pair(design))
    except ConfigError:
        raise
    except ValueError as exc:
        raise ConfigError(str(exc)) from None
    # As written, but a number is a number however it is spelt (10, 10.0, 1e1): the hash
    # of the design must not depend on it (docs/architecture.md, design identity).
    written = tuple(
        (k, float(v) if isinstance(v, int) and not isinstance(v, bool) else v)
        for k, v in raw.items()
    )
    return DynamicsTable(values=tuple(values.items()), table=written)
