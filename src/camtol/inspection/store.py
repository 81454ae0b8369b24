"""A store of inspection records: SQLite by default, PostgreSQL by URL (an I/O edge).

Every inspected cam becomes one record: the design it was checked against (name and content
hash, with the design text kept once per hash), the part's traceability, the method, the
verdict, the summary figures, the tolerance, the camtol version and the radial deviation
curve Δr(θ) on a uniform grid. A record is written in one transaction: either the design,
the record and its curve are all stored, or nothing is.

The curve is stored as one little-endian float32 blob per curve in a child table
``curves`` (not one row per angle): a 0.1° curve is 3,600 values, 14.4 kB as a blob against
3,600 rows; float32 keeps 24 bits of mantissa, a relative 6e-8 (6e-6 µm on a 100 µm
deviation), far below any measurement's uncertainty. The grid is implied: θ_i = 360° i / n.

SQLAlchemy (≥ 2.0) is imported lazily: install ``camtol[store]``; PostgreSQL needs
``camtol[postgres]`` (psycopg 3). The tables are documented in ``docs/records.md``.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar

import numpy as np
import numpy.typing as npt

from camtol.exceptions import RecordError
from camtol.jet import FloatArray

if TYPE_CHECKING:
    from collections.abc import Callable

    from camtol.design import CamDesign

T = TypeVar("T")
Float32Array = npt.NDArray[np.float32]

__all__ = [
    "SCHEMA_VERSION",
    "InspectionRecord",
    "InspectionStore",
    "Method",
    "Traceability",
    "design_identity",
    "make_record",
    "open_store",
    "record_inspection",
]

#: Version of the store's tables; a store written by a newer camtol is refused.
SCHEMA_VERSION = 1

Method = Literal["conjugate-fixture", "cmm"]
METHODS: tuple[str, ...] = ("conjugate-fixture", "cmm")
CAMS: tuple[str, ...] = ("A", "B", "")
VERDICTS: tuple[str, ...] = ("pass", "fail")
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
        Largest |ΔS| of the follower motion measured on the part, when the method gives it
        (in µm, or µrad for an oscillating follower). [µm]
    tolerance_um : tuple of float
        Radial tolerance (lower, upper) the verdict was taken against. [µm]
    camtol_version : str
        Version of camtol that made the record.
    n_points : int
        Number n of points of the deviation curve.
    dr_um : ndarray of float32
        Deviation curve Δr(θ) at θ_i = 360° i / n (empty when read without curves). [µm]
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
            "tolerance_um": list(self.tolerance_um),
            "camtol_version": self.camtol_version,
            "n_points": self.n_points,
        }


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
) -> InspectionRecord:
    """Validate the parts of a record and compute its summary figures (not stored yet).

    The curve is rounded to float32 first, so the summary describes exactly what is stored.

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
        Largest |ΔS| of the measured follower motion, when known. [µm]

    Returns
    -------
    InspectionRecord
        With ``id`` None.

    Raises
    ------
    RecordError
        A field outside what is allowed (named in the message).
    """
    from camtol import __version__

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
    if max_abs_ds_um is not None and not math.isfinite(max_abs_ds_um):
        raise RecordError(f"max_abs_ds_um={max_abs_ds_um!r}: allowed a finite number or None")
    t = traceability
    hi_dev, lo_dev = float(curve.max()), float(curve.min())
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
        tolerance_um=(lo, hi),
        camtol_version=__version__,
        n_points=int(curve.size),
        dr_um=curve,
    )


def store_url(location: str) -> str:
    """Return a database URL from ``--store``: a URL as given, else a SQLite file path."""
    if "://" in location:
        return location
    return f"sqlite:///{Path(location).expanduser().resolve()}"


def _safe(url: str) -> str:
    """Return the URL without its password, for messages."""
    return re.sub(r"(://[^:/@]*):[^@]*@", r"\1:***@", url)


def open_store(location: str, *, create: bool = True) -> InspectionStore:
    """Open (and on first use create) a store of inspection records.

    Parameters
    ----------
    location : str
        A SQLite file path, a ``sqlite:///FILE.db`` URL or a PostgreSQL URL
        ``postgresql+psycopg://user:password@host:port/database``.
    create : bool, optional
        Create the tables when absent (False: a store without them is an error).

    Returns
    -------
    InspectionStore

    Raises
    ------
    RecordError
        SQLAlchemy or the driver missing, the database unreachable, a missing SQLite
        directory, or a schema newer than this camtol's.
    """
    try:
        import sqlalchemy  # noqa: F401
    except ImportError:  # pragma: no cover - depends on the environment
        raise RecordError(
            "--store needs SQLAlchemy: pip install 'camtol[store]' (PostgreSQL: 'camtol[postgres]')"
        ) from None
    return InspectionStore(store_url(location), create=create)


class InspectionStore:
    """Inspection records in a SQL database (see :func:`open_store`). Use as a context manager."""

    def __init__(self, url: str, *, create: bool = True) -> None:
        from camtol.inspection import _store_sql as sql

        self.url = url
        self._sql = sql
        if url.startswith("sqlite:///") and url != "sqlite:///:memory:":
            parent = Path(url[len("sqlite:///") :]).parent
            if not parent.is_dir():
                raise RecordError(f"--store={url!r}: directory {str(parent)!r} does not exist")
        try:
            self._engine = sql.make_engine(url)
        except RecordError:
            raise
        except Exception as exc:  # a malformed URL, a driver that is not installed
            raise RecordError(
                f"--store={_safe(url)!r}: cannot open the store ({_brief(exc)})"
            ) from None
        try:
            sql.initialise(self._engine, SCHEMA_VERSION, create=create)
        except Exception as exc:  # driver and connection errors of any backend
            self._engine.dispose()
            if isinstance(exc, RecordError):
                raise
            raise RecordError(
                f"--store={_safe(url)!r}: cannot open the store ({_brief(exc)})"
            ) from None

    def __enter__(self) -> InspectionStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Release the database connections."""
        self._engine.dispose()

    def add(self, record: InspectionRecord, *, design_text: str | None = None) -> int:
        """Store a record (and the design text, once per hash) in one transaction.

        Parameters
        ----------
        record : InspectionRecord
            The record (from :func:`make_record`).
        design_text : str, optional
            The design's TOML text, kept once per design hash.

        Returns
        -------
        int
            The new record's id.
        """
        return self.add_all([record], design_text=design_text)[0]

    def add_all(
        self, records: Sequence[InspectionRecord], *, design_text: str | None = None
    ) -> list[int]:
        """Store several records (e.g. cams A and B of a pair) in one transaction.

        Parameters
        ----------
        records : sequence of InspectionRecord
            The records (from :func:`make_record`).
        design_text : str, optional
            The designs' TOML text, kept once per design hash.

        Returns
        -------
        list of int
            The new records' ids, in order. On any error nothing is stored.
        """
        try:
            return list(self._sql.insert_records(self._engine, records, design_text))
        except Exception as exc:
            raise RecordError(
                f"--store={_safe(self.url)!r}: nothing was stored ({_brief(exc)})"
            ) from None

    def get(self, record_id: int) -> InspectionRecord:
        """Return the record with this id, with its curve.

        Parameters
        ----------
        record_id : int
            The record's id.

        Returns
        -------
        InspectionRecord

        Raises
        ------
        RecordError
            No record has this id.
        """
        rec: list[InspectionRecord] = self._guard(
            lambda: self._sql.select_records(self._engine, record_id=record_id)
        )
        if not rec:
            raise RecordError(f"record id {record_id}: no such record in {_safe(self.url)!r}")
        return rec[0]

    def records(
        self,
        *,
        design: str | None = None,
        lot: str | None = None,
        cam: str | None = None,
        with_curves: bool = False,
    ) -> list[InspectionRecord]:
        """Return the records matching every filter given, oldest first (by time, then id).

        Parameters
        ----------
        design : str, optional
            Design name.
        lot : str, optional
            Lot.
        cam : str, optional
            ``"A"``, ``"B"`` or ``""`` (a single cam).
        with_curves : bool, optional
            Read the curves too; without, ``dr_um`` is empty (faster for listing).

        Returns
        -------
        list of InspectionRecord
        """
        return self._guard(
            lambda: self._sql.select_records(
                self._engine, design=design, lot=lot, cam=cam, with_curves=with_curves
            )
        )

    def design_text(self, design_hash: str) -> str | None:
        """Return the TOML text stored for a design hash, if any.

        Parameters
        ----------
        design_hash : str
            ``sha256:<hex>``.

        Returns
        -------
        str or None
            The text, None when the design or its text is not stored.
        """
        found: str | None = self._guard(
            lambda: self._sql.select_design_text(self._engine, design_hash)
        )
        return found

    def _guard(self, fn: Callable[[], T]) -> T:
        try:
            return fn()
        except RecordError:
            raise
        except Exception as exc:
            raise RecordError(f"--store={_safe(self.url)!r}: {_brief(exc)}") from None


