"""Result types of the Monte Carlo study, in internal units (docs/tolerancing.md).

Every figure is in the internal units of THEORY §0: ΔS in mm (translating follower) or
rad (oscillating), ΔV and ΔA per radian of cam angle (``mm/rad``, ``rad/rad2``); the unit
of each statistic is recorded (:attr:`AngleStatistics.unit`). Display units (µm, degrees,
per second at the design's cam speed), the words and the ``--json`` form are the report
layer's business (:mod:`camtol.report.tolerancing_display`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from camtol.jet import FloatArray
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.processes import ProfileProcess

__all__ = [
    "AngleStatistics",
    "ComparisonRow",
    "Contribution",
    "LinearExactDifference",
    "MonteCarloResult",
    "OutsideProbability",
    "Summary",
    "YieldEstimate",
    "FEW_SAMPLES",
    "few_samples_warning",
    "quantile_ci_ranks",
    "sampled_intervals",
]

#: Below this many samples, sampled quantiles carry a warning. [-]
FEW_SAMPLES = 1000

Interval = tuple[float | None, float | None]
#: Probabilities of the quantiles of a :class:`Summary`. [-]
SUMMARY_PROBS = (0.00135, 0.5, 0.99865)


def quantile_ci_ranks(samples: int, prob: float) -> tuple[int, int]:
    """Ranks (1-based) of the order statistics bounding a quantile with ≥ 95 % confidence.

    With B ~ Binomial(n, p) the number of samples below the true p-quantile,
    P(X_(l) ≤ q_p ≤ X_(u)) ≥ P(l ≤ B < u); l is the largest rank with P(B < l) ≤ 0.025
    and u the smallest with P(B < u) ≥ 0.975 (distribution-free, exact binomial).

    Parameters
    ----------
    samples : int
        Number of samples n.
    prob : float
        Probability p of the quantile, in (0, 1). [-]

    Returns
    -------
    (int, int)
        (l, u); l = 0 means no lower bound, u = n + 1 no upper bound at 95 %.
    """
    from scipy.special import bdtr  # binomial CDF, without scipy.stats

    def below(k: int) -> float:  # P(B < k) = P(B ≤ k − 1)
        return 0.0 if k <= 0 else 1.0 if k > samples else float(bdtr(k - 1, samples, prob))

    lo, hi = 0, samples + 1  # largest l with below(l) ≤ 0.025: below(lo) ≤ .025 < below(hi)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if below(mid) <= 0.025 else (lo, mid)
    first = lo
    lo, hi = 0, samples + 1  # smallest u with below(u) ≥ 0.975: below(lo) < .975 ≤ below(hi)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if below(mid) >= 0.975 else (mid, hi)
    return first, hi


def sampled_intervals(
    n: int, mean: float, std: float, order_statistic: Callable[[float], float]
) -> dict[str, tuple[float | None, float | None]]:
    """95 % intervals of a sampled mean and of the 0.135, 50, 99.865 % quantiles.

    Parameters
    ----------
    n : int
        Number of samples.
    mean, std : float
        Sample mean and σ. [unit]
    order_statistic : callable
        Value at the fraction k/n of the sorted samples (the k-th order statistic). [unit]

    Returns
    -------
    dict
        ``mean`` (±1.96 σ/√n) and ``q00135``, ``q50``, ``q99865`` (order statistics,
        :func:`~camtol.tolerancing.results.quantile_ci_ranks`); None where the samples
        are too few to bound it. [unit]
    """
    half = 1.96 * std / math.sqrt(n) if n > 1 else math.inf
    out: dict[str, tuple[float | None, float | None]] = {
        "mean": (mean - half, mean + half) if math.isfinite(half) else (None, None)
    }
    for key, p in zip(("q00135", "q50", "q99865"), SUMMARY_PROBS, strict=True):
        lo, hi = quantile_ci_ranks(n, p)
        out[key] = (
            order_statistic(lo / n) if lo >= 1 else None,
            order_statistic(hi / n) if hi <= n else None,
        )
    return out


def few_samples_warning(samples: int, what: str) -> tuple[str, ...]:
    """Return the one-line warning on quantiles from fewer than FEW_SAMPLES samples.

    Parameters
    ----------
    samples : int
        Number of samples.
    what : str
        Which quantiles are sampled, e.g. ``max |dS|``.

    Returns
    -------
    tuple of str
        One warning, or none from FEW_SAMPLES samples on.
    """
    if samples >= FEW_SAMPLES:
        return ()
    return (
        f"quantiles of {what} from {samples} sample{'s' if samples != 1 else ''}"
        f" (fewer than {FEW_SAMPLES:,}): rough",
    )


@dataclass(frozen=True)
class Summary:
    """Mean, σ and the 0.135 / 50 / 99.865 % quantiles of a scalar over the samples.

    Attributes
    ----------
    mean, std, q00135, q50, q99865 : float
        The sample figures. [unit of the scalar]
    ci95 : dict of str to (float or None, float or None)
        95 % confidence interval of ``mean`` (normal approximation) and of each quantile
        (order statistics, :func:`quantile_ci_ranks`; None where the samples are too
        few to bound it). [unit]
    """

    mean: float
    std: float
    q00135: float
    q50: float
    q99865: float
    ci95: dict[str, Interval] = field(default_factory=dict)

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
    """Per-angle statistics of ΔS (or ΔV, ΔA), in the unit :attr:`unit`.

    The Monte Carlo study gives them in internal units; the report layer makes a copy in
    display units (:func:`camtol.report.tolerancing_display.display_montecarlo`).

    Attributes
    ----------
    quantity : str
        ``lift``, ``velocity`` or ``acceleration``.
    unit : str
        Unit of the figures: internally ``mm`` or ``rad`` for ΔS, ``mm/rad`` or
        ``rad/rad`` for ΔV, ``mm/rad2`` or ``rad/rad2`` for ΔA (per radian of cam angle).
    mean, std, q00135, q50, q99865 : ndarray
        Per-angle mean, σ and quantiles. [unit]
    resolution : float
        Deterministic figures (linear mode): the largest bound over θ on the numerical
        error of the quantiles (:mod:`camtol.tolerancing.convolution`); sampled ones:
        0 (exact order statistics). [unit]
    max_abs : Summary
        Distribution of max_θ |ΔS| (or |ΔV|, |ΔA|) over the samples. [unit]
    method : str
        ``deterministic``: mean, σ, quantiles computed from the source distributions
        without sampling (linear mode); ``sampled``: statistics of the samples.
    tolerance : ndarray or None
        Deterministic: the bound on the error of the quantiles at each angle. [unit]
    max_abs_histogram : (ndarray, ndarray) or None
        Bin edges [unit] and counts of max_θ |ΔS| over the samples.
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
    method: str = "sampled"
    tolerance: FloatArray | None = None
    max_abs_histogram: tuple[FloatArray, NDArray[np.int64]] | None = None


