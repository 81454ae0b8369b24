"""The writes of the inspection store: records in, and voids (SQLAlchemy Core).

Every write is one transaction. The design row and the raw blobs are inserted race-free on
both engines by the dialect's ``INSERT ... ON CONFLICT`` (a design's text is filled in when
a record brings it and the stored row has none); a standing record with the same raw data
for the same serial and cam is refused, by a look-up naming it and, between concurrent
writers, by the partial unique index ``ux_inspections_raw``. A void only marks a record.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from datetime import datetime
from functools import cache
from typing import Any

import numpy as np
from sqlalchemy import Engine, exc, select, update
from sqlalchemy.dialects import postgresql, sqlite

from camtol.exceptions import RecordError
from camtol.records.queries import find_duplicate, select_records, utc
from camtol.records.raw import RawInput
from camtol.records.record import InspectionRecord
from camtol.records.schema import curves, designs, inspection_inputs, inspections, raw_inputs

__all__ = ["duplicate_message", "insert_records", "void_record"]

_DTYPE = np.dtype("<f4")


def duplicate_message(rec: InspectionRecord, found: int | None, when: Any = None) -> str:
    """Return the one line refusing a duplicate record.

    Parameters
    ----------
    rec : InspectionRecord
        The record refused.
    found : int or None
        The id of the standing record with the same raw data (None: stored concurrently).
    when : datetime, optional
        When that record was inspected.

    Returns
    -------
    str
    """
    what = f"record {found}" if found is not None else "a record stored at the same time"
    at = f", stored {utc(when).isoformat()}" if when is not None else ""
    cam = f", cam {rec.cam}" if rec.cam else ""
    return (
        f"serial={rec.serial!r}{cam}: the same raw data ({rec.raw_sha256}) is already"
        f" {what}{at}; nothing was stored (a re-run of a recorded inspection?); give"
        " --allow-duplicate to store it again, or void the other record first"
    )


def insert_records(
    engine: Engine,
    records: Sequence[InspectionRecord],
    design_text: str | None,
    inputs: Sequence[RawInput] = (),
    *,
    allow_duplicate: bool = False,
) -> list[int]:
    """Insert records with their design, curves and raw inputs in one transaction.

    Parameters
    ----------
    engine : Engine
        A writer's engine on a store at the current schema version.
    records : sequence of InspectionRecord
        The records (from :func:`camtol.records.record.make_record`).
    design_text : str or None
        The designs' TOML text.
    inputs : sequence of RawInput
        The raw inputs every record of the call was judged on.
    allow_duplicate : bool
        Store a standing record's raw data again for the same serial and cam.

    Returns
    -------
    list of int
        The new ids, in order.

    Raises
    ------
    RecordError
        A duplicate (naming the record that holds the raw data).
    """
    ids: list[int] = []
    blobs = {raw.sha256: raw for raw in inputs}
    try:
        with engine.begin() as conn:
            st = _statements(conn.dialect.name)
            if not allow_duplicate:
                for rec in records:
                    if rec.raw_sha256 is None:
                        continue
                    found = find_duplicate(conn, rec.serial, rec.cam, rec.raw_sha256)
                    if found is not None:
                        raise RecordError(duplicate_message(rec, *found))
            for name, digest in dict.fromkeys((r.design_name, r.design_hash) for r in records):
                conn.execute(
                    st["design"], {"design_hash": digest, "name": name, "toml": design_text}
                )
            for digest, raw in blobs.items():
                conn.execute(
                    st["raw"],
                    {
                        "sha256": digest,
                        "size_bytes": len(raw.data),
                        "compression": "zlib",
                        "data": raw.compressed(),
                    },
                )
            for rec in records:
                row = _record_row(rec, allow_duplicate)
                new_id = int(conn.execute(st["record"], row).scalar_one())
                conn.execute(
                    st["curve"],
                    {
                        "inspection_id": new_id,
                        "name": "dr_um",
                        "n_points": int(rec.dr_um.size),
                        "data": np.asarray(rec.dr_um, dtype=_DTYPE).tobytes(),
                    },
                )
                if inputs:
                    conn.execute(
                        st["inputs"],
                        [
                            {
                                "inspection_id": new_id,
                                "role": raw.role,
                                "name": raw.name,
                                "sha256": raw.sha256,
                            }
                            for raw in inputs
                        ],
                    )
                ids.append(new_id)
    except exc.IntegrityError as error:
        if "ux_inspections_raw" in str(error.orig) or _unique_raw(error):
            dup = next((r for r in records if r.raw_sha256 is not None), records[0])
            raise RecordError(duplicate_message(dup, None)) from None
        raise
    return ids


@cache
def _statements(dialect: str) -> dict[str, Any]:
    """Return the insert statements of one dialect, built once (values given when run)."""
    dml: Any = postgresql if dialect == "postgresql" else sqlite
    design = dml.insert(designs)
    return {
        "design": design.on_conflict_do_update(
            index_elements=[designs.c.design_hash],
            set_={"toml": design.excluded.toml},
            where=designs.c.toml.is_(None),
        ),
        "raw": dml.insert(raw_inputs).on_conflict_do_nothing(index_elements=[raw_inputs.c.sha256]),
        "record": inspections.insert().returning(inspections.c.id),
        "curve": curves.insert(),
        "inputs": inspection_inputs.insert(),
    }


def _unique_raw(error: exc.IntegrityError) -> bool:
    """Whether SQLite's unique failure names the raw-data columns (its message has no index)."""
    text = str(error.orig)
    return "UNIQUE" in text and "raw_sha256" in text


