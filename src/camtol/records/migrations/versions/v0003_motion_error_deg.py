"""Schema version 3: the follower error of a swing in degrees (issue 31).

Version 2 kept an oscillating follower's max |ΔS| in µrad under ``max_abs_ds_um`` with
``motion_unit = 'urad'``: one quantity, a unit its name did not carry. Version 3 adds
``max_abs_ds_deg`` beside it: a swing's figure moves there, converted to degrees
(µrad · 180 / (π · 10⁶)), ``max_abs_ds_um`` is set NULL for it and its ``motion_unit``
becomes ``'deg'``. A lift's ``max_abs_ds_um`` (µm) is kept as it was.

Revision ID: 0003
Revises: 0002
Create Date: 2026-11-27
"""

from __future__ import annotations

import math

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None

#: µrad → deg.
_URAD_TO_DEG = 180.0 / (math.pi * 1e6)


def upgrade() -> None:
    """Add ``max_abs_ds_deg``, move a swing's µrad figure there in degrees; version 3."""
    op.add_column("inspections", sa.Column("max_abs_ds_deg", sa.Double, nullable=True))
    op.execute(
        sa.text(
            "UPDATE inspections SET max_abs_ds_deg = max_abs_ds_um * :k,"
            " max_abs_ds_um = NULL, motion_unit = 'deg' WHERE motion_unit = 'urad'"
        ).bindparams(k=_URAD_TO_DEG)
    )
    op.execute("UPDATE schema_version SET version = 3")


def downgrade() -> None:
    """Refuse: a store is never downgraded."""
    raise NotImplementedError("camtol never downgrades an inspection store")
