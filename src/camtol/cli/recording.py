"""``--store``: how ``camtol inspect`` and ``camtol conjugate`` record what they inspected.

The ``--store`` and traceability options (:func:`store_options`), their check before any
work (:func:`check_store_options`: the store is opened read-only, never created, its kind
and schema checked), the record(s) of a run with its raw inputs and options
(:func:`cmm_prepared`, :func:`fixture_prepared`: built and checked before any output file,
a duplicate refused there), and the one transaction that stores them last
(:func:`add_records`). Documented in docs/records.md.

Why one module: every part is the part's identity on its way into the store: the
options that state it (the ``[traceability]`` names and their old aliases), the checks
of its text and date, and the records built from it and written with it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from camtol.cli.common import fail

if TYPE_CHECKING:
    from camtol.design.cam_design import CamDesign
    from camtol.inspection.cmm_run import CmmInputs, CmmRun
    from camtol.pair.fixture_run import FixtureInputs, FixtureRun
    from camtol.records.raw import RawInput
    from camtol.records.record import InspectionRecord, Traceability
    from camtol.records.store import InspectionStore

__all__ = [
    "STORE_HELP",
    "Prepared",
    "add_records",
    "check_store_options",
    "check_trace_text",
    "report_traceability",
    "cmm_prepared",
    "fixture_prepared",
    "open_for_reading",
    "store_options",
]

F = TypeVar("F", bound=Callable[..., Any])

STORE_HELP = (
    "Inspection store: a SQLite file (FILE.db), sqlite:///FILE.db or postgresql+psycopg://..."
)


def open_for_reading(location: str) -> InspectionStore:
    """Open a store read-only (a SQLite file must exist; nothing is created or locked).

    Parameters
    ----------
    location : str
        ``--store``.

    Returns
    -------
    InspectionStore
    """
    from camtol.records.store import open_store

    path = location.removeprefix("sqlite:///") if location.startswith("sqlite:///") else location
    if "://" not in path and path != ":memory:" and not Path(path).is_file():
        what = "a directory, not a store file" if Path(path).is_dir() else "no such file"
        fail(f"--store={location!r}: {what} (records are created by --store on an inspection)")
    return open_store(location, create=False, readonly=True)


def store_options(f: F) -> F:
    """Add --store, the traceability options and --allow-duplicate to an inspection command.

    Parameters
    ----------
    f : callable
        The click command function; it receives the options as ``store_store``,
        ``store_part``, ``store_drawing_number``, ``store_revision``, ``store_serial``,
        ``store_lot``, ``store_inspector``, ``store_instrument``, ``store_inspected_at`` and
        ``store_allow_duplicate`` (and the hidden old names ``store_old_part``,
        ``store_old_inspected_at``, merged by :func:`check_store_options`).

    The names are those of the ``[traceability]`` table and ``camtol report``
    (``--part-number``, ``--date``; issue 31); ``--part`` and ``--inspected-at`` are
    hidden aliases that warn. The part's identity applies with or without ``--store``
    (printed in ``--report`` and ``--json``).

    Returns
    -------
    callable
        ``f`` with the options.
    """
    f = click.option(
        "--allow-duplicate",
        "store_allow_duplicate",
        is_flag=True,
        help="Store the record although the same raw data is already recorded for this"
        " serial and cam (with --store).",
    )(f)
    for name, dest, text in reversed(
        [
            ("--store", "store_store", STORE_HELP + " Records each inspected cam there."),
            ("--part-number", "store_part", "Part number of the inspected part."),
            ("--drawing-number", "store_drawing_number", "Drawing number of the part."),
            ("--revision", "store_revision", "Drawing revision."),
            ("--serial", "store_serial", "Serial number of the part."),
            ("--lot", "store_lot", "Production lot of the part."),
            ("--inspector", "store_inspector", "Who inspected it."),
            ("--instrument", "store_instrument", "Instrument used."),
            ("--date", "store_inspected_at", "When, ISO 8601 with a time zone (default now)."),
        ]
    ):
        f = click.option(name, dest, metavar="TEXT" if name != "--store" else "DB", help=text)(f)
    for old, dest in (("--part", "store_old_part"), ("--inspected-at", "store_old_inspected_at")):
        f = click.option(old, dest, metavar="TEXT", hidden=True)(f)
    return f


#: Old option names kept as hidden aliases: (dest, old flag, new flag, new dest).
_ALIASES = (
    ("store_old_part", "--part", "--part-number", "store_part"),
    ("store_old_inspected_at", "--inspected-at", "--date", "store_inspected_at"),
)
#: Options that only mean something with --store.
_STORE_ONLY = ("store_allow_duplicate",)


def _merge_aliases(opts: dict[str, Any]) -> None:
    """Move a hidden old option's value to its new name, with a warning (in place)."""
    for dest, old, new, target in _ALIASES:
        value = opts.pop(dest, None)
        if value is None:
            continue
        if opts.get(target) is not None:
            fail(f"{old} is the old name of {new}: give {new} once")
        click.echo(f"camtol: warning: {old} is renamed {new}; {old} will be removed", err=True)
        opts[target] = value


