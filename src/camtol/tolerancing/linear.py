"""Linear-mode Monte Carlo engine: chunked GEMM of sensitivities × samples (THEORY §3).

For each chunk of samples X (rows), ΔS = G Xᵀ (angles × samples) is formed block by block
in float32 (bounded memory: ``BLOCK_ANGLES`` angles × one chunk at a time) and reduced:

- per angle, a histogram of ΔS over a fixed range that holds every sample (the worst-case
  range of the bounded columns, ±8σ for unbounded ones): the quantiles are read from it
  by linear interpolation inside a bin (resolution: one bin width, reported);
- per sample, max_θ |ΔS| (histogram, plus exact sums for its mean and σ) and whether it
  meets the spec or lies inside a band;
- the sample mean and covariance of the columns, which give the exact sample mean and σ
  of ΔS at every angle (G x̄ and diag(G S Gᵀ)) without forming ΔS.

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

#: Angles per GEMM block (keeps the block × chunk array and its histograms in cache).
BLOCK_ANGLES = 64
#: Bins of the per-angle histograms and of the max |ΔS| histograms.
ANGLE_BINS = 1024
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
    lower, width : dict of str to ndarray
        Histogram range start and bin width per angle, per quantity. [output unit]
    max_top : dict of str to float
        Upper end of the max |ΔS| histogram per quantity. [output unit]
    label_top : ndarray
        Upper end of each label's max |ΔS| histogram (lift). [output unit]
    spec : float or None
        Spec on max |ΔS|. [output unit]
    band : (ndarray, ndarray) or None
        Lower and upper band curves on ΔS. [output unit]
    """

    seed: int
    samples: int
    plan: SamplingPlan
    sens: dict[str, FloatArray]
    lower: dict[str, FloatArray]
    width: dict[str, FloatArray]
    max_top: dict[str, float]
    label_top: FloatArray
    spec: float | None = None
    band: tuple[FloatArray, FloatArray] | None = None

    @property
    def chunks(self) -> int:
        """Number of random streams."""
        return -(-self.samples // CHUNK)


@dataclass
class LinearTotals:
    """Partial or total reductions (see module docstring)."""

    hist: dict[str, IntArray]
    max_hist: dict[str, IntArray]
    label_hist: IntArray
    passed_spec: int = 0
    passed_band: int = 0
    floats: dict[int, tuple[int, FloatArray, FloatArray, dict[str, tuple[float, float]]]] = field(
        default_factory=dict
    )


def _empty(spec: LinearSpec) -> LinearTotals:
    n = next(iter(spec.sens.values())).shape[0]
    return LinearTotals(
        hist={q: np.zeros(n * ANGLE_BINS, np.int64) for q in spec.sens},
        max_hist={q: np.zeros(MAX_BINS, np.int64) for q in spec.sens},
        label_hist=np.zeros((len(spec.plan.labels), MAX_BINS), np.int64),
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
    offs = (np.arange(BLOCK_ANGLES, dtype=np.int32) * ANGLE_BINS)[:, None]
    g32 = {q: np.ascontiguousarray(g, dtype=np.float32) for q, g in spec.sens.items()}
    inv_w = {
        q: np.ascontiguousarray((1.0 / spec.width[q])[:, None], dtype=np.float32) for q in spec.sens
    }
    off = {
        q: np.ascontiguousarray((-spec.lower[q] / spec.width[q])[:, None], dtype=np.float32)
        for q in spec.sens
    }
    buf = np.empty((BLOCK_ANGLES, CHUNK), np.float32)
    gmax = np.abs(spec.sens["lift"])
    for c in chunks:
        start = c * CHUNK
        size = min(CHUNK, spec.samples - start)
        x = plan.sample(chunk_uniforms(spec.seed, c, size, plan.uniforms))
        mean = x.mean(axis=0)
        xc = x - mean
        m2 = xc.T @ xc
        sums: dict[str, tuple[float, float]] = {}
        # Each label alone: max_θ |g_j x_j| for one column, the group's GEMM otherwise.
        for j, (a, b) in enumerate(plan.groups):
            if b - a == 1:
                lab = np.abs(x[:, a]) * float(gmax[:, a].max())
            else:
                lab = np.abs(spec.sens["lift"][:, a:b] @ x[:, a:b].T).max(axis=0)
            out.label_hist[j] += np.bincount(
                _bins(lab, float(spec.label_top[j])), minlength=MAX_BINS
            )
        xt = np.ascontiguousarray(x.T, dtype=np.float32)
        ok_band = np.ones(size, bool)
        for q in spec.sens:
            top = np.full(size, -np.inf, dtype=np.float32)
            bottom = np.full(size, np.inf, dtype=np.float32)
            hist = out.hist[q]
            # Blocks of angles × all the chunk's samples: each block's histograms (and
            # its ΔS values) stay in cache.
            for a0 in range(0, n, BLOCK_ANGLES):
                a1 = min(n, a0 + BLOCK_ANGLES)
                d = g32[q][a0:a1] @ xt
                np.maximum(top, d.max(axis=0), out=top)
                np.minimum(bottom, d.min(axis=0), out=bottom)
                if q == "lift" and spec.band is not None:
                    lo, hi = spec.band
                    ok_band &= np.all((d >= lo[a0:a1, None]) & (d <= hi[a0:a1, None]), axis=0)
                # Bin coordinates (ΔS − lower)/width, in place of a second product (a
                # K = columns + 1 GEMM hits a slow multithreaded OpenBLAS path).
                u = np.multiply(d, inv_w[q][a0:a1], out=buf[: a1 - a0, :size])
                u += off[q][a0:a1]
                np.clip(u, 0.0, ANGLE_BINS - 1, out=u)  # one pass (rounding at the edges)
                idx = u.astype(np.int32)  # float32 → int32 is vectorised; → int64 is not
                idx += offs[: a1 - a0]
                hist[a0 * ANGLE_BINS : a1 * ANGLE_BINS] += np.bincount(
                    idx.ravel(), minlength=(a1 - a0) * ANGLE_BINS
                )
            maxabs = np.maximum(top, -bottom).astype(float)
            out.max_hist[q] += np.bincount(_bins(maxabs, spec.max_top[q]), minlength=MAX_BINS)
            sums[q] = (float(maxabs.sum()), float((maxabs * maxabs).sum()))
            if q == "lift" and spec.spec is not None:
                out.passed_spec += int(np.count_nonzero(maxabs <= spec.spec))
        if spec.band is not None:
            out.passed_band += int(np.count_nonzero(ok_band))
        out.floats[c] = (size, mean, m2, sums)
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
        for q in total.hist:
            total.hist[q] += p.hist[q]
            total.max_hist[q] += p.max_hist[q]
        total.label_hist += p.label_hist
        total.passed_spec += p.passed_spec
        total.passed_band += p.passed_band
        total.floats.update(p.floats)
    return total


def fold_moments(
    totals: LinearTotals, quantities: list[str]
) -> tuple[int, FloatArray, FloatArray, dict[str, tuple[float, float]]]:
    """Fold the per-chunk partials in chunk order (Chan et al.'s pairwise update).

    Returns
    -------
    tuple
        (N, mean of columns, covariance of columns (N − 1 divisor), per quantity the mean
        and σ of max |ΔS| over the samples).
    """
    n_tot = 0
    mean: FloatArray | None = None
    m2: FloatArray | None = None
    acc = {q: [0.0, 0.0] for q in quantities}
    for c in sorted(totals.floats):
        size, cm, cm2, sums = totals.floats[c]
        if mean is None or m2 is None:
            n_tot, mean, m2 = size, cm.copy(), cm2.copy()
        else:
            n_new = n_tot + size
            delta = cm - mean
            mean = mean + delta * (size / n_new)
            m2 = m2 + cm2 + np.outer(delta, delta) * (n_tot * size / n_new)
            n_tot = n_new
        for q in quantities:
            acc[q][0] += sums[q][0]
            acc[q][1] += sums[q][1]
    assert mean is not None and m2 is not None
    cov = m2 / max(n_tot - 1, 1)
    stats = {}
    for q in quantities:
        mu = acc[q][0] / n_tot
        var = max(acc[q][1] / n_tot - mu * mu, 0.0) * n_tot / max(n_tot - 1, 1)
        stats[q] = (mu, float(np.sqrt(var)))
    return n_tot, mean, cov, stats


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
