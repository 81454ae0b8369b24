r"""Records out of the store: one row per inspection, for a spreadsheet or Minitab.

:func:`export_rows` gives, per record, its traceability (part number, serial, lot,
inspector, instrument, UTC time), the design's name and hash, the method, what the verdict
was judged on, the verdict and the summary figures, with the unit in every column name
(``max_dev_um``; the motion figure in ``max_abs_ds_um`` for a lift, ``max_abs_ds_deg``
for a swing). :func:`export_csv` writes them as CSV (one header row, ``\\n`` line ends,
floats to 10 significant digits, an empty field for a value that does not apply),
:func:`export_json` as the ``records export --format json`` document.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from typing import Any

from camtol.records.record import InspectionRecord

__all__ = ["COLUMNS", "VOID_COLUMNS", "export_csv", "export_json", "export_rows"]

#: The columns of an export, in order (docs/records.md, "records export").
COLUMNS = (
    "id",
    "part_number",
    "serial",
    "lot",
    "inspector",
    "instrument",
    "inspected_at_utc",
    "design_name",
    "design_hash",
    "method",
    "cam",
    "judged_on",
    "decision_rule",
    "verdict",
    "max_dev_um",
    "min_dev_um",
    "form_um",
    "tolerance_lower_um",
    "tolerance_upper_um",
    "max_abs_ds_um",
    "max_abs_ds_deg",
    "n_points",
    "raw_sha256",
    "camtol_version",
)

#: Columns added with ``--all`` (voided records included).
VOID_COLUMNS = ("voided", "voided_at_utc", "voided_by", "void_reason")


def _row(rec: InspectionRecord, with_void: bool) -> dict[str, Any]:
    row: dict[str, Any] = {
        "id": rec.id,
        "part_number": rec.part_number,
        "serial": rec.serial,
        "lot": rec.lot,
        "inspector": rec.inspector,
        "instrument": rec.instrument,
        "inspected_at_utc": rec.inspected_at.isoformat(),
        "design_name": rec.design_name,
        "design_hash": rec.design_hash,
        "method": rec.method,
        "cam": rec.cam,
        "judged_on": rec.judged_on,
        "decision_rule": rec.decision_rule,
        "verdict": rec.verdict,
        "max_dev_um": rec.max_dev_um,
        "min_dev_um": rec.min_dev_um,
        "form_um": rec.form_um,
        "tolerance_lower_um": rec.tolerance_um[0],
        "tolerance_upper_um": rec.tolerance_um[1],
        "max_abs_ds_um": rec.max_abs_ds_um,
        "max_abs_ds_deg": rec.max_abs_ds_deg,
        "n_points": rec.n_points,
        "raw_sha256": rec.raw_sha256,
        "camtol_version": rec.camtol_version,
    }
    if with_void:
        row["voided"] = rec.voided
        row["voided_at_utc"] = None if rec.voided_at is None else rec.voided_at.isoformat()
        row["voided_by"] = rec.voided_by
        row["void_reason"] = rec.void_reason
    return row


def export_rows(
    records: Sequence[InspectionRecord], *, with_void: bool = False
) -> list[dict[str, Any]]:
    """One row per record, keyed by :data:`COLUMNS` (and :data:`VOID_COLUMNS`).

    Parameters
    ----------
    records : sequence of InspectionRecord
        The records (summaries are enough).
    with_void : bool
        Add the void columns (an export with ``--all``).

    Returns
    -------
    list of dict
        Values as JSON-ready numbers and text; None where a value does not apply.
    """
    return [_row(r, with_void) for r in records]


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        text = f"{value:.10g}"
        return "0" if text == "-0" else text
    return str(value)


def export_csv(records: Sequence[InspectionRecord], *, with_void: bool = False) -> str:
    """Write the records as CSV text: a header of the column names, one row per record.

    Parameters
    ----------
    records : sequence of InspectionRecord
        The records.
    with_void : bool
        Add the void columns.

    Returns
    -------
    str
        Fields quoted where they hold a comma, a quote or a line break (RFC 4180).
    """
    columns = COLUMNS + (VOID_COLUMNS if with_void else ())
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(columns)
    for row in export_rows(records, with_void=with_void):
        writer.writerow([_cell(row[c]) for c in columns])
    return out.getvalue()


def export_json(records: Sequence[InspectionRecord], *, with_void: bool = False) -> dict[str, Any]:
    """Return the ``records export --format json`` document (without the envelope).

    Parameters
    ----------
    records : sequence of InspectionRecord
        The records.
    with_void : bool
        Add the void columns.

    Returns
    -------
    dict
        ``columns`` (the column names, in order) and ``rows`` (one object per record).
    """
    columns = COLUMNS + (VOID_COLUMNS if with_void else ())
    return {"columns": list(columns), "rows": export_rows(records, with_void=with_void)}