def _brief(exc: BaseException) -> str:
    """Return the first line of an exception's message."""
    orig = getattr(exc, "orig", None) or exc
    text = str(orig).strip().splitlines()
    return f"{type(orig).__name__}: {text[0] if text else ''}"


def record_inspection(
    location: str | InspectionStore,
    design: CamDesign,
    *,
    method: Method,
    cam: str,
    dr_um: FloatArray,
    verdict: str,
    tolerance_um: tuple[float, float],
    traceability: Traceability,
    design_text: str | None = None,
    max_abs_ds_um: float | None = None,
) -> int:
    """Record one inspected cam in a store (the entry point for ``conjugate`` and ``inspect``).

    Parameters
    ----------
    location : str or InspectionStore
        The store (path or URL, or an open store).
    design : CamDesign
        The design the cam was checked against.
    method : {"conjugate-fixture", "cmm"}
        How it was inspected.
    cam : {"A", "B", ""}
        Which cam of a conjugate pair ("" for a single cam).
    dr_um : ndarray
        Radial deviation Δr(θ) on θ_i = 360° i / n (resample a CMM scan first). [µm]
    verdict : {"pass", "fail"}
        The verdict of the inspection.
    tolerance_um : tuple of float
        Radial tolerance (lower, upper) of that verdict. [µm]
    traceability : Traceability
        Part number, serial, lot, inspector, instrument, date-time.
    design_text : str, optional
        The design's TOML text (hashed, and kept in the store once per hash).
    max_abs_ds_um : float, optional
        Largest |ΔS| of the measured follower motion, when the method gives it. [µm]

    Returns
    -------
    int
        The record's id.
    """
    name, digest = design_identity(design, design_text)
    rec = make_record(
        design_name=name,
        design_hash=digest,
        method=method,
        cam=cam,
        dr_um=dr_um,
        verdict=verdict,
        tolerance_um=tolerance_um,
        traceability=traceability,
        max_abs_ds_um=max_abs_ds_um,
    )
    if isinstance(location, InspectionStore):
        return location.add(rec, design_text=design_text)
    with open_store(location) as store:
        return store.add(rec, design_text=design_text)
