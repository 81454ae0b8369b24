"""A store of inspection records: SQLite by default, PostgreSQL by URL (an I/O edge).

Every inspected cam becomes one record: the design it was checked against (name and content
hash, with the design text kept once per hash), the part's traceability, the method, the
verdict and what it was judged on, the summary figures, the tolerance, the camtol version,
the radial deviation curve Δr(θ) on a uniform grid, and the raw inputs with every option
the verdict depended on (so that ``camtol records rerun`` can judge the part again). A
record is written in one transaction: either the design, the record, its curve and its
raw inputs are all stored, or nothing is. Records are never deleted; a void marks one.

Opening a store says what it is (:func:`camtol.records.migrate.open_schema`): a writer
creates or upgrades its tables (Alembic), a reader (``readonly=True``) opens it read-only
and never creates, locks for writing or changes anything. A database that is not a camtol
store, a damaged one or a newer one is refused, untouched.

The curve is stored as one little-endian float32 blob per curve in a child table
``curves`` (not one row per angle): a 0.1° curve is 3,600 values, 14.4 kB as a blob against
3,600 rows; float32 keeps 24 bits of mantissa, a relative 6e-8 (6e-6 µm on a 100 µm
deviation), far below any measurement's uncertainty. The grid is implied: θ_i = 360° i / n.

SQLAlchemy (≥ 2.0) and Alembic are imported lazily: install ``camtol[store]``; PostgreSQL
needs ``camtol[postgres]`` (psycopg 3). The tables are documented in ``docs/records.md``.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camtol.exceptions import RecordError
from camtol.jet import FloatArray
from camtol.records.raw import RawInput
from camtol.records.reader import StoreReader, error_brief, open_error
from camtol.records.record import (  # the data; re-exported where the store's users find it
    SCHEMA_VERSION,
    InspectionRecord,
    Method,
    Traceability,
    design_identity,
    make_record,
)

if TYPE_CHECKING:
    from camtol.design.cam_design import CamDesign

__all__ = [
    "SCHEMA_VERSION",
    "InspectionRecord",
    "InspectionStore",
    "Method",
    "RawInput",
    "Traceability",
    "design_identity",
    "make_record",
    "open_store",
    "record_inspection",
    "store_url",
]


def store_url(location: str) -> str:
    """Return a database URL from ``--store``: a URL as given, else a SQLite file path.

    Parameters
    ----------
    location : str
        A path or a URL.

    Returns
    -------
    str
    """
    if "://" in location:
        return location
    return f"sqlite:///{Path(location).expanduser().resolve()}"


def safe_url(url: str) -> str:
    """Return the URL without its password, for messages.

    Parameters
    ----------
    url : str
        A database URL.

    Returns
    -------
    str
    """
    return re.sub(r"(://[^:/@]*):[^@]*@", r"\1:***@", url)


def open_store(location: str, *, create: bool = True, readonly: bool = False) -> InspectionStore:
    """Open (a writer: on first use create, when older upgrade) a store of inspection records.

    Parameters
    ----------
    location : str
        A SQLite file path, a ``sqlite:///FILE.db`` URL or a PostgreSQL URL
        ``postgresql+psycopg://user:password@host:port/database``.
    create : bool, optional
        Accept a store without tables (a writer creates them; a reader finds no records).
        False: such a store is an error.
    readonly : bool, optional
        Open for reading only: a SQLite file is opened read-only and never created, no
        table is created or upgraded, no write lock is taken.

    Returns
    -------
    InspectionStore

    Raises
    ------
    RecordError
        SQLAlchemy or the driver missing, the database unreachable, a missing SQLite
        directory or file (reading), a database that is not a camtol store, a damaged
        one or one with a schema newer than this camtol's.
    """
    try:
        import sqlalchemy  # noqa: F401
    except ImportError:  # pragma: no cover - depends on the environment
        raise RecordError(
            "--store needs SQLAlchemy: pip install 'camtol[store]' (PostgreSQL: 'camtol[postgres]')"
        ) from None
    return InspectionStore(store_url(location), create=create, readonly=readonly)


class InspectionStore(StoreReader):
    """Inspection records in a SQL database (see :func:`open_store`). Use as a context manager.

    Parameters
    ----------
    url : str
        The database URL.
    create : bool
        Accept a store without tables (see :func:`open_store`).
    readonly : bool
        A reader (see :func:`open_store`).
    """

    def __init__(self, url: str, *, create: bool = True, readonly: bool = False) -> None:
        from camtol.records import schema as sql
        from camtol.records.migrate import open_schema

        super().__init__(url, readonly=readonly)
        self._where = safe_url(url)
        path = sql.sqlite_path(url) if url.startswith("sqlite") else None
        if path is not None:
            p = Path(path)
            if p.is_dir():
                raise RecordError(f"--store={url!r}: a directory, not a store file")
            if not p.parent.is_dir():
                raise RecordError(f"--store={url!r}: directory {str(p.parent)!r} does not exist")
            if readonly and not p.exists():
                raise RecordError(f"--store={url!r}: no such file")
        try:
            self._engine = sql.make_engine(url, readonly=readonly)
        except RecordError:
            raise
        except Exception as exc:  # a malformed URL, a driver that is not installed
            raise RecordError(
                f"--store={self._where!r}: cannot open the store ({error_brief(exc)})"
            ) from None
        self.dialect = self._engine.dialect.name
        try:
            try:
                state = open_schema(self._engine, self._where, write=not readonly, create=create)
            except Exception as exc:  # a writer killed mid-transaction: SQLite's own recovery
                if not (readonly and path and "readonly" in str(exc)):
                    raise
                if not sql.recover_hot_journal(path):
                    raise
                state = open_schema(self._engine, self._where, write=False, create=create)
        except Exception as exc:  # driver and connection errors of any backend
            self._engine.dispose()
            if isinstance(exc, RecordError):
                raise
            raise RecordError(f"--store={self._where!r}: {open_error(exc)}") from None
        #: Schema version of the store (None: an empty database opened for reading).
        self.version = state.version

    def __enter__(self) -> InspectionStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Release the database connections."""
        self._engine.dispose()

    def _writable(self) -> None:
        if self.readonly:
            raise RecordError(f"--store={self._where!r} was opened for reading only")

    def add(
        self,
        record: InspectionRecord,
        *,
        design_text: str | None = None,
        inputs: Sequence[RawInput] = (),
        allow_duplicate: bool = False,
    ) -> int:
        """Store a record (and the design text, once per hash) in one transaction.

        Parameters
        ----------
        record : InspectionRecord
            The record (from :func:`make_record`).
        design_text : str, optional
            The design's TOML text, kept once per design hash.
        inputs : sequence of RawInput
            The raw inputs it was judged on (kept compressed, once per SHA-256).
        allow_duplicate : bool
            Store it although a standing record of the same serial and cam has the same
            raw data (``record.raw_sha256``).

        Returns
        -------
        int
            The new record's id.
        """
        return self.add_all(
            [record], design_text=design_text, inputs=inputs, allow_duplicate=allow_duplicate
        )[0]

    def add_all(
        self,
        records: Sequence[InspectionRecord],
        *,
        design_text: str | None = None,
        inputs: Sequence[RawInput] = (),
        allow_duplicate: bool = False,
    ) -> list[int]:
        """Store several records (e.g. cams A and B of a pair) in one transaction.

        Parameters
        ----------
        records : sequence of InspectionRecord
            The records (from :func:`make_record`).
        design_text : str, optional
            The designs' TOML text, kept once per design hash.
        inputs : sequence of RawInput
            The raw inputs every record was judged on.
        allow_duplicate : bool
            See :meth:`add`.

        Returns
        -------
        list of int
            The new records' ids, in order. On any error nothing is stored.

        Raises
        ------
        RecordError
            A duplicate (naming the record holding the raw data), or a database error.
        """
        self._writable()
        from camtol.records.writes import insert_records

        try:
            return insert_records(
                self._engine, records, design_text, inputs, allow_duplicate=allow_duplicate
            )
        except RecordError:
            raise
        except Exception as exc:
            raise RecordError(
                f"--store={self._where!r}: nothing was stored ({error_brief(exc)})"
            ) from None

    def void(
        self, record_id: int, *, reason: str, by: str, when: datetime | None = None
    ) -> InspectionRecord:
        """Mark a record void, never deleting it: who, when and why are kept.

        Parameters
        ----------
        record_id : int
            The record.
        reason : str
            Why (1 to 500 characters, no NUL).
        by : str
            Who (at most 200 characters, no NUL).
        when : datetime, optional
            When (aware; default now).

        Returns
        -------
        InspectionRecord
            The record, voided.

        Raises
        ------
        RecordError
            No such record, already void, or a reason or name outside what is allowed.
        """
        self._writable()
        self.check_id(record_id)
        if not reason.strip() or len(reason) > 500 or "\x00" in reason:
            raise RecordError(
                f"--reason={reason[:20]!r}: allowed text of 1 to 500 characters without NUL"
                " (say why the record is void)"
            )
        if len(by) > 200 or "\x00" in by:
            raise RecordError(f"--by={by[:20]!r}: allowed text of at most 200 characters")
        when = datetime.now(timezone.utc) if when is None else when
        from camtol.records.writes import void_record

        return self._guard(
            lambda: void_record(self._engine, record_id, reason=reason, by=by, when=when)
        )


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
    inputs: Sequence[RawInput] = (),
    allow_duplicate: bool = False,
    **fields: Any,
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
    inputs : sequence of RawInput
        The raw inputs (the first is the primary raw data: its SHA-256 is the record's
        ``raw_sha256`` unless given in ``fields``).
    allow_duplicate : bool
        Store it although the same raw data is already recorded for this serial and cam.
    **fields
        Further keywords of :func:`make_record` (``extremes_um``, ``judged_on``,
        ``decision_rule``, ``motion_unit``, ``raw_sha256``, ``options``, ``results``).

    Returns
    -------
    int
        The record's id.
    """
    name, digest = design_identity(design, design_text)
    if inputs and "raw_sha256" not in fields:
        fields["raw_sha256"] = inputs[0].sha256
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
        **fields,
    )
    if isinstance(location, InspectionStore):
        return location.add(
            rec, design_text=design_text, inputs=inputs, allow_duplicate=allow_duplicate
        )
    with open_store(location) as store:
        return store.add(
            rec, design_text=design_text, inputs=inputs, allow_duplicate=allow_duplicate
        )
