"""Sobol sensitivity indices of a tolerance study's outputs, with confidence intervals.

Which sources make the spread of a nonlinear output (max |ΔS| over the revolution, ΔS
at one angle followed exactly, Δf of a pair as made)? The variance shares of the linear
model answer for a linear output only. Sobol indices answer for any output: the
first-order index S_i is the share of Var(Y) that source i explains alone, the total
index T_i the share it takes part in, interactions included ([Sa10]).

Estimators (:func:`sobol_indices`): two independent sample matrices A and B of the
sources and, for each source i, A with its column i taken from B (the "radial" design of
[Sa10]), N(k + 2) evaluations of the output for k sources:

    S_i = mean(f(B) · (f(A_B^i) − f(A))) / Var(Y)               ([Sa10] eq. (b))
    T_i = mean((f(A) − f(A_B^i))²) / (2 Var(Y))                  (Jansen, [Sa10] eq. (f))

Their 95 % confidence intervals are percentile bootstrap intervals over the N rows
(resampled together, so the correlation of the terms is kept), with a stated number of
resamples. For a linear output Y = Σ g_i x_i of independent sources S_i = T_i = the
variance share (g_i σ_i)² / Var(Y), which the tests check. The samples come from the
study's own random streams (:func:`~camtol.tolerancing.plan.chunk_uniforms`), so the same
seed gives the same indices.

References
----------
.. [Sa10] A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola,
   "Variance based sensitivity analysis of model output. Design and estimator for the
   total sensitivity index", Computer Physics Communications 181(2):259-270, 2010.
   doi:10.1016/j.cpc.2009.09.018
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.plan import SamplingPlan, chunk_uniforms

__all__ = ["SobolIndices", "exact_sobol", "sobol_indices"]

#: Bootstrap resamples of the confidence intervals.
BOOTSTRAP = 200
#: Smallest N: below it the estimators' spread swamps the indices.
MIN_SOBOL_SAMPLES = 64


@dataclass(frozen=True)
class SobolIndices:
    """First-order and total Sobol indices of one output, with 95 % intervals.

    Attributes
    ----------
    labels : tuple of str
        The sources.
    first, total : ndarray
        S_i and T_i per source. [-]
    first_ci95, total_ci95 : ndarray
        Bootstrap 95 % intervals, shape (sources, 2). [-]
    variance : float
        Var(Y) of the output. [output unit²]
    samples : int
        N (the model was evaluated N(k + 2) times).
    """

    labels: tuple[str, ...]
    first: FloatArray
    total: FloatArray
    first_ci95: FloatArray
    total_ci95: FloatArray
    variance: float
    samples: int

    def to_dict(self) -> dict[str, dict[str, object]]:
        """Return ``{source: {first, first_ci95, total, total_ci95}}``."""
        return {
            lab: {
                "first": float(self.first[i]),
                "first_ci95": [float(v) for v in self.first_ci95[i]],
                "total": float(self.total[i]),
                "total_ci95": [float(v) for v in self.total_ci95[i]],
            }
            for i, lab in enumerate(self.labels)
        }


def _estimates(
    fa: FloatArray, fb: FloatArray, fab: FloatArray
) -> tuple[FloatArray, FloatArray, float]:
    """S_i and T_i of one output from f(A) (N,), f(B) (N,) and f(A_B^i) (k, N)."""
    var = float(np.var(np.concatenate([fa, fb])))
    if var <= 0.0:
        zero = np.zeros(fab.shape[0])
        return zero, zero, var
    first = (fb[None, :] * (fab - fa[None, :])).mean(axis=1) / var
    total = 0.5 * ((fa[None, :] - fab) ** 2).mean(axis=1) / var
    return first, total, var


def sobol_indices(
    model: Callable[[FloatArray], FloatArray],
    plan: SamplingPlan,
    samples: int,
    *,
    outputs: tuple[str, ...] = ("output",),
    seed: int = 0,
    bootstrap: int = BOOTSTRAP,
) -> dict[str, SobolIndices]:
    """Sobol indices of ``model``'s outputs over the plan's sources (module docstring).

    Parameters
    ----------
    model : callable
        Maps sample rows (n, columns) [mm or rad] to the outputs of every row, shape
        (n,) for one output or (n, outputs).
    plan : SamplingPlan
        The sources and their distributions (constant sources only: one column each).
    samples : int
        N, rows of each of the matrices A and B (≥ 64).
    outputs : tuple of str
        Names of the model's outputs, in its column order.
    seed : int
        Seed of A and B (two streams of the study's generator apart from Monte Carlo's).
    bootstrap : int
        Resamples of the confidence intervals.

    Returns
    -------
    dict of str to SobolIndices
        By output name.

    Raises
    ------
    DesignError
        Too few samples, or a plan with a profile process (several columns per source).
    """
    if samples < MIN_SOBOL_SAMPLES:
        raise DesignError(
            f"Sobol indices need at least {MIN_SOBOL_SAMPLES} samples; {samples} were asked"
        )
    if plan.processes:
        raise DesignError(
            "Sobol indices are computed for constant sources only; leave out"
            " [statistics] profile_process for --sobol"
        )
    k = plan.columns
    # A and B: the study's chunk streams 2^20 and 2^20 + 1, apart from Monte Carlo's own
    a = plan.sample(chunk_uniforms(seed, 2**20, samples, plan.uniforms))
    b = plan.sample(chunk_uniforms(seed, 2**20 + 1, samples, plan.uniforms))
    ab = np.repeat(a[None, :, :], k, axis=0)
    for i in range(k):
        ab[i, :, i] = b[:, i]
    m = len(outputs)

    def run(x: FloatArray) -> FloatArray:
        return np.asarray(model(x), dtype=float).reshape(x.shape[0], m)

    fa, fb = run(a), run(b)
    fab = run(ab.reshape(k * samples, k)).reshape(k, samples, m)
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=(2**21,))))
    picks = [rng.integers(0, samples, samples) for _ in range(bootstrap)]
    out = {}
    for j, name in enumerate(outputs):
        first, total, var = _estimates(fa[:, j], fb[:, j], fab[:, :, j])
        boot = np.array([_estimates(fa[i, j], fb[i, j], fab[:, i, j])[:2] for i in picks])
        out[name] = SobolIndices(
            labels=plan.labels,
            first=first,
            total=total,
            first_ci95=np.quantile(boot[:, 0], [0.025, 0.975], axis=0).T,
            total_ci95=np.quantile(boot[:, 1], [0.025, 0.975], axis=0).T,
            variance=var,
            samples=int(samples),
        )
    return out


def exact_sobol(
    design: CamDesign, samples: int, *, seed: int = 0, step_deg: float = 1.0
) -> dict[str, SobolIndices]:
    """Sobol indices of a design's outputs followed exactly (THEORY §5; issue 28 item 6).

    A single cam: max_θ |ΔS| (``max_abs_ds``) and ΔS at the angle where the linear σ is
    largest (``ds_at_worst_angle``). A conjugate pair: Δf at its worst angle
    (``df_at_worst_angle``) and each cam's max_θ |ΔS| (``max_abs_ds_a``, ...). Every
    evaluation follows the cam (or the pair) as made.

    Parameters
    ----------
    design : CamDesign
        The design, with constant tolerances (no profile process).
    samples : int
        N of the estimators; the design is followed N(k + 2) times for k sources.
    seed : int
        Seed.
    step_deg : float
        θ grid step of the exact evaluations. [deg]

    Returns
    -------
    dict of str to SobolIndices
        By output name.
    """
    from camtol.pair.kinematics import is_pair

    if is_pair(design):
        return _pair_sobol(design, samples, seed=seed, step_deg=step_deg)
    from camtol.contact.as_made import follow_as_made
    from camtol.design.sources import AsMade, apply_source
    from camtol.tolerancing.study import prepare

    study = prepare(design, step_deg=step_deg)
    d = study.design
    g = study.sens["lift"]
    worst = int(np.argmax((g * g) @ study.plan.column_variance()))
    nominal = d.program.evaluate(study.theta_rad, left_limit=study.left_limit).lift

    def model(x: FloatArray) -> FloatArray:
        out = np.empty((x.shape[0], 2))
        for n, row in enumerate(x):
            state = AsMade(d.mechanism)
            for lab, value in zip(study.plan.labels, row.tolist(), strict=True):
                state = apply_source(state, lab, value)
            res = follow_as_made(
                state, d.mechanism, d.program, study.theta_rad, left_limit=study.left_limit
            )
            ds = res.lift - nominal
            out[n] = (np.abs(ds).max(), ds[worst])
        return out

    return sobol_indices(
        model, study.plan, samples, outputs=("max_abs_ds", "ds_at_worst_angle"), seed=seed
    )


def _pair_sobol(
    design: CamDesign, samples: int, *, seed: int, step_deg: float
) -> dict[str, SobolIndices]:
    from camtol.pair.as_made import follow_pair_as_made
    from camtol.tolerancing.pair import prepare_pair

    study = prepare_pair(design, step_deg=step_deg)
    worst = int(np.argmax((study.df**2) @ study.plan.column_variance()))
    letters = study.letters

    def model(x: FloatArray) -> FloatArray:
        out = np.empty((x.shape[0], 1 + len(letters)))
        for n, row in enumerate(x):
            values = dict(zip(study.plan.labels, row.tolist(), strict=True))
            res = follow_pair_as_made(design, study.sources, values, study.theta_rad)
            out[n, 0] = res.df_mm[worst]
            for j, letter in enumerate(letters):
                out[n, 1 + j] = np.abs(res.motion[letter]).max()
        return out

    names = ("df_at_worst_angle", *(f"max_abs_ds_{letter.lower()}" for letter in letters))
    return sobol_indices(model, study.plan, samples, outputs=names, seed=seed)
