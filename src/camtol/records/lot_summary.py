"""A production lot from the store, summarised: which records pool, and their statistics.

:func:`summarise_lot` takes the records a query returned (``camtol records stats``; the
Python API gets the same) and refuses to pool what must not be pooled (records of several
cams, records judged against different tolerances or on different deviations, Δn and Δr),
orders the parts in production (integer serials when every record has one, else
inspection order), and computes :func:`~camtol.records.lots.lot_statistics` (per-angle
figures, yield, trend) and, on one characteristic per part (:data:`CHARACTERISTICS`), the
statistical process control of :mod:`camtol.spc`: capability (ISO 22514-2), the control
chart and its run rules. :meth:`LotSummary.to_dict` is the ``records stats --json``
document (schema ``records-stats.schema.json``, schema_version 2.0).

Why one module: it is the one place that turns stored records into a lot, deciding what
pools (cams, tolerances, judgement bases, motion specs), which value each record
contributes (:func:`characteristic_values`), in which production order, against which
frozen limits, and how the result reads as the JSON document; split, those decisions
would have to agree across modules. The statistics themselves are in :mod:`camtol.spc`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from camtol.exceptions import RecordError
from camtol.records.lots import LotStatistics, lot_statistics
from camtol.records.record import InspectionRecord
from camtol.spc.binomial import clopper_pearson
from camtol.spc.capability import Capability, capability
from camtol.spc.charts import ChartLimits, ControlChart, chart_limits, control_chart, within_sigma
from camtol.spc.rules import run_rules

__all__ = [
    "CHARACTERISTICS",
    "JSON_SCHEMA_VERSION",
    "LotSpc",
    "LotSummary",
    "characteristic_values",
    "summarise_lot",
]

#: ``schema_version`` of the ``records stats --json`` document (2.0: ``cp``/``cpk`` are
#: within-σ indices of one characteristic, no longer overall-σ figures of the extremes).
JSON_SCHEMA_VERSION = "2.0"

#: Characteristic → (description, which limit it has). The deviation is the one the
#: records were judged on: Δn (the method's results) when judged on Δn, else Δr.
CHARACTERISTICS: dict[str, tuple[str, str]] = {
    "max_dev": ("largest deviation of the part", "upper"),
    "min_dev": ("smallest deviation of the part", "lower"),
    "form": ("form (largest minus smallest deviation)", "upper"),
    "max_abs_ds": ("largest |ΔS| of the follower motion", "upper"),
}


@dataclass(frozen=True)
class LotSpc:
    """Statistical process control of one characteristic over a lot.

    Attributes
    ----------
    characteristic : str
        A key of :data:`CHARACTERISTICS`.
    unit : str
        Unit of the values (``um``, or ``deg`` for the swing of ``max_abs_ds``).
    order : tuple of int
        Indices into the summary's records in production order.
    values : ndarray
        The characteristic per part, in production order. [unit]
    capability : Capability
    chart : ControlChart
    rules : {"we", "nelson"}
    out_of_control : tuple of (int, str, str)
        (record id, serial, rule code) of every flagged part, in production order.
    warnings : tuple of str
    """

    characteristic: str
    unit: str
    order: tuple[int, ...]
    values: np.ndarray[Any, np.dtype[np.float64]]
    capability: Capability
    chart: ControlChart
    rules: str
    out_of_control: tuple[tuple[int, str, str], ...]
    warnings: tuple[str, ...]


@dataclass(frozen=True)
class LotSummary:
    """The statistics of one lot and the records they pool.

    Attributes
    ----------
    design_name : str
        The design the records were checked against.
    lot : str or None
        The lot selected (None: every record of the design).
    records : tuple of InspectionRecord
        The pooled records, oldest first.
    statistics : LotStatistics
        Per-angle and per-part figures, failing fraction, trend.
    trend_basis : {"serial", "inspection order"}
        What orders the parts for the trend and the control chart.
    spc : LotSpc
        Capability, control chart and run rules of the chosen characteristic.
    yield_ci95 : tuple of float
        Clopper-Pearson 95 % interval of the yield (passing fraction).
    per_angle : bool
        Whether the records came with their curves: without them (the web page reads
        summaries only) the per-part extremes are the records' own and the per-angle
        figures are None.
    """

    design_name: str
    lot: str | None
    records: tuple[InspectionRecord, ...]
    statistics: LotStatistics
    trend_basis: str
    spc: LotSpc
    yield_ci95: tuple[float, float]
    per_angle: bool = True

    def to_dict(self) -> dict[str, Any]:
        """Return the ``records stats --json`` document (non-finite figures as None).

        Returns
        -------
        dict
            Keys as documented in docs/records.md. [µm, µm per part]
        """
        st, recs, spc = self.statistics, self.records, self.spc
        cap, chart = spc.capability, spc.chart
        lim = chart.limits

        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        def ang(x: float) -> float | None:  # a per-angle figure: None without curves
            return num(x) if self.per_angle else None

        by_point = {i: k for k, members in enumerate(chart.members) for i in members}
        parts = []
        for pos, i in enumerate(spc.order):
            r = recs[i]
            parts.append(
                {
                    "record_id": r.id,
                    "serial": r.serial,
                    "value": float(spc.values[pos]),
                    "verdict": r.verdict,
                    "point": by_point.get(pos),
                }
            )
        doc: dict[str, Any] = {
            "design_name": self.design_name,
            "lot": self.lot,
            "cam": recs[0].cam,
            "design_hashes": sorted({r.design_hash for r in recs}),
            "methods": sorted({r.method for r in recs}),
            "record_ids": [r.id for r in recs],
            "judged_on": recs[0].judged_on,
            "characteristic": spc.characteristic,
            "unit": spc.unit,
            "count": cap.count,
            "spec": {"lsl": cap.lsl, "usl": cap.usl},
            "mean": cap.mean,
            "sigma": {
                "overall": num(cap.sigma_overall),
                "within": num(cap.sigma_within),
                "within_method": cap.within_method,
                "dof_overall": cap.dof_overall,
                "dof_within": num(cap.dof_within),
            },
        }
        doc.update({k: v.to_dict() for k, v in cap.indices.items()})
        doc.update(
            {
                "capable": cap.capable,
                "capable_at": cap.capable_at,
                "capable_basis": cap.capable_basis,
                "normality": {
                    "test": "Anderson-Darling",
                    "statistic": num(cap.normality.statistic),
                    "p_value": num(cap.normality.p_value),
                    "normal": cap.normality.normal,
                },
                "percentile": (
                    {"method": cap.percentile_method, **cap.percentile} if cap.percentile else None
                ),
                "chart": {
                    "kind": lim.kind,
                    "subgroup": lim.subgroup,
                    "frozen": chart.frozen,
                    "center": lim.center,
                    "lcl": lim.lcl,
                    "ucl": lim.ucl,
                    "dispersion_center": lim.dispersion_center,
                    "dispersion_lcl": lim.dispersion_lcl,
                    "dispersion_ucl": lim.dispersion_ucl,
                    "left_out": chart.left_out,
                },
                "rules": spc.rules,
                "out_of_control": [
                    {"record_id": rid, "serial": serial, "rule": rule}
                    for rid, serial, rule in spc.out_of_control
                ],
                "yield": {"value": 1.0 - st.fraction_failing, "ci95": list(self.yield_ci95)},
                "parts": parts,
                "warnings": list(spc.warnings),
                "n_parts": st.n_parts,
                "n_points": int(st.theta_deg.size) if self.per_angle else None,
                "record_n_points": sorted({r.n_points for r in recs}),
                "tolerance_um": list(st.tolerance_um),
                "mean_of_max_um": float(st.part_max_um.mean()),
                "mean_of_min_um": float(st.part_min_um.mean()),
                "envelope_max_um": ang(float(st.max_um.max())),
                "envelope_min_um": ang(float(st.min_um.min())),
                "max_std_um": ang(float(st.std_um.max())),
                "n_failing": st.n_failing,
                "fraction_failing": st.fraction_failing,
                "fraction_failing_ci": list(st.fraction_failing_ci),
                "confidence": st.confidence,
                "trend_basis": self.trend_basis,
                "trend_um_per_part": num(st.trend_um_per_part),
                "trend_stderr_um_per_part": num(st.trend_stderr_um_per_part),
            }
        )
        return doc


def production_order(records: Sequence[InspectionRecord]) -> tuple[list[float], str]:
    """Production order for the trend: integer serials when all have one, else time order.

    Parameters
    ----------
    records : sequence of InspectionRecord
        The lot's records, oldest first.

    Returns
    -------
    (list of float, str)
        The parts' positions and what they are (``serial`` or ``inspection order``).
    """
    try:
        return [float(int(r.serial)) for r in records], "serial"
    except ValueError:
        return [float(i) for i in range(len(records))], "inspection order"


def characteristic_values(
    records: Sequence[InspectionRecord], characteristic: str
) -> tuple[np.ndarray[Any, np.dtype[np.float64]], float | None, float | None, str]:
    """Return the characteristic of each record, its specification limits and unit.

    Parameters
    ----------
    records : sequence of InspectionRecord
        Records already checked to pool (one tolerance, one judgement basis).
    characteristic : str
        A key of :data:`CHARACTERISTICS`.

    Returns
    -------
    (ndarray, float or None, float or None, str)
        Values, lower and upper specification limits, unit (``um`` or ``deg``).

    Raises
    ------
    RecordError
        An unknown characteristic, or one some records lack (naming the first of them).
    """
    if characteristic not in CHARACTERISTICS:
        raise RecordError(
            f"--characteristic={characteristic!r}: allowed {', '.join(CHARACTERISTICS)}"
        )
    lo, hi = records[0].tolerance_um
    if characteristic == "max_abs_ds":
        return _motion_values(records)
    dn = records[0].judged_on == "dn"
    key = {"max_dev": "max_dn_um", "min_dev": "min_dn_um", "form": "form_dn_um"}[characteristic]
    values = []
    for r in records:
        if dn:
            v = (r.results or {}).get(key)
            if v is None:
                raise RecordError(
                    f"--characteristic={characteristic}: record id {r.id} was judged on Δn"
                    f" but keeps no {key} in its results; select records made by camtol"
                    " inspect, or another characteristic"
                )
            values.append(float(v))
        else:
            values.append(
                {"max_dev": r.max_dev_um, "min_dev": r.min_dev_um, "form": r.form_um}[
                    characteristic
                ]
            )
    x = np.asarray(values, dtype=np.float64)
    if characteristic == "max_dev":
        return x, None, hi, "um"
    if characteristic == "min_dev":
        return x, lo, None, "um"
    return x, None, hi - lo, "um"


def _motion_values(
    records: Sequence[InspectionRecord],
) -> tuple[np.ndarray[Any, np.dtype[np.float64]], float | None, float | None, str]:
    """|ΔS| per record and the motion spec it was judged against (µm for a lift, deg swing)."""
    specs, units = set(), set()
    values = []
    for r in records:
        opts = r.options or {}
        lift, swing = r.max_abs_ds_um, getattr(r, "max_abs_ds_deg", None)
        if lift is None and swing is None:
            raise RecordError(
                f"--characteristic=max_abs_ds: record id {r.id} (serial {r.serial!r}) has no"
                " measured |ΔS| (its method gives none); choose max_dev, min_dev or form"
            )
        spec, unit = (
            (opts.get("spec_um"), "um") if lift is not None else (opts.get("spec_deg"), "deg")
        )
        if spec is None:
            raise RecordError(
                f"--characteristic=max_abs_ds: record id {r.id} (serial {r.serial!r}) was"
                f" judged without a motion spec (--spec-{unit}): no upper limit"
            )
        specs.add(float(spec))
        units.add(unit)
        values.append(float(lift if lift is not None else swing))  # type: ignore[arg-type]
    if len(specs) > 1 or len(units) > 1:
        raise RecordError(
            "--characteristic=max_abs_ds: records judged against different motion specs"
            f" {sorted(specs)} ({', '.join(sorted(units))}); select one lot with --lot"
        )
    return np.asarray(values, dtype=np.float64), None, specs.pop(), units.pop()


def _check_pooling(recs: Sequence[InspectionRecord], where: str) -> None:
    """Refuse records of several cams, tolerances or judgement bases (naming them)."""
    cams = sorted({r.cam or "single" for r in recs})
    if len(cams) > 1:
        raise RecordError(
            f"{where}: records of cams {', '.join(cams)}; give --cam with one of them"
        )
    tolerances = sorted({r.tolerance_um for r in recs})
    if len(tolerances) > 1:
        raise RecordError(
            f"{where}: records taken against different tolerances {tolerances} µm; select one"
            " lot with --lot"
        )
    bases = sorted({r.judged_on for r in recs if r.judged_on is not None})
    if len(bases) > 1:
        raise RecordError(
            f"{where}: records judged on different deviations (Δn and Δr: judged_on"
            f" {', '.join(bases)}) with their tolerances; select them with --method or --lot"
        )


def _default_chart(subgroup: int) -> str:
    return "imr" if subgroup <= 1 else ("xbar-r" if subgroup <= 8 else "xbar-s")


def reference_limits(
    records: Sequence[InspectionRecord],
    *,
    lot: str,
    characteristic: str,
    chart: str,
    subgroup: int,
    method: str | None = None,
) -> tuple[ChartLimits, tuple[float, float], str | None]:
    """Control limits frozen from a reference lot's records (``--limits-from LOT``).

    Returns
    -------
    (ChartLimits, (float, float), str or None)
        The limits, and the reference records' tolerance and judgement basis (the lot
        charted against them must share both).
    """
    recs = [r for r in records if method is None or r.method == method]
    if not recs:
        raise RecordError(
            f"--limits-from={lot!r}: no records of that lot (see `camtol records list`)"
        )
    _check_pooling(recs, f"--limits-from={lot!r}")
    order, _ = production_order(recs)
    idx = sorted(range(len(recs)), key=lambda i: order[i])
    values, _, _, _ = characteristic_values([recs[i] for i in idx], characteristic)
    return (
        chart_limits(values, chart, subgroup),
        recs[0].tolerance_um,
        recs[0].judged_on,
    )


def summarise_lot(
    records: Sequence[InspectionRecord],
    *,
    design: str,
    lot: str | None = None,
    method: str | None = None,
    confidence: float = 0.95,
    characteristic: str = "max_dev",
    subgroup: int = 1,
    chart: str | None = None,
    rules: str = "we",
    capable_at: float = 1.33,
    reference: tuple[ChartLimits, tuple[float, float], str | None] | None = None,
) -> LotSummary:
    """Pool a lot's records (with their curves) and compute its statistics.

    Parameters
    ----------
    records : sequence of InspectionRecord
        The records a store query returned for the design (and lot, cam), with curves.
    design : str
        The design's name (for the result and messages).
    lot : str, optional
        The lot queried (for the result and messages).
    method : {"cmm", "conjugate-fixture"}, optional
        Keep only records of this inspection method.
    confidence : float
        Level of the failing fraction's interval (Clopper-Pearson), in (0, 1).
    characteristic : str
        Per-part characteristic of the capability and the chart (:data:`CHARACTERISTICS`).
    subgroup : int
        Subgroup size N of the chart and of σ_within (1: individuals).
    chart : {"imr", "xbar-r", "xbar-s"}, optional
        Chart kind; by default ``imr`` for individuals, ``xbar-r`` up to N = 8, else
        ``xbar-s``.
    rules : {"we", "nelson"}
        Run rules flagged on the chart.
    capable_at : float
        Threshold of the capability judgement.
    reference : tuple, optional
        Frozen limits from :func:`reference_limits` (``--limits-from``).

    Returns
    -------
    LotSummary

    Raises
    ------
    RecordError
        A confidence outside (0, 1); no record; records of several cams, judged against
        different tolerances or on different deviations (Δn, Δr) (naming what to select);
        a characteristic the records lack; a subgroup larger than the lot; reference limits
        of another basis.
    """
    if not (math.isfinite(confidence) and 0.0 < confidence < 1.0):
        raise RecordError(
            f"--confidence={confidence!r}: allowed a level between 0 and 1, e.g. 0.95"
        )
    if characteristic not in CHARACTERISTICS:
        raise RecordError(
            f"--characteristic={characteristic!r}: allowed {', '.join(CHARACTERISTICS)}"
        )
    if subgroup < 1:
        raise RecordError(f"--subgroup={subgroup}: allowed 1 (individuals) or an integer ≥ 2")
    recs = [r for r in records if method is None or r.method == method]
    where = f"--design={design!r}" + ("" if lot is None else f" --lot={lot!r}")
    where += "" if method is None else f" --method={method}"
    if not recs:
        raise RecordError(f"{where}: no records match in the store (see `camtol records list`)")
    _check_pooling(recs, where)
    if subgroup > len(recs):
        raise RecordError(
            f"--subgroup={subgroup}: larger than the lot ({len(recs)} parts); allowed 2 to"
            f" {len(recs)}"
        )
    if len(recs) < 2:
        raise RecordError(
            f"{where}: a single record; capability and a control chart need at least 2 parts"
        )
    kind = chart or _default_chart(subgroup)
    order, basis = production_order(recs)
    idx = tuple(sorted(range(len(recs)), key=lambda i: order[i]))
    values, lsl, usl, unit = characteristic_values([recs[i] for i in idx], characteristic)

    frozen: ChartLimits | None = None
    if reference is not None:
        frozen, ref_tol, ref_basis = reference
        if ref_tol != recs[0].tolerance_um or ref_basis != recs[0].judged_on:
            raise RecordError(
                f"--limits-from: the reference lot was judged against {list(ref_tol)} µm on"
                f" {ref_basis}, this lot against {list(recs[0].tolerance_um)} µm on"
                f" {recs[0].judged_on}: its limits do not apply"
            )
    cc: ControlChart = control_chart(values, kind, subgroup, limits=frozen)
    sigma_w, dof_w, how = within_sigma(values, subgroup)
    cap = capability(
        values,
        lsl=lsl,
        usl=usl,
        sigma_within=sigma_w,
        dof_within=dof_w,
        within_method=how,
        capable_at=capable_at,
    )
    flags = run_rules(cc.points, cc.limits.center, cc.limits.sigma, rules)
    flagged = []
    for k in range(cc.points.size):
        for code, hit in flags.items():
            if hit[k]:
                flagged += [
                    (int(recs[idx[m]].id or 0), recs[idx[m]].serial, code) for m in cc.members[k]
                ]
    warnings = list(cap.warnings)
    if cc.left_out:
        warnings.append(
            f"the last {cc.left_out} part(s) do not fill a subgroup of {subgroup}: not charted"
        )
    if flagged:
        warnings.append(
            f"{len(flagged)} out-of-control signal(s): the process is not in statistical"
            " control, Cp/Cpk describe no stable process"
        )
    per_angle = all(r.dr_um.size > 0 for r in recs)
    st = lot_statistics(
        # without curves: each part's own extremes, so the per-part figures stay right
        [r.dr_um if per_angle else np.array([r.max_dev_um, r.min_dev_um]) for r in recs],
        recs[0].tolerance_um,
        [r.verdict == "fail" for r in recs],
        sequence=order,
        confidence=confidence,
    )
    n_pass = st.n_parts - st.n_failing
    spc = LotSpc(
        characteristic=characteristic,
        unit=unit,
        order=idx,
        values=values,
        capability=cap,
        chart=cc,
        rules=rules,
        out_of_control=tuple(flagged),
        warnings=tuple(warnings),
    )
    return LotSummary(
        design, lot, tuple(recs), st, basis, spc, clopper_pearson(n_pass, st.n_parts), per_angle
    )
