"""Per-angle distributions without sampling noise (issue 28, item 5): validation.

The deterministic figures of :mod:`camtol.tolerancing.convolution` are checked against

- closed forms: a sum of uniform sources has a piecewise-polynomial CDF (the general
  Irwin-Hall formula); one harmonic of a process is an arcsine variable; a Gaussian
  process is a normal;
- the closed-form σ = sqrt(Σ (g_j σ_j)²) (the RSS of sensitivity × source σ);
- a 10⁷-sample Monte Carlo at three angles of cw06-translating with mixed distributions.

Tolerances and why: each quantile must lie within its stated bound b = (n + 1) h / 2
(guaranteed by construction: rounding n components to a lattice of step h and reading
the CDF inside a cell move every outcome by at most b); the observed error against the
closed forms is also held to 1e-4 σ, since the rounding errors are nearly independent
and centred and the error is of order h²/σ (measured 1.3e-5 σ at 2048 points). Against
sampling, the deterministic CDF at its own quantile must equal the sampled fraction
within 4.5 binomial standard errors (a false alarm once in ~150,000 runs; 4.6e-5 in
probability at 0.135 % with 10⁷ samples).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.tolerancing import ProfileProcess, SourceDistribution, StatisticalModel, monte_carlo
from camtol.tolerancing.convolution import abs_quantile, angle_distributions, lattice
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.plan import SamplingPlan, chunk_uniforms
from camtol.tolerancing.study import prepare

PROBS = (0.00135, 0.1, 0.5, 0.99865)
CW06 = load_example("cw06-translating")


def _uniform(lo: float, hi: float) -> ResolvedDistribution:
    return ResolvedDistribution("uniform", lo, hi, 0.5 * (lo + hi), 1.0, True)


def _plan(dists: tuple[ResolvedDistribution, ...]) -> SamplingPlan:
    n = len(dists)
    labels = tuple(f"s{j}" for j in range(n))
    groups = tuple((j, j + 1) for j in range(n))
    devs = tuple(0.5 * (d.upper - d.lower) for d in dists)
    return SamplingPlan(labels, groups, dists, devs, ("mm",) * n)


def _uniform_sum_cdf(x: float, lows: list[float], widths: list[float]) -> float:
    """CDF of a sum of independent uniforms U[a_i, a_i + w_i] (piecewise polynomial).

    F(x) = Σ_{S ⊆ {1..n}} (−1)^|S| (x − Σa − Σ_{i∈S} w_i)_+^n / (n! Π w_i).
    """
    n = len(widths)
    total = 0.0
    for subset in itertools.product((0, 1), repeat=n):
        y = x - sum(lows) - sum(w for w, s in zip(widths, subset, strict=True) if s)
        if y > 0:
            total += (-1) ** sum(subset) * y**n
    return total / (math.factorial(n) * math.prod(widths))


def _bisect(f, lo: float, hi: float, target: float) -> float:
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


# Rows: every source, unequal weights with a negative one, a single source (the lattice
# must reproduce a uniform exactly), an angle where nothing varies, and two sources (an
# even number: the symmetric path inverts by a DCT-I there, a DCT-III for an odd one).
SENS = np.array(
    [[1.0, 1.0, 1.0], [0.3, -2.0, 0.7], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1.0, -1.5]]
)
DISTS = (_uniform(-1.0, 1.0), _uniform(-0.5, 0.5), _uniform(-2.0, 2.0))


def test_sum_of_uniforms_matches_the_piecewise_polynomial_closed_form() -> None:
    plan = _plan(DISTS)
    limits = (np.full(5, -2.0), np.full(5, 1.5))
    r = angle_distributions(SENS, plan, probs=PROBS, limits=limits)
    for i, g in enumerate(SENS):
        lows = [min(gj * d.lower, gj * d.upper) for gj, d in zip(g, DISTS, strict=True) if gj]
        widths = [abs(gj) * (d.upper - d.lower) for gj, d in zip(g, DISTS, strict=True) if gj]
        if not widths:  # ΔS ≡ 0: every quantile 0, nothing outside, no error
            assert all(q[i] == 0.0 for q in r.quantiles) and r.tolerance[i] == 0.0
            assert r.p_out is not None and r.p_out[i] == 0.0
            continue
        sigma = math.sqrt(sum(w * w / 12 for w in widths))
        assert r.std[i] == pytest.approx(sigma, rel=1e-12)

        def cdf(x: float, lows: list[float] = lows, widths: list[float] = widths) -> float:
            return _uniform_sum_cdf(x, lows, widths)

        for k, p in enumerate(PROBS):
            exact = _bisect(cdf, sum(lows), sum(lows) + sum(widths), p)
            err = abs(r.quantiles[k][i] - exact)
            assert err <= r.tolerance[i], (i, p, err)  # the guaranteed bound
            assert err <= 1e-4 * sigma, (i, p, err / sigma)  # what it achieves
        outside = cdf(-2.0) + 1.0 - cdf(1.5)
        assert r.p_out is not None and r.p_out_bounds is not None
        assert r.p_out_bounds[0][i] <= outside <= r.p_out_bounds[1][i]
        assert r.p_out[i] == pytest.approx(outside, abs=1e-5)


def test_lattice_is_a_distribution_with_the_closed_form_mean_and_sigma() -> None:
    # The lattice's own moments: total mass 1, mean exact to rounding, σ within the
    # Minkowski bound sd(rounding) ≤ n h / 2 (and in practice far closer).
    plan = _plan(DISTS)
    lower, h, mass = lattice(SENS[:3], plan)
    assert np.all(mass >= -1e-15)
    np.testing.assert_allclose(mass.sum(axis=1), 1.0, atol=1e-12)
    x = lower[:, None] + h[:, None] * np.arange(mass.shape[1])[None, :]
    mean = (mass * x).sum(axis=1)
    sd = np.sqrt((mass * (x - mean[:, None]) ** 2).sum(axis=1))
    want = angle_distributions(SENS[:3], plan)
    assert np.all(np.abs(mean - want.mean) <= 3 * h / 2)
    assert np.all(np.abs(sd - want.std) <= 3 * h / 2)
    # Each rounding error is nearly uniform on ±h/2: σ² grows by about 3 h²/12.
    np.testing.assert_allclose(sd**2, want.std**2 + 3 * h * h / 12, rtol=2e-5)


def test_symmetric_and_general_paths_agree() -> None:
    # Symmetric sources (centred truncated normals, uniforms, a harmonic's arcsine) take
    # the cosine-transform path; the general rFFT path must give the same distribution:
    # their quantiles differ by at most the sum of their bounds, and in practice by the
    # same 1e-4 σ as against the closed forms.
    from camtol.tolerancing import convolution as cv

    dists = (
        SourceDistribution("normal").resolve(0.01),
        _uniform(-0.02, 0.02),
        SourceDistribution("normal", cp=1.0).resolve(0.005),
        _uniform(0.1, 0.3),  # symmetric about its middle, not about 0
    )
    theta = np.linspace(0.0, 2 * np.pi, 300)
    sens = np.stack([np.cos(theta), 0.5 * np.sin(2 * theta), np.ones_like(theta), theta - 3])
    sens = sens.T.copy()
    sens[::7, 1] = 0.0  # rows with an odd and with an even number of active sources
    plan = _plan(dists)
    comps, offset = cv.components(sens, plan)
    assert all(c.symmetric for c in comps)
    rows = slice(0, sens.shape[0])
    sym = cv._symmetric_block_lattice(comps, offset, rows, cv.POINTS)
    gen = cv._general_block_lattice(comps, offset, rows, cv.POINTS)
    np.testing.assert_array_equal(sym[3], gen[3])  # the same active counts
    assert set(sym[3] % 2) == {0.0, 1.0}  # both inversions (DCT-I and DCT-III) are used
    std = angle_distributions(sens, plan).std
    for p in PROBS:
        qs, qg = cv._quantile(*_shifted(sym), p), cv._quantile(*_shifted(gen), p)
        bounds = (sym[3] + 1) * sym[1] / 2 + (gen[3] + 1) * gen[1] / 2
        assert np.all(np.abs(qs - qg) <= bounds)
        assert np.all(np.abs(qs - qg) <= 1e-4 * std), float(np.max(np.abs(qs - qg) / std))


def _shifted(block: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    lower, h, cdf, _ = block
    return cdf + np.arange(cdf.shape[0])[:, None], lower, h


def test_sigma_is_the_rss_of_sensitivities_times_source_sigmas() -> None:
    model = StatisticalModel(
        sources={
            "e": SourceDistribution("uniform"),
            "phi": SourceDistribution("triangular", bias=0.0),
        },
        default=SourceDistribution("normal", cp=1.33),
    )
    st = prepare(CW06, model=model, step_deg=1.0)
    g = st.sens["lift"]
    sigma = np.array([math.sqrt(d.variance()) for d in st.plan.distributions])
    rss = np.sqrt(((g * sigma[None, :]) ** 2).sum(axis=1))
    r = angle_distributions(g, st.plan)
    np.testing.assert_allclose(r.std, rss, rtol=1e-12, atol=0.0)
    res = monte_carlo(CW06, 10, model=model, step_deg=1.0)  # the result carries them
    np.testing.assert_allclose(res.statistics["lift"].std, rss, rtol=1e-12)
    assert res.statistics["lift"].method == "deterministic"


def test_one_harmonic_is_an_arcsine_and_a_gaussian_process_a_normal() -> None:
    from scipy.special import ndtri

    d = load_example("cw06-translating")
    d = type(d)(**{**d.__dict__, "tolerances": ()})  # the process alone
    for process in (
        ProfileProcess("r", harmonics=((3, 4.0),)),
        ProfileProcess("r", sigma_um=2.0, correlation_deg=20.0),
    ):
        st = prepare(d, model=StatisticalModel(process=process), step_deg=2.0)
        g = st.sens["lift"]
        r = angle_distributions(g, st.plan, probs=PROBS)
        a, b = st.plan.groups[0]
        k = process.orders.size
        for k_p, p in enumerate(PROBS):
            if process.harmonics:
                amp = 4e-3 * np.hypot(g[:, a], g[:, a + k])  # A |s_r(θ)|
                want = -amp * math.cos(math.pi * p)  # a cos φ, φ ~ U(0, 2π)
                scale = amp / math.sqrt(2.0)
            else:
                scale = np.sqrt((g[:, a:b] ** 2) @ st.plan.column_variance()[a:b])
                want = scale * float(ndtri(p))
            err = np.abs(r.quantiles[k_p] - want)
            assert np.all(err <= r.tolerance + 1e-15)
            if process.harmonics and p in (0.00135, 0.99865):
                # A lone arcsine's 0.135 % quantile lies within (πp)²/2 = 9e-6 of its
                # amplitude from the end of the range, inside the lattice's first cell,
                # where the density is infinite: there only the bound holds (error ~h).
                continue
            assert np.all(err <= 1e-4 * scale + 1e-15), float(np.max(err / scale))


def test_abs_quantile_closed_forms() -> None:
    # P(|x| ≤ q) = p: uniform q = p Δ; triangular 1 − (1 − q/Δ)² = p; normal at ±3σ
    # truncated: (2Φ(q/σ) − 1) / 0.9973 = p.
    from scipy.special import ndtr, ndtri

    dev = 0.02
    uni = SourceDistribution("uniform").resolve(dev)
    assert abs_quantile(uni, 0.9973) == pytest.approx(0.9973 * dev, rel=1e-12)
    tri = SourceDistribution("triangular").resolve(dev)
    assert abs_quantile(tri, 0.9973) == pytest.approx(dev * (1 - math.sqrt(0.0027)), rel=1e-12)
    nor = SourceDistribution("normal").resolve(dev)
    z = float(ndtri(0.5 * (1 + 0.9973 * (2 * ndtr(3.0) - 1))))
    assert abs_quantile(nor, 0.9973) == pytest.approx(z * dev / 3, rel=1e-10)


def test_quantiles_against_ten_million_samples_at_three_angles() -> None:
    # Mixed distributions (a biased normal of Cp 1.33, a uniform, a skewed triangular);
    # the sampled fraction below each deterministic quantile must be its probability.
    model = StatisticalModel(
        sources={
            "r": SourceDistribution("normal", cp=1.33, bias=2e-3),
            "e": SourceDistribution("uniform"),
            "phi": SourceDistribution("triangular", bias=-1e-4),
        }
    )
    st = prepare(CW06, model=model, step_deg=1.0)
    g = st.sens["lift"]
    sigma = np.sqrt((g * g) @ st.plan.column_variance())
    share_r = (g[:, 0] ** 2 * st.plan.column_variance()[0]) / sigma**2
    rows = [
        int(np.argmax(sigma)),  # the worst angle: r dominates
        int(np.argmin(np.abs(share_r - 0.5))),  # r and the others alike
        int(np.argmax(np.where(share_r < 0.5, sigma, 0.0))),  # e and φ dominate
    ]
    gs = g[rows]
    spec = 0.6 * sigma[rows]
    r = angle_distributions(gs, st.plan, probs=PROBS, limits=(-spec, spec))
    n, chunk = 10_000_000, 1_000_000
    below = np.zeros((len(PROBS), len(rows)), dtype=np.int64)
    outside = np.zeros(len(rows), dtype=np.int64)
    for c in range(n // chunk):
        x = st.plan.sample(chunk_uniforms(123, c, chunk, st.plan.uniforms))
        for j in range(len(rows)):  # ΔS at one angle for a million samples
            ds = x[:, 0] * gs[j, 0] + x[:, 1] * gs[j, 1] + x[:, 2] * gs[j, 2]
            for k in range(len(PROBS)):
                below[k, j] += np.count_nonzero(ds <= r.quantiles[k][j])
            outside[j] += np.count_nonzero(np.abs(ds) > spec[j])
    for k, p in enumerate(PROBS):
        se = math.sqrt(p * (1 - p) / n)
        np.testing.assert_array_less(np.abs(below[k] / n - p), 4.5 * se)
    assert r.p_out is not None
    se = np.sqrt(r.p_out * (1 - r.p_out) / n)
    np.testing.assert_array_less(np.abs(outside / n - r.p_out), 4.5 * se)


def test_the_linear_result_says_what_is_deterministic_and_what_sampled() -> None:
    from camtol.report.tolerancing_display import display_montecarlo

    res = monte_carlo(CW06, 500, seed=1, spec=0.015, step_deg=1.0)
    lift = res.statistics["lift"]
    assert lift.method == "deterministic" and lift.tolerance is not None
    assert lift.resolution == pytest.approx(float(np.max(lift.tolerance)))
    assert res.outside is not None and res.yield_estimate is not None
    # 1 − max_θ P(outside at θ) bounds the yield over the revolution from above.
    assert res.yield_estimate.ci95[0] <= 1.0 - float(res.outside.lower.max())
    doc = display_montecarlo(res, CW06).to_dict()
    assert doc["methods"]["per_angle"] == "deterministic"
    assert doc["methods"]["max_abs_dS"] == doc["methods"]["yield"] == "sampled"
    assert doc["per_angle"]["tolerance"] == pytest.approx(lift.resolution * 1e3)
    lo, hi = doc["max_abs_dS"]["ci95"]["q99865"]
    assert lo is None or lo <= doc["max_abs_dS"]["q99865"] * 1.01
    assert res.warnings and "fewer than 1,000" in res.warnings[0]
    assert not monte_carlo(CW06, 1000, seed=1, step_deg=1.0).warnings
    # The per-angle figures do not depend on the samples at all.
    other = monte_carlo(CW06, 2000, seed=9, spec=0.015, step_deg=1.0)
    for f in ("mean", "std", "q00135", "q50", "q99865"):
        np.testing.assert_array_equal(getattr(other.statistics["lift"], f), getattr(lift, f))
