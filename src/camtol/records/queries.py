"""The reads of the inspection store: records, designs, raw inputs (SQLAlchemy Core).

Reads join the curves by an outer join (a record without its curve is still listed, with
no points) and read a version-1 store as it is: the columns it lacks are NULL. Raw inputs
are checked against their SHA-256 as they are read; a corrupt blob is named.
"""

from __future__ import annotations

import json
import zlib
from datetime import datetime, timezone
from typing import Any

import numpy as np
from sqlalchemy import Connection, Engine, Select, bindparam, null, select

from camtol.exceptions import RecordError
from camtol.records.raw import RawInput, sha256_of
from camtol.records.record import InspectionRecord
from camtol.records.schema import (
    V2_COLUMNS,
    V3_COLUMNS,
    curves,
    designs,
    inspection_inputs,
    inspections,
    raw_inputs,
)

__all__ = [
    "find_duplicate",
    "select_design_text",
    "select_input_list",
    "select_inputs",
    "select_records",
    "utc",
]

_DTYPE = np.dtype("<f4")


def find_duplicate(
    conn: Connection, serial: str, cam: str, raw_sha256: str
) -> tuple[int, datetime] | None:
    """Return (id, inspected_at) of a standing record with this raw data, serial and cam.

    Parameters
    ----------
    conn : Connection
        An open connection (a version-2 store).
    serial, cam : str
        The part's serial and the cam.
    raw_sha256 : str
        ``sha256:<hex>`` of the raw data.

    Returns
    -------
    (int, datetime) or None
    """
    row = conn.execute(_DUPLICATE, {"serial": serial, "cam": cam, "raw_sha256": raw_sha256}).first()
    return None if row is None else (int(row[0]), row[1])


_DUPLICATE = (
    select(inspections.c.id, inspections.c.inspected_at)
    .where(
        (inspections.c.serial == bindparam("serial"))
        & (inspections.c.cam == bindparam("cam"))
        & (inspections.c.raw_sha256 == bindparam("raw_sha256"))
        & inspections.c.voided_at.is_(None)
    )
    .order_by(inspections.c.id)
    .limit(1)
)


_DETAILS = ("options", "results")


def _columns(version: int, details: bool) -> list[Any]:
    """Return the record columns to read: a version-1 store's missing ones as NULL."""
    out: list[Any] = []
    for col in inspections.c:
        if col.name in _DETAILS and not details:
            continue
        if (version < 2 and col.name in V2_COLUMNS) or (version < 3 and col.name in V3_COLUMNS):
            out.append(null().label(col.name))
        else:
            out.append(col)
    return out


def select_records(
    engine: Engine,
    *,
    version: int,
    record_id: int | None = None,
    design: str | None = None,
    lot: str | None = None,
    cam: str | None = None,
    include_voided: bool = False,
    with_curves: bool = True,
    with_details: bool = False,
) -> list[InspectionRecord]:
    """Select the records matching the filters, oldest first (by time, then id).

    Parameters
    ----------
    engine : Engine
        The store's engine.
    version : int
        The store's schema version (a version-1 store is read as it is).
    record_id : int, optional
        One record.
    design, lot, cam : str, optional
        Filters (``cam`` "" for a single cam).
    include_voided : bool
        Voided records too (by default they are skipped).
    with_curves : bool
        Read the curves (else ``dr_um`` is empty).
    with_details : bool
        Read the options and results (JSON) too.

    Returns
    -------
    list of InspectionRecord
    """
    query: Select[Any] = select(
        *_columns(version, with_details),
        curves.c.n_points,
        *([curves.c.data] if with_curves else []),
    ).select_from(
        inspections.outerjoin(
            curves, (curves.c.inspection_id == inspections.c.id) & (curves.c.name == "dr_um")
        )
    )
    if record_id is not None:
        query = query.where(inspections.c.id == record_id)
    if design is not None:
        query = query.where(inspections.c.design_name == design)
    if lot is not None:
        query = query.where(inspections.c.lot == lot)
    if cam is not None:
        query = query.where(inspections.c.cam == cam)
    if version >= 2 and not include_voided and record_id is None:
        query = query.where(inspections.c.voided_at.is_(None))
    if not with_curves:
        query = query.order_by(inspections.c.inspected_at, inspections.c.id)
    with engine.connect() as conn:
        result = conn.execute(query)
        names = list(result.keys())
        rows = [dict(zip(names, row, strict=True)) for row in result.all()]
        conn.rollback()
    if with_curves:
        # Sorted here, not by SQL: SQLite's sorter would carry every curve's blob (a lot
        # of 10,000 3,600-point curves read 2.5 times slower, bench/bench_spc.py).
        rows.sort(key=lambda row: (row["inspected_at"], row["id"]))
    return [_record(row, with_curves) for row in rows]


def select_design_text(engine: Engine, design_hash: str) -> str | None:
    """Return the stored TOML text of a design (None when not stored).

    Parameters
    ----------
    engine : Engine
        The store's engine.
    design_hash : str
        ``sha256:<hex>``.

    Returns
    -------
    str or None
    """
    with engine.connect() as conn:
        value = conn.execute(
            select(designs.c.toml).where(designs.c.design_hash == design_hash)
        ).scalar()
        conn.rollback()
    return None if value is None else str(value)


