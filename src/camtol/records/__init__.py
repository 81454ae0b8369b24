"""The inspection store and the statistics of a production lot (an I/O edge).

Every inspection kept in SQLite or PostgreSQL (SQLAlchemy), and
the statistics of a production lot from its records (docs/records.md).

An I/O edge (docs/architecture.md): it needs ``camtol[store]``; nothing in the core
imports it.
"""

from __future__ import annotations