def _check_text(opts: dict[str, Any]) -> None:
    """Refuse traceability text that is too long or holds control characters."""
    for key, value in opts.items():
        if key in ("store_store", "store_inspected_at", "store_allow_duplicate"):
            continue
        if not isinstance(value, str):
            continue
        bad = [c for c in value if ord(c) < 32 or 127 <= ord(c) < 160]
        if len(value) > 200 or bad:
            flag = _flag(key)
            what = f"{len(value)} characters" + (
                f", with control character U+{ord(bad[0]):04X}" if bad else ""
            )
            fail(
                f"{flag}={value[:20]!r}... ({what}): allowed text of at most 200 characters"
                " without control characters"
            )


def check_trace_text(values: dict[str, str | None]) -> None:
    """Refuse traceability text (flag → value) that is too long or holds control characters.

    Parameters
    ----------
    values : dict
        Option name (``--part-number``) → its value (None: not given).
    """
    for flag, value in values.items():
        if value is None:
            continue
        bad = [c for c in value if ord(c) < 32 or 127 <= ord(c) < 160]
        if len(value) > 200 or bad:
            what = f"{len(value)} characters" + (
                f", with control character U+{ord(bad[0]):04X}" if bad else ""
            )
            fail(
                f"{flag}={value[:20]!r}... ({what}): allowed text of at most 200 characters"
                " without control characters"
            )


def _flag(key: str) -> str:
    names = {"store_part": "--part-number", "store_inspected_at": "--date"}
    return names.get(key) or "--" + key.removeprefix("store_").replace("_", "-")


def report_traceability(opts: dict[str, Any]) -> dict[str, str]:
    """Return the part's identity for a report (keys of the ``[traceability]`` table).

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options` (checked by :func:`check_store_options`).

    Returns
    -------
    dict of str to str
        ``part_number``, ``drawing_number``, ``revision``, ``serial``, ``lot``,
        ``inspector``, ``instrument``, ``date`` (those given; ``date`` as given, ISO 8601).
    """
    keys = {
        "store_part": "part_number",
        "store_drawing_number": "drawing_number",
        "store_revision": "revision",
        "store_serial": "serial",
        "store_lot": "lot",
        "store_inspector": "inspector",
        "store_instrument": "instrument",
        "store_inspected_at": "date",
    }
    return {keys[k]: str(v) for k, v in opts.items() if k in keys and v is not None}


def traceability(opts: dict[str, Any]) -> Traceability:
    """Return the part's traceability from the options (the date checked; default now).

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options`.

    Returns
    -------
    Traceability
    """
    from camtol.records.record import Traceability

    when = opts.get("store_inspected_at")
    at = datetime.now(timezone.utc)
    if when is not None:
        try:
            at = datetime.fromisoformat(when.replace("Z", "+00:00"))
        except ValueError:
            fail(f"--date={when!r}: allowed ISO 8601, e.g. 2026-11-23T12:00:00+00:00")
        if at.tzinfo is None:
            fail(f"--date={when!r}: give a time zone, e.g. 2026-11-23T12:00:00+00:00")
    return Traceability(
        part_number=opts.get("store_part") or "",
        serial=opts.get("store_serial") or "",
        lot=opts.get("store_lot") or "",
        inspector=opts.get("store_inspector") or "",
        instrument=opts.get("store_instrument") or "",
        inspected_at=at,
    )


