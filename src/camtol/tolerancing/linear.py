"""Linear-mode Monte Carlo engine: chunked GEMM of sensitivities × samples (THEORY §3).

Only what couples the angles is sampled (issue 28): the per-angle mean, σ, quantiles and
probability of leaving the limits are computed without samples
(:mod:`camtol.tolerancing.convolution`). For each chunk of samples X (rows),
ΔS = G Xᵀ (angles × samples) is formed block by block in float32 (bounded memory:
``BLOCK_ANGLES`` angles × one chunk at a time) and reduced per sample:

- max_θ |ΔS| (a histogram, plus exact sums for its mean and σ) and whether it meets the
  spec or lies inside a band at every angle;
- for a profile process, max_θ |ΔS| of its columns alone (a histogram: its Monte Carlo
  99.73 % figure in the comparison table; a constant source's is a closed form).

Integer histograms add up in any order; floating partials are kept per chunk and folded
in chunk order, so the numbers are identical however chunks are grouped into tasks.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from camtol.jet import FloatArray
from camtol.tolerancing.plan import CHUNK, SamplingPlan, chunk_uniforms

__all__ = ["LinearSpec", "LinearTotals", "run_task", "merge"]

#: Angles per GEMM block (keeps the block × chunk array in cache).
BLOCK_ANGLES = 64
#: Bins of the max |ΔS| histograms.
MAX_BINS = 16384

IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class LinearSpec:
    """Everything a worker needs (picklable; internal units).

    Attributes
    ----------
    seed, samples : int
        Study seed and total number of samples.
    plan : SamplingPlan
        Columns and distributions.
    sens : dict of str to ndarray
        Sensitivities per quantity, shape (angles, columns).
    max_top : dict of str to float
        Upper end of the max |ΔS| histogram per quantity. [output unit]
    label_top : ndarray
        Upper end of each sampled label's max |ΔS| histogram (lift). [output unit]
    spec : float or None
        Spec on max |ΔS|. [output unit]
    band : (ndarray, ndarray) or None
        Lower and upper band curves on ΔS. [output unit]
    sampled_labels : tuple of int
        Labels (indices into ``plan.groups``) whose max |ΔS| is sampled: the profile
        process (several columns); a constant source's is a closed form.
    """

    seed: int
    samples: int
    plan: SamplingPlan
    sens: dict[str, FloatArray]
    max_top: dict[str, float]
    label_top: FloatArray
    spec: float | None = None
    band: tuple[FloatArray, FloatArray] | None = None
    sampled_labels: tuple[int, ...] = ()

    @property
    def chunks(self) -> int:
        """Number of random streams."""
        return -(-self.samples // CHUNK)


@dataclass
class LinearTotals:
    """Partial or total reductions (see module docstring).

    ``floats`` holds, per chunk, its size and per quantity the sum and sum of squares
    of max |ΔS| (folded in chunk order).
    """

    max_hist: dict[str, IntArray]
    label_hist: IntArray
    passed_spec: int = 0
    passed_band: int = 0
    floats: dict[int, tuple[int, dict[str, tuple[float, float]]]] = field(default_factory=dict)


def _empty(spec: LinearSpec) -> LinearTotals:
    return LinearTotals(
        max_hist={q: np.zeros(MAX_BINS, np.int64) for q in spec.sens},
        label_hist=np.zeros((len(spec.sampled_labels), MAX_BINS), np.int64),
    )


def _bins(values: FloatArray, top: float) -> IntArray:
    k = np.floor(values * (MAX_BINS / top)) if top > 0 else np.zeros_like(values)
    return np.clip(k, 0, MAX_BINS - 1).astype(np.int64)


def run_task(spec: LinearSpec, chunks: tuple[int, ...]) -> LinearTotals:
    """Reduce the given chunks of samples (a worker's task).

    Parameters
    ----------
    spec : LinearSpec
        The study.
    chunks : tuple of int
        Chunk indices to process.
    """
    out = _empty(spec)
    plan = spec.plan
    n = next(iter(spec.sens.values())).shape[0]
    g32 = {q: np.ascontiguousarray(g, dtype=np.float32) for q, g in spec.sens.items()}
    buf = np.empty((BLOCK_ANGLES, CHUNK), np.float32)
    for c in chunks:
        start = c * CHUNK
        size = min(CHUNK, spec.samples - start)
        x = plan.sample(chunk_uniforms(spec.seed, c, size, plan.uniforms))
        sums: dict[str, tuple[float, float]] = {}
        for row, j in enumerate(spec.sampled_labels):
            a, b = plan.groups[j]
            lab = np.abs(spec.sens["lift"][:, a:b] @ x[:, a:b].T).max(axis=0)
            out.label_hist[row] += np.bincount(
                _bins(lab, float(spec.label_top[row])), minlength=MAX_BINS
            )
        xt = np.ascontiguousarray(x.T, dtype=np.float32)
        ok_band = np.ones(size, bool)
        for q in spec.sens:
            top = np.full(size, -np.inf, dtype=np.float32)
            bottom = np.full(size, np.inf, dtype=np.float32)
            # Blocks of angles × all the chunk's samples: each block's ΔS stays in cache.
            for a0 in range(0, n, BLOCK_ANGLES):
                a1 = min(n, a0 + BLOCK_ANGLES)
                d = np.matmul(g32[q][a0:a1], xt, out=buf[: a1 - a0, :size])
                np.maximum(top, d.max(axis=0), out=top)
                np.minimum(bottom, d.min(axis=0), out=bottom)
                if q == "lift" and spec.band is not None:
                    lo, hi = spec.band
                    ok_band &= np.all((d >= lo[a0:a1, None]) & (d <= hi[a0:a1, None]), axis=0)
            maxabs = np.maximum(top, -bottom).astype(float)
            out.max_hist[q] += np.bincount(_bins(maxabs, spec.max_top[q]), minlength=MAX_BINS)
            sums[q] = (float(maxabs.sum()), float((maxabs * maxabs).sum()))
            if q == "lift" and spec.spec is not None:
                out.passed_spec += int(np.count_nonzero(maxabs <= spec.spec))
        if spec.band is not None:
            out.passed_band += int(np.count_nonzero(ok_band))
        out.floats[c] = (size, sums)
    return out


def merge(parts: list[LinearTotals]) -> LinearTotals:
    """Add task results (integers in any order; floating partials kept per chunk).

    Parameters
    ----------
    parts : list of LinearTotals
        Task results; the first one receives the sum.
    """
    total = parts[0]
    for p in parts[1:]:
        for q in total.max_hist:
            total.max_hist[q] += p.max_hist[q]
        total.label_hist += p.label_hist
        total.passed_spec += p.passed_spec
        total.passed_band += p.passed_band
        total.floats.update(p.floats)
    return total


def fold_max_moments(
    totals: LinearTotals, quantities: list[str]
) -> tuple[int, dict[str, tuple[float, float]]]:
    """Fold the per-chunk sums in chunk order.

    Returns
    -------
    tuple
        (N, per quantity the mean and σ (N − 1 divisor) of max |ΔS| over the samples).
    """
    n_tot = 0
    acc = {q: [0.0, 0.0] for q in quantities}
    for c in sorted(totals.floats):
        size, sums = totals.floats[c]
        n_tot += size
        for q in quantities:
            acc[q][0] += sums[q][0]
            acc[q][1] += sums[q][1]
    stats = {}
    for q in quantities:
        mu = acc[q][0] / n_tot
        var = max(acc[q][1] / n_tot - mu * mu, 0.0) * n_tot / max(n_tot - 1, 1)
        stats[q] = (mu, float(np.sqrt(var)))
    return n_tot, stats


def hist_quantiles(
    counts: IntArray, lower: FloatArray, width: FloatArray, probs: tuple[float, ...]
) -> list[FloatArray]:
    """Quantiles from per-row histograms, linear inside the bin holding each quantile.

    Parameters
    ----------
    counts : ndarray, shape (rows, bins)
        Histogram counts.
    lower, width : ndarray, shape (rows,)
        Start of the first bin and bin width of each row.
    probs : tuple of float
        Probabilities in (0, 1).
    """
    cum = np.cumsum(counts, axis=1)
    total = cum[:, -1:].astype(float)
    out = []
    for p in probs:
        target = p * total
        k = np.argmax(cum >= target, axis=1)
        rows = np.arange(counts.shape[0])
        before = np.where(k > 0, cum[rows, np.maximum(k - 1, 0)], 0).astype(float)
        inside = np.maximum(counts[rows, k].astype(float), 1.0)
        frac = np.clip((target[:, 0] - before) / inside, 0.0, 1.0)
        out.append(np.asarray(lower + width * (k + frac)))
    return out
