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

import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from camtol.exceptions import RecordError
from camtol.jet import FloatArray
from camtol.records.record import (  # the data; re-exported where the store's users find it
    InspectionRecord,
    Method,
    Traceability,
    design_identity,
    make_record,
)

if TYPE_CHECKING:
    from collections.abc import Callable

    from camtol.design.cam_design import CamDesign

T = TypeVar("T")

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
        from camtol.records import schema as sql

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
