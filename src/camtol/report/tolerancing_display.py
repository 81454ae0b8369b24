"""A Monte Carlo study in display units: the one place that scales its figures for readers.

:func:`camtol.tolerancing.monte_carlo` returns every figure in internal units (THEORY §0:
ΔS in mm or rad, ΔV and ΔA per radian of cam angle; :attr:`AngleStatistics.unit`). The
terminal, ``--json``, ``--curves``, ``--plot`` and the HTML report show ΔS of a
translating follower in µm, of an oscillating one in degrees, ΔV and ΔA per radian of cam
angle or per second (s²) at the design's cam speed (:class:`camtol.report.display.DisplayUnits`,
the same factors as the analysis). :func:`display_montecarlo` converts a result once, on
its statistics (never per sample); :func:`describe_source` puts a source's distribution
into words.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray
from camtol.report.display import DisplayUnits, output_error_unit
from camtol.report.units import pretty_unit

if TYPE_CHECKING:  # pragma: no cover
    from camtol.design.cam_design import CamDesign
    from camtol.tolerancing.distributions import ResolvedDistribution
    from camtol.tolerancing.processes import ProfileProcess
    from camtol.tolerancing.results import (
        AngleStatistics,
        ComparisonRow,
        LinearExactDifference,
        MonteCarloResult,
        YieldEstimate,
    )

__all__ = [
    "MonteCarloDisplay",
    "describe_source",
    "display_montecarlo",
    "yield_spec_text",
]

#: Order of the derivative of ΔS of each statistic.
_ORDER = {"lift": 0, "velocity": 1, "acceleration": 2}


def describe_source(model: ResolvedDistribution | ProfileProcess) -> str:
    """Describe a source's distribution in one line, in display units.

    Parameters
    ----------
    model : ResolvedDistribution or ProfileProcess
        A source's distribution (zone in its internal unit, mm or rad), or the profile
        process (the user's own σ, amplitudes in µm and correlation length in degrees).

    Returns
    -------
    str
        E.g. ``normal Cp=1 mean 0 µm, truncated at [-19, 19] µm`` (µm for a length, °
        for an angle source), ``uniform on [-0.011, 0.011] °``.
    """
    from camtol.tolerancing.processes import ProfileProcess

    if isinstance(model, ProfileProcess):
        what = "radial" if model.target == "r" else "normal"
        if model.harmonics:
            h = ", ".join(f"order {k}: {a:g} µm" for k, a in model.harmonics)
            return f"{what} profile error, harmonics with random phases ({h})"
        return (
            f"{what} profile error, stationary Gaussian σ = {model.sigma_um:g} µm,"
            f" correlation length {model.correlation_deg:g}° ({model.orders.size} harmonics)"
        )
    shown = output_error_unit(model.unit)
    scale, unit = shown.factor, pretty_unit(shown.unit)
    zone = f"[{model.lower * scale:.4g}, {model.upper * scale:.4g}] {unit}"
    if model.kind == "normal":
        cut = "truncated" if model.truncate else "untruncated"
        return f"normal Cp={model.cp:g} mean {model.centre * scale:.4g} {unit}, {cut} at {zone}"
    if model.kind == "triangular":
        return f"triangular mode {model.centre * scale:.4g} {unit} on {zone}"
    return f"uniform on {zone}"


def yield_spec_text(estimate: YieldEstimate, unit: str, scale: float) -> str:
    """Return what a yield was judged against, in words and display units.

    Parameters
    ----------
    estimate : YieldEstimate
        The yield (its spec [mm or rad] or its band's label).
    unit : str
        Display unit of ΔS (``um`` or ``deg``).
    scale : float
        Factor from the internal unit of ΔS to ``unit``. [unit per mm or rad]

    Returns
    -------
    str
        ``max |dS| <= 20 um``, or ``lower <= dS <= upper at every angle, band FILE.csv``.
    """
    if estimate.spec is not None:
        return f"max |dS| <= {estimate.spec * scale:g} {unit}"
    text = "lower <= dS <= upper at every angle"
    return f"{text}, band {estimate.band}" if estimate.band else text


def _scaled_statistics(s: AngleStatistics, unit: str, f: float) -> AngleStatistics:
    m = s.max_abs
    return dataclasses.replace(
        s,
        unit=unit,
        mean=s.mean * f,
        std=s.std * f,
        q00135=s.q00135 * f,
        q50=s.q50 * f,
        q99865=s.q99865 * f,
        resolution=s.resolution * f,
        max_abs=type(m)(*(v * f for v in (m.mean, m.std, m.q00135, m.q50, m.q99865))),
    )


@dataclass(frozen=True)
class MonteCarloDisplay:
    """A Monte Carlo study as the terminal, files and the report show it.

    Attributes
    ----------
    result : MonteCarloResult
        The study (internal units); its unit-free fields (angles, shares,
        contributions, mode, samples, seed) are shown as they are.
    unit : str
        Display unit of ΔS: ``um`` (translating follower) or ``deg`` (oscillating).
    scale : float
        Factor from the internal unit of ΔS (mm or rad) to :attr:`unit`.
    statistics : dict of str to AngleStatistics
        The statistics in display units (ΔV, ΔA per rad, or per s at the design speed).
    limits : (ndarray, ndarray) or None
        The spec or band the yield was judged against. [unit]
    comparison : tuple of ComparisonRow
        Worst case, RSS and Monte Carlo 99.73 %. [unit]
    difference : LinearExactDifference or None
        Exact minus linear (exact mode). [unit]
    sources : dict of str to str
        Each source's distribution in words (:func:`describe_source`).
    yield_spec : str or None
        What the yield was judged against, in words (:func:`yield_spec_text`).
    notes : tuple of str
        The study's notes; the linear mode's first one with the quantile resolution.
    """

    result: MonteCarloResult
    unit: str
    scale: float
    statistics: dict[str, AngleStatistics]
    limits: tuple[FloatArray, FloatArray] | None
    comparison: tuple[ComparisonRow, ...]
    difference: LinearExactDifference | None
    sources: dict[str, str]
    yield_spec: str | None
    notes: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        """Return the ``camtol montecarlo --json`` object (keys in docs/tolerancing.md).

        Returns
        -------
        dict
            Strict-JSON-ready data (non-finite numbers as None), display units.
        """
        r = self.result
        lift = self.statistics["lift"]
        out: dict[str, Any] = {
            "design": r.design_name,
            "samples": r.samples,
            "seed": r.seed,
            "mode": r.mode,
            "unit": self.unit,
            "max_abs_dS": lift.max_abs.to_dict(),
        }
        if r.yield_estimate is not None:
            y = r.yield_estimate
            out["yield"] = {"value": y.value, "ci95": list(y.ci95), "spec": self.yield_spec}
        out["contributions"] = [
            {"source": c.source, "variance_share": c.variance_share} for c in r.contributions
        ]
        out["worst_angle_deg"] = r.worst_angle_deg
        out["comparison"] = [
            {"source": c.source, "worst_case": c.worst_case, "rss": c.rss, "mc_9973": c.mc_9973}
            for c in self.comparison
        ]
        for q in ("velocity", "acceleration"):
            if q in self.statistics:
                s = self.statistics[q]
                out[f"max_abs_d{q[0].upper()}"] = {**s.max_abs.to_dict(), "unit": s.unit}
        out["quantile_resolution"] = lift.resolution
        if self.difference is not None:
            d = self.difference
            out["linear_vs_exact"] = {
                "mean": d.mean,
                "std": d.std,
                "q00135": d.q00135,
                "q99865": d.q99865,
                "max_abs_q99865": d.max_abs_q99865,
                "max_sample": d.max_sample,
            }
        out["sources"] = dict(self.sources)
        out["notes"] = list(self.notes)
        clean: dict[str, Any] = _finite(out)
        return clean


def display_montecarlo(result: MonteCarloResult, design: CamDesign) -> MonteCarloDisplay:
    """Return a Monte Carlo study in display units (converted once, on its statistics).

    Parameters
    ----------
    result : MonteCarloResult
        Result of :func:`camtol.tolerancing.monte_carlo` (internal units).
    design : CamDesign
        The studied design (its follower's output and cam speed fix the display units,
        :meth:`camtol.report.display.DisplayUnits.of`).

    Returns
    -------
    MonteCarloDisplay
        Statistics, limits, comparison and difference scaled; sources and the yield's
        spec in words.
    """
    units = DisplayUnits.of(design)
    unit, f = units.lift, units.lift_scale
    stats = {}
    for q, s in result.statistics.items():
        shown = units.order(_ORDER[q])
        stats[q] = _scaled_statistics(s, shown.unit, shown.factor)
    limits = None
    if result.limits is not None:
        limits = (np.asarray(result.limits[0] * f), np.asarray(result.limits[1] * f))
    comparison = tuple(
        dataclasses.replace(c, worst_case=c.worst_case * f, rss=c.rss * f, mc_9973=c.mc_9973 * f)
        for c in result.comparison
    )
    difference = None
    if result.difference is not None:
        d = result.difference
        difference = type(d)(
            *(v * f for v in (d.mean, d.std, d.q00135, d.q99865, d.max_abs_q99865, d.max_sample))
        )
    notes = result.notes
    if result.mode == "linear" and notes:
        lift = stats["lift"]
        first = f"{notes[0]} (resolution {lift.resolution:.3g} {lift.unit})"
        notes = (first, *notes[1:])
    y = result.yield_estimate
    return MonteCarloDisplay(
        result=result,
        unit=unit,
        scale=f,
        statistics=stats,
        limits=limits,
        comparison=comparison,
        difference=difference,
        sources={k: describe_source(v) for k, v in result.sources.items()},
        yield_spec=None if y is None else yield_spec_text(y, unit, f),
        notes=notes,
    )


def _finite(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
