"""Monte Carlo tolerance analysis of a cam design: linear and exact modes.

Linear mode: ΔS(θ) = Σ_j g_j(θ) x_j from the closed-form sensitivities of THEORY §3
([CW06] §3, [WC05]). Its per-angle mean, σ, quantiles and probability of leaving the
limits are computed from the source distributions without sampling
(:mod:`.convolution`, issue 28); every error source is sampled from its distribution
(:mod:`.distributions`, :mod:`.processes`) in chunks (:mod:`.linear`) for what couples
the angles: max_θ |ΔS| per sample and the yield. Exact mode runs the same samples
through the contact engine (THEORY §5): each sample's follower perturbed
(``Mechanism.perturbed``), its profile carrying its radial/normal errors; it reports the
exact statistics and their difference from the linear ones on the same samples.

References
----------
.. [CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006.
.. [WC05] L.-I. Wu, W.-T. Chang, Proc. IMechE C 219(2):209-224, 2005.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from typing import Any, Literal

import numpy as np

import camtol.tolerancing.linear as lin
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.band import ToleranceBand, band_curves, band_label
from camtol.tolerancing.model import StatisticalModel
from camtol.tolerancing.plan import (
    CHUNK,
    Quantity,
)
from camtol.tolerancing.results import (
    AngleStatistics,
    Contribution,
    MonteCarloResult,
    OutsideProbability,
    Summary,
    YieldEstimate,
    few_samples_warning,
    sampled_intervals,
    spec_limits,
)
from camtol.tolerancing.study import (
    Study,
    comparison_rows,
    prepare,
    source_models,
    variance_shares,
    worst_angle,
)

__all__ = ["Mode", "Study", "monte_carlo", "prepare"]

Mode = Literal["linear", "exact"]
PROBS = (0.00135, 0.5, 0.99865)
#: Largest number of samples of a linear study (memory is bounded; this bounds time).
MAX_LINEAR_SAMPLES = 10**10
#: Largest memory the exact mode may use for its sample curves. [bytes]
MAX_EXACT_BYTES = 2 * 2**30
Progress = Callable[[int, int], None]


def _check_samples(samples: int, mode: Mode, angles: int) -> None:
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples <= 0:
        raise DesignError(f"samples={samples!r} is not allowed; give a whole number ≥ 1")
    if mode == "linear" and samples > MAX_LINEAR_SAMPLES:
        raise DesignError(
            f"samples={samples} is not allowed; a linear study takes at most"
            f" {MAX_LINEAR_SAMPLES:.0e} samples (use a Dask cluster and split the study)"
        )
    need = 3 * 8 * samples * angles
    if mode == "exact" and need > MAX_EXACT_BYTES:
        most = MAX_EXACT_BYTES // (3 * 8 * angles)
        raise DesignError(
            f"samples={samples} is too large for exact mode: it keeps every curve"
            f" ({need / 2**30:.1f} GiB); at most {most} samples on this grid"
        )


def _max_tops(study: Study) -> dict[str, float]:
    """Upper end of each quantity's max |ΔS| histogram: bounds every sample. [unit]

    The worst case of the bounded columns plus ±8σ of the unbounded ones, at the angle
    where it is largest (padded so that no sample falls on the end).
    """
    lo_c, hi_c, bounded = study.plan.column_bounds()
    var = study.plan.column_variance()
    mean = study.plan.column_mean()
    top = {}
    for q, g in study.sens.items():
        gb = g[:, bounded]
        lo = np.minimum(gb * lo_c[bounded], gb * hi_c[bounded]).sum(axis=1)
        hi = np.maximum(gb * lo_c[bounded], gb * hi_c[bounded]).sum(axis=1)
        gu = g[:, ~bounded]
        centre = gu @ mean[~bounded]
        spread = 8.0 * np.sqrt((gu * gu) @ var[~bounded])
        lo = lo + centre - spread
        hi = hi + centre + spread
        span = hi - lo
        floor = max(1e-9 * float(np.max(span)), 1e-30)
        grow = np.maximum(span, floor) - span
        lo, hi = lo - 0.5 * grow, hi + 0.5 * grow
        pad = 1e-9 * (hi - lo)
        top[q] = float(max(np.max(np.abs(lo - pad)), np.max(np.abs(hi + pad))))
    return top


def _sampled_labels(study: Study) -> tuple[int, ...]:
    """Labels whose max |ΔS| alone must be sampled: those of several columns (a process)."""
    return tuple(j for j, (a, b) in enumerate(study.plan.groups) if b - a > 1)


def _label_tops(study: Study, labels: tuple[int, ...]) -> FloatArray:
    lo_c, hi_c, _ = study.plan.column_bounds()
    g = study.sens["lift"]
    b = np.maximum(np.abs(lo_c), np.abs(hi_c))
    groups = [study.plan.groups[j] for j in labels]
    return np.array([float(np.max(np.abs(g[:, a:z]) @ b[a:z])) * 1.000001 for a, z in groups])


@contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Limit BLAS to one thread for the products of the Monte Carlo engine.

    They have 3-20 columns, for which OpenBLAS's threads only cost (10-100x slower on a
    busy machine, measured); parallelism comes from the tasks instead.
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _execute(
    spec: lin.LinearSpec,
    *,
    chunks_per_task: int,
    workers: int,
    scheduler: Any,
    progress: Progress | None,
) -> lin.LinearTotals:
    tasks = [
        tuple(range(i, min(i + chunks_per_task, spec.chunks)))
        for i in range(0, spec.chunks, chunks_per_task)
    ]
    total: lin.LinearTotals | None = None
    done = 0

    def fold(part: lin.LinearTotals) -> None:
        # Fold each task into the total as it arrives (memory stays one task's worth).
        nonlocal total, done
        total = part if total is None else lin.merge([total, part])
        done += 1
        if progress is not None:
            progress(min(done * chunks_per_task * CHUNK, spec.samples), spec.samples)

    if scheduler is not None:
        from camtol.tolerancing.parallel import run_on_dask

        run_on_dask(scheduler, spec, tasks, fold)
    else:
        with single_threaded_blas():
            if workers <= 1 or len(tasks) == 1:
                for t in tasks:
                    fold(lin.run_task(spec, t))
            else:
                with ThreadPoolExecutor(max_workers=workers) as pool:
                    for part in pool.map(lambda t: lin.run_task(spec, t), tasks):
                        fold(part)
    assert total is not None
    return total


def monte_carlo(
    design: CamDesign,
    samples: int,
    *,
    mode: Mode = "linear",
    seed: int = 0,
    model: StatisticalModel | None = None,
    spec: float | None = None,
    band: ToleranceBand | tuple[FloatArray, FloatArray] | None = None,
    quantities: tuple[Quantity, ...] = ("lift",),
    step_deg: float = 0.1,
    chunks_per_task: int = 4,
    workers: int = 1,
    scheduler: Any = None,
    progress: Progress | None = None,
) -> MonteCarloResult:
    """Monte Carlo study of the output error ΔS(θ) of a design (docs/tolerancing.md).

    Parameters
    ----------
    design : CamDesign
        The design (tolerances and optional ``[statistics]`` table).
    samples : int
        Number of mechanisms sampled (≥ 1).
    mode : {"linear", "exact"}
        Closed-form sensitivities (THEORY §3), or the contact engine (THEORY §5).
    seed : int
        Seed; chunk c of 4096 samples uses ``SeedSequence(seed, spawn_key=(c,))``.
    model : StatisticalModel, optional
        Distributions; default the design's ``[statistics]`` table or normal Cp = 1.
    spec : float, optional
        Spec on max_θ |ΔS|, for the yield. [mm, or rad for an oscillating follower]
    band : ToleranceBand or (ndarray, ndarray), optional
        Lower and upper limits of ΔS, for the yield "lower ≤ ΔS ≤ upper at every angle"
        (instead of ``spec``): a :class:`~camtol.tolerancing.band.ToleranceBand`
        (interpolated onto the grid) or two curves on the study's grid. [mm or rad]
    quantities : tuple of {"lift", "velocity", "acceleration"}
        Statistics wanted; ``lift`` is always included.
    step_deg : float
        θ grid step. [deg]
    chunks_per_task, workers : int
        Chunks per task and local workers: threads in linear mode, processes in exact
        mode (from 200 samples per process). Neither changes the numbers.
    scheduler : str or dask.distributed.Client, optional
        Run the tasks on a Dask cluster (``tcp://host:port``) (linear mode).
    progress : callable, optional
        Called with (samples done, samples).

    Returns
    -------
    MonteCarloResult
        Linear mode: deterministic per-angle statistics (``AngleStatistics.method``) with
        the bound on their numerical error, sampled max |ΔS| and yield with 95 %
        intervals; exact mode: everything sampled.

    Raises
    ------
    DesignError
        Bad number of samples, mode or model; both ``spec`` and ``band``; a band of the
        wrong length or not finite.
    """
    if mode not in ("linear", "exact"):
        raise DesignError(f"mode={mode!r} is unknown; allowed: linear, exact")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise DesignError(f"seed={seed!r} is not allowed; give a whole number ≥ 0")
    if spec is not None and not (math.isfinite(spec) and spec > 0):
        raise DesignError(f"spec={spec!r} is not allowed; it must be > 0")
    if spec is not None and band is not None:
        raise DesignError("give spec (on max |ΔS|) or band (lower/upper curves), not both")
    study = prepare(design, model=model, step_deg=step_deg)
    _check_samples(samples, mode, study.theta_rad.size)
    curves = None
    band_text = ""
    if band is not None:
        curves = band_curves(band, study.theta_rad, require_nominal=False)
        band_text = band_label(band)
    qs = ("lift", *(q for q in quantities if q != "lift"))
    if mode == "exact":
        from camtol.tolerancing.exact import run_exact

        if scheduler is not None:
            raise DesignError("scheduler is supported in linear mode only (mode='exact')")
        if len(qs) > 1:
            raise DesignError("ΔV and ΔA statistics are supported in linear mode only")

        return run_exact(
            study,
            int(samples),
            int(seed),
            spec,
            progress,
            band=curves,
            band_text=band_text,
            workers=max(1, int(workers)),
        )
    top = _max_tops(study)
    sampled = _sampled_labels(study)
    lspec = lin.LinearSpec(
        seed=int(seed),
        samples=int(samples),
        plan=study.plan,
        sens={q: study.sens[q] for q in qs},
        max_top={q: top[q] for q in qs},
        label_top=_label_tops(study, sampled),
        spec=spec,
        band=curves,
        sampled_labels=sampled,
    )
    totals = _execute(
        lspec,
        chunks_per_task=max(1, int(chunks_per_task)),
        workers=workers,
        scheduler=scheduler,
        progress=progress,
    )
    return _linear_result(study, lspec, totals, curves, band_text)


def _summary_from_hist(counts: lin.IntArray, top: float, mean: float, std: float) -> Summary:
    """Mean, σ, quantiles and their 95 % intervals of max |ΔS| from its histogram."""
    n = int(counts.sum())
    width = np.array([top / lin.MAX_BINS])

    def at(p: float) -> float:
        return float(lin.hist_quantiles(counts[None, :], np.zeros(1), width, (p,))[0][0])

    q = [at(p) for p in PROBS]
    return Summary(mean, std, q[0], q[1], q[2], sampled_intervals(n, mean, std, at))


def _label_figures(
    study: Study, spec: lin.LinearSpec, totals: lin.LinearTotals
) -> tuple[list[float], list[str]]:
    """99.73 % of max_θ |ΔS_p| per label, and whether it is deterministic or sampled.

    A constant source's max_θ |ΔS_p| is |x_p| max_θ |s_p|: its quantile is a closed form
    of the source's distribution; a process's is read from the samples.
    """
    from camtol.tolerancing.convolution import abs_quantile

    label_q: list[float] = []
    methods: list[str] = []
    g_lift = study.sens["lift"]
    for j, (a, _) in enumerate(study.plan.groups):
        if j in spec.sampled_labels:
            row = spec.sampled_labels.index(j)
            width = np.array([float(spec.label_top[row]) / lin.MAX_BINS])
            counts = totals.label_hist[row][None, :]
            qq = lin.hist_quantiles(counts, np.zeros(1), width, (0.9973,))
            label_q.append(float(qq[0][0]))
            methods.append("sampled")
        else:
            peak = float(np.max(np.abs(g_lift[:, a])))
            label_q.append(peak * abs_quantile(study.plan.distributions[j], 0.9973))
            methods.append("deterministic")
    return label_q, methods


def _linear_result(
    study: Study,
    spec: lin.LinearSpec,
    totals: lin.LinearTotals,
    band: tuple[FloatArray, FloatArray] | None,
    band_text: str = "",
) -> MonteCarloResult:
    from camtol.tolerancing.convolution import POINTS, angle_distributions

    n_tot, max_stats = lin.fold_max_moments(totals, list(spec.sens))
    limits = spec_limits(study.theta_rad.size, spec.spec, band)
    stats: dict[str, AngleStatistics] = {}
    outside = None
    for q, g in spec.sens.items():
        unit = study.unit + ("", "/rad", "/rad2")[("lift", "velocity", "acceleration").index(q)]
        dist = angle_distributions(
            g, study.plan, probs=PROBS, limits=limits if q == "lift" else None
        )
        if dist.p_out is not None and dist.p_out_bounds is not None:
            outside = OutsideProbability(dist.p_out, *dist.p_out_bounds)
        mu, sd = max_stats[q]
        ma = _summary_from_hist(totals.max_hist[q], spec.max_top[q], mu, sd)
        edges = np.linspace(0.0, spec.max_top[q], lin.MAX_BINS + 1)
        stats[q] = AngleStatistics(
            q,
            unit,
            dist.mean,
            dist.std,
            dist.quantiles[0],
            dist.quantiles[1],
            dist.quantiles[2],
            float(np.max(dist.tolerance)),
            ma,
            method="deterministic",
            tolerance=dist.tolerance,
            max_abs_histogram=(edges, totals.max_hist[q].copy()),
        )
    lift = stats["lift"]
    y = None
    if spec.spec is not None:
        y = YieldEstimate.of(totals.passed_spec, n_tot, spec=spec.spec)
    elif band is not None:
        y = YieldEstimate.of(totals.passed_band, n_tot, band=band_text)
    shares = variance_shares(study)
    i = worst_angle(lift.q00135, lift.q99865, band)
    contributions = tuple(
        sorted(
            (Contribution(lab, float(v[i])) for lab, v in shares.items()),
            key=lambda c: -c.variance_share,
        )
    )
    label_q, methods = _label_figures(study, spec, totals)
    methods.append("deterministic")  # combined: the largest half-width of the band
    combined = float(np.max(np.maximum(np.abs(lift.q00135), np.abs(lift.q99865))))
    rows = tuple(
        dataclasses.replace(r, mc_9973_method=m)
        for r, m in zip(comparison_rows(study, label_q, combined), methods, strict=True)
    )
    what = "max |dS|" + (" (and the process's MC 99.73 %)" if spec.sampled_labels else "")
    return MonteCarloResult(
        design_name=study.design.name,
        samples=n_tot,
        seed=spec.seed,
        mode="linear",
        theta_deg=np.degrees(study.theta_rad),
        statistics=stats,
        yield_estimate=y,
        shares=shares,
        worst_angle_deg=float(np.degrees(study.theta_rad[i])),
        contributions=contributions,
        comparison=rows,
        sources=source_models(study),
        limits=limits,
        outside=outside,
        warnings=few_samples_warning(n_tot, what),
        notes=(
            "linear mode: closed-form sensitivities (THEORY §3); per-angle mean, σ,"
            " quantiles and probabilities computed from the source distributions without"
            f" sampling (convolution on {POINTS} lattice points per angle); max |ΔS| and the"
            " yield sampled",
            "zone convention: each source varies in ±Δ of its resolved tolerance (full IT"
            " value), normal σ = Δ/(3 Cp) truncated at the zone",
        ),
    )
