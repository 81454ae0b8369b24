"""Writing a design back as a design file: :func:`dump_design` (issue 8, design identity).

Re-exported as :func:`camtol.config.design_file.dump_design`. The text reads back as an equal design
with the same :attr:`~camtol.design.cam_design.CamDesign.content_hash`.
"""

from __future__ import annotations

import math
from typing import Any

import camtol.config.toml_writer as toml_writer
from camtol.design.cam_design import CamDesign
from camtol.design.motion import LiftTable, SegmentProgram
from camtol.exceptions import ConfigError

__all__ = ["dump_design"]


def _file_value(internal: float, to_internal: Any, approx: float) -> float:
    """Return the file value v with to_internal(v) == internal exactly (shortest repr).

    ``approx`` is the inverse conversion; the exact preimage lies within a few ulps of it.
    """
    if to_internal(approx) == internal:
        best = approx
    else:
        best = math.nan
    lo = hi = approx
    candidates = [] if math.isnan(best) else [best]
    for _ in range(64):
        lo, hi = math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf)
        candidates += [v for v in (lo, hi) if to_internal(v) == internal]
    if not candidates:
        raise ValueError(f"{internal!r} has no exact file value")  # pragma: no cover
    return min(candidates, key=lambda v: (len(repr(v)), abs(v - approx)))


def _deg(internal_rad: float) -> float:
    return _file_value(float(internal_rad), math.radians, math.degrees(internal_rad))


def _motion_table(design: CamDesign) -> dict[str, Any]:
    program = design.program
    oscillating = design.mechanism.output == "oscillating"
    unit = "deg" if oscillating else "mm"
    if isinstance(program, SegmentProgram):
        segments = []
        for g in program.segments:
            seg: dict[str, Any] = {"kind": g.kind}
            if g.kind != "dwell":
                seg["law"] = g.law
            seg["start_deg"] = _deg(g.start_rad)
            seg["end_deg"] = _deg(g.end_rad)
            if g.kind != "dwell":
                seg[f"lift_{unit}"] = _deg(g.height) if oscillating else float(g.height)
            segments.append(seg)
        return {"segments": segments}
    if isinstance(program, LiftTable):
        lifts = [_deg(v) if oscillating else float(v) for v in program.lift]
        return {"table_step_deg": 360.0 / len(lifts), f"table_lift_{unit}": lifts}
    raise ConfigError(f"motion program {type(program).__name__} cannot be written to a file")


def _dynamics_table(design: CamDesign) -> dict[str, Any] | None:
    """Return the ``[dynamics]`` table as written in the file it came from (None: none)."""
    from camtol.dynamics.train import DynamicsTable

    table = design.extras.get("dynamics")
    return (table.to_mapping() or None) if isinstance(table, DynamicsTable) else None


def dump_design(design: CamDesign) -> str:
    """Write a design as a design file (TOML) that reads back equal.

    ``load → dump → load`` gives an equal design with the same
    :attr:`~camtol.design.cam_design.CamDesign.content_hash`: every number is written as the file
    value that converts to the design's internal value bit for bit (an angle in degrees
    whose radians are exactly the stored ones), a lift table inline
    (``table_step_deg`` and ``table_lift_mm``/``table_lift_deg``, whatever file it came
    from), tolerances as given (grade or deviation), and the ``[inspection]`` and
    ``[dynamics]`` tables as read. Comments of the original file are not kept.

    Parameters
    ----------
    design : CamDesign
        A design whose follower type has file parameters (every type of a design file).

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    ConfigError
        If the design holds something a design file cannot (a program built in Python
        that is neither segments nor a lift table, a follower type without parameters).
    """
    mech = design.mechanism
    if not mech.parameters:
        raise ConfigError(f"follower type {mech.kind!r} cannot be written to a design file")
    follower: dict[str, Any] = {"type": mech.kind}
    for p in mech.parameters:
        v = getattr(mech, p.attribute)
        if v is not None:
            follower[p.name] = _deg(v) if p.unit == "deg" else float(v)
    tolerances: dict[str, Any] = {}
    for t in design.tolerances:
        if t.grade is not None:
            tolerances[t.key] = t.grade
        else:
            unit = "um" if design.source(t.key).unit == "mm" else "deg"
            tolerances[f"{t.key}_{unit}"] = t.deviation
    operation = {
        "speed_rpm": design.speed_rpm,
        "pressure_angle_limit_deg": design.pressure_angle_limit_deg,
    }
    doc: dict[str, Any] = {
        "name": design.name,
        "description": design.description or None,
        "reference": design.reference or None,
        "follower": follower,
        "motion": _motion_table(design),
        "tolerances": tolerances or None,
        "operation": {k: v for k, v in operation.items() if v is not None} or None,
        "inspection": (design.inspection.to_mapping() or None) if design.inspection else None,
        "dynamics": _dynamics_table(design),
    }
    return toml_writer.dumps(doc)
