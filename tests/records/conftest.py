"""Stores for the record tests: a SQLite file always, PostgreSQL when a server is given.

PostgreSQL runs for real: ``.ci/run`` starts a throw-away server (``.ci/postgres-start``)
and exports ``CAMTOL_TEST_POSTGRES_URL``; each test gets a database of its own, dropped
afterwards. Without that variable the PostgreSQL cases are skipped, saying why.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from pathlib import Path

import pytest

PG_ENV = "CAMTOL_TEST_POSTGRES_URL"


@pytest.fixture(params=["sqlite", "postgres"])
def store_url(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    """A fresh, empty store location on each backend."""
    if request.param == "sqlite":
        yield str(tmp_path / "records.db")
        return
    base = os.environ.get(PG_ENV)
    if not base:
        pytest.skip(f"PostgreSQL store tests need {PG_ENV} (set by .ci/run via .ci/postgres-start)")
    pytest.importorskip("psycopg", reason="PostgreSQL needs camtol[postgres] (psycopg 3)")
    from sqlalchemy import create_engine, text
    from sqlalchemy.engine import make_url

    name = f"camtol_test_{uuid.uuid4().hex[:12]}"
    admin = create_engine(base, isolation_level="AUTOCOMMIT")
    with admin.connect() as conn:
        conn.execute(text(f'CREATE DATABASE "{name}"'))
    try:
        yield make_url(base).set(database=name).render_as_string(hide_password=False)
    finally:
        with admin.connect() as conn:
            conn.execute(text(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)'))
        admin.dispose()
