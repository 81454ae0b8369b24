"""Reading a store of inspection records: the queries every opened store answers.

:class:`StoreReader` is what a reader and a writer share: a record by id (out-of-range ids
refused in one line), the records of a query (voided ones left out unless asked for), a
design's stored text, the raw inputs of a record (each checked against its SHA-256) and
the standing record holding some raw data. A reader never writes: the engine it is given
opens SQLite read-only and runs PostgreSQL transactions read-only.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

from camtol.exceptions import RecordError
from camtol.records.record import InspectionRecord

if TYPE_CHECKING:
    from sqlalchemy import Engine

    from camtol.records.raw import RawInput

T = TypeVar("T")

__all__ = ["StoreReader"]

#: Largest record id each engine can hold (SQLite's 64-bit rowid, PostgreSQL's integer).
_MAX_ID = {"sqlite": 2**63 - 1, "postgresql": 2**31 - 1}


class StoreReader:
    """The reading half of an inspection store (see :class:`camtol.records.store.InspectionStore`).

    Parameters
    ----------
    url : str
        The database URL.
    readonly : bool
        Opened for reading only.
    """

    _engine: Engine
    _where: str
    #: Schema version of the store (None: an empty database opened for reading).
    version: int | None
    #: The engine's dialect, ``sqlite`` or ``postgresql``.
    dialect: str

    def __init__(self, url: str, *, readonly: bool) -> None:
        self.url = url
        self.readonly = readonly

    def check_id(self, record_id: int) -> None:
        """Refuse an id no record can have (below 1, beyond the engine's integer).

        Parameters
        ----------
        record_id : int
            The id as given.
        """
        top = _MAX_ID.get(self.dialect, 2**31 - 1)
        if not 1 <= record_id <= top:
            raise RecordError(
                f"record id {record_id}: no such record in {self._where!r} (ids are whole"
                f" numbers from 1 to {top})"
            )

    def get(self, record_id: int) -> InspectionRecord:
        """Return the record with this id (voided or not), with its curve and details.

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
        self.check_id(record_id)
        if self.version is None:
            raise RecordError(f"record id {record_id}: no such record in {self._where!r}")
        from camtol.records.queries import select_records

        version = self.version
        rec: list[InspectionRecord] = self._guard(
            lambda: select_records(
                self._engine, version=version, record_id=record_id, with_details=True
            )
        )
        if not rec:
            raise RecordError(f"record id {record_id}: no such record in {self._where!r}")
        return rec[0]

    def records(
        self,
        *,
        design: str | None = None,
        lot: str | None = None,
        cam: str | None = None,
        with_curves: bool = False,
        include_voided: bool = False,
        with_details: bool = False,
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
        include_voided : bool, optional
            Voided records too (by default they are left out).
        with_details : bool, optional
            Read each record's options and results too (``records stats`` judges Δn
            characteristics and motion specs from them).

        Returns
        -------
        list of InspectionRecord
        """
        if self.version is None:
            return []
        from camtol.records.queries import select_records

        version = self.version
        return self._guard(
            lambda: select_records(
                self._engine,
                version=version,
                design=design,
                lot=lot,
                cam=cam,
                with_curves=with_curves,
                include_voided=include_voided,
                with_details=with_details,
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
        if self.version is None:
            return None
        from camtol.records.queries import select_design_text

        found: str | None = self._guard(lambda: select_design_text(self._engine, design_hash))
        return found

    def inputs(self, record_id: int) -> list[RawInput]:
        """Return the raw inputs of a record, each checked against its SHA-256.

        Parameters
        ----------
        record_id : int
            The record's id.

        Returns
        -------
        list of RawInput
            Empty for a record stored without raw data.

        Raises
        ------
        RecordError
            A corrupt blob (naming the record, the input and both hashes).
        """
        self.check_id(record_id)
        if self.version is None:
            return []
        from camtol.records.queries import select_inputs

        version = self.version
        found: list[RawInput] = self._guard(
            lambda: select_inputs(self._engine, record_id, version=version)
        )
        return found

    def input_list(self, record_id: int) -> list[dict[str, Any]]:
        """Return what raw inputs a record has (role, name, sha256, size), blobs unread.

        Parameters
        ----------
        record_id : int
            The record's id.

        Returns
        -------
        list of dict
            ``role``, ``name``, ``sha256``, ``size_bytes``; empty without raw data.
        """
        self.check_id(record_id)
        if self.version is None:
            return []
        from camtol.records.queries import select_input_list

        version = self.version
        found: list[dict[str, Any]] = self._guard(
            lambda: select_input_list(self._engine, record_id, version=version)
        )
        return found

    def find_duplicate(self, serial: str, cam: str, raw_sha256: str) -> int | None:
        """Return the id of a standing record with this raw data for this serial and cam.

        Parameters
        ----------
        serial, cam : str
            The part's serial and the cam.
        raw_sha256 : str
            ``sha256:<hex>`` of the raw data.

        Returns
        -------
        int or None
        """
        if self.version is None or self.version < 2:
            return None
        from camtol.records.queries import find_duplicate

        def look() -> int | None:
            with self._engine.connect() as conn:
                found = find_duplicate(conn, serial, cam, raw_sha256)
                conn.rollback()
            return None if found is None else found[0]

        return self._guard(look)

    def _guard(self, fn: Callable[[], T]) -> T:
        try:
            return fn()
        except RecordError:
            raise
        except Exception as exc:
            raise RecordError(f"--store={self._where!r}: {error_brief(exc)}") from None


def error_brief(exc: BaseException) -> str:
    """Return the first line of an exception's message."""
    orig = getattr(exc, "orig", None) or exc
    text = str(orig).strip().splitlines()
    return f"{type(orig).__name__}: {text[0] if text else ''}"


def open_error(exc: BaseException) -> str:
    """Say what went wrong opening a store, in words."""
    brief = error_brief(exc)
    if "file is not a database" in brief:
        return "not a camtol inspection store (not a SQLite database); it was left untouched"
    return f"cannot open the store ({brief})"
