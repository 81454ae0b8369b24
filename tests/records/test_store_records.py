"""The inspection store on SQLite and PostgreSQL: round trip, atomicity, schema version."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
import textwrap
from datetime import datetime, timedelta, timezone
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import camtol
from camtol.config.design_file import load_example
from camtol.config.examples import example_text
from camtol.exceptions import RecordError
from camtol.records.store import (
    InspectionRecord,
    Traceability,
    design_identity,
    make_record,
    open_store,
    record_inspection,
)

DESIGN = "cw11-conjugate"
HASH = "sha256:" + "ab" * 32
FIELDS = [f.name for f in dataclasses.fields(InspectionRecord) if f.name not in ("id", "dr_um")]


def _record(dr_um: Any, **kw: Any) -> InspectionRecord:
    args: dict[str, Any] = dict(
        design_name=DESIGN,
        design_hash=HASH,
        method="conjugate-fixture",
        cam="A",
        dr_um=dr_um,
        verdict="pass",
        tolerance_um=(-22.0, 22.0),
        traceability=Traceability(serial="1", lot="L1"),
    )
    args.update(kw)
    return make_record(**args)


def assert_same(a: InspectionRecord, b: InspectionRecord) -> None:
    for name in FIELDS:
        assert getattr(a, name) == getattr(b, name), name
    assert a.dr_um.dtype == b.dr_um.dtype == np.float32
    assert a.dr_um.tobytes() == b.dr_um.tobytes()  # bit-identical curve


text_field = st.text(
    alphabet=st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"),
    max_size=40,
)
times = st.datetimes(
    min_value=datetime(1990, 1, 1),
    max_value=datetime(2100, 1, 1),
    timezones=st.sampled_from([timezone.utc, timezone(timedelta(hours=-5, minutes=-30))]),
)
curves = arrays(
    np.float64,
    st.integers(1, 4000),
    elements=st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False),
)


@settings(max_examples=25, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    dr=curves,
    trace=st.builds(
        Traceability,
        part_number=text_field,
        serial=text_field,
        lot=text_field,
        inspector=text_field,
        instrument=text_field,
        inspected_at=times,
    ),
    method=st.sampled_from(["conjugate-fixture", "cmm"]),
    cam=st.sampled_from(["A", "B", ""]),
    verdict=st.sampled_from(["pass", "fail"]),
    ds=st.none() | st.floats(0, 1e3),
    tol=st.tuples(st.floats(-100, -0.001), st.floats(0.001, 100)),
)
def test_round_trip_store_read_gives_identical_records(
    store_url: str,
    dr: np.ndarray,
    trace: Traceability,
    method: str,
    cam: str,
    verdict: str,
    ds: float | None,
    tol: tuple[float, float],
) -> None:
    rec = _record(
        dr,
        method=method,
        cam=cam,
        verdict=verdict,
        traceability=trace,
        max_abs_ds_um=ds,
        tolerance_um=tol,
    )
    with open_store(store_url) as s:
        new_id = s.add(rec)
        back = s.get(new_id)
    assert back.id == new_id
    assert_same(rec, back)
    assert back.inspected_at.utcoffset() == timedelta(0)
    # the summary figures describe the stored (float32) curve exactly
    assert back.max_dev_um == float(back.dr_um.max())
    assert back.form_um == float(back.dr_um.max()) - float(back.dr_um.min())


def test_records_read_from_the_store_are_whole_frozen_records(store_url: str) -> None:
    # The readers build records with InspectionRecord.from_store (no per-field setattr):
    # every field is there, the record stays frozen, and a missing field is refused.
    with open_store(store_url) as s:
        s.add(_record(np.linspace(-3.0, 4.0, 36)))
        (back,) = s.records(with_curves=True, with_details=True)
    assert {f.name for f in dataclasses.fields(back)} <= set(vars(back))
    with pytest.raises(dataclasses.FrozenInstanceError):
        back.verdict = "pass"  # type: ignore[misc]
    assert not back.dr_um.flags.writeable  # the stored curve cannot be changed in place
    fields = dict(vars(back))
    del fields["lot"]
    with pytest.raises(TypeError, match="from_store needs exactly the fields"):
        type(back).from_store(**fields)


def test_record_inspection_keeps_the_design_and_filters(store_url: str) -> None:
    design = load_example(DESIGN)
    text = example_text(DESIGN)
    theta = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    ids = [
        record_inspection(
            store_url,
            design,
            method="conjugate-fixture",
            cam=cam,
            dr_um=5 * np.sin(theta) + k,
            verdict="pass",
            tolerance_um=(-22, 22),
            traceability=Traceability(serial=str(k), lot=lot),
            design_text=text,
        )
        for k, (cam, lot) in enumerate([("A", "L1"), ("B", "L1"), ("A", "L2")])
    ]
    with open_store(store_url) as s:
        assert [r.id for r in s.records()] == ids
        assert [r.id for r in s.records(lot="L1", cam="A")] == ids[:1]
        assert s.records(design="other") == []
        assert s.records()[0].dr_um.size == 0  # summaries only without with_curves
        rec = s.get(ids[2])
        np.testing.assert_allclose(rec.dr_um, 5 * np.sin(theta) + 2, atol=1e-5)
        assert rec.design_hash == design_identity(design, text)[1]
        assert s.design_text(rec.design_hash) == text  # the exact design is retrievable
        assert rec.camtol_version == camtol.__version__
    with pytest.raises(RecordError, match="record id 999: no such record"):
        with open_store(store_url) as s:
            s.get(999)


def _count(url: str) -> dict[str, int]:
    from sqlalchemy import create_engine, text

    from camtol.records.store import store_url as to_url

    engine = create_engine(to_url(url))
    with engine.connect() as conn:
        out = {
            t: int(conn.execute(text(f"SELECT count(*) FROM {t}")).scalar_one())
            for t in ("designs", "inspections", "curves")
        }
    engine.dispose()
    return out


def test_failure_mid_insert_leaves_nothing(store_url: str) -> None:
    """A database error after the record row, before its curve: the transaction rolls back."""
    from sqlalchemy import event

    recs = [_record(np.arange(10.0)), _record(np.arange(20.0), cam="B")]
    with open_store(store_url) as s:
        calls = {"curves": 0}

        @event.listens_for(s._engine, "before_cursor_execute")
        def boom(conn: Any, cursor: Any, statement: str, *args: Any) -> None:
            if statement.startswith("INSERT INTO curves"):
                calls["curves"] += 1
                if calls["curves"] == 2:  # the second cam's curve, after 5 inserts
                    raise RuntimeError("disk full (simulated)")

        with pytest.raises(RecordError, match="nothing was stored.*disk full"):
            s.add_all(recs)
        event.remove(s._engine, "before_cursor_execute", boom)
        assert calls["curves"] == 2
        assert s.records() == []
    assert _count(store_url) == {"designs": 0, "inspections": 0, "curves": 0}
    with open_store(store_url) as s:  # the store still works afterwards
        assert s.add_all(recs) == [1, 2] or len(s.records()) == 2
    assert _count(store_url) == {"designs": 1, "inspections": 2, "curves": 2}


def test_newer_schema_is_refused(store_url: str) -> None:
    from sqlalchemy import create_engine, text

    from camtol.records.store import SCHEMA_VERSION
    from camtol.records.store import store_url as to_url

    open_store(store_url).close()
    engine = create_engine(to_url(store_url))
    with engine.begin() as conn:
        conn.execute(text("UPDATE schema_version SET version = :v"), {"v": SCHEMA_VERSION + 1})
    engine.dispose()
    with pytest.raises(RecordError, match=f"schema version {SCHEMA_VERSION + 1}, newer than"):
        open_store(store_url)


def test_unreachable_database_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(RecordError, match="cannot open the store.*OperationalError"):
        open_store("postgresql+psycopg://camtol:secret@127.0.0.1:1/none")
    try:
        open_store("postgresql+psycopg://camtol:secret@127.0.0.1:1/none")
    except RecordError as exc:
        assert "secret" not in str(exc)  # the password is not printed
    with pytest.raises(RecordError, match="does not exist"):
        open_store(str(tmp_path / "missing" / "r.db"))
    with pytest.raises(RecordError, match="allowed a SQLite file"):
        open_store("mysql://x@y/z")


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"method": "ruler"}, "method='ruler': allowed"),
        ({"cam": "C"}, "cam='C': allowed"),
        ({"verdict": "ok"}, "verdict='ok': allowed"),
        ({"design_hash": "md5:1"}, "design_hash='md5:1'"),
        ({"dr_um": np.array([1.0, np.nan])}, "dr_um: allowed a 1-D array of finite"),
        ({"tolerance_um": (5.0, -5.0)}, r"tolerance_um=\(5.0, -5.0\)"),
        ({"traceability": Traceability(serial="x\x00")}, "serial='x\\\\x00'"),
        (
            {"traceability": Traceability(inspected_at=datetime(2026, 1, 1))},
            "inspected_at='2026-01-01T00:00:00': give a time zone",
        ),
    ],
)
def test_bad_record_fields_are_named(kw: dict[str, Any], match: str) -> None:
    args: dict[str, Any] = {"dr_um": np.zeros(4)}
    args.update(kw)
    with pytest.raises(RecordError, match=match):
        _record(**args)


def test_design_identity_is_the_designs_content_hash() -> None:
    design = load_example(DESIGN)
    name, h = design_identity(design, None)
    assert (name, h) == (DESIGN, "sha256:" + design.content_hash)
    # the file's spelling does not matter: the hash is of the design's content
    assert design_identity(design, example_text(DESIGN) + "# a comment\n") == (name, h)


def test_design_identity_falls_back_to_the_toml_text() -> None:
    class Plain:  # a design object without content_hash
        name = "x"

    text = example_text(DESIGN)
    name, h = design_identity(Plain(), text)  # type: ignore[arg-type]
    assert name == "x" and h.startswith("sha256:") and len(h) == 71
    assert design_identity(Plain(), text.replace("\n", "\r\n") + "\n\n")[1] == h  # type: ignore[arg-type]
    assert design_identity(Plain(), text.replace("22", "23"))[1] != h  # type: ignore[arg-type]
    with pytest.raises(RecordError, match="TOML text is needed"):
        design_identity(Plain(), None)  # type: ignore[arg-type]


WRITER = textwrap.dedent(
    """
    import sys
    import numpy as np
    from camtol.records.store import Traceability, make_record, open_store
    url, tag = sys.argv[1], int(sys.argv[2])
    with open_store(url) as s:
        for k in range(40):
            rec = make_record(
                design_name="d", design_hash="sha256:" + "0" * 64, method="cmm", cam="",
                dr_um=np.full(500, 1000.0 * tag + k), verdict="pass", tolerance_um=(-1, 1),
                traceability=Traceability(serial=f"{tag}-{k}"),
            )
            s.add(rec)
    """
)


def test_concurrent_sqlite_writers_do_not_corrupt(tmp_path: Path) -> None:
    """Two processes write 40 records each into one SQLite file at the same time."""
    url = str(tmp_path / "shared.db")
    src = str(Path(camtol.__file__).resolve().parent.parent)
    env = {"PYTHONPATH": src}
    import os

    env = dict(os.environ, PYTHONPATH=src)
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", WRITER, url, str(tag)], env=env, stderr=subprocess.PIPE
        )
        for tag in (1, 2)
    ]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err.decode()
    with open_store(url) as s:
        recs = s.records(with_curves=True)
    assert len(recs) == 80
    assert len({r.id for r in recs}) == 80
    for r in recs:
        tag, k = (int(x) for x in r.serial.split("-"))
        assert np.all(r.dr_um == np.float32(1000.0 * tag + k))  # each curve with its row
    import sqlite3

    with sqlite3.connect(url) as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone() == ("ok",)
