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
:class:`~camtol.design.cam_design.CamDesign`. The tables of
fields (:mod:`camtol.config.fields`) say which fields exist and what each allows; the
builders below them (follower, motion, tolerances) check what a field alone cannot and turn
each table into its design object, naming fields by the same ``table.field`` paths in
every message; the example and writer helpers are only re-exported here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.config.examples import example_names as example_names
from camtol.config.examples import example_summary as example_summary
from camtol.config.examples import example_text as example_text
from camtol.config.examples import parse_toml as _parse_toml
from camtol.config.fields import (
    AnyTable,
    Choice,
    Field,
    ListOf,
    Number,
    Table,
    Text,
    short_repr,
)
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
# The tables are strict (camtol.config.fields): a string is not a number, a boolean is
# not a length (issue 9 item 11), and every number is finite.


# --- followers: derived from the follower classes ---------------------------------------
@lru_cache(maxsize=32)
def _follower_table(cls: type[Mechanism]) -> Table:
    """Declare the ``[follower]`` table of one follower type from its parameters."""
    fields: dict[str, Field] = {"type": Field(Choice((cls.kind,)))}
    for p in cls.parameters:
        kind = Number(
            p.minimum,
            p.maximum,
            exclusive_minimum=p.exclusive,
            exclusive_maximum=p.exclusive,
            unit=p.unit,
        )
        fields[p.name] = Field(kind) if p.required else Field(kind, p.default)
    return Table(fields)


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
        raise ConfigError(f"follower={short_repr(raw)} must be a table; allowed types: {allowed}")
    ftype = raw.get("type")
    if ftype is None:
        raise ConfigError(f"follower.type is missing; allowed: {allowed}")
    if not isinstance(ftype, str) or ftype not in types:
        raise ConfigError(f"follower.type={short_repr(ftype)} is unknown; allowed: {allowed}")
    values = _follower_table(types[ftype]).validate(raw, "follower")
    del values["type"]
    return types[ftype].from_parameters(values)


# --- motion ----------------------------------------------------------------------------
_LIFT_MM = Number(0.0, LIFT_MAX_MM, exclusive_minimum=True, unit="mm")
_LIFT_DEG = Number(0.0, LIFT_MAX_DEG, exclusive_minimum=True, unit="deg")
_ANGLE = Number(-ANGLE_MAX_DEG, ANGLE_MAX_DEG, unit="deg")

#: One motion segment: kind, law, start/end angle [deg], lift [mm] or swing [deg].
_SEGMENT = Table(
    {
        "kind": Field(Choice(("rise", "return", "dwell"))),
        "law": Field(Choice(MOTION_LAWS, explain=RETIRED_LAWS, noun="motion law"), None),
        "start_deg": Field(_ANGLE, None),
        "end_deg": Field(_ANGLE),
        "lift_mm": Field(_LIFT_MM, None),
        "lift_deg": Field(_LIFT_DEG, None),
    }
)

#: The motion program: segments or a lift table (file, or inline values).
_MOTION = Table(
    {
        "segments": Field(ListOf(_SEGMENT), None),
        "table_file": Field(Text(min_chars=1), None),
        "table_step_deg": Field(Number(0.0, 360.0, exclusive_minimum=True, unit="deg"), None),
        "table_lift_mm": Field(ListOf(Number(-LIFT_MAX_MM, LIFT_MAX_MM, unit="mm")), None),
        "table_lift_deg": Field(ListOf(Number(-LIFT_MAX_DEG, LIFT_MAX_DEG, unit="deg")), None),
    }
)

#: Operating conditions: speed (0, 1e6] rpm, pressure-angle limit (0, 90) deg.
_OPERATION = Table(
    {
        "speed_rpm": Field(Number(0.0, SPEED_MAX_RPM, exclusive_minimum=True, unit="rpm"), None),
        "pressure_angle_limit_deg": Field(
            Number(0.0, 90.0, exclusive_minimum=True, exclusive_maximum=True, unit="deg"), None
        ),
    }
)

#: Optional ``[traceability]`` table: what identifies the part in a QA report.
_TRACEABILITY = Table(
    {
        name: Field(Text(), None)
        for name in (
            "part_number",
            "drawing_number",
            "revision",
            "serial",
            "inspector",
            "instrument",
            "date",
        )
    }
)

#: Optional ``[drawing]`` table: features drawn in the DXF/SVG export only.
_DRAWING = Table(
    {
        "bore_diameter_mm": Field(Number(0.0, exclusive_minimum=True, unit="mm"), None),
        "hub_diameter_mm": Field(Number(0.0, exclusive_minimum=True, unit="mm"), None),
    }
)

