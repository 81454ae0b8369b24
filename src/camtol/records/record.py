"""An inspection record: one inspected cam, as the store keeps it (an I/O edge's data).

The design it was checked against (name and content hash), the part's traceability, the
method, the verdict, the summary figures, the tolerance and what it was judged on (Δn or
Δr, the decision rule), the camtol version, the radial deviation curve Δr(θ) on a uniform
grid, and what makes it re-runnable: the SHA-256 of its raw data, every option the
verdict depended on and the method's own results, validated when made
(:func:`make_record`). The raw inputs themselves (a scan, an indicator record, a
measured Δf: :class:`camtol.records.raw.RawInput`) are kept beside the records,
compressed, once per SHA-256. A
record is never deleted: a void marks it, with who, when and why. Pure data:
:mod:`camtol.records.store` writes and reads it.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from datetime import datetime, timezone
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import numpy.typing as npt

from camtol.exceptions import RecordError
from camtol.jet import FloatArray

if TYPE_CHECKING:
    from camtol.design.cam_design import CamDesign

__all__ = [
    "SCHEMA_VERSION",
    "InspectionRecord",
    "Method",
    "Traceability",
    "design_identity",
    "make_record",
]


#: Version of the store's tables this camtol writes; a store of a newer one is refused.
SCHEMA_VERSION = 3

Float32Array = npt.NDArray[np.float32]
Method = Literal["conjugate-fixture", "cmm"]
METHODS: tuple[str, ...] = ("conjugate-fixture", "cmm")
CAMS: tuple[str, ...] = ("A", "B", "")
VERDICTS: tuple[str, ...] = ("pass", "fail")
JUDGED_ON: tuple[str, ...] = ("dn", "dr")
DECISION_RULES: tuple[str, ...] = ("simple", "guard-band")
MOTION_UNITS: tuple[str, ...] = ("um", "deg")
_CURVE = "dr_um"


@dataclass(frozen=True)
class Traceability:
    """Who, what and when of an inspected part (free text, at most 200 characters each).

    Attributes
    ----------
    part_number, serial, lot, inspector, instrument : str
        The part's drawing number, its serial number, its production lot, who inspected it
        and with which instrument (all optional, "" when unknown).
    inspected_at : datetime, optional
        When, as an aware date-time (converted to UTC); by default now.
    """

    part_number: str = ""
    serial: str = ""
    lot: str = ""
    inspector: str = ""
    instrument: str = ""
    inspected_at: datetime | None = None


@dataclass(frozen=True, eq=False)
class InspectionRecord:
    """One inspected cam, as stored.

    Attributes
    ----------
    id : int or None
        The store's record number (None before it is stored).
    design_name, design_hash : str
        The design's name and content hash (``sha256:<64 hex digits>``).
    method : str
        ``conjugate-fixture`` or ``cmm``.
    cam : str
        ``A`` or ``B`` for a conjugate pair, ``""`` for a single cam.
    part_number, serial, lot, inspector, instrument : str
        Traceability.
    inspected_at : datetime
        When, in UTC (aware).
    verdict : str
        ``pass`` or ``fail``.
    max_dev_um, min_dev_um, form_um : float
        Max and min of Δr(θ) and their difference. [µm]
    max_abs_ds_um : float or None
        Largest |ΔS| of a translating follower's motion measured on the part, when the
        method gives it (None for an oscillating follower: see ``max_abs_ds_deg``). [µm]
    tolerance_um : tuple of float
        Radial tolerance (lower, upper) the verdict was taken against. [µm]
    camtol_version : str
        Version of camtol that made the record.
    n_points : int
        Number n of points of the deviation curve (0: a record stored without one).
    dr_um : ndarray of float32
        Deviation curve Δr(θ) at θ_i = 360° i / n (empty when read without curves). [µm]
    judged_on : {"dn", "dr"} or None
        The deviation the tolerance bounds: normal Δn or radial Δr (None: not recorded,
        a record made before schema version 2).
    decision_rule : {"simple", "guard-band"} or None
        Conformance rule of the verdict (ISO 14253-1; None: not recorded).
    motion_unit : {"um", "deg"} or None
        Unit of the follower error: ``um`` (``max_abs_ds_um``, a lift) or ``deg``
        (``max_abs_ds_deg``, a swing); None: not known.
    raw_sha256 : str or None
        ``sha256:<hex>`` of the inspection's primary raw data (the scan, the indicator
        record or the measured Δf); None without raw data.
    options : dict or None
        Every option the verdict depended on, JSON-ready (None: not recorded).
    results : dict or None
        The method's own figures beyond the summary (Δn extremes, minimum zone, u_f...).
    duplicate_allowed : bool
        Stored with ``--allow-duplicate`` (the same raw data for the same serial and cam).
    voided_at : datetime or None
        When the record was voided (UTC), None while it stands.
    voided_by, void_reason : str
        Who voided it and why ("" while it stands).
    max_abs_ds_deg : float or None
        Largest |ΔS| of an oscillating follower's motion measured on the part (schema
        version 3; a version-2 µrad figure is converted by the migration). [deg]
    """

    id: int | None
    design_name: str
    design_hash: str
    method: str
    cam: str
    part_number: str
    serial: str
    lot: str
    inspector: str
    instrument: str
    inspected_at: datetime
    verdict: str
    max_dev_um: float
    min_dev_um: float
    form_um: float
    max_abs_ds_um: float | None
    tolerance_um: tuple[float, float]
    camtol_version: str
    n_points: int
    dr_um: Float32Array = field(repr=False)
    judged_on: str | None = None
    decision_rule: str | None = None
    motion_unit: str | None = None
    raw_sha256: str | None = None
    options: dict[str, Any] | None = field(default=None, repr=False)
    results: dict[str, Any] | None = field(default=None, repr=False)
    duplicate_allowed: bool = False
    voided_at: datetime | None = None
    voided_by: str = ""
    void_reason: str = ""
    max_abs_ds_deg: float | None = None

    @classmethod
    def from_store(cls, **fields: Any) -> InspectionRecord:
        """Build a record from a store row's fields, every field given and already typed.

        The store's readers build thousands at a time (a lot page reads 10,000), and a
        frozen dataclass's ``__init__`` sets each of its 32 fields through
        ``object.__setattr__``: this fills the instance's ``__dict__`` at once, about ten
        times faster. Anything else constructs records normally.
        """
        if fields.keys() != _FIELD_NAMES:
            raise TypeError(f"from_store needs exactly the fields {sorted(_FIELD_NAMES)}")
        record = object.__new__(cls)
        record.__dict__.update(fields)
        return record

    @property
    def voided(self) -> bool:
        """Whether the record has been voided."""
        return self.voided_at is not None

    @property
    def theta_deg(self) -> FloatArray:
        """The curve's cam angles, 360° i / n. [deg]"""
        return np.asarray(np.arange(self.n_points) * (360.0 / self.n_points), dtype=np.float64)

    def summary(self) -> dict[str, Any]:
        """Return the record without its curve, as JSON-ready values (keys of docs/records.md)."""
        return {
            "id": self.id,
            "design_name": self.design_name,
            "design_hash": self.design_hash,
            "method": self.method,
            "cam": self.cam,
            "part_number": self.part_number,
            "serial": self.serial,
            "lot": self.lot,
            "inspector": self.inspector,
            "instrument": self.instrument,
            "inspected_at": self.inspected_at.isoformat(),
            "verdict": self.verdict,
            "max_dev_um": self.max_dev_um,
            "min_dev_um": self.min_dev_um,
            "form_um": self.form_um,
            "max_abs_ds_um": self.max_abs_ds_um,
            "max_abs_ds_deg": self.max_abs_ds_deg,
            "tolerance_um": list(self.tolerance_um),
            "camtol_version": self.camtol_version,
            "n_points": self.n_points,
            "judged_on": self.judged_on,
            "decision_rule": self.decision_rule,
            "motion_unit": self.motion_unit,
            "raw_sha256": self.raw_sha256,
            "duplicate_allowed": self.duplicate_allowed,
            "voided": self.voided,
            "voided_at": None if self.voided_at is None else self.voided_at.isoformat(),
            "voided_by": self.voided_by,
            "void_reason": self.void_reason,
        }


