"""What an inspection leaves in the store: its records, raw inputs and options.

One function per method turns a run into its record(s), and the same function serves
``camtol inspect --store`` / ``camtol conjugate --store`` and ``camtol records rerun``, so
a re-run is judged exactly as the recorded run was:

- :func:`cmm_record`: a :class:`~camtol.inspection.cmm_run.CmmRun` (method ``cmm``): the
  curve is Δr of the points kept on the record grid (the gap rule of
  :func:`~camtol.records.lots.scan_on_grid`), the extremes and the form are those of the
  measured points, the verdict is judged on Δn or Δr as the run was;
- :func:`fixture_records`: a :class:`~camtol.pair.fixture_run.FixtureRun` (method
  ``conjugate-fixture``): one record per cam, judged on Δr under the decision rule.

:func:`cmm_options` and :func:`fixture_options` write every option the verdict depended on
(JSON-ready); :func:`cmm_inputs` and :func:`fixture_inputs` read them back into the
library's inputs, with the raw files restored. :func:`fixture_raw_inputs` and
:func:`design_files` gather the raw inputs to keep.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.inspection.cmm_run import CmmInputs, CmmRun, datum_from_mapping, datum_to_mapping
from camtol.pair.fixture_run import FixtureInputs, FixtureRun
from camtol.records.lots import scan_on_grid
from camtol.records.raw import RawInput
from camtol.records.record import (
    InspectionRecord,
    Traceability,
    design_identity,
    make_record,
)

__all__ = [
    "FILE_OPTIONS",
    "cmm_inputs",
    "cmm_options",
    "cmm_record",
    "design_files",
    "fixture_inputs",
    "fixture_options",
    "fixture_raw_inputs",
    "fixture_records",
]

#: Options of a fixture inspection that may name a file (kept as a raw input by that role).
FILE_OPTIONS = ("record", "df_mea", "master_a", "master_b", "cmm_a", "cmm_b")

#: The role of the measured Δf given by the design's [inspection] table as a value (kept to
#: identify the measurement; a re-run takes it from the stored design).
DESIGN_DF_MEA = "inspection.df_mea_um"


def _is_csv(value: str | None) -> bool:
    return value is not None and value.strip().lower().endswith(".csv")


def cmm_options(
    inputs: CmmInputs,
    *,
    n_points: int,
    spec_um: float | None = None,
    spec_deg: float | None = None,
) -> dict[str, Any]:
    """Every option a CMM verdict depends on, JSON-ready (a record's ``options``).

    Parameters
    ----------
    inputs : CmmInputs
        The run's inputs (the point file is kept as the raw input ``scan``).
    n_points : int
        Points of the record's curve (360° / ``--step``).
    spec_um, spec_deg : float, optional
        The motion spec as given (``--spec-um``, ``--spec-deg``). [µm, deg]

    Returns
    -------
    dict
        ``points`` (the file as given), ``cam``, ``stylus_radius_mm``, ``columns``,
        ``datum``, ``tolerance_um``, ``tolerance_on``, ``harmonics``, ``step_deg``,
        ``n_points``, ``spec_um``, ``spec_deg`` and ``spec`` (mm or rad).
    """
    kind = inputs.tolerance_kind
    return {
        "points": inputs.points_path,
        "cam": inputs.cam,
        "stylus_radius_mm": inputs.stylus_radius_mm,
        "columns": None if inputs.aliases is None else dict(inputs.aliases),
        "datum": datum_to_mapping(inputs.datum),
        "tolerance_um": None if inputs.tolerance_um is None else list(inputs.tolerance_um),
        "tolerance_on": None if kind is None else ("dn" if kind == "normal" else "dr"),
        "harmonics": inputs.harmonics,
        "step_deg": inputs.step_deg,
        "n_points": n_points,
        "spec_um": spec_um,
        "spec_deg": spec_deg,
        "spec": inputs.spec,
    }


def cmm_inputs(options: Mapping[str, Any], scan_path: str) -> CmmInputs:
    """Return the inputs of a stored CMM record, its scan restored at ``scan_path``.

    Parameters
    ----------
    options : mapping
        The record's options (:func:`cmm_options`).
    scan_path : str
        Where its raw scan was written back.

    Returns
    -------
    CmmInputs
    """
    tol, on = options.get("tolerance_um"), options.get("tolerance_on")
    return CmmInputs(
        points_path=scan_path,
        cam=options.get("cam", "A"),
        stylus_radius_mm=float(options.get("stylus_radius_mm", 0.0)),
        aliases=options.get("columns"),
        datum=datum_from_mapping(options.get("datum") or {}),
        tolerance_um=None if tol is None else (float(tol[0]), float(tol[1])),
        tolerance_kind=None if on is None else ("normal" if on == "dn" else "radial"),
        harmonics=int(options.get("harmonics", 100)),
        step_deg=float(options.get("step_deg", 0.1)),
        spec=options.get("spec"),
    )


def cmm_record(
    design: CamDesign,
    run: CmmRun,
    *,
    n_points: int,
    traceability: Traceability,
    design_text: str | None,
    options: Mapping[str, Any] | None = None,
    raw_sha256: str | None = None,
) -> InspectionRecord:
    """Build the record of a CMM-inspected cam (not stored yet).

    Parameters
    ----------
    design : CamDesign
        The design the scan was checked against.
    run : CmmRun
        The inspection (:func:`camtol.inspection.cmm_run.run_cmm`).
    n_points : int
        Points of the record's curve (360° / ``--step``).
    traceability : Traceability
        Part number, serial, lot, inspector, instrument, date-time.
    design_text : str or None
        The design's TOML text (identifies a design without a content hash).
    options : mapping, optional
        Every option the verdict depended on (:func:`cmm_options`).
    raw_sha256 : str, optional
        SHA-256 of the scan file.

    Returns
    -------
    InspectionRecord
        Curve: Δr of the points kept on θ_j = 360° j / n; extremes and form: those of the
        measured Δr; refused (:class:`~camtol.exceptions.RecordError`) when the scan has
        a gap wider than :data:`~camtol.records.lots.MAX_GAP_STEPS` grid steps.
    """
    insp = run.inspection
    kept = insp.kept
    curve = scan_on_grid(insp.theta_deg[kept], insp.dr_um[kept], n_points, source=insp.source)
    dr_kept = insp.dr_um[kept]
    reg = insp.registration
    func = run.functional
    name, digest = design_identity(design, design_text)
    results = {
        "profile_verdict": "pass" if insp.passed else "fail",
        "motion_verdict": None
        if func is None or func.passed is None
        else ("pass" if func.passed else "fail"),
        "points": int(insp.dn_um.size),
        "outliers": int(np.count_nonzero(insp.outlier)),
        "max_dn_um": insp.max_dn_um,
        "min_dn_um": insp.min_dn_um,
        "form_dn_um": insp.form_um,
        "min_zone_um": insp.min_zone_um,
        "rotation_deg": reg.rotation_deg,
        "dx_mm": reg.dx_mm,
        "dy_mm": reg.dy_mm,
        "failing_intervals_deg": [[a, b] for a, b in insp.failing_intervals_deg],
        "functional_error": run.functional_error,
    }
    return make_record(
        design_name=name,
        design_hash=digest,
        method="cmm",
        cam=insp.cam if len(design.cams()) > 1 else "",
        dr_um=curve,
        verdict=run.verdict,
        tolerance_um=insp.tolerance_um,
        traceability=traceability,
        max_abs_ds_um=run.max_abs_ds_um,
        max_abs_ds_deg=run.max_abs_ds_deg,
        extremes_um=(float(np.max(dr_kept)), float(np.min(dr_kept))),
        judged_on="dn" if insp.tolerance_kind == "normal" else "dr",
        decision_rule="simple",
        motion_unit=run.motion_unit,
        raw_sha256=raw_sha256,
        options=options,
        results=results,
    )


def fixture_raw_inputs(
    inputs: FixtureInputs, design_table: Mapping[str, Any]
) -> tuple[list[RawInput], RawInput | None]:
    """Gather the raw inputs of a fixture inspection, and its primary one (the measurement).

    Parameters
    ----------
    inputs : FixtureInputs
        The run's inputs: files (``record_path``, a CSV ``df_mea`` or master, the CMM
        scans) are read whole; a value given as text is kept as its text.
    design_table : mapping
        The design's ``[inspection]`` table as written (its ``df_mea_um`` is the
        measurement when neither a record nor ``df_mea`` is given).

    Returns
    -------
    (list of RawInput, RawInput or None)
        The inputs (by role: ``record``, ``df_mea``, ``master_a``, ``master_b``, ``cmm_a``,
        ``cmm_b``, or ``inspection.df_mea_um``) and the measurement among them (None when
        there is none).
    """
    out: list[RawInput] = []
    given = {
        "record": inputs.record_path,
        "df_mea": inputs.df_mea,
        "master_a": inputs.master_a,
        "master_b": inputs.master_b,
        "cmm_a": inputs.cmm_a,
        "cmm_b": inputs.cmm_b,
    }
    for role, value in given.items():
        if value is None:
            continue
        file = role in ("record", "cmm_a", "cmm_b") or _is_csv(value)
        out.append(
            RawInput.from_file(role, value.strip()) if file else RawInput.from_text(role, value)
        )
    primary = next((r for r in out if r.role in ("record", "df_mea")), None)
    design_df = design_table.get("df_mea_um")
    if primary is None and design_df is not None and not _is_csv(str(design_df)):
        primary = RawInput.from_text(DESIGN_DF_MEA, str(design_df))
        out.append(primary)
    return out, primary


def fixture_options(inputs: FixtureInputs) -> dict[str, Any]:
    """Every option a fixture verdict depends on, JSON-ready (a record's ``options``).

    Parameters
    ----------
    inputs : FixtureInputs
        The run's inputs.

    Returns
    -------
    dict
        ``record``, ``df_mea``, ``master_a``, ``master_b``, ``cmm_a``, ``cmm_b`` (the value
        or file as given; a file is kept as the raw input of that role), ``files`` (the
        roles given as files), ``drop_bad_revolutions``, ``decision``, ``step_deg``,
        ``cmm_stylus_radius_mm`` and ``cmm_datum``.
    """
    given = {
        "record": inputs.record_path,
        "df_mea": inputs.df_mea,
        "master_a": inputs.master_a,
        "master_b": inputs.master_b,
        "cmm_a": inputs.cmm_a,
        "cmm_b": inputs.cmm_b,
    }
    files = [
        role
        for role, value in given.items()
        if value is not None and (role in ("record", "cmm_a", "cmm_b") or _is_csv(value))
    ]
    return {
        **given,
        "files": files,
        "drop_bad_revolutions": inputs.drop_bad_revolutions,
        "decision": inputs.decision,
        "step_deg": inputs.step_deg,
        "cmm_stylus_radius_mm": inputs.cmm_stylus_radius_mm,
        "cmm_datum": None if inputs.cmm_datum is None else datum_to_mapping(inputs.cmm_datum),
    }


def fixture_inputs(options: Mapping[str, Any], files: Mapping[str, str]) -> FixtureInputs:
    """Return the inputs of a stored fixture record, its files restored.

    Parameters
    ----------
    options : mapping
        The record's options (:func:`fixture_options`).
    files : mapping of str to str
        Role → where its raw file was written back.

    Returns
    -------
    FixtureInputs
    """

    def value(role: str) -> str | None:
        if role in options.get("files", ()):
            return files[role]
        given: str | None = options.get(role)
        return given

    datum = options.get("cmm_datum")
    return FixtureInputs(
        df_mea=value("df_mea"),
        record_path=value("record"),
        drop_bad_revolutions=bool(options.get("drop_bad_revolutions", False)),
        master_a=value("master_a"),
        master_b=value("master_b"),
        decision="guard-band" if options.get("decision") == "guard-band" else "simple",
        cmm_a=value("cmm_a"),
        cmm_b=value("cmm_b"),
        cmm_stylus_radius_mm=float(options.get("cmm_stylus_radius_mm", 0.0)),
        cmm_datum=None if datum is None else datum_from_mapping(datum),
        step_deg=float(options.get("step_deg", 0.1)),
    )


def fixture_records(
    design: CamDesign,
    run: FixtureRun,
    *,
    traceability: Traceability,
    design_text: str | None,
    options: Mapping[str, Any] | None = None,
    raw_sha256: str | None = None,
) -> list[InspectionRecord]:
    """Build the records of the cams of a fixture inspection, one per cam (not stored yet).

    Parameters
    ----------
    design : CamDesign
        The inspected conjugate design.
    run : FixtureRun
        The run (:func:`camtol.pair.fixture_run.run_fixture`), with a measurement.
    traceability : Traceability
        Part number, serial, lot, inspector, instrument, date-time.
    design_text : str or None
        The design's TOML text.
    options : mapping, optional
        Every option the verdict depended on (:func:`fixture_options`).
    raw_sha256 : str, optional
        SHA-256 of the measurement (the record, or the measured Δf).

    Returns
    -------
    list of InspectionRecord
        In the design's cam order; curve Δr_est on the analysis grid, judged on Δr.
    """
    res = run.inspection
    est = res.estimate
    if est is None:
        from camtol.exceptions import RecordError

        raise RecordError(
            "--store records an inspection: give the measured Δf (--record, --df-mea or"
            " inspection.df_mea_um)"
        )
    estimates = {"A": est.dr_a_est_um, "B": est.dr_b_est_um}
    name, digest = design_identity(design, design_text)
    u_f = None if run.record is None else np.asarray(run.record.u_f_um, dtype=float)
    out = []
    for cam in design.cams():
        letter = cam.letter
        curve = np.asarray(estimates[letter], dtype=float)
        verdict = res.verdicts[letter]
        results = {
            "min_margin_um": verdict.min_margin_um,
            "failing_intervals_deg": [[a, b] for a, b in verdict.failing_intervals_deg],
            "u_f_max_um": None if u_f is None else float(np.max(u_f)),
            "u_f_min_um": None if u_f is None else float(np.min(u_f)),
        }
        out.append(
            make_record(
                design_name=name,
                design_hash=digest,
                method="conjugate-fixture",
                cam=letter,
                dr_um=curve,
                verdict="pass" if verdict.passed else "fail",
                tolerance_um=run.spec.band_um(letter),
                traceability=traceability,
                extremes_um=(float(np.max(curve)), float(np.min(curve))),
                judged_on="dr",
                decision_rule=run.decision,
                raw_sha256=raw_sha256,
                options=options,
                results=results,
            )
        )
    return out


def _toml(text: str) -> dict[str, Any]:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except ValueError:
        return {}
    return data


def design_files(design_text: str, base_dir: str | Path | None) -> list[RawInput]:
    """Read the files a design file names (a lift table, CSV error functions) whole.

    Parameters
    ----------
    design_text : str
        The design file's TOML text.
    base_dir : str or Path or None
        Its directory (relative paths are resolved against it); None for a built-in
        example, which names none.

    Returns
    -------
    list of RawInput
        Role ``design:<the path as written>``, for every named file that exists.
    """
    if base_dir is None:
        return []
    data = _toml(design_text)
    named: list[str] = []
    motion = data.get("motion")
    if isinstance(motion, dict) and isinstance(motion.get("table_file"), str):
        named.append(motion["table_file"])
    table = data.get("inspection")
    if isinstance(table, dict):
        named += [v for k, v in table.items() if k.endswith("_um") and isinstance(v, str)]
    out = []
    for written in dict.fromkeys(n.strip() for n in named if n.strip()):
        if not (written.lower().endswith(".csv") or written == _motion_file(motion)):
            continue
        path = Path(written)
        path = path if path.is_absolute() else Path(base_dir) / path
        if path.is_file():
            out.append(RawInput(f"design:{written}", str(path), path.read_bytes()))
    return out


def _motion_file(motion: Any) -> str | None:
    if isinstance(motion, dict) and isinstance(motion.get("table_file"), str):
        return str(motion["table_file"]).strip()
    return None


def restore_files(inputs: Sequence[RawInput], folder: Path) -> dict[str, str]:
    """Write raw files back into a folder: role → path (named as they were).

    Parameters
    ----------
    inputs : sequence of RawInput
        The record's raw inputs (those given as text are skipped).
    folder : Path
        An empty folder.

    Returns
    -------
    dict of str to str
        Each file input's role and where it now is.
    """
    out = {}
    for k, raw in enumerate(inputs):
        if not raw.is_file or raw.role.startswith("design:"):
            continue
        sub = folder / f"{k:02d}"
        sub.mkdir()
        path = sub / (Path(raw.name).name or "input.csv")
        path.write_bytes(raw.data)
        out[raw.role] = str(path)
    return out
