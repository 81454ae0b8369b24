"""A cam design: mechanism + motion program + tolerances (ARCHITECTURE.md).

Tolerances follow the papers' conventions (THEORY §3.6): a tolerance "of grade ITk" is a
deviation equal to the full IT value; the nominal size of the profile tolerance is the
cam's maximum radial dimension; an angle's grade applies the IT table to its number of
degrees and reads the result in thousandths of a degree (not defined by ISO 286).

Why one module: it is the design (:class:`CamDesign`) with its validation, the tolerances
it carries (:class:`ToleranceSpec` and their resolution into deviations) and the single
cams it is made of (:class:`Cam`); a tolerance is checked against the design's sources and
sizes when the design is made, so the three change together.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass, field
from typing import Any, Protocol

from camtol import iso286
from camtol.design.motion import MotionProgram
from camtol.design.sources import DESIGN_SOURCES
from camtol.exceptions import DesignError
from camtol.mechanisms.base import ErrorSource, Mechanism

__all__ = [
    "Cam",
    "CamDesign",
    "InspectionTable",
    "ResolvedTolerance",
    "ToleranceSpec",
    "IT_CONVENTIONS",
]

#: The conventions camtol states wherever IT grades are used (THEORY §3.6).
IT_CONVENTIONS: tuple[str, ...] = (
    "a tolerance of grade ITk is a deviation equal to the full IT value (Δ = +IT)",
    "the nominal size of a profile tolerance (r, n) is the cam's maximum radial dimension",
    "an angle's IT grade applies the ISO 286 table to its number of degrees and reads the"
    " value in thousandths of a degree (a convention of the papers, not defined by ISO 286)",
)


@dataclass(frozen=True)
class ToleranceSpec:
    """A tolerance on one error source: an IT grade or an explicit deviation.

    Parameters
    ----------
    key : str
        Source key (``r``, ``n``, ``e``, ``phi``, ``f``, ...).
    grade : str, optional
        ISO 286 grade such as ``"IT6"``.
    deviation : float, optional
        Explicit deviation in the *file* unit: µm for lengths, degrees for angles.
    """

    key: str
    grade: str | None = None
    deviation: float | None = None

    def __post_init__(self) -> None:
        if (self.grade is None) == (self.deviation is None):
            raise DesignError(
                f"tolerances.{self.key}: give either an IT grade or an explicit deviation"
            )
        if self.grade is not None:
            object.__setattr__(self, "grade", iso286.parse_grade(self.grade))
        if self.deviation is not None and not math.isfinite(self.deviation):
            raise DesignError(f"tolerances.{self.key}={self.deviation!r} must be a finite number")


@dataclass(frozen=True)
class ResolvedTolerance:
    """A tolerance turned into a deviation in internal units.

    Attributes
    ----------
    key : str
        Source key.
    deviation : float
        Δp in internal units. [mm, or rad for angles]
    unit : str
        Internal unit, ``"mm"`` or ``"rad"``.
    origin : str
        How it was obtained, e.g. ``"IT6 at 61.25 mm → 19 µm"``.
    """

    key: str
    deviation: float
    unit: str
    origin: str

    @property
    def display(self) -> str:
        """Deviation in file units, e.g. ``19 µm`` or ``0.011°``."""
        if self.unit == "mm":
            return f"{self.deviation * 1e3:.6g} µm"
        return f"{math.degrees(self.deviation):.6g}°"


class InspectionTable(Protocol):
    """The design's ``[inspection]`` table, as far as the design itself needs it.

    What the table means belongs to the code that reads it (the measuring fixture's
    :class:`camtol.pair.fixture_spec.FixtureSpec`, validated by
    :mod:`camtol.config.inspection_table`); a design only identifies it
    (:meth:`to_mapping`, part of :attr:`CamDesign.content_hash`) and hands each of its
    cams the radial tolerance band the table gives it (:meth:`band_um`).
    """

    def to_mapping(self) -> dict[str, Any]:
        """Return the table as validated (field name -> value)."""
        ...  # a Protocol's method: implemented by the table's type

    def band_um(self, cam: str) -> tuple[float, float] | None:
        """Return the radial tolerance band (lower, upper) of the cam named ``cam``. [µm]

        Parameters
        ----------
        cam : str
            The cam's letter (:attr:`Cam.letter`).
        """
        ...

    def profile_zone(self, cam: str) -> Any:
        """Return the CMM profile zone the table states for cam ``cam`` (or None).

        What it is belongs to :mod:`camtol.inspection.zone` (``ZoneSpec``).

        Parameters
        ----------
        cam : str
            The cam's letter (:attr:`Cam.letter`).
        """
        ...


@dataclass(frozen=True)
class CamDesign:
    """A disk-cam design: follower mechanism, motion program and tolerances.

    Parameters
    ----------
    name : str
        Short name of the design.
    mechanism : Mechanism
        Follower type and nominal dimensions.
    program : MotionProgram
        Motion program S(θ) in the follower's unit (mm, or rad when oscillating).
    tolerances : tuple of ToleranceSpec
        Tolerances of the error sources to analyse.
    speed_rpm : float, optional
        Cam speed; when given, ΔV and ΔA are reported per second as well. [rev/min]
    pressure_angle_limit_deg : float, optional
        Design limit on |pressure angle|: exceeding it is warned about. [deg]
    description, reference : str
        Free text shown in reports.
    inspection : InspectionTable, optional
        The design file's ``[inspection]`` table, validated and typed: the measuring
        fixture's inputs (THEORY §4; :class:`camtol.pair.fixture_spec.FixtureSpec`).
    """

    name: str
    mechanism: Mechanism
    program: MotionProgram
    tolerances: tuple[ToleranceSpec, ...] = ()
    speed_rpm: float | None = None
    pressure_angle_limit_deg: float | None = None
    description: str = ""
    reference: str = ""
    inspection: InspectionTable | None = None
    extras: dict[str, object] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        keys = {s.key for s in self.sources}
        for t in self.tolerances:
            if t.key not in keys:
                raise DesignError(
                    f"tolerances.{t.key} is not an error source of a {self.mechanism.kind}"
                    f" follower; allowed: {', '.join(sorted(keys))}"
                )
        for t in self.tolerances:  # a grade that no profile can make applicable: now
            if t.grade is not None:
                self._check_grade(t.key, t.grade)
        for label, cam in self.mechanism.cams():  # one tolerance per source of each cam
            named: dict[str, str] = {}
            for t in self.tolerances:  # a grade on a source that takes none (η), at once
                own = self.mechanism.cam_source_keys(label).get(t.key)
                if t.grade is not None and own is not None and cam is not self.mechanism:
                    try:
                        cam.nominal_size(own, 1.0)
                    except ValueError as exc:
                        raise DesignError(
                            f"tolerances.{t.key}={t.grade!r} cannot be applied: {exc}; give"
                            f" tolerances.{t.key}_{'um' if self._unit(t.key) == 'mm' else 'deg'}"
                            " as an explicit deviation instead"
                        ) from None
            for key, own in self.mechanism.cam_source_keys(label).items():
                if any(t.key == key for t in self.tolerances):
                    if own in named:
                        raise DesignError(
                            f"tolerances.{named[own]} and tolerances.{key} both set the"
                            f" {own!r} source of cam {label}; give one of them"
                        )
                    named[own] = key
        if self.speed_rpm is not None and not (
            math.isfinite(self.speed_rpm) and self.speed_rpm > 0
        ):
            raise DesignError(f"operation.speed_rpm={self.speed_rpm:g} must be > 0")

    def _unit(self, key: str) -> str:
        return next(s.unit for s in self.sources if s.key == key)

    def grade_nominal_size(self, key: str, max_radius_mm: float) -> float:
        """Nominal size of source ``key`` for an IT grade (THEORY §3.6).

        Parameters
        ----------
        key : str
            Error-source key of the design.
        max_radius_mm : float
            Maximum radial dimension of the cam profile. [mm]

        Returns
        -------
        float
            The size. [mm, or deg for an angle]

        Raises
        ------
        ValueError
            If the source takes no IT grade.
        """
        dsrc = DESIGN_SOURCES.get(key)
        if dsrc is not None:
            return dsrc.nominal_size(self.mechanism, max_radius_mm)
        return self.mechanism.nominal_size(key, max_radius_mm)

    def _check_grade(self, key: str, grade: str) -> None:
        """Refuse, when the design is made, a grade no cam profile can make applicable.

        A size that does not depend on the profile (an offset, a pivot distance, a face
        angle) is known now: checking it here makes every command (analyze, profile,
        precision, cut, size...) accept or refuse the same design the same way, instead of
        only those that resolve tolerances (:meth:`resolve_tolerances`). Profile-sized
        sources (r, n) are checked there, once the profile is known.
        """
        unit = self._unit(key)
        try:
            size = self.grade_nominal_size(key, 1.0)
            if size == self.grade_nominal_size(key, 2.0):  # not the profile's size
                if unit == "mm":
                    iso286.tolerance_um(grade, size)
                else:
                    iso286.angle_tolerance_deg(grade, size)
        except ValueError as exc:
            raise DesignError(
                f"tolerances.{key}={grade!r} cannot be applied: {exc}; give"
                f" tolerances.{key}_{'um' if unit == 'mm' else 'deg'} as an explicit deviation"
                " instead"
            ) from None

    @property
    def sources(self) -> tuple[ErrorSource, ...]:
        """Every error source of the design: the follower's, then the design-level ones.

        Design-level sources (:mod:`camtol.design.sources`, e.g. the cam's angular phase) belong
        to the cam's mounting, not to the follower.
        """
        return self.mechanism.sources + tuple(d.source for d in DESIGN_SOURCES.values())

    def source(self, key: str) -> ErrorSource:
        """Return the error source with this key (follower or design level).

        Parameters
        ----------
        key : str
            Tolerance key, e.g. ``"r"`` or ``"phase"``.

        Returns
        -------
        ErrorSource
            The source.

        Raises
        ------
        KeyError
            If the design has no such source.
        """
        for s in self.sources:
            if s.key == key:
                return s
        raise KeyError(key)

    def cams(self) -> tuple[Cam, ...]:
        """Return the single-contact cams of the design (one, or A and B of a pair).

        Each :class:`Cam` carries a single-contact design with the same program, speed
        and limits, and the tolerances whose keys that cam has. An ordinary design's only
        cam is the design itself (label ``""``).

        Returns
        -------
        tuple of Cam
            In the mechanism's order (A before B).
        """
        out = []
        for index, (label, mech) in enumerate(self.mechanism.cams()):
            letter = chr(ord("A") + index)
            if mech is self.mechanism:
                out.append(Cam(label, mech, self, letter))
                continue
            design = dataclasses.replace(
                self,
                name=f"{self.name} ({label})" if label else self.name,
                mechanism=mech,
                tolerances=self._cam_tolerances(label),
            )
            out.append(Cam(label, mech, design, letter))
        return tuple(out)

    def _cam_tolerances(self, label: str) -> tuple[ToleranceSpec, ...]:
        """Return the tolerances of cam ``label``, under that cam's own source keys."""
        keys = self.mechanism.cam_source_keys(label)
        out = []
        for t in self.tolerances:
            if t.key in keys:
                out.append(dataclasses.replace(t, key=keys[t.key]))
            elif t.key in DESIGN_SOURCES:
                out.append(t)
        return tuple(out)

    def cam(self, letter: str) -> Cam:
        """Return the cam the command line names ``letter`` (``A``, ``B``, ... in order).

        A design's only cam is cam ``A``; the cams of a conjugate pair are ``A`` and ``B``.

        Parameters
        ----------
        letter : str
            The cam's letter (:attr:`Cam.letter`).

        Returns
        -------
        Cam

        Raises
        ------
        DesignError
            If the design has no such cam, naming the cams it has.
        """
        cams = self.cams()
        for c in cams:
            if c.letter == letter:
                return c
        if len(letter) == 1 and letter.isupper():
            raise DesignError(
                f"--cam {letter}: the design {self.name!r} has one cam"
                f" ({self.mechanism.kind}); cam {letter} exists only for a conjugate pair"
                if len(cams) == 1
                else f"--cam {letter}: the design {self.name!r} has cams"
                f" {', '.join(c.letter for c in cams)}"
            )
        raise DesignError(
            f"--cam {letter!r} is not allowed; use {' or '.join(c.letter for c in cams)}"
        )

    def canonical(self) -> dict[str, Any]:
        """Plain data that identifies the design, the input of :attr:`content_hash`.

        Every float is written as its shortest round-trip ``repr`` in internal units
        (mm, rad), so the form does not depend on how a file spelled a number (``40``,
        ``40.0``, ``4e1``) or on the platform.

        Returns
        -------
        dict
            ``format`` (``"camtol-design-1"``), ``name``, ``description``, ``reference``,
            ``follower`` (type and every dataclass field), ``motion``
            (:meth:`camtol.design.motion.MotionProgram.canonical`), ``tolerances`` (key with grade
            or file-unit deviation, in order), ``operation``, ``inspection`` (the
            ``[inspection]`` table as validated; a CSV-backed function enters by its path,
            not its content) and ``extras``.
        """
        mech = self.mechanism
        follower: dict[str, Any] = {"type": mech.kind}
        for f in dataclasses.fields(mech):  # type: ignore[arg-type]
            follower[f.name] = _canonical(getattr(mech, f.name))
        return {
            "format": "camtol-design-1",
            "name": self.name,
            "description": self.description,
            "reference": self.reference,
            "follower": follower,
            "motion": self.program.canonical(),
            "tolerances": [[t.key, t.grade, _canonical(t.deviation)] for t in self.tolerances],
            "operation": {
                "speed_rpm": _canonical(self.speed_rpm),
                "pressure_angle_limit_deg": _canonical(self.pressure_angle_limit_deg),
            },
            "inspection": (
                None if self.inspection is None else _canonical(self.inspection.to_mapping())
            ),
            "extras": _canonical(self.extras),
        }

    @property
    def content_hash(self) -> str:
        """Stable SHA-256 of the design's content (hex), e.g. for inspection records.

        The hash of the JSON text of :meth:`canonical` (keys sorted, no spaces, UTF-8):
        equal designs have equal hashes on every platform and Python version; any change
        of a dimension, the motion, a tolerance, the operating data, the name or the
        ``[inspection]`` table changes it. Comments and number spelling in the file do
        not. A design written back with :func:`camtol.config.design_file.dump_design` keeps it.
        """
        text = json.dumps(self.canonical(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    def describe_motion(self) -> str:
        """Describe the motion program in file units (mm, or degrees when oscillating)."""
        if self.mechanism.output == "translating":
            return self.program.describe(unit=" mm")
        return self.program.describe(unit="°", scale=180.0 / math.pi)

    @property
    def omega_rad_s(self) -> float | None:
        """Cam speed ω, or None. [rad/s]"""
        return None if self.speed_rpm is None else self.speed_rpm * 2.0 * math.pi / 60.0

    def resolve_tolerances(self, max_radius_mm: float) -> tuple[ResolvedTolerance, ...]:
        """Turn every tolerance into a deviation in internal units (THEORY §3.6).

        Parameters
        ----------
        max_radius_mm : float
            Maximum radial dimension of the cam profile, the nominal size of profile
            tolerances. [mm]

        Raises
        ------
        DesignError
            If an IT grade cannot be applied (nominal size 0 or beyond 3150 mm).
        """
        out = []
        for spec in self.tolerances:
            src = self.source(spec.key)
            if spec.deviation is not None:
                if src.unit == "mm":
                    dev, origin = spec.deviation * 1e-3, f"{spec.deviation:g} µm (given)"
                else:
                    dev, origin = math.radians(spec.deviation), f"{spec.deviation:g}° (given)"
            else:
                assert spec.grade is not None
                try:
                    dsrc = DESIGN_SOURCES.get(spec.key)
                    if dsrc is None:
                        nominal = self.mechanism.nominal_size(spec.key, max_radius_mm)
                    else:
                        nominal = dsrc.nominal_size(self.mechanism, max_radius_mm)
                    if src.unit == "mm":
                        um = iso286.tolerance_um(spec.grade, nominal)
                        dev = um * 1e-3
                        origin = f"{spec.grade} at {nominal:.6g} mm → {um:g} µm"
                    else:
                        deg = iso286.angle_tolerance_deg(spec.grade, nominal)
                        dev = math.radians(deg)
                        origin = f"{spec.grade} of {nominal:.6g}° → {deg:g}° (angle convention)"
                except ValueError as exc:
                    raise DesignError(
                        f"tolerances.{spec.key}={spec.grade!r} cannot be applied: {exc};"
                        f" give tolerances.{spec.key}_{'um' if src.unit == 'mm' else 'deg'}"
                        " as an explicit deviation instead"
                    ) from None
            out.append(ResolvedTolerance(spec.key, dev, src.unit, origin))
        return tuple(out)


@dataclass(frozen=True)
class Cam:
    """One single-contact cam of a design (see :meth:`CamDesign.cams`).

    Attributes
    ----------
    label : str
        ``""`` for an ordinary cam, ``"A"`` or ``"B"`` for the cams of a conjugate pair
        (what names and per-cam keys carry).
    mechanism : Mechanism
        The single-contact follower mechanism of this cam.
    design : CamDesign
        The single-contact design of this cam: same program, speed and limits; the
        tolerances whose keys this cam has.
    letter : str
        How the command line and the records name the cam (``--cam A``): ``A``, ``B``,
        ... in the design's order; a design's only cam is ``A``.
    """

    label: str
    mechanism: Mechanism
    design: CamDesign
    letter: str = "A"

    @property
    def inspection_band_um(self) -> tuple[float, float] | None:
        """The radial tolerance band of this cam in the ``[inspection]`` table, or None. [µm]"""
        table = self.design.inspection
        return None if table is None else table.band_um(self.letter)


def _canonical(x: Any) -> Any:
    """Plain JSON data with floats as ``repr`` strings (see CamDesign.canonical)."""
    if x is None or isinstance(x, bool | str | int):
        return x
    if isinstance(x, float):
        return repr(float(x))
    if callable(getattr(x, "to_mapping", None)):  # a table kept as read (e.g. [statistics])
        return _canonical(x.to_mapping())
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return {f.name: _canonical(getattr(x, f.name)) for f in dataclasses.fields(x)}
    if isinstance(x, dict):
        return {str(k): _canonical(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_canonical(v) for v in x]
    try:  # numpy scalars and arrays
        import numpy as np

        if isinstance(x, np.ndarray):
            return [_canonical(v) for v in x.tolist()]
        if isinstance(x, np.generic):
            return _canonical(x.item())
    except ImportError:  # pragma: no cover
        pass
    return repr(x)
