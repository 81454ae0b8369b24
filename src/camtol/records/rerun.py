"""A stored inspection judged again with today's camtol (``camtol records rerun``).

:func:`rerun_record` reads a record's raw inputs (each checked against its SHA-256: a
corrupt blob is named), its options and its design's TOML text, writes them into a
temporary folder as they were, and runs the inspection through the library function the
recording command used (:func:`camtol.inspection.cmm_run.run_cmm` for ``cmm``,
:func:`camtol.pair.fixture_run.run_fixture` for ``conjugate-fixture``), building the
record with the same :mod:`camtol.records.capture` function. :class:`Rerun` compares the
two: verdict, what it was judged on, tolerance, summary figures, the curve and the
method's own results. Under the camtol version that made the record they are identical
bit for bit. A record stored without raw data (made before schema version 2, or through
the Python API without inputs) says so.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.exceptions import RecordError
from camtol.records.raw import RawInput
from camtol.records.record import InspectionRecord, Traceability

if TYPE_CHECKING:
    from camtol.records.store import InspectionStore

__all__ = ["Difference", "Rerun", "compare_records", "rerun_record"]

#: Figures of a record compared by a re-run (besides its curve and its results).
COMPARED = (
    "verdict",
    "judged_on",
    "decision_rule",
    "tolerance_um",
    "max_dev_um",
    "min_dev_um",
    "form_um",
    "max_abs_ds_um",
    "max_abs_ds_deg",
    "motion_unit",
    "n_points",
)


@dataclass(frozen=True)
class Difference:
    """One figure that differs between a stored record and its re-run.

    Attributes
    ----------
    key : str
        The record key (``verdict``, ``max_dev_um``, ``dr_um``, ``results.min_zone_um``...).
    stored, rerun : object
        Its value in the store and in the re-run (for ``dr_um``: the number of points).
    max_abs_difference_um : float or None
        For the curve ``dr_um``: the largest difference at any angle. [µm]
    """

    key: str
    stored: Any
    rerun: Any
    max_abs_difference_um: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """Return the difference as JSON-ready values."""
        out = {"key": self.key, "stored": self.stored, "rerun": self.rerun}
        if self.max_abs_difference_um is not None:
            out["max_abs_difference_um"] = self.max_abs_difference_um
        return out


@dataclass(frozen=True)
class Rerun:
    """A stored record and the same inspection judged again.

    Attributes
    ----------
    stored : InspectionRecord
        The record as stored.
    again : InspectionRecord
        The record the re-run makes (not stored).
    differences : tuple of Difference
        What differs (empty: identical bit for bit).
    """

    stored: InspectionRecord
    again: InspectionRecord
    differences: tuple[Difference, ...]

    @property
    def identical(self) -> bool:
        """Whether every compared figure, the curve and the results are equal bit for bit."""
        return not self.differences

    def to_dict(self) -> dict[str, Any]:
        """Return the ``records rerun --json`` document (docs/records.md).

        Returns
        -------
        dict
            ``id``, ``method``, ``cam``, ``record_camtol_version``, ``identical``,
            ``verdict_identical``, ``stored``, ``rerun`` and ``differences``.
        """
        a, b = self.stored, self.again
        return {
            "id": a.id,
            "method": a.method,
            "cam": a.cam,
            "record_camtol_version": a.camtol_version,
            "identical": self.identical,
            "verdict_identical": a.verdict == b.verdict,
            "stored": _figures(a),
            "rerun": _figures(b),
            "differences": [d.to_dict() for d in self.differences],
        }


def _figures(rec: InspectionRecord) -> dict[str, Any]:
    summary = rec.summary()
    return {key: summary[key] for key in COMPARED}


def compare_records(stored: InspectionRecord, again: InspectionRecord) -> list[Difference]:
    """List what differs between two records of one inspection (bit for bit).

    Parameters
    ----------
    stored, again : InspectionRecord
        The stored record and its re-run.

    Returns
    -------
    list of Difference
        The compared figures (:data:`COMPARED`), the curve ``dr_um`` and every key of the
        method's ``results`` (as ``results.<key>``) that differ.
    """
    out = []
    a, b = _figures(stored), _figures(again)
    for key in COMPARED:
        if a[key] != b[key]:
            out.append(Difference(key, a[key], b[key]))
    if stored.dr_um.size != again.dr_um.size or stored.dr_um.tobytes() != again.dr_um.tobytes():
        worst = (
            float(np.max(np.abs(stored.dr_um.astype(float) - again.dr_um.astype(float))))
            if stored.dr_um.size == again.dr_um.size
            else None
        )
        out.append(Difference("dr_um", int(stored.dr_um.size), int(again.dr_um.size), worst))
    ra, rb = stored.results or {}, again.results or {}
    for key in sorted(set(ra) | set(rb)):
        if ra.get(key) != rb.get(key):
            out.append(Difference(f"results.{key}", ra.get(key), rb.get(key)))
    return out


def rerun_record(
    store: InspectionStore,
    record_id: int,
    *,
    load_design: Callable[[Path], CamDesign],
) -> Rerun:
    """Judge a stored inspection again with today's camtol and compare.

    Parameters
    ----------
    store : InspectionStore
        The store (read-only is enough).
    record_id : int
        The record.
    load_design : callable
        Reads a design file (``camtol.config.design_file.load_design``: the store
        does not read design files itself).

    Returns
    -------
    Rerun

    Raises
    ------
    RecordError
        No such record, a record without raw data or options (saying so), a corrupt raw
        blob (named), a design text not stored, or a file the design names that has
        changed since.
    """
    rec = store.get(record_id)
    made = f"record {record_id} ({rec.method}, made by camtol {rec.camtol_version})"
    inputs = store.inputs(record_id)
    if rec.options is None or not inputs:
        raise RecordError(
            f"{made} was stored without its raw data and options (a record made before"
            " store schema version 2, or through the Python API without inputs): it cannot"
            " be re-run"
        )
    text = store.design_text(rec.design_hash)
    if text is None:
        raise RecordError(
            f"{made}: its design's TOML text is not in the store; it cannot be re-run"
        )
    trace = Traceability(
        part_number=rec.part_number,
        serial=rec.serial,
        lot=rec.lot,
        inspector=rec.inspector,
        instrument=rec.instrument,
        inspected_at=rec.inspected_at,
    )
    from camtol.records import capture

    with tempfile.TemporaryDirectory(prefix="camtol-rerun-") as tmp:
        folder = Path(tmp)
        design = load_design(_restore_design(folder, text, inputs, made))
        files = capture.restore_files(inputs, folder)
        if rec.method == "cmm":
            from camtol.inspection.cmm_run import run_cmm

            if "scan" not in files:
                raise RecordError(f"{made}: its raw scan is not in the store; it cannot be re-run")
            cmm_in = capture.cmm_inputs(rec.options, files["scan"])
            if cmm_in.tolerance_um is None:
                # Judged against the zone the record was judged against: a record made
                # before issue 31 took it from tolerances.r (±IT), which the design's
                # [inspection] zone now replaces (or the stored design has none).
                import dataclasses

                cmm_in = dataclasses.replace(
                    cmm_in,
                    tolerance_um=rec.tolerance_um,
                    tolerance_kind="radial" if rec.judged_on == "dr" else "normal",
                )
            run = run_cmm(design, cmm_in)
            again = capture.cmm_record(
                design,
                run,
                n_points=int(rec.options.get("n_points", rec.n_points)),
                traceability=trace,
                design_text=text,
                options=rec.options,
                raw_sha256=rec.raw_sha256,
            )
        else:
            from camtol.pair.fixture_run import run_fixture

            fixture = run_fixture(design, capture.fixture_inputs(rec.options, files))
            recs = capture.fixture_records(
                design,
                fixture,
                traceability=trace,
                design_text=text,
                options=rec.options,
                raw_sha256=rec.raw_sha256,
            )
            again = next(r for r in recs if r.cam == rec.cam)
    return Rerun(rec, again, tuple(compare_records(rec, again)))


def _restore_design(folder: Path, text: str, inputs: list[RawInput], made: str) -> Path:
    """Write the design file and the files it names (as written in it); return its path."""
    for raw in inputs:
        if not raw.role.startswith("design:"):
            continue
        written = raw.role.removeprefix("design:")
        rel = Path(written)
        if not rel.is_absolute() and ".." not in rel.parts:
            (folder / rel).parent.mkdir(parents=True, exist_ok=True)
            (folder / rel).write_bytes(raw.data)
            continue
        current = rel.read_bytes() if rel.is_file() else None
        if current is None or RawInput(raw.role, raw.name, current).sha256 != raw.sha256:
            raise RecordError(
                f"{made}: its design names {written!r} by a path outside the design's folder,"
                " and that file is missing or has changed since; it cannot be re-run as"
                " recorded"
            )
    path = folder / "design.toml"
    path.write_text(text, encoding="utf-8")
    return path
