"""Result types of the Monte Carlo study and their JSON form (docs/tolerancing.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camtol.jet import FloatArray

__all__ = [
    "AngleStatistics",
    "ComparisonRow",
    "Contribution",
    "LinearExactDifference",
    "MonteCarloResult",
    "Summary",
    "YieldEstimate",
]


@dataclass(frozen=True)
class Summary:
    """Mean, σ and the 0.135 / 50 / 99.865 % quantiles of a scalar over the samples."""

    mean: float
    std: float
    q00135: float
    q50: float
    q99865: float

    def to_dict(self) -> dict[str, float]:
        """JSON object with keys ``mean, std, q00135, q50, q99865``."""
        return {
            "mean": self.mean,
            "std": self.std,
            "q00135": self.q00135,
            "q50": self.q50,
            "q99865": self.q99865,
        }


@dataclass(frozen=True)
class AngleStatistics:
    """Per-angle statistics of ΔS (or ΔV, ΔA) in display units.

    Attributes
    ----------
    quantity : str
        ``lift``, ``velocity`` or ``acceleration``.
    unit : str
        Display unit (``um``, ``deg``, ``um/rad`` ...).
    mean, std, q00135, q50, q99865 : ndarray
        Per-angle mean, σ and quantiles. [unit]
    resolution : float
        Largest histogram bin width of the quantiles (0: exact order statistics). [unit]
    max_abs : Summary
        Distribution of max_θ |ΔS| over the samples. [unit]
    """

    quantity: str
    unit: str
    mean: FloatArray
    std: FloatArray
    q00135: FloatArray
    q50: FloatArray
    q99865: FloatArray
    resolution: float
    max_abs: Summary


@dataclass(frozen=True)
class YieldEstimate:
    """Fraction of mechanisms meeting the spec, with a Clopper-Pearson 95 % interval."""

    value: float
    ci95: tuple[float, float]
    passed: int
    samples: int
    spec: str

    @classmethod
    def of(cls, passed: int, samples: int, spec: str) -> YieldEstimate:
        """Estimate with the exact (Clopper-Pearson) binomial 95 % interval.

        Parameters
        ----------
        passed : int
            Samples meeting the spec.
        samples : int
            Samples drawn.
        spec : str
            The spec, in words.
        """
        from scipy.special import betaincinv  # beta quantile, without scipy.stats

        lo = 0.0 if passed == 0 else float(betaincinv(passed, samples - passed + 1, 0.025))
        hi = 1.0 if passed == samples else float(betaincinv(passed + 1, samples - passed, 0.975))
        return cls(passed / samples, (lo, hi), passed, samples, spec)


@dataclass(frozen=True)
class Contribution:
    """Variance share (0-1) of one source at the angle of the worst spec margin."""

    source: str
    variance_share: float


@dataclass(frozen=True)
class ComparisonRow:
    """Worst case, RSS and Monte Carlo 99.73 % of max |ΔS| for a source or combined."""

    source: str
    worst_case: float
    rss: float
    mc_9973: float


@dataclass(frozen=True)
class LinearExactDifference:
    """Exact minus linear statistics on the same samples (the linearisation error).

    Attributes
    ----------
    mean, std, q00135, q99865 : float
        max over θ of |exact − linear| of each per-angle statistic. [unit]
    max_abs_q99865 : float
        Difference of the 99.865 % quantile of max |ΔS|. [unit]
    max_sample : float
        Largest |exact − linear| of any sample at any angle. [unit]
    """

    mean: float
    std: float
    q00135: float
    q99865: float
    max_abs_q99865: float
    max_sample: float


def spec_limits(
    theta_size: int, spec: float | None, band: tuple[FloatArray, FloatArray] | None, scale: float
) -> tuple[FloatArray, FloatArray] | None:
    """Lower and upper limit curves of a spec (±spec) or a band, in the display unit.

    Parameters
    ----------
    theta_size : int
        Number of grid angles. [-]
    spec : float or None
        Spec on max |ΔS|. [mm or rad]
    band : (ndarray, ndarray) or None
        Lower and upper curves on the grid. [mm or rad]
    scale : float
        Factor to the display unit. [unit per mm or rad]

    Returns
    -------
    (ndarray, ndarray) or None
        [unit]
    """
    if spec is not None:
        return np.full(theta_size, -spec * scale), np.full(theta_size, spec * scale)
    if band is not None:
        return np.asarray(band[0] * scale), np.asarray(band[1] * scale)
    return None


@dataclass(frozen=True)
class MonteCarloResult:
    """Result of :func:`camtol.tolerancing.monte_carlo` (display units).

    Attributes
    ----------
    design_name : str
        The design.
    samples, seed : int
        Number of samples and seed.
    mode : str
        ``linear`` or ``exact``.
    theta_deg : ndarray
        Cam angles. [deg]
    statistics : dict of str to AngleStatistics
        ``lift`` always; ``velocity``, ``acceleration`` when asked.
    yield_estimate : YieldEstimate or None
        When a spec or band was given.
    shares : dict of str to ndarray
        Variance share (0-1) of each source at every angle.
    worst_angle_deg : float
        Angle of the worst spec margin (largest |ΔS| quantile without a spec). [deg]
    contributions : tuple of Contribution
        Shares at that angle, largest first.
    comparison : tuple of ComparisonRow
        Per source, then ``combined``.
    sources : dict of str to str
        Each source's distribution, in words.
    difference : LinearExactDifference or None
        Exact mode: exact minus linear on the same samples.
    notes : tuple of str
        How the numbers were obtained.
    limits : (ndarray, ndarray) or None
        What the yield was judged against, as lower and upper curves on ``theta_deg``
        (−spec and +spec, or the band); None without a spec. [unit]
    """

    design_name: str
    samples: int
    seed: int
    mode: str
    theta_deg: FloatArray
    statistics: dict[str, AngleStatistics]
    yield_estimate: YieldEstimate | None
    shares: dict[str, FloatArray]
    worst_angle_deg: float
    contributions: tuple[Contribution, ...]
    comparison: tuple[ComparisonRow, ...]
    sources: dict[str, str] = field(default_factory=dict)
    difference: LinearExactDifference | None = None
    notes: tuple[str, ...] = ()
    limits: tuple[FloatArray, FloatArray] | None = None

    @property
    def unit(self) -> str:
        """Display unit of ΔS (``um`` or ``deg``)."""
        return self.statistics["lift"].unit

    def to_dict(self) -> dict[str, Any]:
        """Return the ``camtol montecarlo --json`` object (strict JSON; keys in the docs)."""
        lift = self.statistics["lift"]
        out: dict[str, Any] = {
            "design": self.design_name,
            "samples": self.samples,
            "seed": self.seed,
            "mode": self.mode,
            "unit": self.unit,
            "max_abs_dS": lift.max_abs.to_dict(),
        }
        if self.yield_estimate is not None:
            y = self.yield_estimate
            out["yield"] = {"value": y.value, "ci95": list(y.ci95), "spec": y.spec}
        out["contributions"] = [
            {"source": c.source, "variance_share": c.variance_share} for c in self.contributions
        ]
        out["worst_angle_deg"] = self.worst_angle_deg
        out["comparison"] = [
            {"source": r.source, "worst_case": r.worst_case, "rss": r.rss, "mc_9973": r.mc_9973}
            for r in self.comparison
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


def _finite(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