#: Top level of a design file. The tables typed elsewhere are taken whole here:
#: ``[follower]`` by its type (above), ``[tolerances]`` by the follower's sources,
#: ``[inspection]`` by camtol.config.inspection_table (messages name them as
#: ``inspection.<field>``), ``[statistics]`` by camtol.config.statistics_table (issue 11)
#: and ``[dynamics]`` by camtol.config.dynamics_table (issue 33).
_DESIGN = Table(
    {
        "name": Field(Text(min_chars=1, max_chars=200)),
        "description": Field(Text(), ""),
        "reference": Field(Text(), ""),
        "follower": Field(AnyTable()),
        "motion": Field(_MOTION),
        "tolerances": Field(AnyTable(), {}),
        "operation": Field(_OPERATION, {"speed_rpm": None, "pressure_angle_limit_deg": None}),
        "inspection": Field(AnyTable(), {}),
        "statistics": Field(AnyTable(), {}),
        "dynamics": Field(AnyTable(), {}),
        "traceability": Field(_TRACEABILITY, {}),
        "drawing": Field(_DRAWING, {}),
    }
)


def _motion_program(
    m: Mapping[str, Any], oscillating: bool, base_dir: Path | None
) -> MotionProgram:
    unit = "deg" if oscillating else "mm"
    wrong = "mm" if oscillating else "deg"
    kind = "an oscillating" if oscillating else "a translating"
    sources = [m[k] is not None for k in ("segments", "table_file", "table_step_deg")]
    if sum(sources) != 1:
        raise ConfigError(
            "motion: give exactly one of segments, table_file, or table_step_deg with"
            f" table_lift_{unit}"
        )
    scale = math.radians(1.0) if oscillating else 1.0
    if m["segments"] is not None:
        segs = []
        prev_end: float | None = None
        for i, s in enumerate(m["segments"]):
            where = f"motion.segments[{i}]"
            if (s["lift_mm"] if oscillating else s["lift_deg"]) is not None:
                raise ConfigError(
                    f"{where}.lift_{wrong} is not allowed: {kind} follower's lift is given as"
                    f" lift_{unit}"
                )
            seg_lift = s["lift_deg"] if oscillating else s["lift_mm"]
            if s["kind"] == "dwell":
                if seg_lift is not None or s["law"] is not None:
                    raise ConfigError(f"{where}: a dwell takes no law and no lift_{unit}")
            elif seg_lift is None:
                raise ConfigError(f"{where}.lift_{unit} is missing: a {s['kind']} needs its height")
            start = s["start_deg"] if s["start_deg"] is not None else prev_end
            if start is None:
                raise ConfigError(f"{where}.start_deg is missing (needed for the first segment)")
            prev_end = s["end_deg"]
            segs.append(
                Segment(
                    s["kind"],
                    math.radians(start),
                    math.radians(s["end_deg"]),
                    s["law"] or "cycloidal",
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
    if m["table_file"] is not None:
        path = Path(m["table_file"])
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        theta_deg, lift = _read_lift_csv(path, unit)
    else:
        values = m[f"table_lift_{unit}"]
        if m[f"table_lift_{wrong}"] is not None or values is None:
            raise ConfigError(f"motion.table_lift_{unit} is missing ({kind} follower)")
        assert m["table_step_deg"] is not None
        theta_deg = np.arange(len(values)) * m["table_step_deg"]
        lift = np.asarray(values, dtype=float)
        if abs(len(values) * m["table_step_deg"] - 360.0) > 1e-9:
            raise ConfigError(
                f"motion.table_step_deg={m['table_step_deg']:g} with {len(values)} lifts covers"
                f" {len(values) * m['table_step_deg']:g}°; the table must cover exactly 360°"
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
                    f"tolerances.{name}={short_repr(value)}: a bare key takes an IT grade such as"
                    f" 'IT6'; give an explicit deviation as {key}_{want}"
                )
            try:
                specs.append(ToleranceSpec(key, grade=value))
            except ValueError as exc:
                raise ConfigError(f"tolerances.{name}={short_repr(value)}: {exc}") from None
        elif suffix == want:
            limit = DEVIATION_MAX_UM if want == "um" else DEVIATION_MAX_DEG
            if (
                isinstance(value, bool)
                or not isinstance(value, int | float)
                or not math.isfinite(value)
                or abs(value) > limit
            ):
                raise ConfigError(
                    f"tolerances.{name}={short_repr(value)} must be a finite number of {want}"
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
    top = _DESIGN.validate(data)
    try:
        mech = _follower(top["follower"])
        program = _motion_program(top["motion"], mech.output == "oscillating", base_dir)
        design = CamDesign(
            name=top["name"],
            mechanism=mech,
            program=program,
            tolerances=_tolerances(top["tolerances"], mech),
            speed_rpm=top["operation"]["speed_rpm"],
            pressure_angle_limit_deg=top["operation"]["pressure_angle_limit_deg"],
            description=top["description"],
            reference=top["reference"],
            inspection=_inspection(top["inspection"], base_dir),
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


def _extras(top: Mapping[str, Any]) -> dict[str, object]:
    """Return ``[traceability]``, ``[drawing]``, ``[statistics]``, ``[dynamics]`` as extras."""
    out: dict[str, object] = {}
    trace = {k: v for k, v in top["traceability"].items() if v is not None}
    if trace:
        out["traceability"] = trace
    out.update({k: v for k, v in top["drawing"].items() if v is not None})
    if top["statistics"]:
        out["statistics"] = top["statistics"]
    if top["dynamics"]:
        out["dynamics"] = top["dynamics"]
    return out


def _inspection(raw: Mapping[str, Any], base_dir: Path | None) -> FixtureSpec | ZoneTable | None:
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
