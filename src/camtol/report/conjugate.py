"""Reports of conjugate designs: both cams' curves, and the fixture analysis (THEORY §4).

Used by ``camtol analyze`` on a conjugate design (both profiles, pressure and shift angles
per cam) and by ``camtol conjugate`` (extremes, acceptance verdicts, failing intervals).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol._version import __version__
from camtol.analysis.extremes import Extreme
from camtol.analysis.result import Analysis
from camtol.jet import FloatArray
from camtol.pair.acceptance import merge_intervals
from camtol.pair.fixture import FixtureInspection
from camtol.pair.fixture_spec import FixtureSpec
from camtol.report.units import fmt

if TYPE_CHECKING:
    from camtol.pair.indicator import RecordEstimates
    from camtol.report.terminal import Terminal

__all__ = [
    "conjugate_analysis_json",
    "conjugate_profile_columns",
    "fixture_curves_columns",
    "fixture_json",
    "print_fixture",
    "write_fixture_curves_csv",
]


def conjugate_profile_columns(
    a: Analysis, cols: dict[str, np.ndarray[Any, Any]]
) -> dict[str, np.ndarray[Any, Any]]:
    """Curves of ``camtol analyze`` for a conjugate design: both cams' profiles and angles.

    The single-contact columns (cam A) are kept; ``x_mm, y_mm`` become ``xA_mm, yA_mm``
    and cam B's ``xB_mm, yB_mm``, radius, pressure and shift angles and radius of
    curvature follow (suffix ``_A``/``_B``).

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.
    cols : dict of str to ndarray
        Single-contact columns from :func:`camtol.report.tables.curves_columns`, keyed by
        CSV column name (units in the names).

    Returns
    -------
    dict of str to ndarray
        The columns with the cam A/B renaming and cam B's columns added, in CSV order.
    """
    kb = a.cam_kinematics("B")
    out: dict[str, np.ndarray[Any, Any]] = {}
    for name, values in cols.items():
        if name == "x_mm":
            out["xA_mm"] = values
            out["yA_mm"] = cols["y_mm"]
            out["xB_mm"] = kb.contact_x_mm
            out["yB_mm"] = kb.contact_y_mm
        elif name == "y_mm":
            continue
        elif name in ("radius_mm", "curvature_radius_mm"):
            stem = name.removesuffix("_mm")
            out[f"{stem}_A_mm"] = values
            out[f"{stem}_B_mm"] = getattr(kb, name)
        elif name in ("pressure_angle_deg", "shift_angle_deg"):
            stem = name.removesuffix("_deg")
            out[f"{stem}_A_deg"] = values
            out[f"{stem}_B_deg"] = np.degrees(getattr(kb, f"{stem}_rad"))
        else:
            out[name] = values
    return out


def conjugate_analysis_json(a: Analysis) -> dict[str, Any]:
    """Cam B's validity figures for the JSON of ``camtol analyze`` on a conjugate design.

    Parameters
    ----------
    a : Analysis
        Result of :func:`camtol.analysis.result.analyse` for the design.

    Returns
    -------
    dict
        Cam B's largest radius and smallest radius of curvature [mm], where it occurs, and
        the ranges of its pressure and shift angles [deg].
    """
    kb = a.cam_kinematics("B")
    i = int(np.argmin(kb.curvature_radius_mm))
    return {
        "max_radius_mm": float(kb.radius_mm.max()),
        "min_curvature_radius_mm": float(kb.curvature_radius_mm[i]),
        "min_curvature_at_deg": float(np.degrees(kb.theta_rad[i])),
        "pressure_angle_deg": [
            float(np.degrees(kb.pressure_angle_rad.min())),
            float(np.degrees(kb.pressure_angle_rad.max())),
        ],
        "shift_angle_deg": [
            float(np.degrees(kb.shift_angle_rad.min())),
            float(np.degrees(kb.shift_angle_rad.max())),
        ],
    }


#: Fixture columns that may be empty as a whole (all NaN): without a measured Δf, or
#: without the prediction of Δf_est from known errors.
OPTIONAL_FIXTURE_COLUMNS = ("df_mea_um", "df_est_pred_um", "dr_A_est_um", "dr_B_est_um")


def fixture_curves_columns(
    res: FixtureInspection, *, record: RecordEstimates | None = None
) -> dict[str, FloatArray]:
    """Every fixture curve on the grid, keyed by CSV column name (µm, degrees).

    Parameters
    ----------
    res : FixtureInspection
        Result of the conjugate-cam fixture analysis (THEORY §4).
    record : RecordEstimates, optional
        With an indicator record (THEORY §4.4): adds ``u_f_um`` and the estimates at
        Δf_mea ± u_f, ``dr_A_est_upper_um``, ``dr_A_est_lower_um``, ``dr_B_est_upper_um``,
        ``dr_B_est_lower_um`` [µm], on the same grid.

    Returns
    -------
    dict of str to ndarray
        ``theta_deg`` [deg] then the variation, estimate and band curves [µm]; estimate
        columns are NaN when the inspection has no measurement. ``df_est_pred_um`` is the
        Δf_est of CW11 eqs. 14-18 from the known errors of both cams (the master errors),
        beside the measured ``df_mea_um`` (whose ``df_est_um`` is the measurement itself).
    """
    v, b = res.variation, res.bands
    nan = np.full(res.theta_rad.shape, np.nan)
    est = res.estimate
    cols = {
        "theta_deg": np.degrees(res.theta_rad),
        "df_r_um": v.df_r_um,
        "df_rf_um": v.df_rf_um,
        "df_l_um": v.df_l_um,
        "df_eta_um": v.df_eta_um,
        "df_est_um": v.df_est_um,
        "df_mea_um": est.df_mea_um if est is not None else nan,
        "df_est_pred_um": res.predicted.df_est_um if res.predicted is not None else nan,
        "dr_A_est_um": est.dr_a_est_um if est is not None else nan,
        "dr_B_est_um": est.dr_b_est_um if est is not None else nan,
        "df_A_upper_um": b.df_a_upper_um,
        "df_A_lower_um": b.df_a_lower_um,
        "df_B_upper_um": b.df_b_upper_um,
        "df_B_lower_um": b.df_b_lower_um,
        "pressure_angle_A_deg": np.degrees(res.factors.pressure_a_rad),
        "pressure_angle_B_deg": np.degrees(res.factors.pressure_b_rad),
        "shift_angle_A_deg": np.degrees(res.factors.shift_a_rad),
        "shift_angle_B_deg": np.degrees(res.factors.shift_b_rad),
    }
    if record is not None:
        cols |= {f"{k}_um": v for k, v in record.curves().items()}
    return cols


def write_fixture_curves_csv(
    res: FixtureInspection, path: str | Path, *, record: RecordEstimates | None = None
) -> None:
    """Write one row per grid angle (atomically).

    Parameters
    ----------
    res : FixtureInspection
        Result of the conjugate-cam fixture analysis (THEORY §4).
    path : str or Path
        CSV file to write; replaced if it exists.
    record : RecordEstimates, optional
        With an indicator record: adds the columns of u_f and of the estimates at
        Δf_mea ± u_f (see :func:`fixture_curves_columns`). [µm]
    """
    from camtol.files import atomic_write
    from camtol.report.csv_text import csv_text
    from camtol.report.finite import require_finite_columns

    cols = fixture_curves_columns(res, record=record)
    require_finite_columns(cols, optional=OPTIONAL_FIXTURE_COLUMNS, where=str(path))
    data = np.column_stack(list(cols.values()))
    atomic_write(path, csv_text(list(cols), data, blank_nonfinite=True))


def _extreme(mx: Extreme, mn: Extreme) -> dict[str, Any]:
    return {
        "min": mn.value,
        "min_at_deg": round(mn.theta_deg, 4),
        "min_ranges_deg": [[round(a, 4), round(b, 4)] for a, b in mn.ranges_deg],
        "max": mx.value,
        "max_at_deg": round(mx.theta_deg, 4),
        "max_ranges_deg": [[round(a, 4), round(b, 4)] for a, b in mx.ranges_deg],
    }


def fixture_json(
    res: FixtureInspection,
    spec: FixtureSpec,
    name: str,
    *,
    record: RecordEstimates | None = None,
) -> dict[str, Any]:
    """JSON-ready dict: inputs, extremes of every curve, verdicts and failing intervals.

    Parameters
    ----------
    res : FixtureInspection
        Result of the conjugate-cam fixture analysis (THEORY §4).
    spec : FixtureSpec
        The fixture specification the inspection was run with (tolerances and errors).
    name : str
        Design name written to the ``design`` field.
    record : RecordEstimates, optional
        With an indicator record (THEORY §4.4): adds a ``record`` object (revolutions,
        samples per revolution min/max, ``discarded_samples``, ``dropped_revolutions``
        (``revolution``, ``first_sample``, ``last_sample``, 1-based, with
        ``--drop-bad-revolutions``), ``u_f_max_um``, ``u_f_rms_um``, ``df_mea_rms_um``,
        notes) and the extremes of ``u_f_um`` and of the estimates at Δf_mea ± u_f
        (``dr_A_est_upper_um``, ``dr_A_est_lower_um``, ``dr_B_est_upper_um``,
        ``dr_B_est_lower_um``). The verdicts stay those of the mean record.

    Returns
    -------
    dict
        JSON-ready dict; lengths in µm and angles in degrees, as the keys say. With a
        measurement, ``prediction`` compares the Δf_est of CW11 eqs. 14-18 from the known
        errors of both cams (``master_A``, ``master_B``) with Δf_mea:
        ``df_est_minus_mea_rms_um``, ``df_est_minus_mea_max_abs_um`` and ``at_deg``
        (null without a measurement).
    """
    th = np.degrees(res.theta_rad)
    extremes = {f"{k}_um": _extreme(mx, mn) for k, (mx, mn) in res.extremes.items()}
    if record is not None:
        extremes |= {f"{k}_um": _extreme(mx, mn) for k, (mx, mn) in record.extremes.items()}
    e = spec.errors
    out = {
        "camtol_version": __version__,
        "design": name,
        "step_deg": float(th[1] - th[0]),
        "inputs": {
            "tolerance_A_um": list(spec.tolerance_a_um),
            "tolerance_B_um": list(spec.tolerance_b_um),
            "dl_A_um": e.dl_a_mm * 1e3,
            "dl_B_um": e.dl_b_mm * 1e3,
            "drr_C_um": e.drr_c_mm * 1e3,
            "drr_D_um": e.drr_d_mm * 1e3,
            "deta_deg": math.degrees(e.deta_rad),
            "master_A": spec.master_a.description,
            "master_B": spec.master_b.description,
            "df_mea": spec.df_mea.description if spec.df_mea is not None else None,
        },
        "extremes": extremes,
        "prediction": _prediction_json(res),
        "verdicts": {
            cam: {
                "passed": v.passed,
                "failing_intervals_deg": [
                    [round(a, 4), round(b, 4)] for a, b in v.failing_intervals_deg
                ],
                "failing_stretches_deg": [
                    [round(a, 4), round(b, 4)]
                    for a, b in merge_intervals(v.failing_intervals_deg, MERGE_GAP_DEG)
                ],
                "stretch_merge_gap_deg": MERGE_GAP_DEG,
                "min_margin_um": v.min_margin_um,
            }
            for cam, v in res.verdicts.items()
        },
        "passed": res.passed,
    }
    if record is not None:
        out["record"] = _record_json(record)
    return out


def _prediction_json(res: FixtureInspection) -> dict[str, Any] | None:
    """Δf_est (eqs. 14-18, known errors) against Δf_mea: rms and largest difference."""
    diff = res.df_est_minus_mea_um
    if diff is None:
        return None
    i = int(np.argmax(np.abs(diff)))
    return {
        "known_errors": "master_A, master_B",
        "df_est_minus_mea_rms_um": float(np.sqrt(np.mean(diff**2))),
        "df_est_minus_mea_max_abs_um": float(abs(diff[i])),
        "at_deg": float(np.degrees(res.theta_rad[i])),
    }


def _record_json(record: RecordEstimates) -> dict[str, Any]:
    p = record.processed
    return {
        "source": p.source,
        "revolutions": p.revolutions,
        "samples_per_revolution": {
            "min": int(p.samples_per_revolution.min()),
            "max": int(p.samples_per_revolution.max()),
        },
        "discarded_samples": p.discarded_samples,
        "dropped_revolutions": [
            {"revolution": n, "first_sample": a, "last_sample": b}
            for n, a, b in p.dropped_revolutions
        ],
        "grid_step_deg": float(p.theta_deg[1] - p.theta_deg[0]),
        "u_f_max_um": p.u_f_max_um,
        "u_f_rms_um": p.u_f_rms_um,
        "df_mea_rms_um": p.df_mea_rms_um,
        "notes": list(p.notes),
    }


#: Failing intervals closer than this are reported together as one stretch. [deg]
MERGE_GAP_DEG = 1.0


def _interval_text(intervals: list[tuple[float, float]]) -> str:
    stretches = merge_intervals(intervals, MERGE_GAP_DEG)
    text = ", ".join(f"{a:.2f}-{b:.2f}°" for a, b in stretches)
    if len(stretches) < len(intervals):
        text += (
            f" ({len(intervals)} intervals joined across gaps < {MERGE_GAP_DEG:g}°;"
            " the exact ones are in --json)"
        )
    return text


#: Human labels of the fixture's curves in the terminal table (THEORY §4).
FIXTURE_LABELS: dict[str, str] = {
    "df_r": "Δf_r (profile errors)",
    "df_rf": "Δf_rf (roller radii)",
    "df_l": "Δf_l (arm lengths)",
    "df_eta": "Δf_η (arm angle η)",
    "df_est": "Δf_est (total)",
    "df_mea": "Δf_mea (measured)",
    "dr_A_est": "Δr_A,est (cam A)",
    "dr_B_est": "Δr_B,est (cam B)",
    "df_est_pred": "Δf_est predicted",
    "df_A_upper": "cam A band: upper Δf",
    "df_A_lower": "cam A band: lower Δf",
    "df_B_upper": "cam B band: upper Δf",
    "df_B_lower": "cam B band: lower Δf",
}


def fixture_label(key: str) -> str:
    """Human label of a fixture curve key (the key itself when unknown)."""
    return FIXTURE_LABELS.get(key, key)


def print_fixture(
    res: FixtureInspection,
    spec: FixtureSpec,
    name: str,
    *,
    terminal: Terminal | None = None,
    record: RecordEstimates | None = None,
) -> None:
    """Print the extremes table and the verdicts (colour only on a terminal).

    Parameters
    ----------
    res : FixtureInspection
        Result of the conjugate-cam fixture analysis (THEORY §4).
    spec : FixtureSpec
        The fixture specification the inspection was run with (tolerances and errors).
    name : str
        Design name shown in the heading.
    terminal : Terminal, optional
        Where to print (:class:`camtol.report.terminal.Terminal`); standard output by
        default.
    record : RecordEstimates, optional
        With an indicator record (THEORY §4.4): prints the record's summary and the
        extremes of the estimates at Δf_mea ± u_f.
    """
    from camtol.report.terminal import EXTREMES_COLUMNS, Terminal

    term = terminal or Terminal()
    term.paragraph(f"{name}: conjugate-cam fixture analysis (camtol {__version__})", "bold")
    e = spec.errors
    term.key_values(
        [
            ("tolerance cam A", f"{spec.tolerance_a_um[0]:g} .. {spec.tolerance_a_um[1]:g} µm"),
            ("tolerance cam B", f"{spec.tolerance_b_um[0]:g} .. {spec.tolerance_b_um[1]:g} µm"),
            ("Δl_A, Δl_B", f"{e.dl_a_mm * 1e3:g} µm, {e.dl_b_mm * 1e3:g} µm"),
            ("Δr_rC, Δr_rD", f"{e.drr_c_mm * 1e3:g} µm, {e.drr_d_mm * 1e3:g} µm"),
            ("Δη", f"{math.degrees(e.deta_rad):g}°"),
            ("master cam A", spec.master_a.description),
            ("master cam B", spec.master_b.description),
            ("measured Δf", spec.df_mea.description if spec.df_mea else "(none)"),
        ]
    )
    th = np.degrees(res.theta_rad)
    rows = [
        (
            fixture_label(key),
            "µm",
            fmt(mx.value),
            "\n".join(mx.where.split(", ")),
            fmt(mn.value),
            "\n".join(mn.where.split(", ")),
        )
        for key, (mx, mn) in res.extremes.items()
    ]
    term.table(
        EXTREMES_COLUMNS, rows, title=f"Extremes over 0-360° (grid {th[1] - th[0]:g}°, refined)"
    )
    if record is not None:
        _print_record(term, record)
    pred = _prediction_json(res)
    if pred is not None:
        term.paragraph(
            "Δf_est from the known errors of both cams (CW11 eqs. 14-18; the master errors)"
            f" − Δf_mea: rms {pred['df_est_minus_mea_rms_um']:.3f} µm, largest"
            f" {pred['df_est_minus_mea_max_abs_um']:.3f} µm at θ = {pred['at_deg']:.1f}°"
        )
    if not res.verdicts:
        term.paragraph("No measured Δf: forward variation of the master pair only; no verdict.")
        return
    for cam, v in res.verdicts.items():
        if v.passed:
            term.paragraph(f"cam {cam}: PASS (min margin {v.min_margin_um:.3f} µm)", "green")
        else:
            term.paragraph(
                f"cam {cam}: FAIL at θ = {_interval_text(v.failing_intervals_deg)}"
                f" (worst margin {v.min_margin_um:.3f} µm)",
                "red",
            )
    term.paragraph(
        "Acceptance (THEORY §4.3, a necessary condition): Δf_lower,est ≤ Δf_mea ≤ Δf_upper,est;"
        " interval ends located to 1e-4°.",
        "dim",
    )


def _print_record(term: Terminal, record: RecordEstimates) -> None:
    """Print the indicator record's summary and the worst-case estimates (THEORY §4.4)."""
    p = record.processed
    n = p.samples_per_revolution
    spr = f"{n.min()}" if n.min() == n.max() else f"{n.min()}-{n.max()}"
    term.paragraph(
        f"Indicator record {p.source}: {p.revolutions} revolution(s), {spr} samples per"
        f" revolution, resampled every {p.theta_deg[1] - p.theta_deg[0]:g}°;"
        f" rms Δf_mea {p.df_mea_rms_um:.3f} µm, u_f (3σ over revolutions)"
        f" rms {p.u_f_rms_um:.3f} µm, max {p.u_f_max_um:.3f} µm"
    )
    for note in p.notes:
        term.paragraph(f"  note: {note}", "dim", indent="    ")
    for cam in ("A", "B"):
        hi = record.extremes[f"dr_{cam}_est_upper"]
        lo = record.extremes[f"dr_{cam}_est_lower"]
        term.paragraph(
            f"  Δr_{cam},est at Δf_mea + u_f: {hi[1].value:.3f} .. {hi[0].value:.3f} µm;"
            f" at Δf_mea − u_f: {lo[1].value:.3f} .. {lo[0].value:.3f} µm",
            indent="    ",
        )
    term.paragraph(
        "  Verdicts are taken on the mean record Δf_mea (a necessary condition on the mean).",
        "dim",
        indent="    ",
    )
