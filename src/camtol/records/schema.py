"""SQLAlchemy Core tables of the inspection store and its engines (imported lazily).

Tables (documented in docs/records.md), as of schema version 3 (the Alembic revisions in
:mod:`camtol.records.migrations` build them from nothing or from an older store):
``schema_version`` (one row: the version), ``designs`` (one row per design hash, with its
TOML text), ``inspections`` (one row per inspected cam), ``curves`` (one float32 blob per
curve of a record), ``raw_inputs`` (one zlib blob per raw input, by SHA-256) and
``inspection_inputs`` (which raw inputs a record was judged on, and as what).

Engines: a writer's SQLite transactions begin with ``BEGIN IMMEDIATE`` so that concurrent
writers wait for each other (busy timeout 30 s) instead of failing on a lock upgrade; a
reader opens the file read-only (``mode=ro``) and never takes the write lock; a
PostgreSQL reader's transactions are read-only.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any
from urllib.parse import quote

from sqlalchemy import (
    Boolean,
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
    text,
)
from sqlalchemy.engine import URL, make_url

from camtol.exceptions import RecordError

__all__ = [
    "curves",
    "designs",
    "inspection_inputs",
    "inspections",
    "make_engine",
    "metadata",
    "raw_inputs",
    "schema_version",
]

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

#: Where a standing record's raw data must be unique for its serial and cam (a partial
#: unique index: voided records and those stored with --allow-duplicate are left out).
STANDING_UNIQUE = "voided_at IS NULL AND NOT duplicate_allowed"

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
    Column("max_abs_ds_deg", Double, nullable=True),
    Column("tolerance_lower_um", Double, nullable=False),
    Column("tolerance_upper_um", Double, nullable=False),
    Column("camtol_version", String(64), nullable=False),
    # schema version 2
    Column("judged_on", String(2), nullable=True),
    Column("decision_rule", String(10), nullable=True),
    Column("motion_unit", String(4), nullable=True),
    Column("raw_sha256", String(71), nullable=True),
    Column("options", Text, nullable=True),
    Column("results", Text, nullable=True),
    Column("duplicate_allowed", Boolean, nullable=False, server_default=text("false")),
    Column("voided_at", DateTime(timezone=True), nullable=True),
    Column("voided_by", String(200), nullable=False, server_default=""),
    Column("void_reason", String(500), nullable=False, server_default=""),
    CheckConstraint("verdict IN ('pass', 'fail')", name="ck_verdict"),
    CheckConstraint("method IN ('conjugate-fixture', 'cmm')", name="ck_method"),
    CheckConstraint("cam IN ('A', 'B', '')", name="ck_cam"),
    Index("ix_inspections_design_lot", "design_name", "lot"),
    Index(
        "ux_inspections_raw",
        "serial",
        "cam",
        "raw_sha256",
        unique=True,
        sqlite_where=text(STANDING_UNIQUE),
        postgresql_where=text(STANDING_UNIQUE),
    ),
)

#: Columns of ``inspections`` added by schema version 2 (read as NULL from a version-1 store).
V2_COLUMNS = (
    "judged_on",
    "decision_rule",
    "motion_unit",
    "raw_sha256",
    "options",
    "results",
    "duplicate_allowed",
    "voided_at",
    "voided_by",
    "void_reason",
)

#: Columns of ``inspections`` added by schema version 3 (read as NULL from an older store).
V3_COLUMNS = ("max_abs_ds_deg",)

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

raw_inputs = Table(
    "raw_inputs",
    metadata,
    Column("sha256", String(71), primary_key=True),
    Column("size_bytes", Integer, nullable=False),
    Column("compression", String(8), nullable=False),
    Column("data", LargeBinary, nullable=False),
)

inspection_inputs = Table(
    "inspection_inputs",
    metadata,
    Column(
        "inspection_id",
        Integer,
        ForeignKey("inspections.id", ondelete="CASCADE"),
        primary_key=True,
    ),
    Column("role", String(200), primary_key=True),
    Column("name", String(1000), nullable=False),
    Column("sha256", String(71), ForeignKey("raw_inputs.sha256"), nullable=False),
)


def sqlite_path(url: str) -> str | None:
    """Return the file of a SQLite URL (None for another engine or an in-memory database).

    Parameters
    ----------
    url : str
        A database URL.

    Returns
    -------
    str or None
    """
    if not url.startswith("sqlite"):
        return None
    database = make_url(url).database
    return None if database in (None, "", ":memory:") else database


#: Compiled statements, shared by the engines of one URL in a process: a program that
#: records many inspections (each opening the store) compiles each statement once.
_COMPILED: dict[tuple[str, bool], Any] = {}


def _shared_cache(engine: Engine, url: str, readonly: bool) -> Engine:
    from sqlalchemy.util import LRUCache

    cache = _COMPILED.setdefault((url, readonly), LRUCache(500))
    return engine.execution_options(compiled_cache=cache)


def recover_hot_journal(path: str) -> bool:
    """Roll back what a killed SQLite writer left half-written, so that readers can read.

    A writer killed inside its transaction leaves a hot journal (``FILE-journal``); SQLite
    rolls it back on the next read-write open, restoring the last committed state, but a
    read-only connection cannot (``attempt to write a readonly database``). This opens the
    file read-write (never created) just long enough for SQLite's own recovery; nothing
    else is written.

    Parameters
    ----------
    path : str
        The SQLite file.

    Returns
    -------
    bool
        Whether there was a journal to roll back.
    """
    import sqlite3

    if not Path(path + "-journal").exists():
        return False
    conn = sqlite3.connect(f"file:{quote(path)}?mode=rw", uri=True, timeout=30.0)
    try:
        conn.execute("SELECT count(*) FROM sqlite_master").fetchall()
    finally:
        conn.close()
    return True


#: How much of a SQLite file a reader maps into memory. For a lot of 10,000 3,600-point
#: curves (144 MB) SQLite's own read took half as long; the whole query, records built,
#: 0-25 % less (bench/bench_spc.py). [bytes]
_READER_MMAP_BYTES = 1 << 30


def make_engine(url: str, *, readonly: bool = False) -> Engine:
    """Make an engine for ``url``: a writer's (BEGIN IMMEDIATE on SQLite) or a reader's.

    Parameters
    ----------
    url : str
        ``sqlite:///FILE`` or ``postgresql+psycopg://...``.
    readonly : bool
        A reader: SQLite opens the file read-only (``mode=ro``, never created, never
        locked for writing), PostgreSQL runs read-only transactions.

    Returns
    -------
    Engine
    """
    if url.startswith("sqlite"):
        path = sqlite_path(url)
        target: str | URL = url
        if readonly and path is not None:
            target = URL.create(
                "sqlite",
                database=f"file:{quote(str(Path(path)))}",
                query={"mode": "ro", "uri": "true"},
            )
        engine = create_engine(target, connect_args={"timeout": 30.0})
        begin = "BEGIN" if readonly else "BEGIN IMMEDIATE"

        @event.listens_for(engine, "connect")
        def _connect(dbapi_conn: Any, _record: Any) -> None:
            dbapi_conn.isolation_level = None  # transactions are begun below
            dbapi_conn.execute("PRAGMA foreign_keys = ON")
            if readonly:  # a reader maps the file: a lot's curves are read without copies
                dbapi_conn.execute(f"PRAGMA mmap_size = {_READER_MMAP_BYTES}")

        @event.listens_for(engine, "begin")
        def _begin(conn: Any) -> None:
            conn.exec_driver_sql(begin)

        return _shared_cache(engine, url, readonly)
    if url.startswith("postgresql"):
        args: dict[str, Any] = {"connect_timeout": 10}
        if readonly:
            args["options"] = "-c default_transaction_read_only=on"
        return _shared_cache(create_engine(url, connect_args=args), url, readonly)
    raise RecordError(
        f"--store={url.split('://')[0]}://...: allowed a SQLite file, sqlite:///FILE.db or"
        " postgresql+psycopg://user@host:port/database"
    )