#: Every field of a record (what :meth:`InspectionRecord.from_store` must be given).
_FIELD_NAMES = frozenset(f.name for f in fields(InspectionRecord))


def design_identity(design: CamDesign, source_text: str | None = None) -> tuple[str, str]:
    r"""Name and content hash of a design: ``(name, "sha256:<hex>")``.

    Uses ``design.content_hash`` (issue 8: the SHA-256 of the design's canonical content);
    for a design object without it, the SHA-256 of its TOML text with line endings
    normalised to ``\n`` and trailing blanks removed. The one place that defines a
    record's design identity.

    Parameters
    ----------
    design : CamDesign
        The design.
    source_text : str, optional
        The design's TOML text (file contents or a built-in example's text).

    Returns
    -------
    tuple of str
        Design name and its hash.
    """
    own = getattr(design, "content_hash", None)
    if isinstance(own, str) and own:
        return design.name, own if own.startswith("sha256:") else f"sha256:{own}"
    if source_text is None:
        raise RecordError(
            f"design {design.name!r}: its TOML text is needed to identify it in the store"
        )
    lines = [line.rstrip() for line in source_text.replace("\r\n", "\n").split("\n")]
    canonical = "\n".join(lines).strip("\n") + "\n"
    return design.name, "sha256:" + hashlib.sha256(canonical.encode("utf-8")).hexdigest()


