"""Exact-mode Monte Carlo: every sample through the contact engine (THEORY §5).

Each sample's follower is the nominal one with its sampled parameter errors
(``Mechanism.perturbed``), its profile the nominal analytic profile with the sampled
constant radial/normal errors and the sampled profile process Δ(ψ(t))
(:class:`~camtol.tolerancing.processes.ContactAngleError`); ΔS is measured from the
nominal follower's zero. The linear model is evaluated on the same samples, so the
difference of the statistics is the linearisation error in distribution.

Contributions in exact mode: the variance shares of a linear regression of the exact
ΔS(θ) on the samples, share_k = Var(X_k β_k) / Var(ΔS) per source group (squared
standardized regression coefficients; equal to first-order Sobol indices for an additive
linear response, and their sum R² says how linear the response is). A documented
alternative to a Sobol pick-freeze estimate, which would need (k + 2) N contact runs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from camtol.contact.as_made import follow_as_made
from camtol.contact.errors_profile import ProfileError
from camtol.contact.shapes import AnalyticShape
from camtol.design.sources import AsMade, apply_source, can_apply
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism
from camtol.tolerancing.processes import ContactAngleError
from camtol.tolerancing.results import (
    AngleStatistics,
    Contribution,
    LinearExactDifference,
    MonteCarloResult,
    Summary,
    YieldEstimate,
    few_samples_warning,
    sampled_intervals,
    spec_limits,
)

__all__ = ["follow_samples", "perturbed", "run_exact"]

PROBS = (0.00135, 0.5, 0.99865)


def perturbed(mechanism: Mechanism, key: str, delta: float) -> Mechanism:
    """Return the mechanism with the parameter behind source ``key`` moved by ``delta``.

    Parameters
    ----------
    mechanism : Mechanism
        The follower.
    key : str
        Error-source key.
    delta : float
        Deviation. [mm or rad]

    Raises
    ------
    DesignError
        The source has no follower parameter (profile sources r, n) or is unknown.
    """
    return mechanism.perturbed(key, delta)


def _sample_as_made(study: Any, x: FloatArray) -> tuple[AsMade, dict[str, list[ProfileError]]]:
    """Return one sample's cam as made and its profile process, by direction."""
    plan = study.plan
    design = study.design
    as_made = AsMade(design.mechanism)
    for j, lab in enumerate(plan.labels[: len(plan.distributions)]):
        if not can_apply(design.mechanism, lab):
            raise DesignError(
                f"source {lab!r} cannot be re-simulated in exact mode; use --mode linear"
            )
        as_made = apply_source(as_made, lab, float(x[j]))
    process: dict[str, list[ProfileError]] = {"radial": [], "normal": []}
    p = plan.process
    if p is not None:
        a, b = plan.groups[-1]
        k = p.orders.size
        coef = x[a:b]
        target = design.source(p.target)  # the profile source the process perturbs
        process[target.profile or "radial"].append(
            ContactAngleError(design.mechanism, design.program, p.orders, coef[:k], coef[k:])
        )
    return as_made, process


def _stats(y: FloatArray) -> tuple[FloatArray, FloatArray, list[FloatArray]]:
    return (
        y.mean(axis=0),
        y.std(axis=0, ddof=1) if y.shape[0] > 1 else np.zeros(y.shape[1]),
        [np.quantile(y, p, axis=0) for p in PROBS],
    )


def _summary(v: FloatArray) -> Summary:
    q = [float(np.quantile(v, p)) for p in PROBS]
    sd = float(v.std(ddof=1)) if v.size > 1 else 0.0
    ordered = np.sort(v)

    def order_statistic(frac: float) -> float:
        return float(ordered[min(max(round(frac * v.size), 1), v.size) - 1])

    ci = sampled_intervals(v.size, float(v.mean()), sd, order_statistic)
    return Summary(float(v.mean()), sd, q[0], q[1], q[2], ci)


