"""Alembic's environment for the inspection store's migrations.

:func:`camtol.records.migrate.open_schema` runs Alembic's ``upgrade`` with the writer's
own connection (``config.attributes["connection"]``), inside its locked transaction, so a
store is created or upgraded all at once or not at all. From the ``alembic`` command line
(a maintainer writing a revision) the store is ``-x url=...`` or ``sqlalchemy.url``.
Imported anywhere else, this module does nothing.
"""

from __future__ import annotations

from alembic import context

__all__ = ["run_migrations"]


def run_migrations() -> None:
    """Run the pending revisions on the connection given, or on ``-x url=...``."""
    config = context.config
    connection = config.attributes.get("connection")
    if connection is not None:
        context.configure(connection=connection)
        with context.begin_transaction():
            context.run_migrations()
        return
    from sqlalchemy import create_engine

    url = context.get_x_argument(as_dictionary=True).get("url") or config.get_main_option(
        "sqlalchemy.url"
    )
    if not url:
        raise SystemExit("give the store: alembic -x url=sqlite:///records.db ...")
    engine = create_engine(url)
    with engine.begin() as conn:
        context.configure(connection=conn)
        context.run_migrations()
    engine.dispose()


if hasattr(context, "config"):  # run by Alembic: its proxy is installed
    run_migrations()