def select_input_list(engine: Engine, record_id: int, *, version: int) -> list[dict[str, Any]]:
    """Return what raw inputs a record has, without reading their blobs.

    Parameters
    ----------
    engine : Engine
        The store's engine.
    record_id : int
        The record.
    version : int
        The store's schema version (a version-1 store has none).

    Returns
    -------
    list of dict
        ``role``, ``name``, ``sha256`` and ``size_bytes`` (uncompressed) of each, by role.
    """
    if version < 2:
        return []
    rows = _input_rows(engine, record_id)
    return [
        {"role": role, "name": name, "sha256": digest, "size_bytes": size}
        for role, name, digest, size in rows
    ]


def _input_rows(engine: Engine, record_id: int, *extra: Any) -> list[Any]:
    """Return a record's inputs by role: role, name, SHA-256, size, then ``extra``."""
    query = (
        select(
            inspection_inputs.c.role,
            inspection_inputs.c.name,
            inspection_inputs.c.sha256,
            raw_inputs.c.size_bytes,
            *extra,
        )
        .select_from(
            inspection_inputs.outerjoin(
                raw_inputs, raw_inputs.c.sha256 == inspection_inputs.c.sha256
            )
        )
        .where(inspection_inputs.c.inspection_id == record_id)
        .order_by(inspection_inputs.c.role)
    )
    with engine.connect() as conn:
        rows = conn.execute(query).all()
        conn.rollback()  # a reader never holds a transaction open
    return list(rows)


def select_inputs(engine: Engine, record_id: int, *, version: int) -> list[RawInput]:
    """Return a record's raw inputs, each checked against its SHA-256.

    Parameters
    ----------
    engine : Engine
        The store's engine.
    record_id : int
        The record.
    version : int
        The store's schema version (a version-1 store has none).

    Returns
    -------
    list of RawInput
        In role order.

    Raises
    ------
    RecordError
        A blob that does not decompress or whose SHA-256 is not the one it is stored
        under (naming the record, the input's role and file, and both hashes).
    """
    if version < 2:
        return []
    rows = _input_rows(engine, record_id, raw_inputs.c.data)
    out = []
    for role, name, digest, size, blob in rows:
        shown = f"record {record_id}: raw input {role!r}" + (f" ({name})" if name else "")
        if blob is None:
            raise RecordError(f"{shown}: its blob {digest} is missing from the store")
        try:
            data = zlib.decompress(bytes(blob))
        except zlib.error:
            raise RecordError(
                f"{shown} is corrupt: its blob does not decompress (stored as {digest})"
            ) from None
        actual = sha256_of(data)
        if actual != digest or len(data) != size:
            raise RecordError(
                f"{shown} is corrupt: its SHA-256 is {actual}, stored as {digest}"
                f" ({len(data)} bytes, {size} stored)"
            )
        out.append(RawInput(role, name, data))
    return out


def utc(when: datetime) -> datetime:
    """Return an aware UTC date-time (SQLite gives back naive ones, written in UTC).

    Parameters
    ----------
    when : datetime
        A date-time as read or given (naive: UTC).

    Returns
    -------
    datetime
    """
    if when.tzinfo is None:
        return when.replace(tzinfo=timezone.utc)
    return when.astimezone(timezone.utc)


def _json(value: Any) -> dict[str, Any] | None:
    if value is None:
        return None
    out: dict[str, Any] = json.loads(value)
    return out


#: The curve of a record read without curves (shared: it is never written to).
_NO_CURVE = np.empty(0, dtype=np.float32)
_NO_CURVE.flags.writeable = False


def _record(row: dict[str, Any], with_curve: bool) -> InspectionRecord:
    """Build a record from a row (a dict of the columns read)."""
    n_points, data, ds = row["n_points"], row.get("data"), row["max_abs_ds_um"]
    ds_deg, unit = row.get("max_abs_ds_deg"), row["motion_unit"]
    if unit == "urad":  # a version-2 store read as it is: a swing's µrad figure in degrees
        ds_deg, ds, unit = (None if ds is None else float(np.degrees(ds * 1e-6))), None, "deg"
    voided_at = row["voided_at"]
    return InspectionRecord.from_store(
        id=int(row["id"]),
        design_name=row["design_name"],
        design_hash=row["design_hash"],
        method=row["method"],
        cam=row["cam"],
        part_number=row["part_number"],
        serial=row["serial"],
        lot=row["lot"],
        inspector=row["inspector"],
        instrument=row["instrument"],
        inspected_at=utc(row["inspected_at"]),
        verdict=row["verdict"],
        max_dev_um=float(row["max_dev_um"]),
        min_dev_um=float(row["min_dev_um"]),
        form_um=float(row["form_um"]),
        max_abs_ds_um=None if ds is None else float(ds),
        max_abs_ds_deg=None if ds_deg is None else float(ds_deg),
        tolerance_um=(float(row["tolerance_lower_um"]), float(row["tolerance_upper_um"])),
        camtol_version=row["camtol_version"],
        n_points=0 if n_points is None else int(n_points),
        dr_um=(
            # read-only, and no copy where float32 is little-endian
            np.frombuffer(data, dtype=_DTYPE).astype(np.float32, copy=False)
            if with_curve and data is not None
            else _NO_CURVE
        ),
        judged_on=row["judged_on"],
        decision_rule=row["decision_rule"],
        motion_unit=unit,
        raw_sha256=row["raw_sha256"],
        options=_json(row.get("options")),
        results=_json(row.get("results")),
        duplicate_allowed=bool(row["duplicate_allowed"]),
        voided_at=None if voided_at is None else utc(voided_at),
        voided_by=row["voided_by"] or "",
        void_reason=row["void_reason"] or "",
    )
