"""``camtol records``: list, show, statistics, re-run, void and export stored records.

``list``, ``show`` and ``stats`` are here; ``rerun``, ``void`` and ``export`` (what an
auditor does with the records) in :mod:`camtol.cli.records_audit`; the ``--store`` options
of ``camtol inspect`` and ``camtol conjugate`` in :mod:`camtol.cli.recording`. Registered
lazily by :mod:`camtol.cli.app`. Readers open the store read-only. Exit status 0, or 2 on
bad input (unreachable store, not a camtol store, unknown record, a store written by a
newer camtol, no matching records). Documented in docs/records.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import click

from camtol.cli.common import EXIT_OK, _Exit, check_output_path, echo_json, run_guarded
from camtol.cli.recording import STORE_HELP as _STORE_HELP
from camtol.cli.recording import open_for_reading as _open_existing
from camtol.cli.records_audit import export_records, rerun, void

if TYPE_CHECKING:
    from camtol.records.store import InspectionRecord

__all__ = ["records"]


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
    """Inspection records: list, show, lot statistics, re-run, void, export (SQL).

    Records are written by `camtol conjugate --store DB` (cams A and B of a fixture
    inspection) and `camtol inspect --store DB` (a CMM scan), one per inspected cam, with
    the raw data and every option the verdict depended on. DB is a SQLite file,
    sqlite:///FILE.db or postgresql+psycopg://user@host:port/database. Records are never
    deleted: `records void` marks one, and lists, statistics and exports skip it.
    """


@records.command("list")
@click.option("--store", "store", required=True, metavar="DB", help=_STORE_HELP)
@click.option("--design", metavar="NAME", help="Only records of this design name.")
@click.option("--lot", metavar="L", help="Only records of this lot.")
@click.option(
    "--cam", type=click.Choice(["A", "B", "single"]), help="Only this cam (single: not a pair)."
)
@_METHOD_OPTION
@click.option("--all", "include_voided", is_flag=True, help="Voided records too, marked VOID.")
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON.")
def list_records(
    store: str,
    design: str | None,
    lot: str | None,
    cam: str | None,
    method: str | None,
    include_voided: bool,
    as_json: bool,
) -> None:
    """List inspection records, oldest first: id, time, design, cam, part, verdict, figures."""

    def body() -> int:
        with _open_existing(store) as s:
            found = s.records(
                design=design, lot=lot, cam=_cam_filter(cam), include_voided=include_voided
            )
        recs = _of_method(found, method)
        if as_json:
            echo_json({"records": [r.summary() for r in recs]}, command="records list")
            return EXIT_OK
        lines = [
            f"{'id':>5} {'inspected_at (UTC)':19} {'design':18} {'cam':3} {'part':12}"
            f" {'serial':10} {'lot':10} {'on':2} {'verdict':7} {'max_um':>8} {'min_um':>8}"
            f" {'form_um':>8}"
        ]
        lines += [
            f"{r.id:>5} {r.inspected_at.strftime('%Y-%m-%d %H:%M:%S')} {r.design_name:18.18}"
            f" {r.cam or '-':3} {r.part_number:12.12} {r.serial:10.10} {r.lot:10.10}"
            f" {r.judged_on or '?':2} {r.verdict:7} {r.max_dev_um:8.2f} {r.min_dev_um:8.2f}"
            f" {r.form_um:8.2f}" + (" VOID" if r.voided else "")
            for r in recs
        ]
        voided = sum(r.voided for r in recs)
        lines.append(f"{len(recs)} record(s)" + (f", {voided} void" if include_voided else ""))
        click.echo("\n".join(lines))
        return EXIT_OK

    raise _Exit(run_guarded(body))


@records.command("show")
@click.argument("record_id", metavar="ID", type=int)
@click.option("--store", "store", required=True, metavar="DB", help=_STORE_HELP)
@click.option("--json", "as_json", is_flag=True, help="Print the record as JSON.")
@click.option("--curves", metavar="FILE.csv", help="Write its deviation curve: theta_deg, dr_um.")
@click.option(
    "--design",
    "show_design",
    is_flag=True,
    help="Print the design file the record was checked against, as stored.",
)
def show_record(
    record_id: int, store: str, as_json: bool, curves: str | None, show_design: bool
) -> None:
    """Show one inspection record: design identity, traceability, verdict, summary figures."""

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        if show_design and (as_json or curves):
            from camtol.cli.common import fail

            fail("--design prints the design file alone: leave out --json and --curves")
        with _open_existing(store) as s:
            rec = s.get(record_id)
            text = s.design_text(rec.design_hash) if show_design else None
            inputs = s.input_list(record_id)
        if show_design:
            if text is None:
                from camtol.cli.common import fail

                fail(
                    f"record id {record_id}: the text of its design {rec.design_hash} is not"
                    " in the store (recorded through the Python API without it)"
                )
            click.echo(text, nl=not str(text).endswith("\n"))
            return EXIT_OK
        if curves:
            _write_csv(curves, ["theta_deg", "dr_um"], [rec.theta_deg, rec.dr_um])
        data = rec.summary()
        data.update(options=rec.options, results=rec.results, inputs=inputs)
        if as_json:
            # the envelope's camtol_version is this camtol's; the record's is kept beside it
            data["record_camtol_version"] = rec.camtol_version
            echo_json(data, command="records show")
        else:
            for key, value in data.items():
                click.echo(f"{key:17} {'' if value is None else value}")
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


for _command in (rerun, void, export_records):
    records.add_command(_command)
