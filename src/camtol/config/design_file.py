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
    type = "flat_translating"            # see follower_types() for the types
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

Why one module: it is the one mapping from a design file's fields to a
:class:`~camtol.design.cam_design.CamDesign`. The pydantic schema says which fields exist
and the builders below it (follower, motion, tolerances) check what the schema cannot and
turn each table into its design object, naming fields by the same ``table.field`` paths in
every message; the example and writer helpers are only re-exported here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationError,
    create_model,
    field_validator,
)

from camtol.config.examples import example_names as example_names
from camtol.config.examples import example_summary as example_summary
from camtol.config.examples import example_text as example_text
from camtol.config.examples import parse_toml as _parse_toml
from camtol.design.cam_design import CamDesign, ToleranceSpec
from camtol.design.motion import (
    MOTION_LAWS,
    RETIRED_LAWS,
    LiftTable,
    MotionProgram,
    Segment,
    SegmentProgram,
)
from camtol.design.sources import DESIGN_SOURCES
from camtol.design.table_noise import table_resolution
from camtol.exceptions import ConfigError, DesignError, InputFileError
from camtol.grid import drop_closing_row, uniform_table_step
from camtol.mechanisms import MECHANISMS, Mechanism
from camtol.tables import read_table

if TYPE_CHECKING:
    from camtol.inspection.zone import ZoneTable
    from camtol.pair.fixture_spec import FixtureSpec

__all__ = [
    "dump_design",
    "follower_types",
    "design_from_mapping",
    "example_names",
    "example_text",
    "load_design",
    "load_example",
]


#: Plausible ranges of the design-level quantities (the follower's are declared by each
#: follower class, :mod:`camtol.mechanisms.spec`). Values outside are refused with a
#: message naming the field, so that no 1e300 reaches the numerics.
SPEED_MAX_RPM = 1e6
#: Largest lift of a translating follower's segment or table entry. [mm]
LIFT_MAX_MM = 1e5
#: Largest swing of an oscillating follower's segment or table entry. [deg]
LIFT_MAX_DEG = 180.0
#: Segment angles lie within ±this. [deg]
ANGLE_MAX_DEG = 1e4
#: Largest explicit length deviation in [tolerances]. [um]
DEVIATION_MAX_UM = 1e6
#: Largest explicit angle deviation in [tolerances]. [deg]
DEVIATION_MAX_DEG = 90.0
#: Longest value shown in a message (longer ones are shortened with "…"). [characters]
VALUE_CHARS = 80
#: Longest validation message (further problems are counted, not listed). [characters]
MESSAGE_CHARS = 400

_FINITE: dict[str, Any] = {"allow_inf_nan": False}


class _Strict(BaseModel):
    # strict: a string is not a number, a boolean is not a length (issue 9 item 11)
    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)


def _number(lo: float, hi: float, description: str, *, open_low: bool = False) -> Any:
    low: dict[str, Any] = {"gt": lo} if open_low else {"ge": lo}
    return Annotated[float, Field(le=hi, description=description, **low, **_FINITE)]


# --- followers: derived from the follower classes ---------------------------------------
def _follower_model(cls: type[Mechanism]) -> type[BaseModel]:
    """Build the pydantic model of one follower type from its Parameter declarations."""
    fields: dict[str, Any] = {"type": (Literal[cls.kind], ...)}
    for p in cls.parameters:
        bounds: dict[str, Any] = (
            {"gt": p.minimum, "lt": p.maximum}
            if p.exclusive
            else {"ge": p.minimum, "le": p.maximum}
        )
        desc = f"{p.description}; {p.describe_range()}"
        ann: Any = Annotated[float, Field(description=desc, **bounds, **_FINITE)]
        if p.required:
            # Field() without a default marks it required; a bare ``...`` beside an
            # Annotated Field was taken as the default itself by pydantic 2.5.
            fields[p.name] = (ann, Field())
        elif p.default is None:
            fields[p.name] = (ann | None, None)
        else:
            fields[p.name] = (ann, p.default)
    doc = f"``type = {cls.kind!r}``: {cls.title or cls.__name__} follower."
    model: type[BaseModel] = create_model(
        f"{cls.__name__}Schema", __base__=_Strict, __doc__=doc, **fields
    )
    return model


