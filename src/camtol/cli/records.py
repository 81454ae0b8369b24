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
@click.option(
    "--wide", is_flag=True, help="Every column (design, part number, basis): over 80 columns."
)
@click.option("--json", "as_json", is_flag=True, help="Print the records as JSON.")
def list_records(
    store: str,
    design: str | None,
    lot: str | None,
    cam: str | None,
    method: str | None,
    include_voided: bool,
    wide: bool,
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
            echo_json(  # 1.1: max_abs_ds_deg (issue 31)
                {"records": [r.summary() for r in recs]},
                command="records list",
                schema_version="1.1",
            )
            return EXIT_OK
        lines = _list_lines(recs) if not wide else _wide_lines(recs)
        voided = sum(r.voided for r in recs)
        lines.append(f"{len(recs)} record(s)" + (f", {voided} void" if include_voided else ""))
        click.echo("\n".join(lines))
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _list_lines(recs: list[InspectionRecord]) -> list[str]:
    """Format the records within 80 columns (design, part, basis: --wide, --json)."""
    lines = [
        f"{'id':>5} {'inspected (UTC)':16} {'serial':10} {'lot':7} {'cam':3} {'res.':4}"
        f" {'max µm':>7} {'min µm':>7} {'form µm':>7}"
    ]
    lines += [
        f"{r.id:>5} {r.inspected_at.strftime('%Y-%m-%d %H:%M')} {r.serial:10.10}"
        f" {r.lot:7.7} {r.cam or '-':3} {r.verdict:4} {r.max_dev_um:7.2f} {r.min_dev_um:7.2f}"
        f" {r.form_um:7.2f}" + (" VOID" if r.voided else "")
        for r in recs
    ]
    return lines


def _wide_lines(recs: list[InspectionRecord]) -> list[str]:
    """Format every column, as wide as it takes (``--wide``)."""
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
    return lines


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
            echo_json(data, command="records show", schema_version="1.1")  # max_abs_ds_deg
        else:
            for line in _show_lines(data):
                click.echo(line)
        if curves:
            click.echo(f"wrote {curves}", err=as_json)
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _show_value(value: Any) -> str:
    """Format a stored value for reading: numbers to 6 significant digits, no reprs."""
    if value is None or value == "":
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list | tuple):
        return ", ".join(_show_value(v) for v in value) or "none"
    return str(value)


