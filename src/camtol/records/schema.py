"""SQLAlchemy Core tables and statements of the inspection store (imported lazily).

Tables (documented in docs/records.md): ``schema_version``, ``designs`` (one row per design
hash, with its TOML text), ``inspections`` (one row per inspected cam) and ``curves`` (one
float32 blob per curve of a record). SQLite transactions begin with ``BEGIN IMMEDIATE`` so
that concurrent writers wait for each other (busy timeout 30 s) instead of failing on a
lock upgrade; PostgreSQL serialises the first creation of the tables with an advisory lock.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import timezone
from typing import Any

import numpy as np
from sqlalchemy import (
    CheckConstraint,
    Column,
    DateTime,
    Double,
    Engine,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    MetaData,
    String,
    Table,
    Text,
    create_engine,
    event,
    func,
    insert,
    inspect,
    select,
    text,
)

from camtol.exceptions import RecordError
from camtol.records.record import InspectionRecord

metadata = MetaData()

schema_version = Table(
    "schema_version",
    metadata,
    Column("version", Integer, primary_key=True, autoincrement=False),
)

designs = Table(
    "designs",
    metadata,
    Column("design_hash", String(71), primary_key=True),
    Column("name", String(200), nullable=False),
    Column("toml", Text, nullable=True),
)

inspections = Table(
    "inspections",
    metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("design_name", String(200), nullable=False),
    Column("design_hash", String(71), ForeignKey("designs.design_hash"), nullable=False),
    Column("method", String(32), nullable=False),
    Column("cam", String(1), nullable=False),
    Column("part_number", String(200), nullable=False),
    Column("serial", String(200), nullable=False),
    Column("lot", String(200), nullable=False),
    Column("inspector", String(200), nullable=False),
    Column("instrument", String(200), nullable=False),
    Column("inspected_at", DateTime(timezone=True), nullable=False),
    Column("verdict", String(4), nullable=False),
    Column("max_dev_um", Double, nullable=False),
    Column("min_dev_um", Double, nullable=False),
    Column("form_um", Double, nullable=False),
    Column("max_abs_ds_um", Double, nullable=True),
    Column("tolerance_lower_um", Double, nullable=False),
    Column("tolerance_upper_um", Double, nullable=False),
    Column("camtol_version", String(64), nullable=False),
    CheckConstraint("verdict IN ('pass', 'fail')", name="ck_verdict"),
    CheckConstraint("method IN ('conjugate-fixture', 'cmm')", name="ck_method"),
    CheckConstraint("cam IN ('A', 'B', '')", name="ck_cam"),
    Index("ix_inspections_design_lot", "design_name", "lot"),
)

curves = Table(
    "curves",
    metadata,
    Column(
        "inspection_id",
        Integer,
        ForeignKey("inspections.id", ondelete="CASCADE"),
        primary_key=True,
    ),
    Column("name", String(32), primary_key=True),
    Column("n_points", Integer, nullable=False),
    Column("data", LargeBinary, nullable=False),
)

_DTYPE = np.dtype("<f4")


def make_engine(url: str) -> Engine:
    """Make an engine for ``url``; SQLite gets a busy timeout and BEGIN IMMEDIATE transactions."""
    if url.startswith("sqlite"):
        engine = create_engine(url, connect_args={"timeout": 30.0})

        @event.listens_for(engine, "connect")
        def _connect(dbapi_conn: Any, _record: Any) -> None:
            dbapi_conn.isolation_level = None  # transactions are begun below
            dbapi_conn.execute("PRAGMA foreign_keys = ON")

        @event.listens_for(engine, "begin")
        def _begin(conn: Any) -> None:
            conn.exec_driver_sql("BEGIN IMMEDIATE")

        return engine
    if url.startswith("postgresql"):
        return create_engine(url, connect_args={"connect_timeout": 10})
    raise RecordError(
        f"--store={url.split('://')[0]}://...: allowed a SQLite file, sqlite:///FILE.db or"
        " postgresql+psycopg://user@host:port/database"
    )


def initialise(engine: Engine, version: int, *, create: bool) -> None:
    """Create the tables when absent and check the schema version (one transaction)."""
    with engine.begin() as conn:
        if engine.dialect.name == "postgresql":
            conn.execute(text("SELECT pg_advisory_xact_lock(7318120)"))
        if not inspect(conn).has_table("schema_version"):
            if not create:
                raise RecordError(f"--store={engine.url!r} holds no inspection records")
            metadata.create_all(conn)
            conn.execute(insert(schema_version).values(version=version))
            return
        found = conn.execute(select(func.max(schema_version.c.version))).scalar()
        if found is None or found > version:
            raise RecordError(
                f"--store={engine.url.render_as_string(hide_password=True)!r} has schema"
                f" version {found}, newer than the version {version} this camtol reads;"
                " upgrade camtol"
            )
        metadata.create_all(conn)  # tables added since (none yet); existing ones untouched


def insert_records(
    engine: Engine, recs: Sequence[InspectionRecord], design_text: str | None
) -> list[int]:
    """Insert the designs (if new), the records and their curves in one transaction."""
    ids: list[int] = []
    with engine.begin() as conn:
        for rec in recs:
            known = conn.execute(
                select(designs.c.design_hash).where(designs.c.design_hash == rec.design_hash)
            ).first()
            if known is None:
                conn.execute(
                    insert(designs).values(
                        design_hash=rec.design_hash, name=rec.design_name, toml=design_text
                    )
                )
            new_id = conn.execute(
                insert(inspections)
                .values(
                    design_name=rec.design_name,
                    design_hash=rec.design_hash,
                    method=rec.method,
                    cam=rec.cam,
                    part_number=rec.part_number,
                    serial=rec.serial,
                    lot=rec.lot,
                    inspector=rec.inspector,
                    instrument=rec.instrument,
                    inspected_at=rec.inspected_at,
                    verdict=rec.verdict,
                    max_dev_um=rec.max_dev_um,
                    min_dev_um=rec.min_dev_um,
                    form_um=rec.form_um,
                    max_abs_ds_um=rec.max_abs_ds_um,
                    tolerance_lower_um=rec.tolerance_um[0],
                    tolerance_upper_um=rec.tolerance_um[1],
                    camtol_version=rec.camtol_version,
                )
                .returning(inspections.c.id)
            ).scalar_one()
            conn.execute(
                insert(curves).values(
                    inspection_id=new_id,
                    name="dr_um",
                    n_points=int(rec.dr_um.size),
                    data=np.asarray(rec.dr_um, dtype=_DTYPE).tobytes(),
                )
            )
            ids.append(int(new_id))
    return ids


def select_records(
    engine: Engine,
    *,
    record_id: int | None = None,
    design: str | None = None,
    lot: str | None = None,
    cam: str | None = None,
    with_curves: bool = True,
) -> list[InspectionRecord]:
    """Select the records matching the filters, oldest first."""
    query = select(inspections, curves.c.n_points, *([curves.c.data] if with_curves else []))
    query = query.join(
        curves, (curves.c.inspection_id == inspections.c.id) & (curves.c.name == "dr_um")
    )
    if record_id is not None:
        query = query.where(inspections.c.id == record_id)
    if design is not None:
        query = query.where(inspections.c.design_name == design)
    if lot is not None:
        query = query.where(inspections.c.lot == lot)
    if cam is not None:
        query = query.where(inspections.c.cam == cam)
    query = query.order_by(inspections.c.inspected_at, inspections.c.id)
    with engine.connect() as conn:
        rows = conn.execute(query).mappings().all()
    return [_record(row, with_curves) for row in rows]


def select_design_text(engine: Engine, design_hash: str) -> str | None:
    """Return the stored TOML text of a design."""
    with engine.connect() as conn:
        value = conn.execute(
            select(designs.c.toml).where(designs.c.design_hash == design_hash)
        ).scalar()
    return None if value is None else str(value)


def _record(row: Any, with_curve: bool) -> InspectionRecord:
    when = row["inspected_at"]
    when = when.replace(tzinfo=timezone.utc) if when.tzinfo is None else when
    data = (
        np.frombuffer(bytes(row["data"]), dtype=_DTYPE).astype(np.float32)
        if with_curve
        else np.empty(0, dtype=np.float32)
    )
    return InspectionRecord(
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
        inspected_at=when.astimezone(timezone.utc),
        verdict=row["verdict"],
        max_dev_um=float(row["max_dev_um"]),
        min_dev_um=float(row["min_dev_um"]),
        form_um=float(row["form_um"]),
        max_abs_ds_um=None if row["max_abs_ds_um"] is None else float(row["max_abs_ds_um"]),
        tolerance_um=(float(row["tolerance_lower_um"]), float(row["tolerance_upper_um"])),
        camtol_version=row["camtol_version"],
        n_points=int(row["n_points"]),
        dr_um=data,
    )