@lru_cache(maxsize=8)
def _follower_adapter(types: tuple[type[Mechanism], ...]) -> TypeAdapter[Any]:
    models = tuple(_follower_model(c) for c in types)
    union: Any = Union[models]  # noqa: UP007  (a runtime tuple of models)
    return TypeAdapter(Annotated[union, Field(discriminator="type")])


def follower_types() -> dict[str, type[Mechanism]]:
    """Follower types a design file may name (``follower.type``), from the registry.

    Returns
    -------
    dict of str to type
        :data:`camtol.mechanisms.MECHANISMS` restricted to types with file parameters.
    """
    ordered = sorted(MECHANISMS.items(), key=lambda kc: (kc[1].listing_order, kc[0]))
    return {k: c for k, c in ordered if c.parameters}


def _follower(raw: Any) -> Mechanism:
    """Validate ``[follower]`` against the one discriminated union; build the mechanism."""
    types = follower_types()
    allowed = ", ".join(types)
    if not isinstance(raw, Mapping):
        raise ConfigError(f"follower={_short(raw)} must be a table; allowed types: {allowed}")
    ftype = raw.get("type")
    if ftype is None:
        raise ConfigError(f"follower.type is missing; allowed: {allowed}")
    if not isinstance(ftype, str) or ftype not in types:
        raise ConfigError(f"follower.type={_short(ftype)} is unknown; allowed: {allowed}")
    adapter = _follower_adapter(tuple(types.values()))
    try:
        model = adapter.validate_python(dict(raw))
    except ValidationError as exc:
        raise ConfigError(_format_validation_error(exc, "follower.", skip=1)) from None
    values = model.model_dump(exclude={"type"})
    return types[ftype].from_parameters(values)


# --- motion ----------------------------------------------------------------------------
_LIFT_MM = _number(0.0, LIFT_MAX_MM, "segment lift [mm]", open_low=True)
_LIFT_DEG = _number(0.0, LIFT_MAX_DEG, "segment swing [deg]", open_low=True)
_ANGLE = _number(-ANGLE_MAX_DEG, ANGLE_MAX_DEG, "cam angle [deg]")


class SegmentSchema(_Strict):
    """One motion segment: kind, law, start/end angle [deg], lift [mm] or swing [deg]."""

    kind: Literal["rise", "return", "dwell"]
    law: str | None = None
    start_deg: _ANGLE | None = None  # type: ignore[valid-type]
    end_deg: _ANGLE  # type: ignore[valid-type]
    lift_mm: _LIFT_MM | None = None  # type: ignore[valid-type]
    lift_deg: _LIFT_DEG | None = None  # type: ignore[valid-type]

    @field_validator("law")
    @classmethod
    def _known_law(cls, v: str | None) -> str | None:
        if v in RETIRED_LAWS:
            raise ValueError(RETIRED_LAWS[v])
        if v is not None and v not in MOTION_LAWS:
            raise ValueError(f"unknown motion law; allowed: {', '.join(MOTION_LAWS)}")
        return v


_TABLE_MM = Annotated[float, Field(ge=-LIFT_MAX_MM, le=LIFT_MAX_MM, **_FINITE)]
_TABLE_DEG = Annotated[float, Field(ge=-LIFT_MAX_DEG, le=LIFT_MAX_DEG, **_FINITE)]


class MotionSchema(_Strict):
    """The motion program: segments or a lift table (file, or inline values)."""

    segments: list[SegmentSchema] | None = None
    table_file: str | None = None
    table_step_deg: _number(0.0, 360.0, "table step [deg]", open_low=True) | None = None  # type: ignore[valid-type]
    table_lift_mm: list[_TABLE_MM] | None = None
    table_lift_deg: list[_TABLE_DEG] | None = None


