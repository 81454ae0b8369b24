"""Capability, control charts and run rules (camtol.spc) against hand computation and scipy.

Published constants (Montgomery, *Introduction to Statistical Quality Control*, 7th ed.,
appendix VI) are given to 3-4 digits: compared to half a unit of their last digit.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats

from camtol.exceptions import RecordError
from camtol.spc.capability import ad_p_value, anderson_darling, capability, moving_range_dof
from camtol.spc.charts import chart_limits, control_chart, within_sigma
from camtol.spc.constants import A2, A3, B3, B4, D3, D4, c4, d2, d3
from camtol.spc.rules import run_rules

# n: d2, d3, c4, A2, D3, D4, A3, B3, B4 (Montgomery, appendix VI)
PUBLISHED = {
    2: (1.128, 0.853, 0.7979, 1.880, 0.0, 3.267, 2.659, 0.0, 3.267),
    3: (1.693, 0.888, 0.8862, 1.023, 0.0, 2.574, 1.954, 0.0, 2.568),
    4: (2.059, 0.880, 0.9213, 0.729, 0.0, 2.282, 1.628, 0.0, 2.266),
    5: (2.326, 0.864, 0.9400, 0.577, 0.0, 2.114, 1.427, 0.0, 2.089),
    8: (2.847, 0.820, 0.9650, 0.373, 0.136, 1.864, 1.099, 0.185, 1.815),
    10: (3.078, 0.797, 0.9727, 0.308, 0.223, 1.777, 0.975, 0.284, 1.716),
    25: (3.931, 0.708, 0.9896, 0.153, 0.459, 1.541, 0.606, 0.565, 1.435),
}


@pytest.mark.parametrize("n", sorted(PUBLISHED))
def test_constants_match_the_published_tables(n: int) -> None:
    got = (d2(n), d3(n), c4(n), A2(n), D3(n), D4(n), A3(n), B3(n), B4(n))
    for name, g, p in zip(("d2 d3 c4 A2 D3 D4 A3 B3 B4".split()), got, PUBLISHED[n], strict=True):
        digits = 4 if name == "c4" else 3
        # the tables round D4(3) = 2.5735 to 2.574 and our 2.575 is the other side: 1 unit
        assert g == pytest.approx(p, abs=1.01 * 10**-digits), (n, name, g, p)


# A hand-computed lot of 10 parts [µm], upper limit 20 µm, lower 0 µm.
LOT = np.array([10.0, 12.0, 11.0, 13.0, 12.0, 14.0, 11.0, 12.0, 13.0, 12.0])
# by hand: mean 120/10 = 12.0; Σ(x − 12)² = 4+0+1+1+0+4+1+0+1+0 = 12, s = √(12/9) = 1.154701
# moving ranges 2,1,2,1,2,3,1,1,1: MR̄ = 14/9 = 1.555556, σ_within = MR̄/1.128 = 1.379039
MEAN, S, MRBAR = 12.0, math.sqrt(12.0 / 9.0), 14.0 / 9.0


def test_capability_of_a_hand_computed_lot() -> None:
    sigma_w, dof_w, how = within_sigma(LOT)
    assert how == "moving range"
    assert sigma_w == pytest.approx(MRBAR / 1.128, rel=5e-4)  # d2(2) to 4 digits
    cap = capability(
        LOT, lsl=0.0, usl=20.0, sigma_within=sigma_w, dof_within=dof_w, within_method=how
    )
    ix = cap.indices
    assert ix["pp"].value == pytest.approx(20.0 / (6 * S), rel=1e-12)  # 2.886751
    assert ix["ppk"].value == pytest.approx(8.0 / (3 * S), rel=1e-12)  # min(8, 12)/(3s)
    assert ix["cp"].value == pytest.approx(20.0 / (6 * 1.379039), rel=5e-4)
    assert ix["cpk"].value == pytest.approx(8.0 / (3 * 1.379039), rel=5e-4)
    # chi-square interval of Pp, ν = 9: χ²(0.025, 9) = 2.700389, χ²(0.975, 9) = 19.022768
    pp = 20.0 / (6 * S)
    assert ix["pp"].ci95 == pytest.approx(
        (pp * math.sqrt(2.700389 / 9), pp * math.sqrt(19.022768 / 9)), rel=1e-6
    )
    # Bissell: Ppk ± 1.959964 √(1/(9n) + Ppk²/(2(n − 1)))
    ppk = 8.0 / (3 * S)
    half = 1.959964 * math.sqrt(1 / 90 + ppk**2 / 18)
    assert ix["ppk"].ci95 == pytest.approx((ppk - half, ppk + half), rel=1e-6)
    # the within interval uses the moving range's effective degrees of freedom
    cpk = ix["cpk"].value
    half = 1.959964 * math.sqrt(1 / 90 + cpk**2 / (2 * dof_w))
    assert ix["cpk"].ci95 == pytest.approx((cpk - half, cpk + half), rel=1e-6)
    # judged on the lower bound of Ppk, 2.309 − 1.087 = 1.222, not on Ppk 2.31 itself
    assert ix["ppk"].ci95[0] == pytest.approx(1.222, abs=1e-3)
    assert not cap.capable and "lower 95 % confidence bound of Ppk" in cap.capable_basis
    assert capability(
        LOT, lsl=0.0, usl=20.0, sigma_within=sigma_w, dof_within=dof_w,
        within_method=how, capable_at=1.2,
    ).capable  # fmt: skip


def test_the_issue_lot_bissell_interval() -> None:
    """Issue 30's lot of 30 parts: Ppk 0.64, Bissell's 95 % interval [0.44, 0.84].

    Rebuilt from its published figures (mean 30 − 3·0.64·4.26 against the upper limit 30,
    σ 4.26), compared to the issue's two decimals (half a unit: 0.005).
    """
    from camtol.spc.capability import _bissell

    lo, hi = _bissell(0.64, 30, 29.0)
    assert (lo, hi) == pytest.approx((0.44, 0.84), abs=0.005)
    # and through capability(): 30 values with that mean and σ
    z = stats.norm.ppf((np.arange(30) + 0.5) / 30)
    x = 30.0 - 3 * 0.64 * 4.26 + 4.26 * z / z.std(ddof=1)
    cap = capability(
        x, lsl=None, usl=30.0, sigma_within=2.93, dof_within=moving_range_dof(30),
        within_method="moving range",
    )  # fmt: skip
    assert cap.indices["ppu"].value == pytest.approx(0.64, abs=1e-9)
    assert cap.indices["ppu"].ci95 == pytest.approx((0.44, 0.84), abs=0.005)
    # the within σ of the issue (2.93 µm) gives its Cpk 0.93
    assert cap.indices["cpu"].value == pytest.approx(0.93, abs=0.005)


def test_one_sided_characteristics_give_ppu_cpu_only() -> None:
    sigma_w, dof_w, how = within_sigma(LOT)
    cap = capability(
        LOT, lsl=None, usl=20.0, sigma_within=sigma_w, dof_within=dof_w, within_method=how
    )
    assert set(cap.indices) == {"ppu", "cpu"}
    assert cap.indices["ppu"].value == pytest.approx(8.0 / (3 * S))
    low = capability(
        LOT, lsl=0.0, usl=None, sigma_within=sigma_w, dof_within=dof_w, within_method=how
    )
    assert set(low.indices) == {"ppl", "cpl"}
    assert low.indices["ppl"].value == pytest.approx(12.0 / (3 * S))


def test_moving_range_effective_dof_against_simulation() -> None:
    """ν from the exact variance of MR̄/d2; checked by simulation (20,000 lots of 30)."""
    rng = np.random.default_rng(7)
    x = rng.normal(size=(20000, 30))
    sig = np.abs(np.diff(x, axis=1)).mean(axis=1) / d2(2)
    nu_sim = 1.0 / (2.0 * sig.var(ddof=1))
    # Monte Carlo standard error of a variance from 20,000 draws: about 1 %; allow 4 %
    assert moving_range_dof(30) == pytest.approx(nu_sim, rel=0.04)
    assert moving_range_dof(30) == pytest.approx(0.605 * 29, rel=0.03)  # Cryer & Ryan


def test_anderson_darling_against_scipy() -> None:
    rng = np.random.default_rng(3)
    for x in (rng.normal(size=30), rng.exponential(size=30), rng.uniform(size=50)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # scipy ≥ 1.17 asks for a p-value method
            ref = stats.anderson(x, dist="norm")
        got = anderson_darling(x)
        assert got.statistic == pytest.approx(float(ref.statistic), rel=1e-10)
    rejected = anderson_darling(rng.exponential(size=60))
    assert not rejected.normal and rejected.p_value < 0.01


def test_anderson_darling_p_value_against_the_simulated_null() -> None:
    """The p-value is the tail probability of A² under normality (n = 30, simulated).

    20,000 normal samples of 30 give the null distribution of A² (mean and σ estimated);
    at A² of 0.4 to 1.0 the empirical tail (p from 0.37 down to 0.01) and the
    D'Agostino-Stephens p-value agree within 10 % (the fitted formula is good to a few
    per cent; the simulation's standard error is below 7 % at p = 0.01). Independent of
    scipy's version, whose critical values changed between 1.10 and 1.17.
    """
    rng = np.random.default_rng(5)
    null = np.array([anderson_darling(rng.normal(size=30)).statistic for _ in range(20_000)])
    for a2 in (0.4, 0.6, 0.8, 1.0):
        empirical = float(np.mean(null >= a2))
        assert ad_p_value(a2, 30) == pytest.approx(empirical, rel=0.1), (a2, empirical)


def test_percentile_indices_when_normality_fails() -> None:
    rng = np.random.default_rng(11)
    x = 5.0 + rng.lognormal(mean=1.0, sigma=0.6, size=200)
    sigma_w, dof_w, how = within_sigma(x)
    cap = capability(x, lsl=None, usl=40.0, sigma_within=sigma_w, dof_within=dof_w,
                     within_method=how)  # fmt: skip
    assert not cap.normality.normal
    assert "lognormal" in cap.percentile_method
    # the true quantiles of 5 + LN(1, 0.6): X50 = 5 + e, X99.865 = 5 + e^(1 + 0.6·3)
    true_ppu = (40.0 - (5 + math.e)) / (math.exp(1 + 0.6 * 3.0) - math.e)
    assert cap.percentile["ppu"] == pytest.approx(true_ppu, rel=0.25)  # 200 parts: ~10 %
    assert cap.warnings and "not normal" in cap.warnings[0]


def test_imr_and_xbar_r_limits_by_hand() -> None:
    lim = chart_limits(LOT, "imr")
    # x̄ ± E2 MR̄, E2 = 3/d2(2) published as 2.66 (two decimals: half a unit, 0.005 MR̄)
    assert lim.ucl == pytest.approx(MEAN + 2.66 * MRBAR, abs=0.005 * MRBAR)
    assert lim.lcl == pytest.approx(MEAN - 2.66 * MRBAR, abs=0.005 * MRBAR)
    assert lim.dispersion_ucl == pytest.approx(3.267 * MRBAR, rel=2e-4)
    assert lim.dispersion_lcl == 0.0
    # X̄-R with N = 5: subgroups (10,12,11,13,12) and (14,11,12,13,12): means 11.6, 12.4,
    # ranges 3 and 3: X̿ = 12, R̄ = 3; A2 = 0.577, D4 = 2.114, D3 = 0
    xr = chart_limits(LOT, "xbar-r", 5)
    assert (xr.center, xr.dispersion_center) == pytest.approx((12.0, 3.0))
    assert xr.ucl == pytest.approx(12.0 + 0.577 * 3.0, abs=1.5e-3)
    assert xr.lcl == pytest.approx(12.0 - 0.577 * 3.0, abs=1.5e-3)
    assert xr.dispersion_ucl == pytest.approx(2.114 * 3.0, abs=3e-3)
    assert xr.dispersion_lcl == 0.0
    cc = control_chart(LOT, "xbar-r", 5)
    np.testing.assert_allclose(cc.points, [11.6, 12.4])
    assert cc.members == ((0, 1, 2, 3, 4), (5, 6, 7, 8, 9))
    # X̄-S: S̄ = mean of the two subgroup s; A3 = 1.427
    s_bar = (np.std(LOT[:5], ddof=1) + np.std(LOT[5:], ddof=1)) / 2
    xs = chart_limits(LOT, "xbar-s", 5)
    assert xs.ucl == pytest.approx(12.0 + 1.427 * s_bar, abs=1.5e-3)
    assert xs.dispersion_ucl == pytest.approx(2.089 * s_bar, abs=3e-3)
    # pooled within-subgroup σ: √(Σ SS / Σ(n − 1)) / c4(9); SS = 5.2 + 5.2, ν = 8
    sigma, dof, how = within_sigma(LOT, 5)
    assert how == "pooled subgroups" and dof == 8
    assert sigma == pytest.approx(math.sqrt(10.4 / 8) / 0.9693, rel=1e-4)  # c4(9) = 0.9693


def _neutral(n: int) -> list[float]:
    """Points alternating ±0.2σ in pairs: no rule of either set fires on them."""
    return [0.2, 0.2, -0.2, -0.2] * (n // 4) + [0.2] * (n % 4)


def test_western_electric_rules_each_planted_once() -> None:
    z = (
        _neutral(8)
        + [3.5]  # 8: WE1
        + _neutral(8)
        + [2.5, 0.1, 2.4]  # 17-19: WE2 at 19
        + _neutral(8)
        + [-1.5, -1.2, 0.0, -1.8, -1.1]  # 28-32: WE3 at 32
        + _neutral(8)
        + [0.5] * 8  # 41-48: WE4 at 48 (the neutral points before it end below the centre)
        + [-0.2, -0.2]  # and the run ends
        + _neutral(8)
    )
    flags = run_rules(z, 0.0, 1.0, "we")
    hits = {code: list(np.flatnonzero(v)) for code, v in flags.items()}
    assert hits == {"WE1": [8], "WE2": [19], "WE3": [32], "WE4": [48]}


def test_nelson_rules_each_planted() -> None:
    segments = {
        "N1": [-3.2],
        "N2": [0.3] * 9,
        "N3": [-0.9, -0.6, -0.3, 0.05, 0.35, 0.65],
        "N4": [0.5, -0.5] * 7,
        "N5": [-2.2, -0.1, -2.6],
        "N6": [1.2, 1.4, 0.1, 1.6, 1.3],
        "N7": [0.3, -0.3, 0.4, 0.4, -0.3, -0.3] * 2 + [0.3, 0.3, -0.3],
        "N8": [1.5, 1.5, -1.5, -1.5] * 2,
    }
    for code, seg in segments.items():
        z = _neutral(8) + seg + _neutral(8)
        flags = run_rules(z, 0.0, 1.0, "nelson")
        fired = {c for c, v in flags.items() if v.any()}
        assert code in fired, (code, fired)
        assert flags[code][8 + len(seg) - 1], code  # flagged where the pattern completes


def test_bad_rule_set_and_subgroup() -> None:
    with pytest.raises(RecordError, match="--rules='x'"):
        run_rules([1.0], 0.0, 1.0, "x")
    with pytest.raises(RecordError, match="--subgroup=12: larger than the lot"):
        chart_limits(LOT, "xbar-r", 12)


@pytest.mark.parametrize(
    ("k", "n", "confidence"), [(0, 10, 0.95), (3, 12, 0.95), (30, 30, 0.9), (997, 1000, 0.99)]
)
def test_clopper_pearson_is_scipys_exact_interval(k: int, n: int, confidence: float) -> None:
    # The one binomial interval of lots, lot yields and Monte Carlo yields.
    from camtol.spc.binomial import clopper_pearson

    ci = stats.binomtest(k, n).proportion_ci(confidence_level=confidence, method="exact")
    assert clopper_pearson(k, n, confidence) == pytest.approx(
        (ci.low, ci.high), rel=1e-9, abs=1e-15
    )