@dataclass(frozen=True)
class YieldEstimate:
    """Fraction of mechanisms meeting the spec, with a Clopper-Pearson 95 % interval.

    Attributes
    ----------
    value : float
        Fraction of the samples meeting the spec. [-]
    ci95 : (float, float)
        Clopper-Pearson 95 % interval of the yield. [-]
    passed, samples : int
        Samples meeting the spec; samples drawn.
    spec : float or None
        The spec on max |ΔS| it was judged against (None for a band). [mm or rad]
    band : str or None
        The band ``lower ≤ ΔS ≤ upper`` it was judged against instead: its label (the
        file's name, or ``""`` for curves without a name); None for a spec.
    """

    value: float
    ci95: tuple[float, float]
    passed: int
    samples: int
    spec: float | None = None
    band: str | None = None

    @classmethod
    def of(
        cls, passed: int, samples: int, spec: float | None = None, band: str | None = None
    ) -> YieldEstimate:
        """Estimate with the exact (Clopper-Pearson) binomial 95 % interval.

        Parameters
        ----------
        passed : int
            Samples meeting the spec.
        samples : int
            Samples drawn.
        spec : float, optional
            The spec on max |ΔS|. [mm or rad]
        band : str, optional
            The band's label, when judged against a band instead.

        Returns
        -------
        YieldEstimate
            The yield and its interval.
        """
        from camtol.spc.binomial import clopper_pearson

        return cls(passed / samples, clopper_pearson(passed, samples), passed, samples, spec, band)


@dataclass(frozen=True)
class OutsideProbability:
    """Probability that ΔS(θ) lies outside the limits at each angle (deterministic).

    Attributes
    ----------
    value : ndarray
        P(ΔS(θ) < lower(θ) or ΔS(θ) > upper(θ)) at every angle. [-]
    lower, upper : ndarray
        Guaranteed bounds on ``value`` given the numerical tolerance. [-]
    """

    value: FloatArray
    lower: FloatArray
    upper: FloatArray

    @property
    def worst(self) -> int:
        """Index of the angle of the largest probability."""
        return int(np.argmax(self.value))