def regression_shares(
    x: FloatArray, y: FloatArray, groups: tuple[tuple[int, int], ...]
) -> FloatArray:
    """Variance shares of a linear regression of y (samples × angles) on x, per group.

    Returns
    -------
    ndarray, shape (groups, angles)
        Var(x_g β_g) / Var(y) (0 where y does not vary).
    """
    xc = x - x.mean(axis=0)
    yc = y - y.mean(axis=0)
    beta, *_ = np.linalg.lstsq(xc, yc, rcond=None)
    vy = (yc * yc).sum(axis=0)
    safe = np.where(vy > 0, vy, 1.0)
    out = []
    for a, b in groups:
        part = xc[:, a:b] @ beta[a:b]
        out.append(np.where(vy > 0, (part * part).sum(axis=0) / safe, 0.0))
    return np.asarray(out)


#: Fewest samples per worker process worth its start (a new interpreter importing camtol,
#: about half a second, against some 7 ms per sample).
MIN_SAMPLES_PER_PROCESS = 200


def follow_samples(study: Any, x: FloatArray) -> FloatArray:
    """Exact ΔS of each sample row of ``x``, shape (rows, angles). [mm or rad]

    Every sample's profile is the nominal one with its errors: its nominal geometry on
    the seeding polygon is computed once for the block, not per sample. Each row depends
    on its own values only, so blocks may run in any process in any order.

    Parameters
    ----------
    study : Study
        The prepared design.
    x : ndarray, shape (rows, columns)
        Sample rows. [mm or rad]
    """
    design = study.design
    theta, left = study.theta_rad, study.left_limit
    nominal = design.program.evaluate(theta, left_limit=left).lift
    shape = AnalyticShape(design.mechanism, design.program)
    out = np.empty((x.shape[0], theta.size))
    for i in range(x.shape[0]):
        as_made, process = _sample_as_made(study, x[i])
        res = follow_as_made(
            as_made,
            design.mechanism,
            design.program,
            theta,
            left_limit=left,
            radial_errors=process["radial"],
            normal_errors=process["normal"],
            nominal_shape=shape,
        )
        out[i] = res.lift - nominal
    return out