class OperationSchema(_Strict):
    """Operating conditions: speed (0, 1e6] rpm, pressure-angle limit (0, 90) deg."""

    speed_rpm: _number(0.0, SPEED_MAX_RPM, "cam speed [rpm]", open_low=True) | None = None  # type: ignore[valid-type]
    pressure_angle_limit_deg: (
        Annotated[float, Field(gt=0, lt=90, description="design limit [deg]", **_FINITE)] | None
    ) = None


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

    name: str = Field(min_length=1, max_length=200)
    description: str = ""
    reference: str = ""
    follower: dict[str, Any]
    motion: MotionSchema
    tolerances: dict[str, Any] = {}
    operation: OperationSchema = OperationSchema()
    # The conjugate fixture's inputs: typed by camtol.pair.fixture_spec (field names checked
    # there, so that messages name them as `inspection.<field>`).
    inspection: dict[str, Any] = {}
    # The statistical tolerance model, parsed by camtol.tolerancing.model (issue 11).
    statistics: dict[str, Any] = {}
    # The follower train at speed, parsed by camtol.config.dynamics_table (issue 33).
    dynamics: dict[str, Any] = {}
    traceability: TraceabilitySchema = TraceabilitySchema()
    drawing: DrawingSchema = DrawingSchema()


def _short(value: Any) -> str:
    """Repr of a value, at most :data:`VALUE_CHARS` characters."""
    text = repr(value)
    return text if len(text) <= VALUE_CHARS else text[: VALUE_CHARS - 1] + "…"


