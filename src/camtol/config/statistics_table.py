"""The ``[statistics]`` table of a design file, validated (docs/tolerancing.md).

A table of fields per entry (:mod:`camtol.config.fields`: a number may be written as an
integer, a string is not a number), then the checks
that need the design: every entry names a toleranced source of the design (or
``default``, ``profile_process``), biases and zones in the source's own unit, a profile
process on a profile source the follower has. The result is the design's
:class:`~camtol.tolerancing.model.StatisticalModel`, which keeps the table as written
for the design's identity. Messages name the field, the value and what is allowed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from camtol.config.fields import (
    Field,
    Flag,
    Integer,
    ListOf,
    Number,
    Table,
    Text,
)
from camtol.design.cam_design import CamDesign
from camtol.exceptions import ConfigError
from camtol.tolerancing.distributions import SourceDistribution
from camtol.tolerancing.model import StatisticalModel
from camtol.tolerancing.processes import ProfileProcess

__all__ = ["parse_statistics"]


_OPTIONAL = Field(Number(), None)

#: One source's distribution (in the source's unit: ``_um`` or ``_deg``).
_SOURCE = Table(
    {
        "distribution": Field(Text(), "normal"),
        "cp": Field(Number(), 1.0),
        "truncate": Field(Flag(), True),
        **{
            f"{name}_{unit}": _OPTIONAL
            for name in ("bias", "zone_lower", "zone_upper")
            for unit in ("um", "deg")
        },
    }
)

#: A profile process: random (sigma, correlation) and harmonic (order, amplitude) errors.
_PROCESS = Table(
    {
        "target": Field(Text(), "r"),
        "sigma_um": _OPTIONAL,
        "correlation_deg": _OPTIONAL,
        "harmonics": Field(
            ListOf(
                Table(
                    {
                        "order": Field(Integer(minimum=1)),
                        "amplitude_um": Field(Number(0.0, unit="µm")),
                    }
                )
            ),
            [],
        ),
    }
)


def _source(data: Any, where: str, unit: str) -> SourceDistribution:
    s = _SOURCE.validate(data, where)
    want, other = ("um", "deg") if unit == "mm" else ("deg", "um")
    for name in ("bias", "zone_lower", "zone_upper"):
        if s[f"{name}_{other}"] is not None:
            raise ConfigError(
                f"{where}.{name}_{other}: this source is in {want}; use {name}_{want}"
            )

    def conv(v: float | None) -> float | None:
        if v is None:
            return None
        return v * 1e-3 if unit == "mm" else math.radians(v)

    try:
        return SourceDistribution(
            kind=s["distribution"],
            cp=s["cp"],
            bias=conv(s[f"bias_{want}"]) or 0.0,
            zone_lower=conv(s[f"zone_lower_{want}"]),
            zone_upper=conv(s[f"zone_upper_{want}"]),
            truncate=s["truncate"],
            label=where,
        )
    except ConfigError:
        raise
    except ValueError as exc:
        raise ConfigError(str(exc)) from None


def parse_statistics(raw: Mapping[str, Any], design: CamDesign) -> StatisticalModel:
    """Parse a ``[statistics]`` table for a design.

    Parameters
    ----------
    raw : mapping
        The table as read from TOML.
    design : CamDesign
        The design (its sources and their units).

    Returns
    -------
    StatisticalModel

    Raises
    ------
    ConfigError
        One line naming the field, the value and what is allowed.
    """
    units = {s.key: s.unit for s in design.sources}
    toleranced = [t.key for t in design.tolerances]
    sources: dict[str, SourceDistribution] = {}
    default = SourceDistribution()
    process = None
    from camtol.pair.kinematics import is_pair

    letters = [c.letter for c in design.cams()] if is_pair(design) else []
    per_cam = {f"profile_process_{letter.lower()}": letter for letter in letters}
    cam_processes: dict[str, ProfileProcess] = {}
    for key, value in raw.items():
        where = f"statistics.{key}"
        if key == "profile_process":
            process = _process(value, where, design)
        elif key in per_cam:
            cam = design.cam(per_cam[key])
            cam_processes[per_cam[key]] = _process(value, where, cam.design)
        elif key.startswith("profile_process_") and not letters:
            raise ConfigError(
                f"{where}: a process per cam applies to a conjugate pair; this"
                f" {design.mechanism.kind} design takes statistics.profile_process"
            )
        elif key == "default":
            default = _source(value, where, "mm")
            if (
                any(v is not None for v in (default.zone_lower, default.zone_upper))
                or default.bias != 0.0
            ):
                raise ConfigError(
                    f"{where}: bias and zone depend on the source; give them per source"
                )
        elif key in toleranced:
            sources[key] = _source(value, where, units[key])
        else:
            allowed = ", ".join([*toleranced, "default", "profile_process", *per_cam])
            raise ConfigError(
                f"{where} is not a toleranced source of this design; allowed: {allowed}"
            )
    return StatisticalModel(
        sources, default, process, cam_processes=cam_processes, table=tuple(raw.items())
    )


def _process(value: Any, where: str, design: CamDesign) -> ProfileProcess:
    """Validate a ``profile_process`` table for a (single-contact) design."""
    p = _PROCESS.validate(value, where)
    try:
        process = ProfileProcess(
            target=p["target"],
            sigma_um=p["sigma_um"],
            correlation_deg=p["correlation_deg"],
            harmonics=tuple((h["order"], h["amplitude_um"]) for h in p["harmonics"]),
        )
    except ValueError as exc:  # its messages name statistics.profile_process
        raise ConfigError(str(exc).replace("statistics.profile_process", where, 1)) from None
    own = {s.key for s in design.mechanism.sources}
    if process.target not in own:
        ok = ", ".join(k for k in "rn" if k in own)
        raise ConfigError(
            f"{where}.target={process.target!r}: a {design.mechanism.kind} follower"
            f" has no such profile source; allowed: {ok}"
        )
    return process