@dataclass(frozen=True)
class Contribution:
    """Variance share (0-1) of one source at the angle of the worst spec margin."""

    source: str
    variance_share: float


@dataclass(frozen=True)
class ComparisonRow:
    """Worst case, RSS and Monte Carlo 99.73 % of max |ΔS| for a source or combined.

    Attributes
    ----------
    source : str
        Source label, or ``combined``.
    worst_case, rss, mc_9973 : float
        max_θ of the worst case and of the RSS, and the 99.73 % quantile of the Monte
        Carlo max |ΔS|. [unit of ΔS: mm or rad]
    mc_9973_method : str
        ``deterministic`` (from the source distributions, linear mode: a constant source,
        whose max |ΔS_p| is |x_p| max_θ |s_p|, and ``combined``, the largest half-width of
        the per-angle band) or ``sampled`` (a profile process, exact mode).
    """

    source: str
    worst_case: float
    rss: float
    mc_9973: float
    mc_9973_method: str = "sampled"


@dataclass(frozen=True)
class LinearExactDifference:
    """Exact minus linear statistics on the same samples (the linearisation error).

    Attributes
    ----------
    mean, std, q00135, q99865 : float
        max over θ of |exact − linear| of each per-angle statistic. [mm or rad]
    max_abs_q99865 : float
        Difference of the 99.865 % quantile of max |ΔS|. [mm or rad]
    max_sample : float
        Largest |exact − linear| of any sample at any angle. [mm or rad]
    """

    mean: float
    std: float
    q00135: float
    q99865: float
    max_abs_q99865: float
    max_sample: float


def spec_limits(
    theta_size: int, spec: float | None, band: tuple[FloatArray, FloatArray] | None
) -> tuple[FloatArray, FloatArray] | None:
    """Lower and upper limit curves of a spec (±spec) or a band. [mm or rad]

    Parameters
    ----------
    theta_size : int
        Number of grid angles. [-]
    spec : float or None
        Spec on max |ΔS|. [mm or rad]
    band : (ndarray, ndarray) or None
        Lower and upper curves on the grid. [mm or rad]

    Returns
    -------
    (ndarray, ndarray) or None
        Lower and upper curves on the grid. [mm or rad]
    """
    if spec is not None:
        return np.full(theta_size, -spec), np.full(theta_size, spec)
    if band is not None:
        return np.asarray(band[0], dtype=float), np.asarray(band[1], dtype=float)
    return None


@dataclass(frozen=True)
class MonteCarloResult:
    """Result of :func:`camtol.tolerancing.monte_carlo` (internal units).

    ΔS figures are in mm (translating follower) or rad (oscillating), ΔV and ΔA per
    radian of cam angle; :func:`camtol.report.tolerancing_display.display_montecarlo`
    shows them in µm or degrees (per second at the design's speed) and writes the JSON.

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
    sources : dict of str to ResolvedDistribution or ProfileProcess
        Each label's distribution (zone in the source's internal unit,
        :attr:`ResolvedDistribution.unit`), or the profile process.
    difference : LinearExactDifference or None
        Exact mode: exact minus linear on the same samples.
    notes : tuple of str
        How the numbers were obtained.
    limits : (ndarray, ndarray) or None
        What the yield was judged against, as lower and upper curves on ``theta_deg``
        (−spec and +spec, or the band); None without a spec. [mm or rad]
    outside : OutsideProbability or None
        Linear mode with a spec or band: the deterministic probability of leaving the
        limits at each angle (1 − its maximum bounds the yield from above).
    warnings : tuple of str
        What the reader must know before using the figures (e.g. quantiles from fewer
        than :data:`FEW_SAMPLES` samples).
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
    sources: dict[str, ResolvedDistribution | ProfileProcess] = field(default_factory=dict)
    difference: LinearExactDifference | None = None
    notes: tuple[str, ...] = ()
    limits: tuple[FloatArray, FloatArray] | None = None
    outside: OutsideProbability | None = None
    warnings: tuple[str, ...] = ()

    @property
    def unit(self) -> str:
        """Internal unit of ΔS: ``mm`` (translating follower) or ``rad`` (oscillating)."""
        return self.statistics["lift"].unit