def _format_validation_error(exc: ValidationError, prefix: str = "", *, skip: int = 0) -> str:
    """Format each problem as ``field=value: what is allowed``, on one bounded line."""
    parts = []
    for err in exc.errors():
        loc = ".".join(str(p) if not isinstance(p, int) else f"[{p}]" for p in err["loc"][skip:])
        loc = (prefix + loc).replace(".[", "[").rstrip(".")
        if err["type"] == "missing":
            parts.append(f"{loc} is missing")
        elif err["type"] == "extra_forbidden":
            parts.append(f"{loc} is not a known field")
        else:
            msg = err["msg"].removeprefix("Value error, ")
            parts.append(f"{loc}={_short(err.get('input'))}: {msg}")
    out = parts[0]
    for n, part in enumerate(parts[1:], start=1):
        if len(out) + len(part) + 2 > MESSAGE_CHARS:
            return f"{out}; and {len(parts) - n} more problem(s)"
        out += "; " + part
    return out


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
        # SegmentProgram's balance test, reported here in the user's unit (the program
        # holds radians for an oscillating follower and cannot name the unit).
        levels = np.cumsum([0.0] + [g.signed_height for g in segs]) / scale
        if abs(levels[-1] * scale) > 1e-9 * max(1.0, float(np.max(np.abs(levels))) * scale):
            rises = sum(g.height for g in segs if g.kind == "rise") / scale
            returns = sum(g.height for g in segs if g.kind == "return") / scale
            sym = "°" if oscillating else " mm"
            side = "above" if levels[-1] > 0 else "below"
            raise ConfigError(
                f"motion.segments end {abs(levels[-1]):.6g}{sym} {side} where they start"
                f" (rises {rises:.6g}{sym}, returns {returns:.6g}{sym}); the"
                " rises and returns must balance over a revolution"
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
        theta, lift = table.column("theta_deg"), table.column(col)
        # The same rules, and messages naming the line, as `camtol derive` (grid module).
        theta, lift = drop_closing_row(
            theta, lift, source=str(path), name=col, line_of=table.line_of
        )
        uniform_table_step(theta, source=str(path), line_of=table.line_of)
    except InputFileError as exc:
        detail = str(exc).removeprefix(str(path)).lstrip(":, ")
        sep = ", " if detail.startswith(("line ", "row ")) else " "
        raise ConfigError(f"motion.table_file={str(path)!r}{sep}{detail}") from None
    limit = LIFT_MAX_DEG if unit == "deg" else LIFT_MAX_MM  # as for table_lift_{unit}
    bad = ~(np.abs(lift) <= limit)  # NaN and ±inf included
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ConfigError(
            f"motion.table_file={str(path)!r}, line {table.line_of(i)}: {col}={lift[i]:g} is"
            f" not allowed; give a finite lift of at most {limit:g} {unit} in size"
        )
    return theta, lift


#: What a tolerance key may end in: a unit (a wrong one is named as such); anything else
#: after the source's key is another key (e.g. a pair's ``r_a`` on a single cam).
_UNIT_SUFFIXES = ("um", "deg", "mm", "m", "rad", "mrad", "in", "arcsec")


def _takes_grade(mech: Mechanism, key: str, unit: str) -> bool:
    """Whether source ``key`` of this follower can take an IT grade (for the allowed list).

    Sources without a nominal size (a phase, an arm angle) take none, nor does a size
    ISO 286 does not tabulate (an offset of 0): the same rule as
    :meth:`camtol.design.cam_design.CamDesign._check_grade`, tried on IT6.
    """
    from camtol import iso286

    try:
        dsrc = DESIGN_SOURCES.get(key)
        size = dsrc.nominal_size(mech, 1.0) if dsrc else mech.nominal_size(key, 1.0)
        if unit == "mm":
            iso286.tolerance_um("IT6", size)
        else:
            iso286.angle_tolerance_deg("IT6", size)
    except (ValueError, KeyError):
        return False
    return True


def _tolerances(raw: Mapping[str, Any], mech: Mechanism) -> tuple[ToleranceSpec, ...]:
    specs = []
    seen: set[str] = set()
    units = {s.key: s.unit for s in mech.sources}
    units.update({k: d.source.unit for k, d in DESIGN_SOURCES.items()})
    allowed = ", ".join(
        f"{k} (grade) or {k}_{'um' if u == 'mm' else 'deg'}"
        if _takes_grade(mech, k, u)
        else f"{k}_{'um' if u == 'mm' else 'deg'}"
        for k, u in units.items()
    )
    for name, value in raw.items():
        # the longest source key first: a pair's "r_a" is a source, "r_um" is r in µm
        key, suffix = (name, "") if name in units else name.rpartition("_")[::2]
        if key not in units or suffix not in ("", *_UNIT_SUFFIXES):
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
                    f"tolerances.{name}={_short(value)}: a bare key takes an IT grade such as"
                    f" 'IT6'; give an explicit deviation as {key}_{want}"
                )
            try:
                specs.append(ToleranceSpec(key, grade=value))
            except ValueError as exc:
                raise ConfigError(f"tolerances.{name}={_short(value)}: {exc}") from None
        elif suffix == want:
            limit = DEVIATION_MAX_UM if want == "um" else DEVIATION_MAX_DEG
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not math.isfinite(value)
                or abs(value) > limit
            ):
                raise ConfigError(
                    f"tolerances.{name}={_short(value)} must be a finite number of {want}"
                    f" with |value| ≤ {limit:g}"
                )
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
    try:
        mech = _follower(top.follower)
        program = _motion_program(top.motion, mech.output == "oscillating", base_dir)
        design = CamDesign(
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
        raw = design.extras.get("statistics")
        if isinstance(raw, Mapping):  # validated now, kept as the design's model
            from camtol.config.statistics_table import parse_statistics

            design.extras["statistics"] = parse_statistics(raw, design)
        raw = design.extras.get("dynamics")
        if isinstance(raw, Mapping):  # validated now, kept as the design's table
            from camtol.config.dynamics_table import parse_dynamics

            design.extras["dynamics"] = parse_dynamics(raw, design)
        return design
    except ConfigError:
        raise
    except DesignError as exc:
        raise ConfigError(str(exc)) from None


def _extras(top: DesignSchema) -> dict[str, object]:
    """Return ``[traceability]``, ``[drawing]``, ``[statistics]``, ``[dynamics]`` as extras."""
    out: dict[str, object] = {}
    trace = top.traceability.model_dump(exclude_none=True)
    if trace:
        out["traceability"] = trace
    out.update(top.drawing.model_dump(exclude_none=True))
    if top.statistics:
        out["statistics"] = top.statistics
    if top.dynamics:
        out["dynamics"] = top.dynamics
    return out


def _inspection(raw: dict[str, Any], base_dir: Path | None) -> FixtureSpec | ZoneTable | None:
    """Return the ``[inspection]`` table as a typed, frozen spec (None when absent)."""
    if not raw:
        return None
    from camtol.config.inspection_table import fixture_spec_from_mapping

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
    from camtol.textfile import read_text

    text = read_text(p, what="design file", error=ConfigError, max_bytes=16 * 2**20)
    where = f"design file {str(p)!r}"
    data = _parse_toml(text, where)
    try:
        return design_from_mapping(data, base_dir=p.parent)
    except DesignError as exc:  # name the file: a shell script may load several
        raise type(exc)(f"{where}: {exc}") from None


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


from camtol.config.writer import dump_design  # noqa: E402  (re-exported here)
