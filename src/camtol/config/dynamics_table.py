"""The ``[dynamics]`` table of a design file, validated (docs/file-formats.md, THEORY §9.1).

A strict pydantic schema (a string is not a number, a boolean is not a mass) with the
bounds of every field, then the checks that need the design: the follower's output picks
the field names (``mass_kg`` or ``inertia_kg_mm2`` ...), a conjugate pair takes no spring
and no train stiffness, gravity only for a translating follower. The result is the
design's :class:`~camtol.dynamics.train.DynamicsTable`, which keeps the table as written
(numbers as floats, however spelt) for the design's identity. Messages name the field,
the value and what is allowed.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from camtol.design.cam_design import CamDesign
from camtol.dynamics.train import DynamicsTable, check_applicable
from camtol.exceptions import ConfigError

__all__ = ["parse_dynamics"]

_POSITIVE = Annotated[float, Field(gt=0, allow_inf_nan=False)]
_NONNEGATIVE = Annotated[float, Field(ge=0, allow_inf_nan=False)]
_POISSON = Annotated[float, Field(ge=0, lt=0.5, allow_inf_nan=False)]


class DynamicsSchema(BaseModel):
    """Fields of the ``[dynamics]`` table (THEORY §9.1), all optional, in file units."""

    model_config = ConfigDict(extra="forbid", strict=True)

    mass_kg: _POSITIVE | None = None
    spring_rate_n_per_mm: _POSITIVE | None = None
    preload_n: _NONNEGATIVE | None = None
    follower_stiffness_n_per_mm: _POSITIVE | None = None
    inertia_kg_mm2: _POSITIVE | None = None
    spring_rate_nm_per_rad: _POSITIVE | None = None
    preload_nm: _NONNEGATIVE | None = None
    follower_stiffness_nm_per_rad: _POSITIVE | None = None
    damping_ratio: Annotated[float, Field(ge=0, lt=2, allow_inf_nan=False)] | None = None
    face_width_mm: _POSITIVE | None = None
    youngs_modulus_cam_gpa: _POSITIVE | None = None
    youngs_modulus_follower_gpa: _POSITIVE | None = None
    poisson_ratio_cam: _POISSON | None = None
    poisson_ratio_follower: _POISSON | None = None
    gravity: bool = False
    gravity_angle_deg: Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False)] | None = None


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
        table = DynamicsSchema.model_validate(dict(raw))
    except ValidationError as exc:
        e = exc.errors()[0]
        loc = ".".join(str(p) for p in e["loc"])
        if e["type"] == "extra_forbidden":
            allowed = ", ".join(DynamicsSchema.model_fields)
            raise ConfigError(
                f"dynamics.{loc} is not a field of the [dynamics] table; allowed: {allowed}"
            ) from None
        msg = e["msg"].removeprefix("Value error, ")
        raise ConfigError(f"dynamics.{loc}={e.get('input')!r}: {msg}") from None
    values = {k: v for k, v in table.model_dump().items() if v is not None and v is not False}
    if table.gravity_angle_deg is not None and not table.gravity:
        raise ConfigError(
            f"dynamics.gravity_angle_deg={table.gravity_angle_deg:g} needs gravity = true"
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