def check_store_options(opts: dict[str, Any]) -> str | None:
    """Check --store and the traceability options before any work; the store or None.

    An existing store is opened read-only (its kind and schema version checked: not a
    camtol store, a damaged or a newer one stop the command before the analysis); a new
    SQLite file is not created here (only by the record's transaction at the end, so a
    refused command leaves no file), but its directory must exist and be writable. The
    traceability texts (at most 200 characters, no NUL) and the date are checked too.

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options` (``store_store``, ``store_part``, ...).

    Returns
    -------
    str or None
        The store's location, None without ``--store``.
    """
    _merge_aliases(opts)
    _check_text(opts)  # the store's rule for text fields, before any work
    traceability(opts)  # validate the date before the analysis
    location = opts.get("store_store")
    if location is None:
        given = [k for k in _STORE_ONLY if opts.get(k) not in (None, False)]
        if given:
            fail(f"{_flag(given[0])} applies to a stored record: give --store DB as well")
        return None
    from camtol.records.schema import sqlite_path
    from camtol.records.store import open_store, store_url

    url = store_url(str(location))
    path = sqlite_path(url) if url.startswith("sqlite") else None
    if path is not None and not Path(path).exists():
        parent = Path(path).parent
        if not parent.is_dir():
            fail(f"--store={url!r}: directory {str(parent)!r} does not exist")
        if not os.access(parent, os.W_OK | os.X_OK):
            fail(f"--store={url!r}: directory {str(parent)!r} is not writable")
        return str(location)
    open_store(str(location), create=True, readonly=True).close()
    return str(location)


def _design_text(design_path: str | None, example: str | None) -> str:
    """Return the TOML text the command read: the built-in example's or the design file's."""
    if example is not None:
        from camtol.config.examples import example_text

        return example_text(example)
    return Path(str(design_path)).read_text(encoding="utf-8")


@dataclass(frozen=True)
class Prepared:
    """Records of one run, built and checked, waiting to be stored after the outputs.

    Attributes
    ----------
    records : tuple of InspectionRecord
        The record(s): one per inspected cam.
    design_text : str
        The design's TOML text.
    inputs : tuple of RawInput
        The raw inputs they were judged on.
    allow_duplicate : bool
        ``--allow-duplicate``.
    """

    records: tuple[InspectionRecord, ...]
    design_text: str
    inputs: tuple[RawInput, ...]
    allow_duplicate: bool


def _refuse_duplicates(location: str, prepared: Prepared) -> None:
    """Refuse a duplicate before any output (the insert refuses it again, race-free)."""
    if prepared.allow_duplicate:
        return
    from camtol.records.schema import sqlite_path
    from camtol.records.store import open_store, store_url
    from camtol.records.writes import duplicate_message

    url = store_url(location)
    path = sqlite_path(url) if url.startswith("sqlite") else None
    if path is not None and not Path(path).exists():
        return
    with open_store(location, create=True, readonly=True) as store:
        for rec in prepared.records:
            if rec.raw_sha256 is None:
                continue
            found = store.find_duplicate(rec.serial, rec.cam, rec.raw_sha256)
            if found is not None:
                fail(duplicate_message(rec, found))


