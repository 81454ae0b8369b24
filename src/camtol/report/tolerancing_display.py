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
    "DIFFERENCE_DEFINITION",
    "MonteCarloDisplay",
    "describe_source",
    "display_montecarlo",
    "source_numbers",
    "yield_spec_text",
]

#: What ``linear_vs_exact`` is (its figures are differences, not a distribution).
DIFFERENCE_DEFINITION = (
    "linearisation error: exact minus linear on the same samples; mean, std, q00135,"
    " q99865: the largest |difference| over the angles between the exact and the linear"
    " per-angle statistic; max_abs_q99865: difference of the 99.865 % quantiles of"
    " max |dS|; max_sample: the largest |exact - linear| of any sample at any angle"
)

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


def source_numbers(model: ResolvedDistribution | ProfileProcess) -> dict[str, Any]:
    """Return a source's distribution as numbers in display units (``--json`` ``sources``).

    Parameters
    ----------
    model : ResolvedDistribution or ProfileProcess
        A source's distribution (internal units), or the profile process.

    Returns
    -------
    dict
        ``distribution`` (``normal``, ``uniform``, ``triangular``, ``gaussian_process``
        or ``harmonics``), ``unit`` (``um`` or ``deg``), ``mean``, ``std``, ``lower`` and
        ``upper`` (the limits of the values; None for an unbounded distribution),
        ``zone`` ([lower, upper] of the tolerance zone; a process: None), the
        distribution's own parameters (``cp``, ``truncated``, ``centre`` of a normal,
        ``mode`` of a triangular, ``target``, ``sigma_um``, ``correlation_deg``,
        ``harmonics`` of a process) and ``text`` (:func:`describe_source`). [unit]
    """
    from camtol.tolerancing.processes import ProfileProcess

    if isinstance(model, ProfileProcess):
        # At any point Σ A_k cos(kψ + φ_k) has variance Σ A_k²/2 (a_k, b_k: A_k²/2 each).
        var = float(np.sum(model.coefficient_variance_mm2())) if model.harmonics else None
        out: dict[str, Any] = {
            "distribution": "harmonics" if model.harmonics else "gaussian_process",
            "unit": "um",
            "mean": 0.0,
            "std": math.sqrt(var) * 1e3 if var is not None else float(model.sigma_um or 0.0),
            "lower": None,
            "upper": None,
            "zone": None,
            "target": model.target,
        }
        if model.harmonics:
            total = float(sum(a for _, a in model.harmonics))
            out["lower"], out["upper"] = -total, total
            out["harmonics"] = [{"order": k, "amplitude_um": a} for k, a in model.harmonics]
        else:
            out["sigma_um"] = model.sigma_um
            out["correlation_deg"] = model.correlation_deg
        out["text"] = describe_source(model)
        return out
    shown = output_error_unit(model.unit)
    f = shown.factor
    zone = [model.lower * f, model.upper * f]
    out = {
        "distribution": model.kind,
        "unit": shown.unit,
        "mean": model.mean() * f,
        "std": math.sqrt(max(model.variance(), 0.0)) * f,
        "lower": zone[0] if model.bounded else None,
        "upper": zone[1] if model.bounded else None,
        "zone": zone,
    }
    if model.kind == "normal":
        out.update(cp=model.cp, truncated=model.truncate, centre=model.centre * f)
    elif model.kind == "triangular":
        out["mode"] = model.centre * f
    out["text"] = describe_source(model)
    return out


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
    ci = {
        k: (None if lo is None else lo * f, None if hi is None else hi * f)
        for k, (lo, hi) in m.ci95.items()
    }
    hist = s.max_abs_histogram
    return dataclasses.replace(
        s,
        unit=unit,
        mean=s.mean * f,
        std=s.std * f,
        q00135=s.q00135 * f,
        q50=s.q50 * f,
        q99865=s.q99865 * f,
        resolution=s.resolution * f,
        max_abs=type(m)(m.mean * f, m.std * f, m.q00135 * f, m.q50 * f, m.q99865 * f, ci),
        tolerance=None if s.tolerance is None else s.tolerance * f,
        max_abs_histogram=None if hist is None else (hist[0] * f, hist[1]),
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
        The study's notes; the linear mode's first one with the quantiles' tolerance.
    source_values : dict of str to dict
        Each source's distribution as numbers (:func:`source_numbers`).
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
    source_values: dict[str, dict[str, Any]] = dataclasses.field(default_factory=dict)

    @property
    def worst_index(self) -> int:
        """Grid index of the angle of the worst margin (``result.worst_angle_deg``)."""
        return int(np.argmin(np.abs(self.result.theta_deg - self.result.worst_angle_deg)))

    def methods(self) -> dict[str, Any]:
        """Which figures are computed from the distributions and which are sampled.

        Returns
        -------
        dict
            ``per_angle`` (mean, σ, quantiles of ΔS at each angle), ``max_abs_dS``,
            ``yield``, ``outside`` (when present) and ``comparison_mc_9973`` (per
            source): ``deterministic`` or ``sampled``.
        """
        r = self.result
        out: dict[str, Any] = {
            "per_angle": self.statistics["lift"].method,
            "max_abs_dS": "sampled",
        }
        if r.yield_estimate is not None:
            out["yield"] = "sampled"
        if r.outside is not None:
            out["outside"] = "deterministic"
        out["comparison_mc_9973"] = {c.source: c.mc_9973_method for c in r.comparison}
        return out

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
            "max_abs_dS": {
                **lift.max_abs.to_dict(),
                "method": "sampled",
                "ci95": {k: list(v) for k, v in lift.max_abs.ci95.items()},
            },
        }
        if r.yield_estimate is not None:
            y = r.yield_estimate
            out["yield"] = {"value": y.value, "ci95": list(y.ci95), "spec": self.yield_spec}
        out["contributions"] = [
            {"source": c.source, "variance_share": c.variance_share} for c in r.contributions
        ]
        out["worst_angle_deg"] = r.worst_angle_deg
        out["comparison"] = [
            {
                "source": c.source,
                "worst_case": c.worst_case,
                "rss": c.rss,
                "mc_9973": c.mc_9973,
                "mc_9973_method": c.mc_9973_method,
            }
            for c in self.comparison
        ]
        for q in ("velocity", "acceleration"):
            if q in self.statistics:
                s = self.statistics[q]
                out[f"max_abs_d{q[0].upper()}"] = {**s.max_abs.to_dict(), "unit": s.unit}
        out["quantile_resolution"] = lift.resolution
        out["per_angle"] = self._per_angle()
        if r.outside is not None:
            o, i = r.outside, r.outside.worst
            out["outside"] = {
                "max": float(o.value[i]),
                "bounds": [float(o.lower[i]), float(o.upper[i])],
                "angle_deg": float(r.theta_deg[i]),
            }
        out["methods"] = self.methods()
        if self.difference is not None:
            d = self.difference
            out["linear_vs_exact"] = {
                "mean": d.mean,
                "std": d.std,
                "q00135": d.q00135,
                "q99865": d.q99865,
                "max_abs_q99865": d.max_abs_q99865,
                "max_sample": d.max_sample,
                "definition": DIFFERENCE_DEFINITION,
            }
        out["sources"] = {k: dict(v) for k, v in self.source_values.items()}
        out["warnings"] = list(r.warnings)
        out["notes"] = list(self.notes)
        clean: dict[str, Any] = _finite(out)
        return clean

    def _per_angle(self) -> dict[str, Any]:
        """Return the ``per_angle`` object: how the per-angle figures were obtained.

        With the figures at the angle of the worst margin.
        """
        s = self.statistics["lift"]
        i = self.worst_index
        deterministic = s.method == "deterministic"
        at = {
            "angle_deg": float(self.result.theta_deg[i]),
            **{k: float(getattr(s, k)[i]) for k in ("mean", "std", "q00135", "q50", "q99865")},
        }
        return {
            "method": s.method,
            "tolerance": float(s.resolution) if deterministic else None,
            "lattice_points": self.lattice_points if deterministic else None,
            "at_worst_angle": at,
        }

    @property
    def lattice_points(self) -> int:
        """Lattice points per angle of the deterministic distributions."""
        from camtol.tolerancing.convolution import POINTS

        return POINTS


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
        spelt = {"um": " µm", "deg": "°"}.get(lift.unit, f" {lift.unit}")
        first = f"{notes[0]} (quantiles within ±{lift.resolution:.3g}{spelt}, a bound)"
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
        source_values={k: source_numbers(v) for k, v in result.sources.items()},
    )


def _finite(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
