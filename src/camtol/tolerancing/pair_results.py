"""What a conjugate pair's tolerance study gives (:mod:`camtol.tolerancing.pair`).

Deterministic per-angle moments of each linear output (:class:`AngleMoments`), summaries
of sampled figures (:class:`SampledSummary`), and the whole result with its ``--json``
document and ``--curves`` columns (:class:`PairMonteCarloResult`), in internal units
(mm, rad) with the display units named where they are converted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camtol.jet import FloatArray
from camtol.pair.sources import PairSource
from camtol.tolerancing.plan import SamplingPlan
from camtol.tolerancing.results import YieldEstimate

__all__ = ["AngleMoments", "PairMonteCarloResult", "SampledSummary", "moments"]


@dataclass(frozen=True)
class AngleMoments:
    """The distribution of a linear output at every angle, without sampling noise.

    Mean and σ are closed forms of the sources' moments; the quantiles come from the
    convolution of the sources' densities (:func:`camtol.tolerancing.convolution
    .angle_distributions`), each within ``tolerance`` of the exact one.

    Attributes
    ----------
    mean, std : ndarray
        Over θ, in the output's internal unit. [mm or rad]
    shares : dict of str to ndarray
        Each source's share of the variance at every angle, (s_k σ_k)² / Σ. [-]
    q00135, q50, q99865 : ndarray
        The 0.135 %, 50 % and 99.865 % quantiles over θ. [mm or rad]
    tolerance : ndarray
        Bound on the numerical error of every quantile at each angle. [mm or rad]
    """

    mean: FloatArray
    std: FloatArray
    shares: dict[str, FloatArray]
    q00135: FloatArray
    q50: FloatArray
    q99865: FloatArray
    tolerance: FloatArray


def moments(g: FloatArray, plan: SamplingPlan, *, quantiles: bool = True) -> AngleMoments:
    """Mean, σ and variance shares of Σ_j g_j(θ) x_j over θ (independent columns).

    Parameters
    ----------
    g : ndarray
        Sensitivities, shape (angles, columns). [output unit per column unit]
    plan : SamplingPlan
        The columns' distributions.
    quantiles : bool
        Also the quantiles (the convolution); without, they are NaN.

    Returns
    -------
    AngleMoments
    """
    from camtol.tolerancing.convolution import angle_distributions

    part = g * g * plan.column_variance()[None, :]
    total = part.sum(axis=1)
    safe = np.where(total > 0, total, 1.0)
    shares = {lab: np.where(total > 0, part[:, j] / safe, 0.0) for j, lab in enumerate(plan.labels)}
    if not quantiles:
        nan = np.full(g.shape[0], np.nan)
        mean = np.asarray(g @ plan.column_mean())
        return AngleMoments(mean, np.sqrt(total), shares, nan, nan, nan, nan)
    dist = angle_distributions(g, plan)
    low, mid, high = dist.quantiles
    return AngleMoments(dist.mean, np.sqrt(total), shares, low, mid, high, dist.tolerance)


@dataclass(frozen=True)
class SampledSummary:
    """Mean, 99.865 % quantile and largest value of a sampled figure.

    Attributes
    ----------
    mean, q99865, max : float
        In the figure's unit. [µm, or the follower's unit]
    """

    mean: float
    q99865: float
    max: float

    @classmethod
    def of(cls, values: FloatArray) -> SampledSummary:
        """Summarise samples (empirical quantile).

        Parameters
        ----------
        values : ndarray
            One value per sample.

        Returns
        -------
        SampledSummary
        """
        v = np.asarray(values, dtype=float)
        return cls(float(v.mean()), float(np.quantile(v, 0.99865)), float(v.max()))

    def to_dict(self) -> dict[str, float]:
        """Return ``{mean, q99865, max}``."""
        return {"mean": self.mean, "q99865": self.q99865, "max": self.max}


@dataclass(frozen=True)
class PairMonteCarloResult:
    """A pair's tolerance study (see the module docstring).

    Attributes
    ----------
    design_name : str
        The design.
    samples, seed : int
        Samples drawn and the seed.
    theta_deg : ndarray
        The grid. [deg]
    motion : dict of str to AngleMoments
        By cam letter: ΔS of the follower with that cam holding its roller (deterministic).
        [rad]
    df : AngleMoments
        Δf = f* − f of the assembled pair (deterministic). [mm]
    max_abs_motion : dict of str to SampledSummary
        By cam letter: each sample's max_θ |ΔS| (sampled). [rad]
    interference_mm, backlash_mm : SampledSummary
        Each sample's max_θ max(Δf − Δf₀, 0) and max_θ max(Δf₀ − Δf, 0) (sampled). [mm]
    fixture_yield : dict of str to YieldEstimate
        By cam letter: the fraction the fixture accepts (sampled; empty without an
        ``[inspection]`` table).
    pair_yield : YieldEstimate or None
        Interference and backlash within their limits (sampled; None without limits).
    interference_max_mm, backlash_max_mm : float or None
        The limits of the pair yield. [mm]
    df_worst_angle_deg : float
        Where |mean| + 3σ of Δf is largest. [deg]
    df_contributions : dict of str to float
        Each source's share of Δf's variance there, largest first. [-]
    sources : tuple of PairSource
        The sampled sources.
    plan : SamplingPlan
        Their distributions (and the profile processes, last).
    notes : tuple of str
        What is deterministic and what sampled.
    process_cams : tuple of (str, str)
        For each of ``plan.processes``: its cam's letter and the ``[statistics]`` table it
        comes from (``profile_process_a``, or ``profile_process`` for both cams).
    """

    design_name: str
    samples: int
    seed: int
    theta_deg: FloatArray
    motion: dict[str, AngleMoments]
    df: AngleMoments
    max_abs_motion: dict[str, SampledSummary]
    interference_mm: SampledSummary
    backlash_mm: SampledSummary
    fixture_yield: dict[str, YieldEstimate]
    pair_yield: YieldEstimate | None
    interference_max_mm: float | None
    backlash_max_mm: float | None
    df_worst_angle_deg: float
    df_contributions: dict[str, float]
    sources: tuple[PairSource, ...]
    plan: SamplingPlan
    notes: tuple[str, ...] = field(default=())
    process_cams: tuple[tuple[str, str], ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """Return the pair's part of ``camtol montecarlo --json`` (internal units named).

        Returns
        -------
        dict
            ``interference_um``, ``backlash_um`` (each ``{mean, q99865, max}``),
            ``fixture_yield`` (``{a: {value, ci95}, b: {...}}``), ``pair_yield``,
            ``df_contributions``, ``max_abs_ds_deg`` per cam, ``sources`` and ``notes``.
        """

        def um(s: SampledSummary) -> dict[str, float]:
            return {k: v * 1e3 for k, v in s.to_dict().items()}

        def deg(s: SampledSummary) -> dict[str, float]:
            return {k: math.degrees(v) for k, v in s.to_dict().items()}

        def yield_dict(y: YieldEstimate) -> dict[str, Any]:
            return {"value": y.value, "ci95": list(y.ci95), "passed": y.passed}

        return {
            "design": self.design_name,
            "samples": self.samples,
            "seed": self.seed,
            "interference_um": um(self.interference_mm),
            "backlash_um": um(self.backlash_mm),
            "fixture_yield": {k.lower(): yield_dict(v) for k, v in self.fixture_yield.items()}
            or None,
            "pair_yield": None if self.pair_yield is None else yield_dict(self.pair_yield),
            "interference_max_um": None
            if self.interference_max_mm is None
            else self.interference_max_mm * 1e3,
            "backlash_max_um": None if self.backlash_max_mm is None else self.backlash_max_mm * 1e3,
            "df_worst_angle_deg": self.df_worst_angle_deg,
            "df_contributions": self.df_contributions,
            "max_abs_ds_deg": {k.lower(): deg(v) for k, v in self.max_abs_motion.items()},
            "sources": [
                {
                    "key": s.key,
                    "tolerance_key": s.design_key,
                    "cams": [letter for letter, _ in s.cams],
                    "unit": s.tolerance.unit,
                    "deviation": s.tolerance.deviation,
                    "distribution": d.kind,
                    "mean": d.mean(),
                    "sigma": math.sqrt(d.variance()),
                    "limits": list(d.support()) if d.bounded else None,
                }
                for s, d in zip(self.sources, self.plan.distributions, strict=True)
            ]
            + [
                {
                    "key": label,
                    "tolerance_key": table,
                    "cams": [letter],
                    "unit": "mm",
                    "deviation": p.deviation_mm(),
                    "distribution": "gaussian_process" if p.gaussian else "harmonics",
                    "mean": 0.0,
                    # the process's σ at any point: Σ over orders of Var a_k (= Var b_k)
                    "sigma": math.sqrt(float(p.coefficient_variance_mm2().sum())),
                    "limits": None if p.gaussian else [-p.deviation_mm(), p.deviation_mm()],
                    "target": p.target,
                }
                for label, (letter, table), p in zip(
                    self.plan.labels[len(self.sources) :],
                    self.process_cams,
                    self.plan.processes,
                    strict=True,
                )
            ],
            "notes": list(self.notes),
        }

    def curves_columns(self) -> dict[str, FloatArray]:
        """Return the ``--curves`` columns: Δf in µm and each cam's ΔS in degrees.

        Returns
        -------
        dict of str to ndarray
            ``theta_deg``; ``df_<stat>_um`` and, per cam, ``dS_<cam>_<stat>_deg`` for
            each of mean, std, q00135, q50, q99865 (deterministic).
        """
        stats = ("mean", "std", "q00135", "q50", "q99865")
        out: dict[str, FloatArray] = {"theta_deg": self.theta_deg}
        for stat in stats:
            out[f"df_{stat}_um"] = getattr(self.df, stat) * 1e3
        for letter, m in self.motion.items():
            for stat in stats:
                out[f"dS_{letter}_{stat}_deg"] = np.degrees(getattr(m, stat))
        return out
