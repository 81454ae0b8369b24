"""Monte Carlo tolerance analysis (issue 11): validation against closed forms and CW06."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.design.cam_design import ToleranceSpec
from camtol.exceptions import DesignError
from camtol.report.tolerancing_display import display_montecarlo
from camtol.tolerancing import (
    ProfileProcess,
    SourceDistribution,
    StatisticalModel,
    allocate,
    monte_carlo,
)
from camtol.tolerancing.plan import CHUNK
from camtol.tolerancing.study import prepare, sample_matrix

CW06 = load_example("cw06-translating")


def _closed_form_std(design, model, step_deg):
    st = prepare(design, model=model, step_deg=step_deg)
    g = st.sens["lift"]
    return np.sqrt((g * g) @ st.plan.column_variance()), st  # [mm]


def test_linear_variance_matches_closed_form():
    # Var ΔS(θ) = Σ s_k² σ_k² (independent sources). The sample variance of N samples has
    # a relative standard error sqrt((κ − 1)/N) with kurtosis κ ≤ 3 here (truncated
    # normals): 0.71 % for N = 40,000. We allow 4 %: over 5 standard errors.
    model = StatisticalModel(sources={"e": SourceDistribution("uniform")})
    res = monte_carlo(CW06, 40000, seed=3, model=model, step_deg=1.0)
    want, _ = _closed_form_std(CW06, model, 1.0)
    got = res.statistics["lift"].std
    np.testing.assert_allclose(got**2, want**2, rtol=0.04)


def test_cw06_rss_is_the_9973_band_of_untruncated_normals():
    # THEORY §8.1: ΔS_rms max 19.87 µm at 103.89°. With untruncated normals at Cp = 1
    # (σ = Δ/3), ΔS(θ) ~ N(0, (ΔS_rms/3)²) and the 0.135 / 99.865 % quantiles are ∓ΔS_rms.
    # Standard error of those quantiles for N = 60,000: sqrt(p(1−p)/N)/φ(3) σ ≈ 0.034 σ
    # ≈ 1.1 % of ΔS_rms, plus a histogram bin (~0.05 µm); we allow 4 %.
    model = StatisticalModel(default=SourceDistribution("normal", cp=1.0, truncate=False))
    res = monte_carlo(CW06, 60000, seed=11, model=model, step_deg=1.0)
    st = prepare(CW06, model=model, step_deg=1.0)
    rss = np.sqrt(((st.sens["lift"] * np.array(st.plan.deviations)) ** 2).sum(axis=1)) * 1e3
    shown = display_montecarlo(res, CW06)  # µm, as published
    s = shown.statistics["lift"]
    half = 0.5 * (s.q99865 - s.q00135)
    np.testing.assert_allclose(half, rss, rtol=0.04)
    assert max(half) == pytest.approx(19.87, rel=0.04)
    combined = shown.comparison[-1]
    assert combined.rss == pytest.approx(19.87, abs=0.01)  # published, 4 digits
    assert combined.worst_case == pytest.approx(25.57, abs=0.01)


def test_max_abs_never_exceeds_worst_case():
    st = prepare(CW06, step_deg=1.0)
    x = sample_matrix(st.plan, 5, 20000)
    worst = (np.abs(st.sens["lift"]) @ np.array(st.plan.deviations)).max()
    max_abs = np.abs(x @ st.sens["lift"].T).max(axis=1)
    assert max_abs.max() <= worst * (1 + 1e-12)
    res = monte_carlo(CW06, 20000, seed=5, step_deg=1.0)
    assert res.statistics["lift"].max_abs.q99865 <= res.comparison[-1].worst_case
    assert res.comparison[-1].mc_9973 <= res.comparison[-1].worst_case


def _halved(design):
    rmax = __import__("camtol.analysis.result", fromlist=["max_radius_mm"]).max_radius_mm(design)
    tols = design.resolve_tolerances(rmax)
    specs = []
    for t in tols:
        v = t.deviation * 1e3 if t.unit == "mm" else math.degrees(t.deviation)
        specs.append(ToleranceSpec(t.key, deviation=v / 2))
    return dataclasses.replace(design, tolerances=tuple(specs))


def test_exact_vs_linear_is_second_order():
    # Same seed, every zone halved: the samples are exactly halved, so a second-order
    # linearisation error falls by about 4 (THEORY §5, as `camtol verify` checks per source).
    d = load_example("roller-translating")
    d = dataclasses.replace(d, tolerances=(*d.tolerances, ToleranceSpec("phase", deviation=0.05)))
    full = monte_carlo(d, 12, mode="exact", seed=2, step_deg=1.0)
    half = monte_carlo(_halved(d), 12, mode="exact", seed=2, step_deg=1.0)
    assert full.difference is not None and half.difference is not None
    ratio = full.difference.max_sample / half.difference.max_sample
    assert 3.0 <= ratio <= 5.0
    assert full.difference.max_sample < 0.01 * full.statistics["lift"].max_abs.q99865 + 1e-9


def test_exact_mode_with_profile_process_matches_linear():
    d = load_example("roller-translating")
    model = StatisticalModel(process=ProfileProcess("r", harmonics=((2, 3.0), (5, 1.0))))
    res = monte_carlo(d, 6, mode="exact", seed=4, model=model, step_deg=1.0)
    assert res.difference is not None
    assert res.difference.max_sample < 0.02 * res.statistics["lift"].max_abs.q99865
    assert "r_process" in res.shares


def test_process_variance_and_contact_angle():
    # Harmonic of amplitude A with random phase: Var = A²/2 at every point; the follower
    # feels it at the contact point's polar angle ψ(θ), so Var ΔS(θ) = s_r² A²/2.
    d = dataclasses.replace(CW06, tolerances=())
    model = StatisticalModel(process=ProfileProcess("r", harmonics=((3, 4.0),)))
    res = monte_carlo(d, 40000, seed=9, model=model, step_deg=1.0)
    st = prepare(d, model=model, step_deg=1.0)
    a, b = st.plan.groups[0]
    # s_r(θ) from the cos/sin columns: g_cos² + g_sin² = s_r².
    s_r2 = (st.sens["lift"][:, a:b] ** 2).sum(axis=1)
    want = np.sqrt(s_r2 * (4e-3) ** 2 / 2) * 1e3  # [µm]
    shown = display_montecarlo(res, d).statistics["lift"]
    np.testing.assert_allclose(shown.std, want, rtol=0.04)


def test_stationary_process_point_variance():
    p = ProfileProcess("r", sigma_um=2.0, correlation_deg=10.0)
    assert np.sum(p.coefficient_variance_mm2()) == pytest.approx((2e-3) ** 2)


def test_same_seed_same_numbers_whatever_the_chunking():
    n = 3 * CHUNK + 77
    ref = monte_carlo(CW06, n, seed=7, spec=0.02, step_deg=1.0, chunks_per_task=100)
    for kw in ({"chunks_per_task": 1}, {"chunks_per_task": 2, "workers": 2}):
        other = monte_carlo(CW06, n, seed=7, spec=0.02, step_deg=1.0, **kw)
        assert display_montecarlo(other, CW06).to_dict() == display_montecarlo(ref, CW06).to_dict()
        for f in ("mean", "std", "q00135", "q50", "q99865"):
            np.testing.assert_array_equal(
                getattr(other.statistics["lift"], f), getattr(ref.statistics["lift"], f)
            )


def test_same_seed_same_numbers_on_a_dask_local_cluster():
    distributed = pytest.importorskip(
        "distributed", reason="the camtol[dask] extra is not installed (CI installs it)"
    )
    n = 2 * CHUNK + 5
    ref = monte_carlo(CW06, n, seed=8, spec=0.02, step_deg=1.0, chunks_per_task=1)
    with (
        distributed.LocalCluster(n_workers=2, processes=False, dashboard_address=None) as cluster,
        distributed.Client(cluster) as client,
    ):
        res = monte_carlo(CW06, n, seed=8, spec=0.02, step_deg=1.0, scheduler=client)
    assert display_montecarlo(res, CW06).to_dict() == display_montecarlo(ref, CW06).to_dict()
    np.testing.assert_array_equal(res.statistics["lift"].q99865, ref.statistics["lift"].q99865)


def test_yield_interval_contains_value():
    res = monte_carlo(CW06, 5000, seed=1, spec=0.012, step_deg=1.0)
    y = res.yield_estimate
    assert y is not None and 0 < y.value < 1
    assert y.ci95[0] <= y.value <= y.ci95[1]


def test_contribution_shares_sum_to_one():
    res = monte_carlo(CW06, 2000, seed=1, step_deg=1.0)
    total = sum(res.shares.values())
    np.testing.assert_allclose(total, 1.0, atol=1e-12)
    assert res.contributions[0].source == "r"


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"kind": "weibull"}, "distribution='weibull' is unknown"),
        ({"cp": 0.0}, "Cp must be > 0"),
        ({"zone_lower": 1e-3, "zone_upper": -1e-3}, "zone lower"),
    ],
)
def test_bad_distribution(kwargs, match):
    with pytest.raises(DesignError, match=match):
        SourceDistribution(**kwargs)


def test_bad_samples():
    with pytest.raises(DesignError, match="samples=0"):
        monte_carlo(CW06, 0)
    with pytest.raises(DesignError, match="too large for exact mode"):
        monte_carlo(CW06, 10**7, mode="exact")


def test_velocity_and_acceleration_statistics():
    # ΔV, ΔA: the same samples through dΔS/dθ and d²ΔS/dθ² sensitivities (THEORY §3.5);
    # σ against the closed form Σ s'_k² σ_k² within the sampling error (as above, 4 %).
    res = monte_carlo(
        CW06, 20000, seed=6, quantities=("lift", "velocity", "acceleration"), step_deg=1.0
    )
    st = prepare(CW06, step_deg=1.0)
    var = st.plan.column_variance()
    for q in ("velocity", "acceleration"):
        g = st.sens[q]
        want = (
            np.sqrt((g * g) @ var)
            * 1e3
            * (CW06.omega_rad_s or 1.0) ** (1 if q == "velocity" else 2)
        )
        got = display_montecarlo(res, CW06).statistics[q].std  # µm per rad (or per s)
        mask = want > 1e-6 * want.max()
        np.testing.assert_allclose(got[mask], want[mask], rtol=0.04)
    doc = display_montecarlo(res, CW06).to_dict()
    assert "max_abs_dV" in doc and "max_abs_dA" in doc


def test_linear_only_options_refused_in_exact_mode():
    with pytest.raises(DesignError, match="linear mode only"):
        monte_carlo(CW06, 2, mode="exact", scheduler="tcp://127.0.0.1:1", step_deg=1.0)
    with pytest.raises(DesignError, match="linear mode only"):
        monte_carlo(CW06, 2, mode="exact", quantities=("velocity",), step_deg=1.0)


def test_band_yield():
    st = prepare(CW06, step_deg=1.0)
    n = st.theta_rad.size
    wide = (np.full(n, -1.0), np.full(n, 1.0))
    res = monte_carlo(CW06, 1000, seed=2, band=wide, step_deg=1.0)
    assert res.yield_estimate is not None and res.yield_estimate.value == 1.0
    tight = (np.full(n, -0.005), np.full(n, 0.005))
    res = monte_carlo(CW06, 1000, seed=2, band=tight, step_deg=1.0)
    x = sample_matrix(st.plan, 2, 1000)
    d = x @ st.sens["lift"].T
    want = np.count_nonzero(np.all(np.abs(d) <= 0.005, axis=1)) / 1000
    assert res.yield_estimate is not None
    assert res.yield_estimate.value == pytest.approx(want, abs=2e-3)  # float32 ΔS at edges


def test_a_conjugate_pair_is_sampled_through_cam_a() -> None:
    # Its error sources are cam A's contact's, the output error analyze computes; the
    # command failed with "a conjugate pair is two cams" before.
    from camtol.analysis.result import analyse

    pair = load_example("cw11-conjugate")
    cam_a = pair.cams()[0].design
    study = prepare(pair, step_deg=1.0)
    assert study.design == cam_a and study.unit == "rad"
    a = monte_carlo(pair, samples=2000, seed=3, step_deg=1.0).statistics["lift"]
    b = monte_carlo(cam_a, samples=2000, seed=3, step_deg=1.0).statistics["lift"]
    np.testing.assert_array_equal(a.mean, b.mean)
    np.testing.assert_array_equal(a.std, b.std)
    # No sample exceeds analyze's worst case of the same sources (linear mode).
    worst = analyse(pair, step_deg=1.0).extremes["dS_worst"][0].value
    assert 0.0 < a.max_abs.q99865 <= worst
    chosen = allocate(
        pair, spec=math.radians(0.05), step_deg=1.0, samples=2000, verify_samples=2000
    )
    assert set(chosen.grades) == {t.key for t in cam_a.tolerances}  # cam A's own sources
    assert chosen.unit == "rad" and chosen.achieved <= math.radians(0.05)


def test_exact_mode_on_worker_processes_gives_the_same_numbers(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Exact samples followed on two processes equal those followed on one, bit for bit."""
    import camtol.tolerancing.exact as exact_mode
    from camtol.config import load_example
    from camtol.tolerancing import monte_carlo

    monkeypatch.setattr(exact_mode, "MIN_SAMPLES_PER_PROCESS", 4)  # processes from 8 samples
    d = load_example("cw06-translating")
    one = monte_carlo(d, 12, mode="exact", seed=4, step_deg=1.0, workers=1)
    two = monte_carlo(d, 12, mode="exact", seed=4, step_deg=1.0, workers=2)
    for a, b in ((one.statistics["lift"].std, two.statistics["lift"].std),):
        np.testing.assert_array_equal(a, b)
    assert one.statistics["lift"].max_abs == two.statistics["lift"].max_abs
