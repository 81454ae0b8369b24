"""``camtol records rerun|void|export``: what an auditor does with stored records.

``rerun`` judges a stored inspection again with today's camtol
(:func:`camtol.records.rerun.rerun_record`) and says whether it is identical; ``void``
marks a record void with who, when and why (never deleting it); ``export`` writes one row
per record for a spreadsheet (:mod:`camtol.records.exports`). Registered on the
``records`` group by :mod:`camtol.cli.records`. Exit status 0; 1 when a re-run differs;
2 on bad input (the database untouched). Documented in docs/records.md.
"""

from __future__ import annotations

import getpass
import json

import click

from camtol.cli.common import (
    EXIT_FAIL,
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    fail,
    run_guarded,
)
from camtol.cli.recording import STORE_HELP, open_for_reading

__all__ = ["export_records", "rerun", "void"]


@click.command("rerun")
@click.argument("record_id", metavar="ID", type=int)
@click.option("--store", "store", required=True, metavar="DB", help=STORE_HELP)
@click.option("--json", "as_json", is_flag=True, help="Print the comparison as JSON.")
def rerun(record_id: int, store: str, as_json: bool) -> None:
    """Re-run a stored inspection with today's camtol from its raw data and compare.

    The raw inputs (each checked against its SHA-256), the options and the design stored
    with the record are judged again by the same library function the recording command
    used; the verdict, what it was judged on, the tolerance, the summary figures, the curve
    and the method's own results are compared bit for bit. Exit status 0 when identical,
    1 when they differ, 2 when the record cannot be re-run (no raw data, a corrupt blob).
    """

    def body() -> int:
        from camtol.config.design_file import load_design
        from camtol.records.rerun import rerun_record

        with open_for_reading(store) as s:
            result = rerun_record(s, record_id, load_design=load_design)
        data = result.to_dict()
        if as_json:
            echo_json(data, command="records rerun", schema_version="1.1")  # max_abs_ds_deg
        else:
            from camtol._version import __version__

            rec = result.stored
            cam = f", cam {rec.cam}" if rec.cam else ""
            state = "identical" if result.identical else "DIFFERENT"
            click.echo(
                f"record {rec.id} ({rec.method}{cam}, made by camtol {rec.camtol_version})"
                f" re-run with camtol {__version__}:"
            )
            click.echo(f"  {state}; verdict {rec.verdict} -> {result.again.verdict}")
            for d in result.differences:
                extra = (
                    ""
                    if d.max_abs_difference_um is None
                    else f" (max |difference| {d.max_abs_difference_um:.6g} µm)"
                )
                click.echo(f"  {d.key}: stored {d.stored!r}, re-run {d.rerun!r}{extra}")
        return EXIT_OK if result.identical else EXIT_FAIL

    raise _Exit(run_guarded(body))


def _login() -> str:
    """Return the login name, "" when it cannot be known."""
    try:
        return getpass.getuser()[:200]
    except Exception:  # no user name in the environment or the password database
        return ""


@click.command("void")
@click.argument("record_id", metavar="ID", type=int)
@click.option("--store", "store", required=True, metavar="DB", help=STORE_HELP)
@click.option(
    "--reason", required=True, metavar="TEXT", help="Why the record is void (1-500 characters)."
)
@click.option("--by", metavar="NAME", help="Who voids it (default: the login name).")
def void(record_id: int, store: str, reason: str, by: str | None) -> None:
    """Mark a record void (never deleted): who, when and why are kept with it.

    Lists, statistics and exports skip a voided record (`records list --all` and
    `records export --all` show it, marked); `records show` and `records rerun` still read
    it. A record already void, an unknown id or a missing --reason changes nothing.
    """

    def body() -> int:
        who = _login() if by is None else by
        with open_for_reading(store) as s:  # refuse an unknown or void id untouched
            rec = s.get(record_id)
            if rec.voided:
                assert rec.voided_at is not None
                fail(
                    f"record id {record_id} is already void (since"
                    f" {rec.voided_at.isoformat()}, by {rec.voided_by!r}: {rec.void_reason!r});"
                    " nothing was changed"
                )
        from camtol.records.store import open_store

        with open_store(store, create=False) as s:
            done = s.void(record_id, reason=reason, by=who)
        assert done.voided_at is not None
        click.echo(
            f"record {record_id} voided at {done.voided_at.isoformat()} by"
            f" {done.voided_by or '(unknown)'}: {done.void_reason}"
        )
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _json_text(data: dict[str, object]) -> str:
    """Return the JSON document as ``echo_json`` prints it (envelope first)."""
    from camtol._version import __version__
    from camtol.report.finite import require_no_nan_json
    from camtol.report.units import json_ready

    require_no_nan_json(data)
    head = {
        "schema_version": "1.1",  # max_abs_ds_deg replaces max_abs_ds_urad (issue 31)
        "command": "records export",
        "camtol_version": __version__,
    }
    return json.dumps(json_ready({**head, **data}), indent=2, allow_nan=False, ensure_ascii=False)


@click.command("export")
@click.option("--store", "store", required=True, metavar="DB", help=STORE_HELP)
@click.option("--lot", metavar="L", help="Only records of this lot.")
@click.option(
    "--all", "include_voided", is_flag=True, help="Voided records too, with the void columns."
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "json"]),
    required=True,
    help="CSV (one header row) or JSON (columns and rows).",
)
@click.option(
    "-o",
    "--output",
    metavar="FILE",
    help="Write to FILE (.csv or .json, as --format) instead of standard output.",
)
def export_records(
    store: str, lot: str | None, include_voided: bool, fmt: str, output: str | None
) -> None:
    """Export the records, one row per inspection with units in the column names.

    Traceability (part number, serial, lot, inspector, instrument, UTC time), design name
    and hash, method, what the verdict was judged on, the verdict and the summary figures,
    ready for Minitab or a spreadsheet. Voided records are left out unless --all.
    """

    def body() -> int:
        check_output_path(output, "--output", [f".{fmt}"])
        from camtol.records.exports import export_csv, export_json

        with open_for_reading(store) as s:
            recs = s.records(lot=lot, include_voided=include_voided)
        if fmt == "json" and output is None:
            echo_json(  # 1.1: max_abs_ds_deg replaces max_abs_ds_urad (issue 31)
                export_json(recs, with_void=include_voided),
                command="records export",
                schema_version="1.1",
            )
            return EXIT_OK
        if fmt == "csv":
            text = export_csv(recs, with_void=include_voided)
        else:
            text = _json_text(export_json(recs, with_void=include_voided)) + "\n"
        if output is None:
            click.echo(text, nl=False)
            return EXIT_OK
        from camtol.files import atomic_write

        atomic_write(output, text)
        click.echo(f"wrote {output} ({len(recs)} record(s))")
        return EXIT_OK

    raise _Exit(run_guarded(body))
