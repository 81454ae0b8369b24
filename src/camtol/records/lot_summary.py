"""A production lot from the store, summarised: which records pool, and their statistics.

:func:`summarise_lot` takes the records a query returned (``camtol records stats``; the
Python API gets the same) and refuses to pool what must not be pooled (records of several
cams, records judged against different tolerances or on different deviations, Δn and Δr),
orders the parts for the trend (integer serials when every record has one, else
inspection order), and computes
:func:`~camtol.records.lots.lot_statistics`. :meth:`LotSummary.to_dict` is the
``records stats --json`` document (schema ``records-stats.schema.json``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from camtol.exceptions import RecordError
from camtol.records.lots import LotStatistics, lot_statistics
from camtol.records.record import InspectionRecord

__all__ = ["LotSummary", "summarise_lot"]


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
        What orders the parts for the trend.
    """

    design_name: str
    lot: str | None
    records: tuple[InspectionRecord, ...]
    statistics: LotStatistics
    trend_basis: str

    def to_dict(self) -> dict[str, Any]:
        """Return the ``records stats --json`` document (non-finite figures as None).

        Returns
        -------
        dict
            Keys as documented in docs/records.md. [µm, µm per part]
        """
        st, recs = self.statistics, self.records

        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "design_name": self.design_name,
            "lot": self.lot,
            "cam": recs[0].cam,
            "design_hashes": sorted({r.design_hash for r in recs}),
            "methods": sorted({r.method for r in recs}),
            "record_ids": [r.id for r in recs],
            "n_parts": st.n_parts,
            "n_points": int(st.theta_deg.size),
            "record_n_points": sorted({r.n_points for r in recs}),
            "tolerance_um": list(st.tolerance_um),
            "mean_of_max_um": float(st.part_max_um.mean()),
            "mean_of_min_um": float(st.part_min_um.mean()),
            "envelope_max_um": float(st.max_um.max()),
            "envelope_min_um": float(st.min_um.min()),
            "max_std_um": num(float(st.std_um.max())),
            "cp": num(st.cp),
            "cpk_upper": num(st.cpk_upper),
            "cpk_lower": num(st.cpk_lower),
            "cpk": num(st.cpk),
            "n_failing": st.n_failing,
            "fraction_failing": st.fraction_failing,
            "fraction_failing_ci": list(st.fraction_failing_ci),
            "confidence": st.confidence,
            "trend_basis": self.trend_basis,
            "trend_um_per_part": num(st.trend_um_per_part),
            "trend_stderr_um_per_part": num(st.trend_stderr_um_per_part),
        }


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


def summarise_lot(
    records: Sequence[InspectionRecord],
    *,
    design: str,
    lot: str | None = None,
    method: str | None = None,
    confidence: float = 0.95,
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

    Returns
    -------
    LotSummary

    Raises
    ------
    RecordError
        A confidence outside (0, 1); no record; records of several cams, judged against
        different tolerances or on different deviations (Δn, Δr) (naming what to select).
    """
    if not (math.isfinite(confidence) and 0.0 < confidence < 1.0):
        raise RecordError(
            f"--confidence={confidence!r}: allowed a level between 0 and 1, e.g. 0.95"
        )
    recs = [r for r in records if method is None or r.method == method]
    where = f"--design={design!r}" + ("" if lot is None else f" --lot={lot!r}")
    where += "" if method is None else f" --method={method}"
    if not recs:
        raise RecordError(f"{where}: no records match in the store (see `camtol records list`)")
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
    order, basis = production_order(recs)
    st = lot_statistics(
        [r.dr_um for r in recs],
        tolerances[0],
        [r.verdict == "fail" for r in recs],
        sequence=order,
        confidence=confidence,
    )
    return LotSummary(design, lot, tuple(recs), st, basis)
