"""Statistical process control on a lot's per-part values: capability, control charts, rules.

Pure numpy and scipy (no store, no plotting): :mod:`camtol.spc.constants` (the control
chart constants d2, d3, c4 and the factors built on them), :mod:`camtol.spc.capability`
(ISO 22514-2 capability indices, their intervals, normality and the percentile method),
:mod:`camtol.spc.charts` (individuals and subgroup control charts and their limits) and
:mod:`camtol.spc.rules` (Western Electric and Nelson run rules), and
:mod:`camtol.spc.binomial` (the exact interval of a yield, shared with the Monte Carlo
yields of :mod:`camtol.tolerancing`).

Why a package of its own, low in the layers (docs/architecture.md): the store
(:mod:`camtol.records.lot_summary`), the lot report (:mod:`camtol.report.lot_report`) and
the quality department's page (:mod:`camtol.web`) all use these results, and the report and
the store sit side by side and may not import each other; below both, the statistics are
shared without the store's database libraries.
"""

from __future__ import annotations