def _record_row(rec: InspectionRecord, allow_duplicate: bool) -> dict[str, Any]:
    """Return the ``inspections`` row of a record (its id left to the database)."""
    return {
        "design_name": rec.design_name,
        "design_hash": rec.design_hash,
        "method": rec.method,
        "cam": rec.cam,
        "part_number": rec.part_number,
        "serial": rec.serial,
        "lot": rec.lot,
        "inspector": rec.inspector,
        "instrument": rec.instrument,
        "inspected_at": rec.inspected_at,
        "verdict": rec.verdict,
        "max_dev_um": rec.max_dev_um,
        "min_dev_um": rec.min_dev_um,
        "form_um": rec.form_um,
        "max_abs_ds_um": rec.max_abs_ds_um,
        "max_abs_ds_deg": rec.max_abs_ds_deg,
        "tolerance_lower_um": rec.tolerance_um[0],
        "tolerance_upper_um": rec.tolerance_um[1],
        "camtol_version": rec.camtol_version,
        "judged_on": rec.judged_on,
        "decision_rule": rec.decision_rule,
        "motion_unit": rec.motion_unit,
        "raw_sha256": rec.raw_sha256,
        "options": None if rec.options is None else json.dumps(rec.options, sort_keys=True),
        "results": None if rec.results is None else json.dumps(rec.results, sort_keys=True),
        "duplicate_allowed": bool(allow_duplicate and rec.raw_sha256 is not None),
        "voided_by": "",
        "void_reason": "",
    }


def void_record(
    engine: Engine, record_id: int, *, reason: str, by: str, when: datetime
) -> InspectionRecord:
    """Mark a standing record void (one transaction); return it as it is now.

    Parameters
    ----------
    engine : Engine
        A writer's engine on a store at the current schema version.
    record_id : int
        The record.
    reason, by : str
        Why and who.
    when : datetime
        When (aware).

    Returns
    -------
    InspectionRecord
        The voided record (without its curve).

    Raises
    ------
    RecordError
        No such record, or already void (naming when, by whom and why).
    """
    with engine.begin() as conn:
        done = conn.execute(
            update(inspections)
            .where((inspections.c.id == record_id) & inspections.c.voided_at.is_(None))
            .values(voided_at=utc(when), voided_by=by, void_reason=reason)
        ).rowcount
        if done != 1:
            row = conn.execute(
                select(
                    inspections.c.voided_at, inspections.c.voided_by, inspections.c.void_reason
                ).where(inspections.c.id == record_id)
            ).first()
            if row is None:
                raise RecordError(f"record id {record_id}: no such record")
            raise RecordError(
                f"record id {record_id} is already void (since {utc(row[0]).isoformat()},"
                f" by {row[1]!r}: {row[2]!r}); nothing was changed"
            )
    (rec,) = select_records(engine, version=2, record_id=record_id, with_curves=False)
    return rec
