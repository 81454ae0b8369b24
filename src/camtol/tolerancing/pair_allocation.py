"""IT grades for every source of a conjugate pair, against a pair yield (issue 28 item 4).

``camtol allocate --criterion pair_yield``: the fraction of assembled pairs whose
interference and backlash stay within their limits must reach a target yield. Every
source of the pair that takes an IT grade (each cam's profile, each roller, each arm,
the centre distance) gets one; a source given as an explicit deviation (the arm angle
``eta_deg``, the shaft's ``phase_deg``) keeps it.

The search is greedy on cost: all sources start at the coarsest candidate grade; while
the sampled pair yield (:func:`camtol.tolerancing.pair.pair_monte_carlo`) is below the
target, the source with the largest share of Δf's variance at its worst angle (the
deterministic contributions) moves one grade finer. The result is verified with more
samples and says whether the target is met (``met``) with the yield's Clopper-Pearson
interval. A greedy step is not guaranteed cheapest among all combinations (single-cam
allocation searches them all, :mod:`camtol.tolerancing.allocation`); it is the order a
production engineer would tighten in, and each step is reported.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from camtol import iso286
from camtol.design.cam_design import CamDesign, ToleranceSpec
from camtol.exceptions import DesignError
from camtol.pair.sources import pair_sources
from camtol.tolerancing.allocation import DEFAULT_GRADES
from camtol.tolerancing.pair import pair_monte_carlo, prepare_pair
from camtol.tolerancing.results import YieldEstimate

__all__ = ["PairAllocation", "allocate_pair"]


@dataclass(frozen=True)
class PairAllocation:
    """The grades chosen for a pair and the yield they give.

    Attributes
    ----------
    grades : dict of str to str
        IT grade per pair source (``r_a``, ``rf_d``, ``f``, ...).
    fixed : tuple of str
        Sources kept at their explicit deviation.
    yield_estimate : YieldEstimate
        The verified pair yield (interference and backlash within the limits).
    target_yield : float
        The yield asked for. [-]
    met : bool
        Whether the verified yield reaches the target.
    steps : tuple of (str, str, float)
        Each tightening: source, its new grade, the yield estimate that led to it.
    design : CamDesign
        The design with the chosen grades (per-cam keys).
    """

    grades: dict[str, str]
    fixed: tuple[str, ...]
    yield_estimate: YieldEstimate
    target_yield: float
    met: bool
    steps: tuple[tuple[str, str, float], ...]
    design: CamDesign

    def to_dict(self) -> dict[str, Any]:
        """Return the pair's ``camtol allocate --json`` object."""
        y = self.yield_estimate
        return {
            "criterion": "pair_yield",
            "grades": self.grades,
            "fixed": list(self.fixed),
            "target_yield": self.target_yield,
            "pair_yield": {"value": y.value, "ci95": list(y.ci95), "samples": y.samples},
            "met": self.met,
            "steps": [{"source": s, "grade": g, "yield_before": v} for s, g, v in self.steps],
        }


def _with_grades(
    design: CamDesign, grades: dict[str, str], fixed: dict[str, ToleranceSpec]
) -> CamDesign:
    specs = [ToleranceSpec(key, grade=grade) for key, grade in grades.items()]
    specs += list(fixed.values())
    return dataclasses.replace(design, tolerances=tuple(specs))


def _gap_shares(design: CamDesign, step_deg: float) -> dict[str, float]:
    """Each source's share of Var(Δf − Δf₀) where its σ is largest (what decides the yield)."""
    study = prepare_pair(design, step_deg=step_deg)
    gap = study.df.copy()
    if study.centre_column is not None:
        gap[:, study.centre_column] -= 1.0
    part = gap * gap * study.plan.column_variance()[None, :]
    worst = int(np.argmax(part.sum(axis=1)))
    total = float(part[worst].sum()) or 1.0
    return {lab: float(part[worst, j]) / total for j, lab in enumerate(study.plan.labels)}


def allocate_pair(
    design: CamDesign,
    *,
    interference_max_mm: float,
    backlash_max_mm: float,
    target_yield: float = 0.99,
    grades: tuple[str, ...] = DEFAULT_GRADES,
    samples: int = 4000,
    verify_samples: int = 20000,
    seed: int = 0,
    step_deg: float = 0.5,
) -> PairAllocation:
    """Allocate IT grades to a pair's sources against its interference/backlash yield.

    Parameters
    ----------
    design : CamDesign
        A conjugate design; its toleranced sources are allocated (values ignored).
    interference_max_mm, backlash_max_mm : float
        Limits of the pair yield. [mm]
    target_yield : float
        Yield to reach, in (0, 1). [-]
    grades : tuple of str
        Candidate grades, finest to coarsest or in any order.
    samples, verify_samples : int
        Pairs sampled per step and for the final verification.
    seed : int
        Seed of every run.
    step_deg : float
        θ grid step. [deg]

    Returns
    -------
    PairAllocation

    Raises
    ------
    DesignError
        Not a pair, no source to allocate, a target outside (0, 1), bad limits.
    """
    if not 0.0 < target_yield < 1.0:
        raise DesignError(f"--yield={target_yield!r} is not allowed; give a value in (0, 1)")
    order = sorted({iso286.parse_grade(g) for g in grades}, key=lambda g: int(g[2:]))
    if not order:
        raise DesignError("give at least one candidate grade")
    sources = pair_sources(design)
    fixed = {
        s.design_key: t
        for s in sources
        for t in design.tolerances
        if t.key == s.design_key and t.grade is None
    }
    free = [s.key for s in sources if s.design_key not in fixed]
    if not free:
        raise DesignError(
            "the pair has no source to allocate: give its tolerances as IT grades in"
            " [tolerances] (explicit deviations are kept)"
        )
    current = {key: order[-1] for key in free}  # the coarsest candidate first
    steps: list[tuple[str, str, float]] = []

    def run(n: int) -> Any:
        return pair_monte_carlo(
            _with_grades(design, current, fixed),
            n,
            seed=seed,
            step_deg=step_deg,
            interference_max_mm=interference_max_mm,
            backlash_max_mm=backlash_max_mm,
            quantiles=False,
            fixture_yield=False,  # the criterion is interference and backlash only
        )

    for _ in range(len(free) * len(order)):
        res = run(samples)
        assert res.pair_yield is not None
        if res.pair_yield.value >= target_yield:
            break
        shares = _gap_shares(_with_grades(design, current, fixed), step_deg)
        tighten = [
            k
            for k in sorted(shares, key=lambda k: -shares[k])
            if k in current and current[k] != order[0]
        ]
        if not tighten:
            break  # every source at the finest grade: the target cannot be met
        key = tighten[0]
        current[key] = order[order.index(current[key]) - 1]
        steps.append((key, current[key], res.pair_yield.value))
    final = run(verify_samples)
    assert final.pair_yield is not None
    return PairAllocation(
        grades=dict(current),
        fixed=tuple(fixed),
        yield_estimate=final.pair_yield,
        target_yield=target_yield,
        met=final.pair_yield.value >= target_yield,
        steps=tuple(steps),
        design=_with_grades(design, current, fixed),
    )
