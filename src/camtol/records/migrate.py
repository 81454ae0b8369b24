"""What a store is, and bringing it to this camtol's schema (Alembic, applied on open).

:func:`open_schema` is the first thing every store opening does. It names what it finds
and refuses, leaving the database untouched, what is not a camtol store (tables but no
``schema_version``), a damaged one (the version table empty, with several rows or a value
that is not a version, a version-1 table missing) or a newer one. A reader stops there: it
never creates or changes a table. A writer, inside one locked transaction (SQLite
``BEGIN IMMEDIATE``; a PostgreSQL advisory lock), creates the tables of an empty database
or upgrades an older store with the Alembic revisions of :mod:`camtol.records.migrations`:
everything or nothing. A store made before the migrations (schema version 1, no
``alembic_version`` table) is first stamped with revision ``0001``, whose tables it holds.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from sqlalchemy import Connection, Engine, inspect, text

from camtol.exceptions import RecordError
from camtol.records.record import SCHEMA_VERSION

__all__ = ["StoreState", "open_schema"]

#: The Alembic revision of each schema version.
REVISIONS = {1: "0001", 2: "0002", 3: "0003"}

#: Tables every camtol store holds (those of version 1).
V1_TABLES = frozenset({"schema_version", "designs", "inspections", "curves"})

MIGRATIONS = Path(__file__).resolve().parent / "migrations"

_ADVISORY_LOCK = 7318120


class StoreState:
    """What :func:`open_schema` found: the schema version, None for an empty database.

    Parameters
    ----------
    version : int or None
        The store's schema version after opening (None: an empty database, read-only).
    """

    def __init__(self, version: int | None) -> None:
        self.version = version


def open_schema(engine: Engine, where: str, *, write: bool, create: bool) -> StoreState:
    """Identify the store; for a writer, create or upgrade its tables (one transaction).

    Parameters
    ----------
    engine : Engine
        The store's engine (a writer's or a reader's, :func:`camtol.records.schema.make_engine`).
    where : str
        The store as the user gave it (password hidden), for messages.
    write : bool
        A writer: create the tables of an empty database, upgrade an older store.
    create : bool
        Accept an empty database (a writer creates the tables; a reader finds nothing).

    Returns
    -------
    StoreState
        The schema version now (:data:`SCHEMA_VERSION` after a writer's open).

    Raises
    ------
    RecordError
        Not a camtol store, a damaged one, a newer one, or an empty database where
        records are expected (``create`` False); the database is left untouched.
    """
    if not write:
        with engine.connect() as conn:
            version = _identify(conn, where)
            conn.rollback()
        if version is None and not create:
            raise RecordError(f"--store={where!r} holds no inspection records")
        return StoreState(version)
    with engine.begin() as conn:
        if engine.dialect.name == "postgresql":
            conn.execute(text(f"SELECT pg_advisory_xact_lock({_ADVISORY_LOCK})"))
        names = _table_names(conn)
        version = _identify(conn, where, names)
        if version is None and not create:
            raise RecordError(f"--store={where!r} holds no inspection records")
        if version != SCHEMA_VERSION or not _at_head(conn, names):
            _upgrade(conn, version, where, names)
    return StoreState(SCHEMA_VERSION)


def _table_names(conn: Connection) -> set[str]:
    """Return the tables of the database (of its default schema on PostgreSQL)."""
    return set(inspect(conn).get_table_names())


def _identify(conn: Connection, where: str, names: set[str] | None = None) -> int | None:
    """Return the schema version of the database, None when it holds no table at all."""
    names = _table_names(conn) if names is None else names
    if not names:
        return None
    if "schema_version" not in names:
        shown = ", ".join(sorted(names)[:5]) + (", ..." if len(names) > 5 else "")
        raise RecordError(
            f"--store={where!r} is not a camtol inspection store: it holds other tables"
            f" ({shown}) and no schema_version table; it was left untouched (give a new"
            " file or an empty database)"
        )
    rows = conn.execute(text("SELECT version FROM schema_version")).all()
    if not rows:
        raise RecordError(
            f"--store={where!r}: its schema_version table is empty (one row, the schema"
            " version, is expected): a damaged store, left untouched"
        )
    if len(rows) > 1:
        raise RecordError(
            f"--store={where!r}: its schema_version table holds {len(rows)} rows (one, the"
            " schema version, is expected): a damaged store, left untouched"
        )
    version: Any = rows[0][0]
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise RecordError(
            f"--store={where!r}: its schema_version table holds {version!r}, not a schema"
            " version (a whole number from 1): a damaged store, left untouched"
        )
    if version > SCHEMA_VERSION:
        raise RecordError(
            f"--store={where!r} has schema version {version}, newer than this camtol reads"
            f" ({SCHEMA_VERSION}); upgrade camtol"
        )
    missing = sorted(V1_TABLES - names)
    if missing:
        raise RecordError(
            f"--store={where!r}: schema version {version} but its table(s)"
            f" {', '.join(missing)} are missing: a damaged store, left untouched"
        )
    return int(version)


def _at_head(conn: Connection, names: set[str]) -> bool:
    """Whether Alembic's version table says the head revision."""
    if "alembic_version" not in names:
        return False
    rows = conn.execute(text("SELECT version_num FROM alembic_version")).all()
    return [r[0] for r in rows] == [REVISIONS[SCHEMA_VERSION]]


def _upgrade(conn: Connection, version: int | None, where: str, names: set[str]) -> None:
    """Run the Alembic revisions up to the head on this connection (its transaction)."""
    from alembic import command
    from alembic.config import Config
    from alembic.migration import MigrationContext
    from alembic.script import ScriptDirectory
    from alembic.util import CommandError

    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("path_separator", "os")
    cfg.attributes["connection"] = conn
    if version is not None and "alembic_version" not in names:
        # made before the migrations: it holds the tables of its version's revision
        MigrationContext.configure(conn).stamp(ScriptDirectory.from_config(cfg), REVISIONS[version])
    try:
        command.upgrade(cfg, "head")
    except CommandError as exc:  # a revision this camtol does not know: a newer store
        raise RecordError(
            f"--store={where!r}: its migration history is not this camtol's ({exc}); upgrade camtol"
        ) from None
