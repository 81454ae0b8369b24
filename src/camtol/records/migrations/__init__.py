"""Alembic migrations of the inspection store (docs/records.md, "Schema and migrations").

``env.py`` is Alembic's environment, ``versions/`` holds one revision per schema version
(``0001``: the tables of camtol before issue 29; ``0002``: raw inputs, options, judged-on
basis, voids). :func:`camtol.records.migrate.open_schema` applies them when a writer
opens a store; readers never do. Forward only: a store is never downgraded.
"""

from __future__ import annotations
