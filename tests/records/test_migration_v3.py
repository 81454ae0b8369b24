"""Schema version 3 (issue 31): a swing's follower error in degrees, in its own column.

A version-2 store kept an oscillating follower's max |ΔS| in µrad under
``max_abs_ds_um`` (``motion_unit = 'urad'``). A reader converts it as it reads a
version-2 store (without changing it); a writer's migration moves it to
``max_abs_ds_deg`` in degrees; a lift's µm figure is left where it was. On SQLite and,
with CAMTOL_TEST_POSTGRES_URL, on PostgreSQL.
"""

from __future__ import annotations

import math

import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")
pytest.importorskip("alembic", reason="the store's migrations need camtol[store] (Alembic)")

from camtol.records.migrate import MIGRATIONS, REVISIONS
from camtol.records.record import SCHEMA_VERSION
from camtol.records.store import open_store

#: The figure of the issue: 0.00727° stored as 126.888523005797 µrad.
URAD = 126.888523005797


def _version_2_store(url: str) -> None:
    """A store at revision 0002 with a swing's (µrad) and a lift's (µm) CMM record."""
    from alembic import command
    from alembic.config import Config
    from sqlalchemy import create_engine, text

    from camtol.records.store import store_url as to_url

    engine = create_engine(to_url(url))
    cfg = Config()
    cfg.set_main_option("script_location", str(MIGRATIONS))
    cfg.set_main_option("path_separator", "os")
    with engine.begin() as conn:
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, REVISIONS[2])
        conn.execute(text("INSERT INTO designs VALUES ('sha256:" + "0" * 64 + "', 'd', NULL)"))
        for serial, ds, unit in (("swing", URAD, "urad"), ("lift", 12.5, "um")):
            conn.execute(
                text(
                    "INSERT INTO inspections (design_name, design_hash, method, cam,"
                    " part_number, serial, lot, inspector, instrument, inspected_at, verdict,"
                    " max_dev_um, min_dev_um, form_um, max_abs_ds_um, tolerance_lower_um,"
                    " tolerance_upper_um, camtol_version, motion_unit) VALUES ('d', 'sha256:"
                    + "0"
                    * 64
                    + "', 'cmm', '', '', :serial, '', '', '', '2026-01-01 00:00:00', 'pass',"
                    " 1.5, -1.0, 2.5, :ds, -5, 5, '0.1.0', :unit)"
                ),
                {"serial": serial, "ds": ds, "unit": unit},
            )
    engine.dispose()


def test_version_2_urad_becomes_degrees(store_url: str) -> None:
    _version_2_store(store_url)
    deg = math.degrees(URAD * 1e-6)
    assert deg == pytest.approx(0.00727, abs=5e-6)  # the terminal figure
    with open_store(store_url, create=False, readonly=True) as s:  # read as it is
        assert s.version == 2
        swing, lift = sorted(s.records(), key=lambda r: r.serial != "swing")
    assert swing.max_abs_ds_deg == pytest.approx(deg, rel=1e-12) and swing.max_abs_ds_um is None
    assert swing.motion_unit == "deg" and lift.max_abs_ds_um == 12.5 and lift.motion_unit == "um"
    with open_store(store_url) as s:  # a writer migrates
        assert s.version == SCHEMA_VERSION == 3
        swing, lift = sorted(s.records(), key=lambda r: r.serial != "swing")
    assert swing.max_abs_ds_deg == pytest.approx(deg, rel=1e-12) and swing.max_abs_ds_um is None
    assert swing.motion_unit == "deg"
    assert lift.max_abs_ds_um == 12.5 and lift.max_abs_ds_deg is None
    summary = swing.summary()
    assert summary["max_abs_ds_deg"] == pytest.approx(deg) and summary["max_abs_ds_um"] is None


def test_the_record_schema_names_the_unit_it_holds() -> None:
    # Every figure column of the store carries its unit, and the follower error has one
    # column per unit: a µrad figure under a _um name cannot come back.
    from camtol.records.record import MOTION_UNITS
    from camtol.records.schema import inspections

    figures = [c.name for c in inspections.c if str(c.type).upper().startswith(("DOUBLE", "FLOAT"))]
    assert figures and all(n.endswith(("_um", "_deg")) for n in figures), figures
    assert {"max_abs_ds_um", "max_abs_ds_deg"} <= set(figures)
    assert {f"max_abs_ds_{u}" for u in MOTION_UNITS} <= set(figures)
    from camtol.exceptions import RecordError
    from camtol.records.record import Traceability, make_record

    with pytest.raises(RecordError, match="max_abs_ds_deg needs motion_unit='deg'"):
        make_record(
            design_name="d",
            design_hash="sha256:" + "0" * 64,
            method="cmm",
            cam="",
            dr_um=[0.0, 1.0],
            verdict="pass",
            tolerance_um=(-1.0, 1.0),
            traceability=Traceability(),
            max_abs_ds_deg=0.01,
            motion_unit="um",
        )