def _show_lines(data: dict[str, Any], width: int = 80) -> list[str]:
    """Lay out ``records show`` as label/value lines within ``width`` columns.

    Nested tables (the method's options and results, the input files) become indented
    ``key: value`` lines; a value too long for its line (a hash, a path) goes on the next
    line, indented, and is wrapped only if it is longer than a whole line.
    """
    import textwrap

    out: list[str] = []

    def put(label: str, value: str, indent: int) -> None:
        head = " " * indent + f"{label:{17 - indent}} "
        if len(head) + len(value) <= width:
            out.append(head + value)
            return
        out.append(head.rstrip())
        pad = " " * (indent + 2)
        out.extend(textwrap.wrap(value, width, initial_indent=pad, subsequent_indent=pad))

    for key, value in data.items():
        if isinstance(value, dict):
            out.append(key)
            for k, v in value.items():
                if isinstance(v, dict):
                    out.append(f"  {k}")
                    for k2, v2 in v.items():
                        put(k2, _show_value(v2), 4)
                else:
                    put(k, _show_value(v), 2)
        elif key == "inputs" and isinstance(value, list):
            out.append("inputs")
            for item in value:
                if isinstance(item, dict):
                    put(str(item.get("role", "file")), str(item.get("name", "")), 2)
                    for k in ("sha256", "size_bytes"):
                        if k in item:
                            put(k, _show_value(item[k]), 4)
        else:
            put(key, _show_value(value), 0)
    return out


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
    "--characteristic",
    type=click.Choice(["max_dev", "min_dev", "form", "max_abs_ds"]),
    default="max_dev",
    show_default=True,
    help="Per-part value charted and judged (max_dev, form, max_abs_ds: upper limit only;"
    " min_dev: lower).",
)
@click.option(
    "--subgroup",
    type=int,
    default=1,
    show_default=True,
    metavar="N",
    help="Subgroups of N consecutive parts (1: individuals, σ within from moving ranges).",
)
@click.option(
    "--chart",
    type=click.Choice(["imr", "xbar-r", "xbar-s"]),
    help="Control chart (default: imr; xbar-r for N ≤ 8, xbar-s above).",
)
@click.option(
    "--rules",
    type=click.Choice(["we", "nelson"]),
    default="we",
    show_default=True,
    help="Run rules flagged: Western Electric WE1-WE4 or Nelson N1-N8.",
)
@click.option(
    "--limits-from",
    metavar="LOT",
    help="Freeze the control limits from this reference lot (same design, cam).",
)
@click.option(
    "--capable-at",
    type=float,
    default=1.33,
    show_default=True,
    help="Capable when the lower 95 % bound of Ppk (Ppu, Ppl) reaches this.",
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
@click.option(
    "--plot", metavar="FILE.png", help="Write the control chart and histogram (PNG/SVG/PDF)."
)
@click.option("--report", metavar="FILE.html", help="Write the lot report (HTML, printable).")
def stats(
    store: str,
    design: str,
    lot: str | None,
    cam: str | None,
    characteristic: str,
    subgroup: int,
    chart: str | None,
    rules: str,
    limits_from: str | None,
    capable_at: float,
    method: str | None,
    confidence: float,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    report: str | None,
) -> None:
    """Lot statistics: capability with intervals, control chart and run rules, yield, trend.

    Capability as ISO 22514-2 computes it on one characteristic per part: Pp/Ppk (overall
    σ) and Cp/Cpk (σ within: moving ranges, or pooled subgroups with --subgroup), or the
    one-sided Ppu/Cpu (Ppl/Cpl), each with its 95 % interval (chi-square, Bissell); an
    Anderson-Darling normality test (percentile indices when it fails); the judgement on
    the lower confidence bound. A control chart with Western Electric or Nelson run rules;
    the yield with its exact interval; per-angle curves with --curves. Records judged on
    different bases are never pooled. Documented in docs/records.md and docs/spc.md.
    """

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        check_output_path(report, "--report", [".html"])
        from camtol.records.lot_summary import reference_limits, summarise_lot

        if chart is not None and chart != "imr" and subgroup < 2:
            from camtol.cli.common import fail

            fail(f"--chart={chart} needs --subgroup N with N ≥ 2 (consecutive parts)")
        with _open_existing(store) as s:
            recs = s.records(
                design=design, lot=lot, cam=_cam_filter(cam), with_curves=True, with_details=True
            )
            ref_recs = (
                s.records(design=design, lot=limits_from, cam=_cam_filter(cam), with_details=True)
                if limits_from is not None
                else None
            )
        kind = chart or ("imr" if subgroup <= 1 else ("xbar-r" if subgroup <= 8 else "xbar-s"))
        reference = (
            reference_limits(
                ref_recs,
                lot=str(limits_from),
                characteristic=characteristic,
                chart=kind,
                subgroup=subgroup,
                method=method,
            )
            if ref_recs is not None
            else None
        )
        summary = summarise_lot(
            recs,
            design=design,
            lot=lot,
            method=method,
            confidence=confidence,
            characteristic=characteristic,
            subgroup=subgroup,
            chart=kind,
            rules=rules,
            capable_at=capable_at,
            reference=reference,
        )
        st = summary.statistics
        if curves:
            _write_csv(
                curves,
                ["theta_deg", "mean_um", "std_um", "max_um", "min_um"],
                [st.theta_deg, st.mean_um, st.std_um, st.max_um, st.min_um],
            )
        out = _stats_document(summary.to_dict())
        if plot:
            from camtol.report.lot_report import write_lot_plot

            write_lot_plot(out, plot)
        if report:
            from camtol.files import atomic_write
            from camtol.report.lot_report import lot_report_html

            atomic_write(
                report, lot_report_html(out, records=[r.summary() for r in summary.records])
            )
        if as_json:
            echo_json(out)
        else:
            from camtol.report.lot_report import lot_text

            click.echo("\n".join(lot_text(out)))
        for path in (curves, plot, report):
            if path:
                click.echo(f"wrote {path}", err=as_json)
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _stats_document(data: dict[str, Any]) -> dict[str, Any]:
    """Put the envelope (its own schema_version) on the ``records stats --json`` document."""
    from camtol._version import __version__
    from camtol.records.lot_summary import JSON_SCHEMA_VERSION

    head = {
        "schema_version": JSON_SCHEMA_VERSION,
        "command": "records stats",
        "camtol_version": __version__,
    }
    return {**head, **data}


for _command in (rerun, void, export_records):
    records.add_command(_command)
