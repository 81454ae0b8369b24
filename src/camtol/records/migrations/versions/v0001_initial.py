"""Schema version 1: the tables of camtol before issue 29.

Designs, inspections (traceability, verdict, summary figures, tolerance) and their curves.
A store made before the migrations existed holds exactly these tables and no
``alembic_version``: :func:`camtol.records.migrate.open_schema` stamps it with this
revision, then upgrades it.

Revision ID: 0001
Revises:
Create Date: 2026-11-27
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    """Create the version-1 tables and the version row."""
    version = op.create_table(
        "schema_version",
        sa.Column("version", sa.Integer, primary_key=True, autoincrement=False),
    )
    op.create_table(
        "designs",
        sa.Column("design_hash", sa.String(71), primary_key=True),
        sa.Column("name", sa.String(200), nullable=False),
        sa.Column("toml", sa.Text, nullable=True),
    )
    op.create_table(
        "inspections",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("design_name", sa.String(200), nullable=False),
        sa.Column(
            "design_hash", sa.String(71), sa.ForeignKey("designs.design_hash"), nullable=False
        ),
        sa.Column("method", sa.String(32), nullable=False),
        sa.Column("cam", sa.String(1), nullable=False),
        sa.Column("part_number", sa.String(200), nullable=False),
        sa.Column("serial", sa.String(200), nullable=False),
        sa.Column("lot", sa.String(200), nullable=False),
        sa.Column("inspector", sa.String(200), nullable=False),
        sa.Column("instrument", sa.String(200), nullable=False),
        sa.Column("inspected_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("verdict", sa.String(4), nullable=False),
        sa.Column("max_dev_um", sa.Double, nullable=False),
        sa.Column("min_dev_um", sa.Double, nullable=False),
        sa.Column("form_um", sa.Double, nullable=False),
        sa.Column("max_abs_ds_um", sa.Double, nullable=True),
        sa.Column("tolerance_lower_um", sa.Double, nullable=False),
        sa.Column("tolerance_upper_um", sa.Double, nullable=False),
        sa.Column("camtol_version", sa.String(64), nullable=False),
        sa.CheckConstraint("verdict IN ('pass', 'fail')", name="ck_verdict"),
        sa.CheckConstraint("method IN ('conjugate-fixture', 'cmm')", name="ck_method"),
        sa.CheckConstraint("cam IN ('A', 'B', '')", name="ck_cam"),
    )
    op.create_index("ix_inspections_design_lot", "inspections", ["design_name", "lot"])
    op.create_table(
        "curves",
        sa.Column(
            "inspection_id",
            sa.Integer,
            sa.ForeignKey("inspections.id", ondelete="CASCADE"),
            primary_key=True,
        ),
        sa.Column("name", sa.String(32), primary_key=True),
        sa.Column("n_points", sa.Integer, nullable=False),
        sa.Column("data", sa.LargeBinary, nullable=False),
    )
    op.bulk_insert(version, [{"version": 1}])


def downgrade() -> None:
    """Refuse: a store is never downgraded."""
    raise NotImplementedError("camtol never downgrades an inspection store")
