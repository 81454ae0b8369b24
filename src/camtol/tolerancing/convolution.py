"""Per-angle distributions of the linear ΔS without sampling noise (issue 28, item 5).

In linear mode ΔS(θ) = Σ_j g_j(θ) x_j (THEORY §3): at one angle a weighted sum of
independent variables of known distributions (:mod:`.distributions`: truncated or
untruncated normal, uniform, triangular; :mod:`.processes`: a stationary Gaussian process
is a normal at every angle, a harmonic of amplitude A with a random phase contributes
A·|g(θ)|·cos φ, an arcsine variable). Its mean and σ are closed forms (Σ g_j E x_j and
sqrt(Σ g_j² Var x_j)); its quantiles and the probability of leaving a limit are computed
here by convolving the source densities, for every angle at once.

Method
------
At each angle the n components (one per constant source; the normal parts of the study,
untruncated normals and a Gaussian process, merged into one normal cut at ±9σ, whose
tails hold 2·10⁻¹⁹; one arcsine per harmonic) are rounded to a common lattice of step
h(θ) = W(θ) / (N − 3n − 1), W being the sum of their ranges: each component's mass in
every cell [k h − h/2, k h + h/2] is taken from its exact CDF (no density sampling, so a
truncation jump or an arcsine's integrable peak costs nothing). The lattice masses are
convolved by FFT (length N = :data:`POINTS`, large enough that the sum never wraps
around), added up into a CDF, and read with linear interpolation inside a cell (the
lattice sum plus a uniform variable of width h).

When every component is symmetric about its middle (centred truncated normals, uniforms,
symmetric triangles, the harmonics' arcsines and the merged normal: the usual case), each
is rounded to cells placed symmetrically about its middle, its spectrum is real, and the
convolution runs on cosine transforms of half the length (a DCT-II per component, a
DCT-I or DCT-III to invert: :func:`_symmetric_block_lattice`), about three times faster
than the general rFFT path with the same rounding bound; a test holds the two paths to
each other's bounds.

Tolerance
---------
Rounding moves each component by at most h/2 and the interpolation by at most h/2, so the
computed variable differs from the true ΔS by at most b = (n + 1) h / 2 in every
outcome: each quantile is within ±b of the true one (a bound, stated per angle as
``tolerance``), and the true probability of leaving [lower, upper] lies between the
computed probabilities for the limits moved by ±b (``p_out_bounds``). The bound is far
from tight: the rounding errors are nearly independent and centred, and the observed
quantile errors are of order h²/σ, about 10⁻⁵ σ at the default N (tests against closed
forms for sums of uniform sources and against 10⁷ samples, tests/tolerancing).

Why one module: it is one computation, the lattice distribution of ΔS per angle: the
components it is built from, its two convolution paths (which must agree, and a test holds
them to each other) and the quantiles and probabilities read from the one CDF they give.

Work is done in blocks of :data:`BLOCK` angles (each block's arrays stay in cache),
vectorised over the angles of a block and over the lattice; each component is evaluated
only over the lattice cells its range covers in that block.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camtol.jet import FloatArray
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.plan import SamplingPlan

__all__ = [
    "BLOCK",
    "POINTS",
    "AngleDistribution",
    "abs_quantile",
    "angle_distributions",
    "lattice",
]

#: FFT length (lattice points) per angle.
POINTS = 2048
#: Angles per block.
BLOCK = 128
#: Normal parts are cut at ±Z_TAIL σ (the mass beyond is 2.3e-19).
Z_TAIL = 9.0


@dataclass(frozen=True)
class _Component:
    """x = loc·g + (unit·g)·Z per angle, Z of CDF ``cdf`` on [z_lo, z_hi] (mass ``norm``).

    ``scale`` is unit·g per angle (any sign); ``cdf`` need not be normalised (``norm`` is
    its increase over [z_lo, z_hi]).
    """

    cdf: Callable[[FloatArray], FloatArray]
    z_lo: float
    z_hi: float
    norm: float
    scale: FloatArray
    #: The density is symmetric about the middle of [z_lo, z_hi].
    symmetric: bool = False


def _ndtr(z: FloatArray) -> FloatArray:
    from scipy.special import ndtr

    return np.asarray(ndtr(z, out=z) if z.ndim else ndtr(z))


def _uniform(z: FloatArray) -> FloatArray:
    return z


def _arcsine(z: FloatArray) -> FloatArray:
    return np.asarray(np.arcsin(z, out=z))  # the 1/π is in the component's norm


def _triangular(mode: float) -> Callable[[FloatArray], FloatArray]:
    """CDF on [0, 1] of a triangular variable with its mode at ``mode`` ∈ [0, 1]."""

    def cdf(z: FloatArray) -> FloatArray:
        with np.errstate(divide="ignore", invalid="ignore"):
            left = z * z / mode if mode > 0 else np.zeros_like(z)
            right = 1.0 - (1.0 - z) ** 2 / (1.0 - mode) if mode < 1 else np.ones_like(z)
        return np.asarray(np.where(z <= mode, left, right))

    return cdf


def _source_component(d: ResolvedDistribution, g: FloatArray) -> tuple[_Component, FloatArray]:
    """Return the component of a bounded source and its constant part g·loc per angle."""
    if d.kind == "normal":
        s = d.sigma
        a, b = (d.lower - d.centre) / s, (d.upper - d.centre) / s
        norm = float(_ndtr(np.array([b]))[0] - _ndtr(np.array([a]))[0])
        return _Component(_ndtr, a, b, norm, g * s, a == -b), g * d.centre
    width = d.upper - d.lower
    if d.kind == "uniform":
        return _Component(_uniform, 0.0, 1.0, 1.0, g * width, True), g * d.lower
    mode = min(max((d.centre - d.lower) / width, 0.0), 1.0)
    comp = _Component(_triangular(mode), 0.0, 1.0, 1.0, g * width, mode == 0.5)
    return comp, g * d.lower


def abs_quantile(d: ResolvedDistribution, prob: float) -> float:
    """Quantile of |x| for one source: the q with P(|x| ≤ q) = prob. [mm or rad]

    Bisection on the exact CDF to the last bit (a source's max_θ |g(θ) x| is
    |x| max_θ |g|, so this gives its Monte Carlo 99.73 % figure without sampling).

    Parameters
    ----------
    d : ResolvedDistribution
        The source's distribution. [mm or rad]
    prob : float
        Probability in (0, 1). [-]

    Returns
    -------
    float
        The quantile of |x|. [mm or rad]
    """
    if d.kind == "normal" and not d.truncate:
        loc, scale, z_lo, z_hi = d.centre, d.sigma, -np.inf, np.inf
        cdf: Callable[[FloatArray], FloatArray] = _ndtr
        norm = 1.0
    else:
        comp, shift = _source_component(d, np.ones(1))
        loc, scale = float(shift[0]), float(comp.scale[0])
        cdf, z_lo, z_hi, norm = comp.cdf, comp.z_lo, comp.z_hi, comp.norm

    def inside(q: float) -> float:
        z = np.clip(np.array([(-q - loc) / scale, (q - loc) / scale]), z_lo, z_hi)
        f = cdf(z)
        return float(f[1] - f[0]) / norm

    lo, hi = 0.0, max(abs(d.lower), abs(d.upper), abs(d.centre) + 40.0 * d.sigma)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        lo, hi = (lo, mid) if inside(mid) >= prob else (mid, hi)
    return hi


def components(sens: FloatArray, plan: SamplingPlan) -> tuple[list[_Component], FloatArray]:
    """Return the independent components of Σ_j g_j x_j per angle, and a constant offset.

    Parameters
    ----------
    sens : ndarray, shape (angles, columns)
        Sensitivities of the plan's columns. [output unit per column unit]
    plan : SamplingPlan
        Columns and their distributions.

    Returns
    -------
    (list of _Component, ndarray)
        Components and the constant part of ΔS per angle. [output unit]
    """
    n = sens.shape[0]
    offset = np.zeros(n)
    normal_mean = np.zeros(n)
    normal_var = np.zeros(n)
    comps: list[_Component] = []
    for j, d in enumerate(plan.distributions):
        g = np.ascontiguousarray(sens[:, j], dtype=float)
        if d.kind == "normal" and not d.truncate:
            normal_mean += g * d.centre
            normal_var += (g * d.sigma) ** 2
            continue
        if not np.any(g):
            continue  # the output does not depend on this source (e.g. f in Δf)
        comp, shift = _source_component(d, g)
        comps.append(comp)
        offset += shift
    for p, (a, b) in zip(plan.processes, plan.process_groups, strict=True):
        k = p.orders.size
        gc, gs = sens[:, a : a + k], sens[:, a + k : b]
        if p.gaussian:
            var = p.coefficient_variance_mm2()
            normal_var += (gc * gc + gs * gs) @ var
        else:
            amp = p.coefficient_bounds_mm()
            for i in range(k):
                scale = amp[i] * np.hypot(gc[:, i], gs[:, i])
                comps.append(_Component(_arcsine, -1.0, 1.0, np.pi, scale, True))
    if np.any(normal_var > 0):
        sd = np.sqrt(normal_var)
        norm = float(_ndtr(np.array([Z_TAIL]))[0] - _ndtr(np.array([-Z_TAIL]))[0])
        comps.append(_Component(_ndtr, -Z_TAIL, Z_TAIL, norm, sd, True))
    offset += normal_mean
    return comps, offset


@dataclass(frozen=True)
class AngleDistribution:
    """Per-angle distribution of a linear output error, computed without sampling.

    Attributes
    ----------
    mean, std : ndarray
        Closed-form mean and σ at every angle. [output unit]
    quantiles : tuple of ndarray
        One curve per probability of ``probs``. [output unit]
    probs : tuple of float
        The probabilities. [-]
    tolerance : ndarray
        Bound b on the numerical error of every quantile at each angle (module
        docstring). [output unit]
    points : int
        Lattice points (FFT length) per angle.
    p_out : ndarray or None
        With limits: probability that ΔS(θ) lies outside [lower(θ), upper(θ)]. [-]
    p_out_bounds : (ndarray, ndarray) or None
        Guaranteed bounds on ``p_out`` (the limits moved by ∓b and ±b). [-]
    """

    mean: FloatArray
    std: FloatArray
    quantiles: tuple[FloatArray, ...]
    probs: tuple[float, ...]
    tolerance: FloatArray
    points: int
    p_out: FloatArray | None = None
    p_out_bounds: tuple[FloatArray, FloatArray] | None = None


def _block_lattice(
    comps: list[_Component], offset: FloatArray, rows: slice, points: int
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Lattice start, step, CDF at the cell ends and active components of a block.

    Symmetric components only (the usual case: centred tolerances, processes) take the
    cosine-transform path, about three times faster; any other takes the general one.
    """
    if points % 2 == 0 and all(c.symmetric for c in comps):
        return _symmetric_block_lattice(comps, offset, rows, points)
    return _general_block_lattice(comps, offset, rows, points)


