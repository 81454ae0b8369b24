"""Schema version 2: re-runnable records, duplicates refused, voids (issue 29).

Adds to ``inspections`` what a verdict was judged on (``judged_on``, ``decision_rule``),
the unit of the motion figure, the SHA-256 of the raw data, every option and the
method's own results (JSON text), the ``--allow-duplicate`` mark and the void (when, by
whom, why); a partial unique index refuses the same raw data twice for a standing record
of one serial and cam; and the tables ``raw_inputs`` (zlib blobs by SHA-256) and
``inspection_inputs``. Records of version 1 keep everything they had: a fixture record
was always judged on Δr (set here), the rest of theirs is unknown (NULL).

Revision ID: 0002
Revises: 0001
Create Date: 2026-11-27
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None

_STANDING = "voided_at IS NULL AND NOT duplicate_allowed"


def upgrade() -> None:
    """Add the columns, tables and index of version 2; set the version row to 2."""
    for column in (
        sa.Column("judged_on", sa.String(2), nullable=True),
        sa.Column("decision_rule", sa.String(10), nullable=True),
        sa.Column("motion_unit", sa.String(4), nullable=True),
        sa.Column("raw_sha256", sa.String(71), nullable=True),
        sa.Column("options", sa.Text, nullable=True),
        sa.Column("results", sa.Text, nullable=True),
        sa.Column("duplicate_allowed", sa.Boolean, nullable=False, server_default=sa.text("false")),
        sa.Column("voided_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("voided_by", sa.String(200), nullable=False, server_default=""),
        sa.Column("void_reason", sa.String(500), nullable=False, server_default=""),
    ):
        op.add_column("inspections", column)
    op.create_index(
        "ux_inspections_raw",
        "inspections",
        ["serial", "cam", "raw_sha256"],
        unique=True,
        sqlite_where=sa.text(_STANDING),
        postgresql_where=sa.text(_STANDING),
    )
    op.create_table(
        "raw_inputs",
        sa.Column("sha256", sa.String(71), primary_key=True),
        sa.Column("size_bytes", sa.Integer, nullable=False),
        sa.Column("compression", sa.String(8), nullable=False),
        sa.Column("data", sa.LargeBinary, nullable=False),
    )
    op.create_table(
        "inspection_inputs",
        sa.Column(
            "inspection_id",
            sa.Integer,
            sa.ForeignKey("inspections.id", ondelete="CASCADE"),
            primary_key=True,
        ),
        sa.Column("role", sa.String(200), primary_key=True),
        sa.Column("name", sa.String(1000), nullable=False),
        sa.Column("sha256", sa.String(71), sa.ForeignKey("raw_inputs.sha256"), nullable=False),
    )
    op.execute("UPDATE inspections SET judged_on = 'dr' WHERE method = 'conjugate-fixture'")
    op.execute("UPDATE schema_version SET version = 2")


def downgrade() -> None:
    """Refuse: a store is never downgraded."""
    raise NotImplementedError("camtol never downgrades an inspection store")
