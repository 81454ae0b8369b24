"""A design prepared for tolerance sampling, and what every sampling mode derives from it.

:func:`prepare` resolves a design's grid, tolerances, sampling plan and closed-form
sensitivities (THEORY §3) once; the linear (:mod:`.montecarlo`) and exact
(:mod:`.exact`) modes and the allocation (:mod:`.allocation`) share it, with the sample
matrix (:func:`sample_matrix`), the variance shares and the comparison of worst case,
RSS and Monte Carlo per source.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.kinematics import analysis_grid
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.model import StatisticalModel, statistical_model
from camtol.tolerancing.plan import (
    CHUNK,
    SamplingPlan,
    chunk_uniforms,
    make_plan,
    sensitivity_matrices,
)
from camtol.tolerancing.processes import ProfileProcess
from camtol.tolerancing.results import ComparisonRow

__all__ = [
    "Study",
    "comparison_rows",
    "prepare",
    "sample_matrix",
    "source_models",
    "variance_shares",
    "worst_angle",
]


@dataclass(frozen=True)
class Study:
    """A design prepared for sampling (grid, tolerances, plan, sensitivities).

    Attributes
    ----------
    design : CamDesign
        The design.
    theta_rad : ndarray
        Cam angles of the grid. [rad]
    left_limit : ndarray of bool
        Rows taking left limits at segment boundaries.
    plan : SamplingPlan
        Columns of the sample matrix.
    sens : dict of str to ndarray
        Sensitivities of ΔS, ΔV, ΔA to every column, shape (angles, columns).
    unit : str
        Internal unit of ΔS: ``mm`` (translating follower) or ``rad`` (oscillating).
    """

    design: CamDesign
    theta_rad: FloatArray
    left_limit: NDArray[np.bool_]
    plan: SamplingPlan
    sens: dict[str, FloatArray]
    unit: str


def prepare(
    design: CamDesign, *, model: StatisticalModel | None = None, step_deg: float = 0.1
) -> Study:
    """Grid, resolved tolerances, sampling plan and sensitivities of a design.

    Parameters
    ----------
    design : CamDesign
        The design; its ``[statistics]`` table gives the model unless ``model`` is given.
    model : StatisticalModel, optional
        Distributions and process.
    step_deg : float
        θ grid step. [deg]

    Raises
    ------
    DesignError
        No toleranced source and no process, or an invalid model.
    GeometryError, UndercutError
        A cam of the design cannot produce its motion.

    Notes
    -----
    A conjugate pair is sampled through cam A, whose contact carries the pair's error
    sources: the output error ``analyze`` computes (THEORY §4); both cams are checked.
    """
    from camtol.analysis.result import max_radius_mm
    from camtol.analysis.validity import check_design_geometry

    # Every cam, whatever the grid (as analyze): a pair whose cam B cannot work fails.
    check_design_geometry(design)
    name = design.name
    design = design.cams()[0].design  # cam A of a pair (the design itself otherwise)
    model = statistical_model(design) if model is None else model
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    tolerances = design.resolve_tolerances(max_radius_mm(design))
    plan = make_plan(design, model, tolerances)
    if plan.columns == 0:
        raise DesignError(
            f"design {name!r} has no [tolerances] and no profile process: nothing to sample"
        )
    sens = sensitivity_matrices(design, plan, theta, left)
    return Study(design, theta, left, plan, sens, design.mechanism.output_unit)


def variance_shares(study: Study) -> dict[str, FloatArray]:
    """Variance share of each source at every angle (linear model: g² Var / Σ g² Var).

    Parameters
    ----------
    study : Study
        The prepared design.

    Returns
    -------
    dict of str to ndarray
        By label, the share of ΔS's variance at each angle. [-]
    """
    g = study.sens["lift"]
    part = g * g * study.plan.column_variance()[None, :]
    total = part.sum(axis=1)
    safe = np.where(total > 0, total, 1.0)
    return {
        lab: np.where(total > 0, part[:, a:b].sum(axis=1) / safe, 0.0)
        for lab, (a, b) in zip(study.plan.labels, study.plan.groups, strict=True)
    }


def worst_angle(
    q_low: FloatArray, q_high: FloatArray, band: tuple[FloatArray, FloatArray] | None
) -> int:
    """Index of the angle of the worst spec margin (largest |quantile| without a band).

    Parameters
    ----------
    q_low, q_high : ndarray
        Lower and upper quantile of ΔS at each angle. [mm or rad]
    band : (ndarray, ndarray) or None
        Lower and upper limit of a tolerance band at each angle. [mm or rad]

    Returns
    -------
    int
        Index into the grid.
    """
    if band is None:
        return int(np.argmax(np.maximum(np.abs(q_low), np.abs(q_high))))
    return int(np.argmin(np.minimum(band[1] - q_high, q_low - band[0])))


def comparison_rows(
    study: Study, label_q9973: list[float], combined_mc: float
) -> tuple[ComparisonRow, ...]:
    """Worst case, RSS and MC 99.73 % per source and combined. [mm or rad]

    Parameters
    ----------
    study : Study
        The prepared design.
    label_q9973 : list of float
        Monte Carlo 99.73 % quantile of each label's |ΔS| contribution. [mm or rad]
    combined_mc : float
        Monte Carlo 99.73 % bound of the combined |ΔS|. [mm or rad]

    Returns
    -------
    tuple of ComparisonRow
        One row per label, then ``combined``.
    """
    g = study.sens["lift"]
    per = np.zeros((g.shape[0], len(study.plan.labels)))
    for j, ((a, b), d) in enumerate(zip(study.plan.groups, study.plan.deviations, strict=True)):
        if b - a == 1:
            per[:, j] = np.abs(g[:, a]) * d
    if study.plan.process is not None:
        # The process column group: the target's sensitivity times its 3σ or Σ amplitudes.
        from camtol.analysis.errors import error_analysis
        from camtol.design.cam_design import ResolvedTolerance

        p = study.plan.process
        unit_t = (ResolvedTolerance(p.target, 1.0, "mm", "unit"),)
        st = error_analysis(study.design, unit_t, study.theta_rad, left_limit=study.left_limit)
        per[:, -1] = np.abs(st.sources[p.target].sensitivity) * study.plan.deviations[-1]
    rows = [
        ComparisonRow(lab, float(per[:, j].max()), float(per[:, j].max()), label_q9973[j])
        for j, lab in enumerate(study.plan.labels)
    ]
    rows.append(
        ComparisonRow(
            "combined",
            float(per.sum(axis=1).max()),
            float(np.sqrt((per * per).sum(axis=1)).max()),
            combined_mc,
        )
    )
    return tuple(rows)


def source_models(study: Study) -> dict[str, ResolvedDistribution | ProfileProcess]:
    """Each label's distribution (internal units, :attr:`ResolvedDistribution.unit`).

    Parameters
    ----------
    study : Study
        The prepared design.

    Returns
    -------
    dict of str to ResolvedDistribution or ProfileProcess
        By label, in report order; the profile process last.
    """
    out: dict[str, ResolvedDistribution | ProfileProcess] = {}
    for j, d in enumerate(study.plan.distributions):
        out[study.plan.labels[j]] = d
    if study.plan.process is not None:
        out[study.plan.labels[-1]] = study.plan.process
    return out


def sample_matrix(plan: SamplingPlan, seed: int, samples: int) -> FloatArray:
    """All sample rows of a (small) study, chunk by chunk. [mm or rad]

    Parameters
    ----------
    plan : SamplingPlan
        The columns to sample.
    seed : int
        Seed of the chunked generator (the same rows at any chunking).
    samples : int
        Number of rows.

    Returns
    -------
    ndarray
        Shape (samples, columns). [mm or rad]
    """
    rows = []
    for c in range(-(-samples // CHUNK)):
        size = min(CHUNK, samples - c * CHUNK)
        rows.append(plan.sample(chunk_uniforms(seed, c, size, plan.uniforms)))
    return np.vstack(rows)