def _symmetric_block_lattice(
    comps: list[_Component], offset: FloatArray, rows: slice, points: int
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`_block_lattice` for components that are all symmetric about their middles.

    Each active component (scale ≠ 0) is rounded to 2m cells of width h placed
    symmetrically about its middle c (cell centres c + (i + ½) h, i = −m … m − 1,
    m = ⌈half-range / h⌉), each cell's mass taken from the exact CDF as in the general
    path; a component of scale 0 on a row is its point mass at c. A symmetric lattice
    distribution has a real spectrum, R(ω) = 2 Σ_{i≥0} y_i cos(ω (i + ½)) with y_i the
    masses right of c, which at ω_k = π k / L (L = N / 2) is the DCT-II of y: N/2 points
    instead of an rFFT of N, and the halves left of c are never evaluated. The product
    of the spectra is inverted by a DCT-III when the number of active components is odd
    (the sum's lattice is then at half-integer steps from the sum of the middles) and by
    a DCT-I when it is even; both are exact inversions of the length-N DFT, whose
    periodicity the sum never wraps around: it spans Σ 2m − n + 1 ≤ W / h + n + 1 ≤ N
    points with h = W / (N − n − 1).
    """
    import scipy.fft as sf

    half_n = points // 2
    off = offset[rows]
    nr = off.size
    scales = [np.abs(c.scale[rows]) for c in comps]
    widths = [s * (c.z_hi - c.z_lo) for c, s in zip(comps, scales, strict=True)]
    total = np.sum(widths, axis=0) if widths else np.zeros(nr)
    flat = total <= 0
    h = np.where(flat, 1.0, total / (points - len(comps) - 1))
    middle = off.copy()
    spectrum = np.ones((nr, half_n))
    active = np.zeros(nr)
    buf = np.zeros((nr, half_n))
    dirty = 0
    for c, s, w in zip(comps, scales, widths, strict=True):
        z_mid = 0.5 * (c.z_lo + c.z_hi)
        middle += c.scale[rows] * z_mid
        zero = s == 0
        active += ~zero
        m = np.ceil(0.5 * w / h)
        cols = int(min(half_n, np.max(m)))
        if cols == 0:
            continue  # a point mass on every row of the block
        safe = np.where(zero, 1.0, s)
        # Cell ends z_mid + i h / |s|, i = 0 … cols, in the component's own variable Z.
        z = np.multiply.outer(h / safe, np.arange(cols + 1, dtype=float))
        z += z_mid
        np.minimum(z, c.z_hi, out=z)
        g = c.cdf(z)
        y = buf[:, :cols]
        np.subtract(g[:, 1:], g[:, :-1], out=y)
        y *= 1.0 / c.norm
        if dirty > cols:
            buf[:, cols:dirty] = 0.0
        dirty = cols
        r = sf.dct(buf, type=2, axis=1)
        r[zero] = 1.0  # a point mass at the middle: spectrum 1
        spectrum *= r
    pmf = np.empty((nr, points))
    odd = active % 2 == 1
    if np.any(odd):  # lattice at middle + (k − L + ½) h, k = 0 … N − 1
        q = sf.dct(spectrum[odd], type=3, axis=1) / points
        pmf[odd, half_n:] = q
        pmf[odd, :half_n] = q[:, ::-1]
    even = ~odd
    if np.any(even):  # lattice at middle + (k − L + 1) h; Nyquist term 0 unless no source
        ext = np.empty((int(np.sum(even)), half_n + 1))
        ext[:, :half_n] = spectrum[even]
        ext[:, half_n] = active[even] == 0
        q = sf.dct(ext, type=1, axis=1) / points
        pmf[even, half_n - 1 :] = q
        pmf[even, : half_n - 1] = q[:, half_n - 1 : 0 : -1]
    # No source varies (as in the general path): the point mass at index 0.
    pmf[flat] = 0.0
    pmf[flat, 0] = 1.0
    lower = middle - np.where(flat, 0.0, np.where(odd, half_n - 0.5, half_n - 1.0)) * h
    cdf = np.cumsum(pmf, axis=1)
    cdf /= cdf[:, -1:]
    return lower, h, cdf, active


def _general_block_lattice(
    comps: list[_Component], offset: FloatArray, rows: slice, points: int
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`_block_lattice` for components of any shape (an rFFT per component).

    Each component's lattice points lie symmetrically about the middle of its range
    (2m + 1 points, m = ⌈half-range / h⌉), so a symmetric component rounds to a
    symmetric set of masses and a sum of symmetric components has its median exactly at
    its centre. The sum spans Σ 2m_c + 1 ≤ Σ (w_c / h + 3) − n + 1 ≤ N points (h =
    W / (N − 3n − 1)), so it fits in the FFT length N without wrapping around.
    """
    import scipy.fft as sf

    off = offset[rows]
    nr = off.size
    scales = [c.scale[rows] for c in comps]
    widths = [np.abs(s) * (c.z_hi - c.z_lo) for c, s in zip(comps, scales, strict=True)]
    total = np.sum(widths, axis=0) if widths else np.zeros(nr)
    m = points - 3 * len(comps) - 1
    flat = total <= 0
    h = np.where(flat, 1.0, total / m)
    lower = off.copy()
    spectrum: np.ndarray | None = None
    # Each component's masses go into one zeroed buffer of the FFT length (an FFT of a
    # padded input copies it first, doubling its cost); ``dirty`` columns hold old data.
    buf = np.zeros((nr, points))
    dirty = 0
    for c, s, w in zip(comps, scales, widths, strict=True):
        half = np.ceil(0.5 * w / h)  # m: points 0..2m at mid + (k − m) h
        mid = 0.5 * s * (c.z_lo + c.z_hi)
        start = mid - half * h
        lower += start
        cols = int(min(points, 2 * np.max(half) + 1))
        k = np.arange(cols + 1, dtype=float) - 0.5
        zero = s == 0
        safe = np.where(zero, 1.0, s)
        # Cell ends in the component's own variable Z (value = s Z): decreasing in k
        # when s < 0, hence the sign of the differences.
        z = np.multiply.outer(h / safe, k)
        z += (start / safe)[:, None]
        np.clip(z, c.z_lo, c.z_hi, out=z)
        z[zero, 0], z[zero, 1:] = c.z_lo, c.z_hi  # s = 0: all the mass at 0
        g = c.cdf(z)
        pmf = buf[:, :cols]
        np.subtract(g[:, 1:], g[:, :-1], out=pmf)
        pmf *= (np.where(s >= 0, 1.0, -1.0) / c.norm)[:, None]
        if dirty > cols:
            buf[:, cols:dirty] = 0.0
        dirty = cols
        f = sf.rfft(buf, axis=1)
        spectrum = f if spectrum is None else np.multiply(spectrum, f, out=spectrum)
    if spectrum is None:
        pmf_sum = np.zeros((nr, points))
        pmf_sum[:, 0] = 1.0
    else:
        pmf_sum = sf.irfft(spectrum, n=points, axis=1)
    cdf = np.cumsum(pmf_sum, axis=1)
    cdf /= cdf[:, -1:]
    active = np.sum([w > 0 for w in widths], axis=0) if widths else np.zeros(nr)
    return lower, h, cdf, np.asarray(active, dtype=float)


def _quantile(shifted: FloatArray, lower: FloatArray, h: FloatArray, p: float) -> FloatArray:
    """Return the quantile p per row from the CDF at the cell ends plus the row index.

    Row r's CDF shifted to [r, r + 1]: the rows laid end to end are one increasing array
    and one binary search finds every row's cell.
    """
    cdf = shifted
    rows = np.arange(cdf.shape[0])
    n = cdf.shape[1]
    k = np.searchsorted(cdf.ravel(), rows + p, side="left") - rows * n
    k = np.clip(k, 0, n - 1)
    prev = np.where(k > 0, cdf[rows, np.maximum(k - 1, 0)] - rows, 0.0)
    cur = cdf[rows, k] - rows
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(cur > prev, (p - prev) / (cur - prev), 0.5)
    return np.asarray(lower + (k - 0.5 + np.clip(frac, 0.0, 1.0)) * h)


def _cdf_at(cdf: FloatArray, lower: FloatArray, h: FloatArray, x: FloatArray) -> FloatArray:
    """CDF of the lattice sum plus a uniform of width h, at x (one value per row)."""
    n = cdf.shape[1]
    y = np.clip((x - lower) / h + 0.5, 0.0, float(n))
    k = np.minimum(np.floor(y).astype(np.intp), n - 1)
    rows = np.arange(cdf.shape[0])
    prev = np.where(k > 0, cdf[rows, np.maximum(k - 1, 0)], 0.0)
    cur = cdf[rows, k]
    return np.asarray(np.clip(prev + (y - k) * (cur - prev), 0.0, 1.0))


def _outside(
    cdf: FloatArray,
    lower: FloatArray,
    h: FloatArray,
    lo: FloatArray,
    hi: FloatArray,
    flat: np.ndarray,
) -> FloatArray:
    """Return P(ΔS < lo or ΔS > hi) per row.

    A row without spread is a point mass: outside iff it lies outside.
    """
    below = _cdf_at(cdf, lower, h, lo)
    above = 1.0 - _cdf_at(cdf, lower, h, hi)
    point = ((lower < lo) | (lower > hi)).astype(float)
    return np.asarray(np.where(flat, point, np.clip(below + above, 0.0, 1.0)))


def lattice(
    sens: FloatArray, plan: SamplingPlan, *, points: int = POINTS
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Lattice start, step and cell masses of ΔS at every row of ``sens`` (for checks).

    Parameters
    ----------
    sens : ndarray, shape (angles, columns)
        Sensitivities. [output unit per column unit]
    plan : SamplingPlan
        Columns and their distributions.
    points : int
        Lattice points per angle.

    Returns
    -------
    (ndarray, ndarray, ndarray)
        Start L and step h per angle [output unit], and the masses at L + k h, shape
        (angles, points) [-].
    """
    comps, offset = components(sens, plan)
    lower, h, cdf, _ = _block_lattice(comps, offset, slice(0, sens.shape[0]), points)
    return lower, h, np.diff(cdf, axis=1, prepend=0.0)


def angle_distributions(
    sens: FloatArray,
    plan: SamplingPlan,
    *,
    probs: tuple[float, ...] = (0.00135, 0.5, 0.99865),
    limits: tuple[FloatArray, FloatArray] | None = None,
    points: int = POINTS,
) -> AngleDistribution:
    """Mean, σ, quantiles and the probability outside limits of Σ_j g_j(θ) x_j, per angle.

    Parameters
    ----------
    sens : ndarray, shape (angles, columns)
        Sensitivities g_j(θ) of the plan's columns. [output unit per column unit]
    plan : SamplingPlan
        Columns and their distributions.
    probs : tuple of float
        Probabilities of the quantiles, in (0, 1). [-]
    limits : (ndarray, ndarray), optional
        Lower and upper limit at every angle, for ``p_out``. [output unit]
    points : int
        Lattice points (FFT length) per angle; the tolerance falls as 1/points.

    Returns
    -------
    AngleDistribution
        Deterministic figures and the bound on their numerical error.
    """
    n = sens.shape[0]
    mean = sens @ plan.column_mean()
    std = np.sqrt(np.maximum((sens * sens) @ plan.column_variance(), 0.0))
    comps, offset = components(sens, plan)
    qs = [np.empty(n) for _ in probs]
    tol = np.empty(n)
    p_out = np.empty(n) if limits is not None else None
    p_lo = np.empty(n) if limits is not None else None
    p_hi = np.empty(n) if limits is not None else None
    for a0 in range(0, n, BLOCK):
        rows = slice(a0, min(n, a0 + BLOCK))
        lower, h, cdf, active = _block_lattice(comps, offset, rows, points)
        flat = active == 0
        b = np.where(flat, 0.0, (active + 1.0) * h * 0.5)
        tol[rows] = b
        shifted = cdf + np.arange(cdf.shape[0], dtype=float)[:, None]
        for q, p in zip(qs, probs, strict=True):
            q[rows] = np.where(flat, lower, _quantile(shifted, lower, h, p))
        if limits is not None:
            assert p_out is not None and p_lo is not None and p_hi is not None
            lo, hi = limits[0][rows], limits[1][rows]
            for target, shift in ((p_out, 0.0 * b), (p_lo, -b), (p_hi, b)):
                target[rows] = _outside(cdf, lower, h, lo + shift, hi - shift, flat)
    bounds = None if p_lo is None or p_hi is None else (p_lo, p_hi)
    return AngleDistribution(
        mean=np.asarray(mean),
        std=np.asarray(std),
        quantiles=tuple(qs),
        probs=tuple(probs),
        tolerance=tol,
        points=points,
        p_out=p_out,
        p_out_bounds=bounds,
    )
