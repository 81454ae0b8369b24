"""Design files: TOML schema, validation and built-in examples.

A design file describes one cam: the follower, the motion program, the tolerances and
optionally the operating speed. Every field carries its unit in its name (``_mm``,
``_deg``, ``_um``, ``_rpm``). Validation errors name the field, the value and what is
allowed, in one line (:class:`~camtol.exceptions.ConfigError`).

Schema (see ``camtol examples show cw06-translating`` for a complete file)::

    name = "my-cam"                      # required
    description = "..."                  # optional free text
    reference = "..."                    # optional source

    [follower]
    type = "flat_translating"            # see FOLLOWER_SCHEMAS for the types
    base_radius_mm = 40.0
    offset_mm = 10.0
    face_angle_deg = 15.0

    [motion]                             # either segments ...
    segments = [
      { kind = "rise", law = "cycloidal", start_deg = 0, end_deg = 120, lift_mm = 22 },
      { kind = "dwell", start_deg = 120, end_deg = 190 },
      ...
    ]
    # ... or a lift table: table_file = "lift.csv" (columns theta_deg and lift_mm or
    # lift_deg), or table_step_deg = 1.0 with table_lift_mm = [...] (or table_lift_deg)

    [tolerances]                         # per error source: a grade or a deviation
    r = "IT6"                            # grade (THEORY §3.6 conventions)
    e_um = 9.0                           # explicit length deviation [µm]
    phi_deg = 0.011                      # explicit angle deviation [deg]

    [operation]                          # optional
    speed_rpm = 300
    pressure_angle_limit_deg = 30

Lifts are in mm for translating followers (``lift_mm``) and degrees for oscillating ones
(``lift_deg``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from camtol.design import CamDesign, ToleranceSpec
from camtol.examples import example_names as example_names
from camtol.examples import example_summary as example_summary
from camtol.examples import example_text as example_text
from camtol.examples import parse_toml as _parse_toml
from camtol.exceptions import ConfigError, DesignError, InputFileError
from camtol.mechanisms import FlatOscillating, FlatTranslating, Mechanism
from camtol.motion import (
    MOTION_LAWS,
    LiftTable,
    MotionProgram,
    Segment,
    SegmentProgram,
    table_resolution,
)
from camtol.sources import DESIGN_SOURCES
from camtol.tables import read_table

if TYPE_CHECKING:
    from camtol.inspection.spec import FixtureSpec

__all__ = [
    "FOLLOWER_SCHEMAS",
    "design_from_mapping",
    "example_names",
    "example_text",
    "load_design",
    "load_example",
]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# --- followers -------------------------------------------------------------------------
class FlatTranslatingSchema(_Strict):
    """``type = "flat_translating"``: offset translating oblique flat face (THEORY §2.1)."""

    type: Literal["flat_translating"]
    base_radius_mm: float = Field(gt=0)
    offset_mm: float = 0.0
    face_angle_deg: float = Field(default=0.0, gt=-90, lt=90)

    def build(self) -> Mechanism:
        """Return the mechanism."""
        return FlatTranslating(
            self.base_radius_mm, self.offset_mm, math.radians(self.face_angle_deg)
        )


class FlatOscillatingSchema(_Strict):
    """``type = "flat_oscillating"``: oscillating flat face (THEORY §2.2)."""

    type: Literal["flat_oscillating"]
    base_radius_mm: float = Field(gt=0)
    pivot_distance_mm: float = Field(gt=0)
    face_offset_mm: float = 0.0

    def build(self) -> Mechanism:
        """Return the mechanism."""
        return FlatOscillating(self.base_radius_mm, self.pivot_distance_mm, self.face_offset_mm)


class RollerTranslatingSchema(_Strict):
    """``type = "roller_translating"``: offset translating roller (THEORY §2.3)."""

    type: Literal["roller_translating"]
    base_radius_mm: float = Field(gt=0)
    roller_radius_mm: float = Field(gt=0)
    offset_mm: float = 0.0

    def build(self) -> Mechanism:
        """Return the mechanism."""
        from camtol.mechanisms.roller_translating import RollerTranslating

        return RollerTranslating(self.base_radius_mm, self.roller_radius_mm, self.offset_mm)


class RollerOscillatingSchema(_Strict):
    """``type = "roller_oscillating"``: oscillating roller, cam A alone (THEORY §2.4)."""

    type: Literal["roller_oscillating"]
    base_radius_mm: float = Field(gt=0)
    roller_radius_mm: float = Field(gt=0)
    pivot_distance_mm: float = Field(gt=0)
    arm_length_mm: float = Field(gt=0)

    def build(self) -> Mechanism:
        """Return the mechanism."""
        from camtol.mechanisms.roller_oscillating import RollerOscillating

        return RollerOscillating(
            self.base_radius_mm, self.roller_radius_mm, self.pivot_distance_mm, self.arm_length_mm
        )


class ConjugateSchema(_Strict):
    """``type = "conjugate"``: conjugate cams A and B, double-roller follower (THEORY §2.4).

    The fixture data of ``camtol conjugate`` go in the ``[inspection]`` table
    (:mod:`camtol.inspection.spec`).
    """

    type: Literal["conjugate"]
    base_radius_mm: float = Field(gt=0)
    roller_radius_mm: float = Field(gt=0)
    roller_b_radius_mm: float | None = Field(default=None, gt=0)
    pivot_distance_mm: float = Field(gt=0)
    arm_a_mm: float = Field(gt=0)
    arm_b_mm: float = Field(gt=0)
    arm_angle_deg: float = Field(gt=0, lt=180)

    def build(self) -> Mechanism:
        """Return the mechanism (cam A's view; cam B via ``.cam_b``)."""
        from camtol.mechanisms.conjugate import ConjugatePair

        return ConjugatePair(
            self.base_radius_mm,
            self.roller_radius_mm,
            self.pivot_distance_mm,
            self.arm_a_mm,
            self.arm_b_mm,
            math.radians(self.arm_angle_deg),
            self.roller_b_radius_mm,
        )


#: Follower schema by ``follower.type``. Each schema's ``build()`` returns the mechanism.
FOLLOWER_SCHEMAS: dict[str, type[Any]] = {
    "flat_translating": FlatTranslatingSchema,
    "flat_oscillating": FlatOscillatingSchema,
    "roller_translating": RollerTranslatingSchema,
    "roller_oscillating": RollerOscillatingSchema,
    "conjugate": ConjugateSchema,
}


# --- motion ----------------------------------------------------------------------------
class SegmentSchema(_Strict):
    """One motion segment."""

    kind: Literal["rise", "return", "dwell"]
    law: str | None = None
    start_deg: float | None = None
    end_deg: float
    lift_mm: float | None = Field(default=None, gt=0)
    lift_deg: float | None = Field(default=None, gt=0)

    @field_validator("law")
    @classmethod
    def _known_law(cls, v: str | None) -> str | None:
        if v is not None and v not in MOTION_LAWS:
            raise ValueError(f"unknown motion law; allowed: {', '.join(MOTION_LAWS)}")
        return v


class MotionSchema(_Strict):
    """The motion program: segments or a lift table."""

    segments: list[SegmentSchema] | None = None
    table_file: str | None = None
    table_step_deg: float | None = Field(default=None, gt=0)
    table_lift_mm: list[float] | None = None
    table_lift_deg: list[float] | None = None


class OperationSchema(_Strict):
    """Operating conditions."""

    speed_rpm: float | None = Field(default=None, gt=0)
    pressure_angle_limit_deg: float | None = Field(default=None, gt=0, lt=90)


class TraceabilitySchema(_Strict):
    """Optional ``[traceability]`` table: what identifies the part in a QA report."""

    part_number: str | None = None
    drawing_number: str | None = None
    revision: str | None = None
    serial: str | None = None
    inspector: str | None = None
    instrument: str | None = None
    date: str | None = None


class DrawingSchema(_Strict):
    """Optional ``[drawing]`` table: features drawn in the DXF/SVG export only."""

    bore_diameter_mm: float | None = Field(default=None, gt=0)
    hub_diameter_mm: float | None = Field(default=None, gt=0)


class DesignSchema(_Strict):
    """Top level of a design file."""

    name: str = Field(min_length=1)
    description: str = ""
    reference: str = ""
    follower: dict[str, Any]
    motion: MotionSchema
    tolerances: dict[str, Any] = {}
    operation: OperationSchema = OperationSchema()
    # The conjugate fixture's inputs: typed by camtol.inspection.spec (field names checked
    # there, so that messages name them as `inspection.<field>`).
    inspection: dict[str, Any] = {}
    traceability: TraceabilitySchema = TraceabilitySchema()
    drawing: DrawingSchema = DrawingSchema()


def _format_validation_error(exc: ValidationError, prefix: str = "") -> str:
    parts = []
    for err in exc.errors():
        loc = ".".join(str(p) if not isinstance(p, int) else f"[{p}]" for p in err["loc"])
        loc = (prefix + loc).replace(".[", "[")
        if err["type"] == "missing":
            parts.append(f"{loc} is missing")
        elif err["type"] == "extra_forbidden":
            parts.append(f"{loc} is not a known field")
        else:
            msg = err["msg"].removeprefix("Value error, ")
            parts.append(f"{loc}={err.get('input')!r}: {msg}")
    return "; ".join(parts)


def _validate(model: type[Any], data: Any, prefix: str = "") -> Any:
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise ConfigError(_format_validation_error(exc, prefix)) from None


def _motion_program(m: MotionSchema, oscillating: bool, base_dir: Path | None) -> MotionProgram:
    unit = "deg" if oscillating else "mm"
    wrong = "mm" if oscillating else "deg"
    kind = "an oscillating" if oscillating else "a translating"
    sources = [m.segments is not None, m.table_file is not None, m.table_step_deg is not None]
    if sum(sources) != 1:
        raise ConfigError(
            "motion: give exactly one of segments, table_file, or table_step_deg with"
            f" table_lift_{unit}"
        )
    scale = math.radians(1.0) if oscillating else 1.0
    if m.segments is not None:
        segs = []
        prev_end: float | None = None
        for i, s in enumerate(m.segments):
            where = f"motion.segments[{i}]"
            if (s.lift_mm if oscillating else s.lift_deg) is not None:
                raise ConfigError(
                    f"{where}.lift_{wrong} is not allowed: {kind} follower's lift is given as"
                    f" lift_{unit}"
                )
            seg_lift = s.lift_deg if oscillating else s.lift_mm
            if s.kind == "dwell":
                if seg_lift is not None or s.law is not None:
                    raise ConfigError(f"{where}: a dwell takes no law and no lift_{unit}")
            elif seg_lift is None:
                raise ConfigError(f"{where}.lift_{unit} is missing: a {s.kind} needs its height")
            start = s.start_deg if s.start_deg is not None else prev_end
            if start is None:
                raise ConfigError(f"{where}.start_deg is missing (needed for the first segment)")
            prev_end = s.end_deg
            segs.append(
                Segment(
                    s.kind,
                    math.radians(start),
                    math.radians(s.end_deg),
                    s.law or "cycloidal",
                    (seg_lift or 0.0) * scale,
                )
            )
        return SegmentProgram(tuple(segs))
    if m.table_file is not None:
        path = Path(m.table_file)
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        theta_deg, lift = _read_lift_csv(path, unit)
    else:
        values = m.table_lift_deg if oscillating else m.table_lift_mm
        if (m.table_lift_mm if oscillating else m.table_lift_deg) is not None or values is None:
            raise ConfigError(f"motion.table_lift_{unit} is missing ({kind} follower)")
        assert m.table_step_deg is not None
        theta_deg = np.arange(len(values)) * m.table_step_deg
        lift = np.asarray(values, dtype=float)
        if abs(len(values) * m.table_step_deg - 360.0) > 1e-9:
            raise ConfigError(
                f"motion.table_step_deg={m.table_step_deg:g} with {len(values)} lifts covers"
                f" {len(values) * m.table_step_deg:g}°; the table must cover exactly 360°"
                " (omit the closing 360° entry)"
            )
    q = table_resolution(lift)
    return LiftTable(
        np.radians(theta_deg),
        np.asarray(lift, dtype=float) * scale,
        resolution=None if q is None else q * scale,
    )


def _read_lift_csv(path: Path, unit: str) -> tuple[np.ndarray[Any, Any], np.ndarray[Any, Any]]:
    col = f"lift_{unit}"
    try:
        table = read_table(path, required=["theta_deg", col], what="lift table")
    except InputFileError as exc:
        detail = str(exc).removeprefix(str(path)).lstrip(":, ")
        raise ConfigError(f"motion.table_file={str(path)!r} {detail}") from None
    theta, lift = table.column("theta_deg"), table.column(col)
    if theta.size > 1 and abs(theta[-1] - 360.0) < 1e-9:  # a closing 360° row repeats 0°
        theta, lift = theta[:-1], lift[:-1]
    return theta, lift


def _tolerances(raw: Mapping[str, Any], mech: Mechanism) -> tuple[ToleranceSpec, ...]:
    specs = []
    seen: set[str] = set()
    units = {s.key: s.unit for s in mech.sources}
    units.update({k: d.source.unit for k, d in DESIGN_SOURCES.items()})
    allowed = ", ".join(
        f"{k} (grade) or {k}_{'um' if u == 'mm' else 'deg'}" for k, u in units.items()
    )
    for name, value in raw.items():
        key, _, suffix = name.partition("_")
        if key not in units:
            raise ConfigError(
                f"tolerances.{name} is not an error source of a {mech.kind} follower;"
                f" allowed: {allowed}"
            )
        if key in seen:
            raise ConfigError(f"tolerances.{key} is given twice")
        seen.add(key)
        want = "um" if units[key] == "mm" else "deg"
        if suffix == "":
            if not isinstance(value, str):
                raise ConfigError(
                    f"tolerances.{name}={value!r}: a bare key takes an IT grade such as 'IT6';"
                    f" give an explicit deviation as {key}_{want}"
                )
            try:
                specs.append(ToleranceSpec(key, grade=value))
            except ValueError as exc:
                raise ConfigError(f"tolerances.{name}={value!r}: {exc}") from None
        elif suffix == want:
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(f"tolerances.{name}={value!r} must be a number of {want}")
            specs.append(ToleranceSpec(key, deviation=float(value)))
        else:
            raise ConfigError(
                f"tolerances.{name}: the unit suffix must be _{want} for source {key!r}"
            )
    return tuple(specs)


def design_from_mapping(data: Mapping[str, Any], *, base_dir: Path | None = None) -> CamDesign:
    """Build and validate a :class:`CamDesign` from parsed TOML.

    Parameters
    ----------
    data : mapping
        The parsed file.
    base_dir : Path, optional
        Directory for relative paths in the file (lift tables).

    Raises
    ------
    ConfigError
        Naming the field, the value and what is allowed.
    """
    top = _validate(DesignSchema, data)
    ftype = top.follower.get("type")
    if ftype not in FOLLOWER_SCHEMAS:
        raise ConfigError(
            f"follower.type={ftype!r} is unknown; allowed: {', '.join(FOLLOWER_SCHEMAS)}"
        )
    fschema = _validate(FOLLOWER_SCHEMAS[ftype], top.follower, "follower.")
    try:
        mech = fschema.build()
        program = _motion_program(top.motion, mech.output == "oscillating", base_dir)
        return CamDesign(
            name=top.name,
            mechanism=mech,
            program=program,
            tolerances=_tolerances(top.tolerances, mech),
            speed_rpm=top.operation.speed_rpm,
            pressure_angle_limit_deg=top.operation.pressure_angle_limit_deg,
            description=top.description,
            reference=top.reference,
            inspection=_inspection(top.inspection, base_dir),
            extras=_extras(top),
        )
    except ConfigError:
        raise
    except DesignError as exc:
        raise ConfigError(str(exc)) from None


def _extras(top: DesignSchema) -> dict[str, object]:
    """``[traceability]`` and ``[drawing]`` as ``CamDesign.extras`` (only the fields given)."""
    out: dict[str, object] = {}
    trace = top.traceability.model_dump(exclude_none=True)
    if trace:
        out["traceability"] = trace
    out.update(top.drawing.model_dump(exclude_none=True))
    return out


def _inspection(raw: dict[str, Any], base_dir: Path | None) -> FixtureSpec | None:
    """Return the ``[inspection]`` table as a typed, frozen spec (None when absent)."""
    if not raw:
        return None
    from camtol.inspection.spec import fixture_spec_from_mapping

    return fixture_spec_from_mapping(raw, base_dir=base_dir)


def load_design(path: str | Path) -> CamDesign:
    """Read a design file (TOML).

    Parameters
    ----------
    path : str or Path
        Design file; relative paths inside it are resolved against its directory.

    Returns
    -------
    CamDesign
        The validated design.

    Raises
    ------
    ConfigError
        The file is missing, not TOML, or invalid.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"design file {str(p)!r} cannot be read: {exc.strerror}") from None
    return design_from_mapping(_parse_toml(text, f"design file {str(p)!r}"), base_dir=p.parent)


def load_example(name: str) -> CamDesign:
    """Load a built-in example design by name (see :func:`example_names`).

    Parameters
    ----------
    name : str
        Example name, one of :func:`example_names`.

    Returns
    -------
    CamDesign
        The validated design.

    Raises
    ------
    ConfigError
        If there is no such example.
    """
    return design_from_mapping(_parse_toml(example_text(name), f"example {name!r}"))