def _text(value: str, name: str) -> str:
    if not isinstance(value, str) or len(value) > 200 or "\x00" in value:
        raise RecordError(
            f"{name}={value!r}: allowed is text of at most 200 characters without NUL"
        )
    return value


def _utc(when: datetime | None) -> datetime:
    if when is None:
        return datetime.now(timezone.utc)
    if when.tzinfo is None:
        raise RecordError(f"inspected_at={when.isoformat()!r}: give a time zone (e.g. +00:00)")
    return when.astimezone(timezone.utc)


def make_record(
    *,
    design_name: str,
    design_hash: str,
    method: str,
    cam: str,
    dr_um: FloatArray,
    verdict: str,
    tolerance_um: tuple[float, float],
    traceability: Traceability,
    max_abs_ds_um: float | None = None,
    extremes_um: tuple[float, float] | None = None,
    max_abs_ds_deg: float | None = None,
    judged_on: str | None = None,
    decision_rule: str | None = None,
    motion_unit: str | None = None,
    raw_sha256: str | None = None,
    options: Mapping[str, Any] | None = None,
    results: Mapping[str, Any] | None = None,
) -> InspectionRecord:
    """Validate the parts of a record and compute its summary figures (not stored yet).

    The curve is rounded to float32 first. The extremes and the form are those of the
    measured values when given (``extremes_um``: a CMM scan's points, not the curve
    resampled from them), else those of the stored (float32) curve.

    Parameters
    ----------
    design_name, design_hash : str
        The design's identity (see :func:`design_identity`).
    method : {"conjugate-fixture", "cmm"}
        How the cam was inspected.
    cam : {"A", "B", ""}
        Which cam of a pair ("" for a single cam).
    dr_um : ndarray
        Radial deviation Δr(θ) on θ_i = 360° i / n. [µm]
    verdict : {"pass", "fail"}
        The inspection's verdict.
    tolerance_um : tuple of float
        Radial tolerance (lower, upper) of the verdict. [µm]
    traceability : Traceability
        Part number, serial, lot, inspector, instrument, date-time.
    max_abs_ds_um : float, optional
        Largest |ΔS| of a translating follower's measured motion, when known. [µm]
    extremes_um : (float, float), optional
        Largest and smallest measured Δr (default: the curve's). [µm]
    max_abs_ds_deg : float, optional
        Largest |ΔS| of an oscillating follower's measured motion, when known. [deg]
    judged_on : {"dn", "dr"}, optional
        The deviation the tolerance bounds.
    decision_rule : {"simple", "guard-band"}, optional
        Conformance rule of the verdict.
    motion_unit : {"um", "deg"}, optional
        ``um`` with ``max_abs_ds_um``, ``deg`` with ``max_abs_ds_deg``.
    raw_sha256 : str, optional
        ``sha256:<hex>`` of the primary raw data.
    options : mapping, optional
        Every option the verdict depended on (JSON-ready values).
    results : mapping, optional
        The method's own figures (JSON-ready values).

    Returns
    -------
    InspectionRecord
        With ``id`` None.

    Raises
    ------
    RecordError
        A field outside what is allowed (named in the message).
    """
    from camtol._version import __version__

    if method not in METHODS:
        raise RecordError(f"method={method!r}: allowed {', '.join(METHODS)}")
    if cam not in CAMS:
        raise RecordError(f"cam={cam!r}: allowed 'A', 'B' or '' (a single cam)")
    if verdict not in VERDICTS:
        raise RecordError(f"verdict={verdict!r}: allowed 'pass' or 'fail'")
    if not re.fullmatch(r"sha256:[0-9a-f]{64}", design_hash):
        raise RecordError(f"design_hash={design_hash!r}: allowed 'sha256:' + 64 hex digits")
    curve = np.ascontiguousarray(np.asarray(dr_um, dtype=np.float64).astype(np.float32))
    if curve.ndim != 1 or curve.size < 1 or not np.all(np.isfinite(curve)):
        raise RecordError(
            "dr_um: allowed a 1-D array of finite deviations [µm] on a uniform grid over"
            f" [0°, 360°); got shape {curve.shape}"
        )
    lo, hi = float(tolerance_um[0]), float(tolerance_um[1])
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise RecordError(f"tolerance_um={tolerance_um!r}: allowed [lower, upper], lower < upper")
    for name, ds in (("max_abs_ds_um", max_abs_ds_um), ("max_abs_ds_deg", max_abs_ds_deg)):
        if ds is not None and not math.isfinite(ds):
            raise RecordError(f"{name}={ds!r}: allowed a finite number or None")
    if max_abs_ds_um is not None and max_abs_ds_deg is not None:
        raise RecordError("max_abs_ds_um and max_abs_ds_deg: a follower is a lift or a swing")
    for name, ds, unit in (
        ("max_abs_ds_um", max_abs_ds_um, "um"),
        ("max_abs_ds_deg", max_abs_ds_deg, "deg"),
    ):
        if ds is not None and motion_unit is not None and motion_unit != unit:
            raise RecordError(f"{name} needs motion_unit={unit!r}, not {motion_unit!r}")
    for name, value, allowed in (
        ("judged_on", judged_on, JUDGED_ON),
        ("decision_rule", decision_rule, DECISION_RULES),
        ("motion_unit", motion_unit, MOTION_UNITS),
    ):
        if value is not None and value not in allowed:
            raise RecordError(f"{name}={value!r}: allowed {', '.join(allowed)} or None")
    if raw_sha256 is not None and not re.fullmatch(r"sha256:[0-9a-f]{64}", raw_sha256):
        raise RecordError(f"raw_sha256={raw_sha256!r}: allowed 'sha256:' + 64 hex digits")
    t = traceability
    hi_dev, lo_dev = float(curve.max()), float(curve.min())
    if extremes_um is not None:
        hi_dev, lo_dev = float(extremes_um[0]), float(extremes_um[1])
        if not (math.isfinite(hi_dev) and math.isfinite(lo_dev) and lo_dev <= hi_dev):
            raise RecordError(f"extremes_um={extremes_um!r}: allowed finite (max, min), min ≤ max")
    return InspectionRecord(
        id=None,
        design_name=_text(design_name, "design_name"),
        design_hash=design_hash,
        method=method,
        cam=cam,
        part_number=_text(t.part_number, "part_number"),
        serial=_text(t.serial, "serial"),
        lot=_text(t.lot, "lot"),
        inspector=_text(t.inspector, "inspector"),
        instrument=_text(t.instrument, "instrument"),
        inspected_at=_utc(t.inspected_at),
        verdict=verdict,
        max_dev_um=hi_dev,
        min_dev_um=lo_dev,
        form_um=hi_dev - lo_dev,
        max_abs_ds_um=None if max_abs_ds_um is None else float(max_abs_ds_um),
        max_abs_ds_deg=None if max_abs_ds_deg is None else float(max_abs_ds_deg),
        tolerance_um=(lo, hi),
        camtol_version=__version__,
        n_points=int(curve.size),
        dr_um=curve,
        judged_on=judged_on,
        decision_rule=decision_rule,
        motion_unit=motion_unit,
        raw_sha256=raw_sha256,
        options=_json_object(options, "options"),
        results=_json_object(results, "results"),
    )


def _json_object(value: Mapping[str, Any] | None, name: str) -> dict[str, Any] | None:
    """Return a JSON-ready copy of a mapping (round-tripped: what is stored is read)."""
    if value is None:
        return None
    try:
        text = json.dumps(dict(value), sort_keys=True, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise RecordError(f"{name}: allowed JSON-ready values, finite numbers ({exc})") from None
    out: dict[str, Any] = json.loads(text)
    return out
