"""Result types of the Monte Carlo study, in internal units (docs/tolerancing.md).

Every figure is in the internal units of THEORY §0: ΔS in mm (translating follower) or
rad (oscillating), ΔV and ΔA per radian of cam angle (``mm/rad``, ``rad/rad2``); the unit
of each statistic is recorded (:attr:`AngleStatistics.unit`). Display units (µm, degrees,
per second at the design's cam speed), the words and the ``--json`` form are the report
layer's business (:mod:`camtol.report.tolerancing_display`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from camtol.jet import FloatArray
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.processes import ProfileProcess

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
        Largest histogram bin width of the quantiles (0: exact order statistics). [unit]
    max_abs : Summary
        Distribution of max_θ |ΔS| (or |ΔV|, |ΔA|) over the samples. [unit]
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
        from scipy.special import betaincinv  # beta quantile, without scipy.stats

        lo = 0.0 if passed == 0 else float(betaincinv(passed, samples - passed + 1, 0.025))
        hi = 1.0 if passed == samples else float(betaincinv(passed + 1, samples - passed, 0.975))
        return cls(passed / samples, (lo, hi), passed, samples, spec, band)


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
    """

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

    @property
    def unit(self) -> str:
        """Internal unit of ΔS: ``mm`` (translating follower) or ``rad`` (oscillating)."""
        return self.statistics["lift"].unit