def _follow_all(
    study: Any,
    x: FloatArray,
    workers: int,
    progress: Callable[[int, int], None] | None,
) -> FloatArray:
    """Exact ΔS of every sample, on ``workers`` processes when there are enough samples.

    Processes, not threads: a sample's contact solve is many small array operations
    whose Python overhead holds the interpreter lock. They start with ``spawn`` (no fork
    of a process that may hold BLAS or Dask threads); the rows come back in order, so
    the result does not depend on the number of workers.
    """
    n = x.shape[0]
    procs = min(int(workers), n // MIN_SAMPLES_PER_PROCESS)
    if procs <= 1:
        out = np.empty((n, study.theta_rad.size))
        step = 16
        for a in range(0, n, step):
            out[a : a + step] = follow_samples(study, x[a : a + step])
            if progress is not None:
                progress(min(a + step, n), n)
        return out
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures.process import BrokenProcessPool

    blocks = np.array_split(np.arange(n), 4 * procs)  # several per process: even finish
    out = np.empty((n, study.theta_rad.size))
    done = 0
    context = multiprocessing.get_context("spawn")
    try:
        with ProcessPoolExecutor(max_workers=procs, mp_context=context) as pool:
            results = pool.map(follow_samples, [study] * len(blocks), [x[b] for b in blocks])
            for rows, block in zip(blocks, results, strict=True):
                out[rows] = block
                done += rows.size
                if progress is not None:
                    progress(done, n)
    except BrokenProcessPool:
        raise DesignError(
            f"workers={workers}: the worker processes could not run (a script that calls"
            " camtol must start under `if __name__ == '__main__':`, as multiprocessing"
            " requires); use workers=1"
        ) from None
    return out


def run_exact(
    study: Any,
    samples: int,
    seed: int,
    spec: float | None,
    progress: Callable[[int, int], None] | None,
    *,
    band: tuple[FloatArray, FloatArray] | None = None,
    band_text: str = "",
    workers: int = 1,
) -> MonteCarloResult:
    """Run an exact-mode study (see the module docstring).

    Parameters
    ----------
    study : Study
        The prepared design (:func:`camtol.tolerancing.montecarlo.prepare`).
    samples : int
        Number of samples.
    seed : int
        Seed of the random streams.
    spec : float or None
        Spec on max |ΔS|. [mm or rad]
    progress : callable or None
        Called with (samples done, samples).
    band : (ndarray, ndarray), optional
        Lower and upper curves of ΔS on the study's grid: the yield counts the samples
        whose exact ΔS(θ) lies inside at every angle (instead of ``spec``). [mm or rad]
    band_text : str
        The band's label (its file's name), for the yield.
    workers : int
        Processes following the samples (used from :data:`MIN_SAMPLES_PER_PROCESS`
        samples per process; the numbers do not depend on it).

    Returns
    -------
    MonteCarloResult
        The exact statistics (internal units: mm or rad) and their difference from the
        linear ones on the same samples.
    """
    from camtol.tolerancing.study import (
        comparison_rows,
        sample_matrix,
        source_models,
        variance_shares,
        worst_angle,
    )

    design = study.design
    theta = study.theta_rad
    x = sample_matrix(study.plan, seed, samples)
    exact = _follow_all(study, x, workers, progress)
    linear = x @ study.sens["lift"].T
    em, es, eq = _stats(exact)
    lm, ls, lq = _stats(linear)
    e_max = np.max(np.abs(exact), axis=1)
    l_max = np.max(np.abs(linear), axis=1)
    counts, edges = np.histogram(e_max, bins=64, range=(0.0, float(e_max.max()) or 1.0))
    stats = {
        "lift": AngleStatistics(
            "lift",
            study.unit,
            em,
            es,
            eq[0],
            eq[1],
            eq[2],
            0.0,
            _summary(e_max),
            method="sampled",
            max_abs_histogram=(edges, counts.astype(np.int64)),
        )
    }
    diff = LinearExactDifference(
        mean=float(np.max(np.abs(em - lm))),
        std=float(np.max(np.abs(es - ls))),
        q00135=float(np.max(np.abs(eq[0] - lq[0]))),
        q99865=float(np.max(np.abs(eq[2] - lq[2]))),
        max_abs_q99865=float(abs(np.quantile(e_max, PROBS[2]) - np.quantile(l_max, PROBS[2]))),
        max_sample=float(np.max(np.abs(exact - linear))),
    )
    y = None
    if spec is not None:
        y = YieldEstimate.of(int(np.count_nonzero(e_max <= spec)), samples, spec=spec)
    elif band is not None:
        inside = np.all((exact >= band[0][None, :]) & (exact <= band[1][None, :]), axis=1)
        y = YieldEstimate.of(int(np.count_nonzero(inside)), samples, band=band_text)
    if samples > study.plan.columns + 1:
        sh = regression_shares(x, exact, study.plan.groups)
        shares = {lab: sh[j] for j, lab in enumerate(study.plan.labels)}
        how = "variance shares of a linear regression of the exact ΔS on the samples"
    else:
        shares = variance_shares(study)
        how = "too few samples to regress: linear-model variance shares"
    i = worst_angle(eq[0], eq[2], band)
    contributions = tuple(
        sorted(
            (Contribution(k, float(v[i])) for k, v in shares.items()),
            key=lambda c: -c.variance_share,
        )
    )
    label_q = []
    g = study.sens["lift"]
    for a, b in study.plan.groups:
        lab_max = np.max(np.abs(x[:, a:b] @ g[:, a:b].T), axis=1)
        label_q.append(float(np.quantile(lab_max, 0.9973)))
    combined = float(np.max(np.maximum(np.abs(eq[0]), np.abs(eq[2]))))
    return MonteCarloResult(
        design_name=design.name,
        samples=samples,
        seed=seed,
        mode="exact",
        theta_deg=np.degrees(theta),
        statistics=stats,
        yield_estimate=y,
        shares=shares,
        worst_angle_deg=float(math.degrees(theta[i])),
        contributions=contributions,
        comparison=comparison_rows(study, label_q, combined),
        sources=source_models(study),
        difference=diff,
        limits=spec_limits(theta.size, spec, band),
        warnings=few_samples_warning(samples, "dS at each angle and of max |dS|"),
        notes=(
            "exact mode: every sample through the contact engine (THEORY §5); quantiles are"
            " exact order statistics; per-source Monte Carlo columns use the linear model",
            f"contributions: {how}",
        ),
    )
