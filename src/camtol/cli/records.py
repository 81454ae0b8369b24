"""``camtol records``: list, show and lot statistics of stored inspection records.

Also the ``--store`` and traceability options that ``camtol conjugate`` (and later
``camtol inspect``) use to record each inspected cam. Registered lazily by
:mod:`camtol.cli.app`. Exit status 0, or 2 on bad input (unreachable store, unknown record,
a store written by a newer camtol, no matching records). Documented in docs/records.md.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from camtol.cli.common import EXIT_OK, _Exit, check_output_path, echo_json, fail, run_guarded

if TYPE_CHECKING:
    from camtol.records.store import InspectionRecord, InspectionStore

__all__ = [
    "check_store_options",
    "cmm_record_curve",
    "records",
    "add_records",
    "cmm_record",
    "fixture_records",
    "store_options",
]

F = TypeVar("F", bound=Callable[..., Any])

_STORE_HELP = (
    "Inspection store: a SQLite file (FILE.db), sqlite:///FILE.db or postgresql+psycopg://..."
)


def _open_existing(location: str) -> InspectionStore:
    """Open a store for reading: a SQLite file must exist."""
    from camtol.records.store import open_store

    path = location.removeprefix("sqlite:///") if location.startswith("sqlite:///") else location
    if "://" not in path and path != ":memory:" and not Path(path).is_file():
        what = "a directory, not a store file" if Path(path).is_dir() else "no such file"
        fail(f"--store={location!r}: {what} (records are created by --store on an inspection)")
    return open_store(location, create=False)


def _write_csv(path: str, header: Sequence[str], columns: Sequence[Any]) -> None:
    import numpy as np

    from camtol.files import atomic_write
    from camtol.report.csv_text import csv_text

    data = np.column_stack([np.asarray(c, dtype=np.float64) for c in columns])
    atomic_write(path, csv_text(header, data, blank_nonfinite=True))


def _cam_filter(cam: str | None) -> str | None:
    return None if cam is None else ("" if cam == "single" else cam)


_METHOD_OPTION = click.option(
    "--method",
    type=click.Choice(["cmm", "conjugate-fixture"]),
    help="Only records of this inspection method (default: every method).",
)


def _of_method(recs: list[InspectionRecord], method: str | None) -> list[InspectionRecord]:
    return recs if method is None else [r for r in recs if r.method == method]


@click.group()
def records() -> None:
    """Query stored inspection records: list, show one, lot statistics (SQLite, PostgreSQL).

    Records are written by `camtol conjugate --store DB` (cams A and B of a fixture
    inspection) and `camtol inspect --store DB` (a CMM scan), one per inspected cam. DB is
    a SQLite file, sqlite:///FILE.db or postgresql+psycopg://user@host:port/database.
    """


@records.command("list")
@click.option("--store", "store", required=True, metavar="DB", help=_STORE_HELP)
@click.option("--design", metavar="NAME", help="Only records of this design name.")
@click.option("--lot", metavar="L", help="Only records of this lot.")
@click.option(
    "--cam", type=click.Choice(["A", "B", "single"]), help="Only this cam (single: not a pair)."
)
@_METHOD_OPTION
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON.")
def list_records(
    store: str,
    design: str | None,
    lot: str | None,
    cam: str | None,
    method: str | None,
    as_json: bool,
) -> None:
    """List inspection records, oldest first: id, time, design, cam, part, verdict, figures."""

    def body() -> int:
        with _open_existing(store) as s:
            recs = _of_method(s.records(design=design, lot=lot, cam=_cam_filter(cam)), method)
        if as_json:
            echo_json({"records": [r.summary() for r in recs]}, command="records list")
            return EXIT_OK
        click.echo(
            f"{'id':>5} {'inspected_at (UTC)':19} {'design':18} {'cam':3} {'part':12}"
            f" {'serial':10} {'lot':10} {'verdict':7} {'max_um':>8} {'min_um':>8} {'form_um':>8}"
        )
        for r in recs:
            click.echo(
                f"{r.id:>5} {r.inspected_at.strftime('%Y-%m-%d %H:%M:%S')} {r.design_name:18.18}"
                f" {r.cam or '-':3} {r.part_number:12.12} {r.serial:10.10} {r.lot:10.10}"
                f" {r.verdict:7} {r.max_dev_um:8.2f} {r.min_dev_um:8.2f} {r.form_um:8.2f}"
            )
        click.echo(f"{len(recs)} record(s)")
        return EXIT_OK

    raise _Exit(run_guarded(body))


@records.command("show")
@click.argument("record_id", metavar="ID", type=int)
@click.option("--store", "store", required=True, metavar="DB", help=_STORE_HELP)
@click.option("--json", "as_json", is_flag=True, help="Print the record as JSON.")
@click.option("--curves", metavar="FILE.csv", help="Write its deviation curve: theta_deg, dr_um.")
def show_record(record_id: int, store: str, as_json: bool, curves: str | None) -> None:
    """Show one inspection record: design identity, traceability, verdict, summary figures."""

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        with _open_existing(store) as s:
            rec = s.get(record_id)
        if curves:
            _write_csv(curves, ["theta_deg", "dr_um"], [rec.theta_deg, rec.dr_um])
        if as_json:
            data = rec.summary()
            # the envelope's camtol_version is this camtol's; the record's is kept beside it
            data["record_camtol_version"] = rec.camtol_version
            echo_json(data, command="records show")
        else:
            for key, value in rec.summary().items():
                click.echo(f"{key:16} {'' if value is None else value}")
        if curves:
            click.echo(f"wrote {curves}", err=as_json)
        return EXIT_OK

    raise _Exit(run_guarded(body))


@records.command("stats")
@click.option("--store", "store", required=True, metavar="DB", help=_STORE_HELP)
@click.option("--design", required=True, metavar="NAME", help="Design name of the records.")
@click.option("--lot", metavar="L", help="Only this lot (default: every record of the design).")
@click.option(
    "--cam",
    type=click.Choice(["A", "B", "single"]),
    help="Which cam; needed when the records hold more than one (a conjugate pair).",
)
@click.option(
    "--confidence",
    type=float,
    default=0.95,
    show_default=True,
    help="Confidence level of the failing fraction's interval (Clopper-Pearson).",
)
@_METHOD_OPTION
@click.option("--json", "as_json", is_flag=True, help="Print the statistics as JSON.")
@click.option(
    "--curves",
    metavar="FILE.csv",
    help="Write per angle: theta_deg, mean_um, std_um, max_um, min_um.",
)
def stats(
    store: str,
    design: str,
    lot: str | None,
    cam: str | None,
    method: str | None,
    confidence: float,
    as_json: bool,
    curves: str | None,
) -> None:
    """Lot statistics: per-angle mean, σ, envelopes; Cp/Cpk; failing fraction; trend."""

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        from camtol.records.lot_summary import summarise_lot

        with _open_existing(store) as s:
            recs = s.records(design=design, lot=lot, cam=_cam_filter(cam), with_curves=True)
        summary = summarise_lot(recs, design=design, lot=lot, method=method, confidence=confidence)
        st = summary.statistics
        if curves:
            _write_csv(
                curves,
                ["theta_deg", "mean_um", "std_um", "max_um", "min_um"],
                [st.theta_deg, st.mean_um, st.std_um, st.max_um, st.min_um],
            )
        out = summary.to_dict()
        if as_json:
            echo_json(out, command="records stats")
        else:
            for key, value in out.items():
                if key != "record_ids":
                    click.echo(f"{key:26} {'-' if value is None else value}")
        if curves:
            click.echo(f"wrote {curves}", err=as_json)
        return EXIT_OK

    raise _Exit(run_guarded(body))


def store_options(f: F) -> F:
    """Add --store and the traceability options to an inspection command.

    Parameters
    ----------
    f : callable
        The click command function; it receives the options as ``store_store``,
        ``store_part``, ``store_serial``, ``store_lot``, ``store_inspector``,
        ``store_instrument`` and ``store_inspected_at``.

    Returns
    -------
    callable
        ``f`` with the options.
    """
    for name, text in reversed(
        [
            ("--store", _STORE_HELP + " Records each inspected cam there."),
            ("--part", "Part number of the inspected part (with --store)."),
            ("--serial", "Serial number of the part (with --store)."),
            ("--lot", "Production lot of the part (with --store)."),
            ("--inspector", "Who inspected it (with --store)."),
            ("--instrument", "Instrument used (with --store)."),
            ("--inspected-at", "When, ISO 8601 with a time zone (with --store; default now)."),
        ]
    ):
        dest = "store_" + name.lstrip("-").replace("-", "_")
        f = click.option(name, dest, metavar="TEXT" if name != "--store" else "DB", help=text)(f)
    return f


def _traceability(opts: dict[str, str | None]) -> Any:
    from datetime import timezone

    from camtol.records.store import Traceability

    when = opts.get("store_inspected_at")
    at = datetime.now(timezone.utc)
    if when is not None:
        try:
            at = datetime.fromisoformat(when.replace("Z", "+00:00"))
        except ValueError:
            fail(f"--inspected-at={when!r}: allowed ISO 8601, e.g. 2026-11-23T12:00:00+00:00")
        if at.tzinfo is None:
            fail(f"--inspected-at={when!r}: give a time zone, e.g. 2026-11-23T12:00:00+00:00")
    return Traceability(
        part_number=opts.get("store_part") or "",
        serial=opts.get("store_serial") or "",
        lot=opts.get("store_lot") or "",
        inspector=opts.get("store_inspector") or "",
        instrument=opts.get("store_instrument") or "",
        inspected_at=at,
    )


def check_store_options(opts: dict[str, str | None]) -> str | None:
    """Check --store and the traceability options before any work; the store or None.

    The store is opened (created on first use, its schema version checked) and closed
    again, so that an unreachable or too new store stops the command before the analysis.
    The traceability texts (at most 200 characters, no NUL) and the date are checked too.

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options` (``store_store``, ``store_part``, ...).

    Returns
    -------
    str or None
        The store's location, None without ``--store``.
    """
    given = [k for k, v in opts.items() if v is not None and k != "store_store"]
    location = opts.get("store_store")
    if location is None:
        if given:
            flag = "--" + given[0].removeprefix("store_").replace("_", "-")
            fail(f"{flag} describes the part for the store: give --store DB as well")
        return None
    for key, value in opts.items():  # the store's rule for text fields, before any work
        if key not in ("store_store", "store_inspected_at") and value is not None:
            if len(value) > 200 or "\x00" in value:
                flag = "--" + key.removeprefix("store_").replace("_", "-")
                what = f"{len(value)} characters" + (", with a NUL" if "\x00" in value else "")
                fail(
                    f"{flag}={value[:20]!r}... ({what}): allowed text of at most 200 characters"
                    " without NUL"
                )
    _traceability(opts)  # validate the date before the analysis
    from camtol.records.store import open_store

    open_store(location).close()
    return location


def _design_text(design_path: str | None, example: str | None) -> str:
    """Return the TOML text the command read: the built-in example's or the design file's."""
    if example is not None:
        from camtol.config.examples import example_text

        return example_text(example)
    return Path(str(design_path)).read_text(encoding="utf-8")


def cmm_record_curve(insp: Any, n_points: int) -> Any:
    """Return a CMM inspection's record curve: Δr of the points kept on θ_j = 360° j / n.

    Parameters
    ----------
    insp : CmmInspection
        The inspection (outliers are left out).
    n_points : int
        Points of the grid (360 / --step).

    Returns
    -------
    ndarray
        Δr on the grid [µm]; refused (:class:`~camtol.exceptions.RecordError`, exit 2) when
        the scan has a gap wider than :data:`~camtol.records.lots.MAX_GAP_STEPS` steps.
    """
    from camtol.records.lots import scan_on_grid

    kept = insp.kept
    return scan_on_grid(insp.theta_deg[kept], insp.dr_um[kept], n_points, source=insp.source)


def cmm_record(
    opts: dict[str, str | None],
    design: Any,
    design_path: str | None,
    example: str | None,
    *,
    cam: str,
    dr_um: Any,
    verdict: str,
    tolerance_um: tuple[float, float],
    max_abs_ds_um: float | None,
) -> tuple[list[InspectionRecord], str]:
    """Build (and validate) the record of a CMM-inspected cam for ``camtol inspect --store``.

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options`.
    design : CamDesign
        The design the scan was checked against.
    design_path, example : str or None
        Where the design came from (its TOML text is hashed and stored).
    cam : {"A", "B", ""}
        The cam of a conjugate pair, "" for a single cam.
    dr_um : ndarray
        Δr on θ_j = 360° j / n (:func:`cmm_record_curve`). [µm]
    verdict : {"pass", "fail"}
        The inspection's overall verdict (profile tolerance and motion spec).
    tolerance_um : tuple of float
        The profile tolerance of that verdict. [µm]
    max_abs_ds_um : float or None
        Max |ΔS| of the measured follower motion (µm, or µrad for a swing).

    Returns
    -------
    (list of InspectionRecord, str)
        The record (not stored yet; see :func:`add_records`) and the design text.
    """
    from camtol.records.store import design_identity, make_record

    text = _design_text(design_path, example)
    name, digest = design_identity(design, text)
    rec = make_record(
        design_name=name,
        design_hash=digest,
        method="cmm",
        cam=cam,
        dr_um=dr_um,
        verdict=verdict,
        tolerance_um=tolerance_um,
        traceability=_traceability(opts),
        max_abs_ds_um=max_abs_ds_um,
    )
    return [rec], text


def add_records(location: str, recs: Sequence[InspectionRecord], design_text: str) -> list[int]:
    """Store records built by :func:`cmm_record` or :func:`fixture_records` in one transaction.

    Parameters
    ----------
    location : str
        The store (path or URL).
    recs : sequence of InspectionRecord
        The records.
    design_text : str
        The design's TOML text.

    Returns
    -------
    list of int
        Their ids; on any error nothing is stored (:class:`~camtol.exceptions.RecordError`).
    """
    from camtol.records.store import open_store

    with open_store(location) as store:
        return store.add_all(recs, design_text=design_text)


def fixture_records(
    opts: dict[str, str | None],
    design: Any,
    design_path: str | None,
    example: str | None,
    res: Any,
    spec: Any,
) -> tuple[list[InspectionRecord], str]:
    """Build (and validate) the records of cams A and B of a fixture inspection.

    Parameters
    ----------
    opts : dict
        The options of :func:`store_options`.
    design : CamDesign
        The inspected design.
    design_path, example : str or None
        Where the design came from (its TOML text is hashed and stored).
    res : FixtureInspection
        The fixture analysis, with a measurement.
    spec : FixtureSpec
        The inspection spec (tolerances of cams A and B).

    Returns
    -------
    (list of InspectionRecord, str)
        The records of A and B (not stored yet; see :func:`add_records`) and the design
        text.
    """
    from camtol.records.store import design_identity, make_record

    if res.estimate is None:
        fail(
            "--store records an inspection: give the measured Δf (--record, --df-mea or"
            " inspection.df_mea_um)"
        )
    text = _design_text(design_path, example)
    name, digest = design_identity(design, text)
    trace = _traceability(opts)
    recs = [
        make_record(
            design_name=name,
            design_hash=digest,
            method="conjugate-fixture",
            cam=cam,
            dr_um=curve,
            verdict="pass" if res.verdicts[cam].passed else "fail",
            tolerance_um=tol,
            traceability=trace,
        )
        for cam, curve, tol in (
            ("A", res.estimate.dr_a_est_um, spec.tolerance_a_um),
            ("B", res.estimate.dr_b_est_um, spec.tolerance_b_um),
        )
    ]
    return recs, text