def cmm_prepared(
    location: str,
    opts: dict[str, Any],
    design: CamDesign,
    design_path: str | None,
    example: str | None,
    inputs: CmmInputs,
    run: CmmRun,
    *,
    n_points: int,
    spec_um: float | None,
    spec_deg: float | None,
) -> Prepared:
    """Build (and check) the record of a CMM-inspected cam for ``camtol inspect --store``.

    Parameters
    ----------
    location : str
        The store (a duplicate already there is refused now, before any output).
    opts : dict
        The options of :func:`store_options`.
    design : CamDesign
        The design the scan was checked against.
    design_path, example : str or None
        Where the design came from (its TOML text is hashed and stored).
    inputs : CmmInputs
        The run's inputs (the scan file is kept as the raw input ``scan``).
    run : CmmRun
        The inspection.
    n_points : int
        Points of the record's curve (360 / --step).
    spec_um, spec_deg : float or None
        The motion spec as given. [µm, deg]

    Returns
    -------
    Prepared
        Not stored yet (see :func:`add_records`).
    """
    from camtol.records.capture import cmm_options, cmm_record, design_files
    from camtol.records.raw import RawInput

    text = _design_text(design_path, example)
    scan = RawInput.from_file("scan", inputs.points_path)
    base = None if design_path is None else Path(design_path).parent
    rec = cmm_record(
        design,
        run,
        n_points=n_points,
        traceability=traceability(opts),
        design_text=text,
        options=cmm_options(inputs, n_points=n_points, spec_um=spec_um, spec_deg=spec_deg),
        raw_sha256=scan.sha256,
    )
    prepared = Prepared(
        (rec,),
        text,
        (scan, *design_files(text, base)),
        bool(opts.get("store_allow_duplicate")),
    )
    _refuse_duplicates(location, prepared)
    return prepared


def fixture_prepared(
    location: str,
    opts: dict[str, Any],
    design: CamDesign,
    design_path: str | None,
    example: str | None,
    inputs: FixtureInputs,
    run: FixtureRun,
) -> Prepared:
    """Build (and check) the records of cams A and B of a fixture inspection.

    Parameters
    ----------
    location : str
        The store (a duplicate already there is refused now, before any output).
    opts : dict
        The options of :func:`store_options`.
    design : CamDesign
        The inspected design.
    design_path, example : str or None
        Where the design came from (its TOML text is hashed and stored).
    inputs : FixtureInputs
        The run's inputs (files and values kept as raw inputs).
    run : FixtureRun
        The fixture run, with a measurement.

    Returns
    -------
    Prepared
        Not stored yet (see :func:`add_records`).
    """
    from camtol.records.capture import (
        design_files,
        fixture_options,
        fixture_raw_inputs,
        fixture_records,
    )

    if run.inspection.estimate is None:
        fail(
            "--store records an inspection: give the measured Δf (--record, --df-mea or"
            " inspection.df_mea_um)"
        )
    text = _design_text(design_path, example)
    base = None if design_path is None else Path(design_path).parent
    table = run.spec.to_mapping()
    raws, primary = fixture_raw_inputs(inputs, table)
    named = design_files(text, base)
    if primary is None:  # the measured Δf is a CSV file the design names
        primary = next(
            (r for r in named if r.name == str(table.get("df_mea_um", "")).strip()), None
        )
    recs = fixture_records(
        design,
        run,
        traceability=traceability(opts),
        design_text=text,
        options=fixture_options(inputs),
        raw_sha256=None if primary is None else primary.sha256,
    )
    prepared = Prepared(tuple(recs), text, (*raws, *named), bool(opts.get("store_allow_duplicate")))
    _refuse_duplicates(location, prepared)
    return prepared


def add_records(location: str, prepared: Prepared) -> list[int]:
    """Store the records of :func:`cmm_prepared` or :func:`fixture_prepared` in one transaction.

    Parameters
    ----------
    location : str
        The store (path or URL): created, or upgraded to this camtol's schema, here.
    prepared : Prepared
        The records, design text and raw inputs.

    Returns
    -------
    list of int
        Their ids; on any error nothing is stored (:class:`~camtol.exceptions.RecordError`).
    """
    from camtol.records.store import open_store

    with open_store(location) as store:
        return store.add_all(
            prepared.records,
            design_text=prepared.design_text,
            inputs=prepared.inputs,
            allow_duplicate=prepared.allow_duplicate,
        )


def ids_text(ids: Sequence[int]) -> str:
    """``1, 2`` for messages."""
    return ", ".join(str(i) for i in ids)
