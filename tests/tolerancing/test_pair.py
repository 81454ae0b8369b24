"""A conjugate pair toleranced as a pair (issue 28 items 1-4): sources, Δf, yields."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camtol.config import design_from_mapping, load_example
from camtol.config.examples import example_text, parse_toml
from camtol.contact import AnalyticShape, FourierError
from camtol.design.cam_design import ToleranceSpec
from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction
from camtol.pair.contact_fixture import Fixture, simulate_fixture
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.fixture_spec import FixtureErrors, fixture_spec
from camtol.pair.sources import pair_sources
from camtol.pair.variation import conjugate_factors, df_sensitivities, fixture_reading_um
from camtol.tolerancing.pair import pair_monte_carlo, prepare_pair
from camtol.tolerancing.plan import chunk_uniforms
from camtol.tolerancing.study import prepare

PAIR = load_example("cw11-conjugate")


def _with_tolerances(text: str) -> object:
    """cw11-conjugate with its [tolerances] table replaced by ``text``."""
    raw = example_text("cw11-conjugate")
    head, _, rest = raw.partition("[tolerances]")
    _, _, tail = rest.partition("\n[inspection]")
    text = head + "[tolerances]\n" + text + "\n[inspection]" + tail
    return design_from_mapping(parse_toml(text, "test design"))


def test_a_pair_declares_every_source_of_both_cams() -> None:
    keys = [s.key for s in pair_sources(PAIR)]
    assert keys == ["r_a", "r_b", "rf_c", "rf_d", "l_a", "l_b", "eta", "f"]
    by_key = {s.key: s for s in pair_sources(PAIR)}
    assert by_key["f"].cams == (("A", "f"), ("B", "f"))  # one source of both cams
    assert by_key["eta"].cams == (("B", "eta"),)
    assert by_key["eta"].tolerance.deviation == pytest.approx(math.radians(0.022))
    assert by_key["f"].tolerance.deviation == pytest.approx(0.022)  # IT6 of 120 mm
    assert by_key["rf_d"].tolerance.deviation == pytest.approx(0.011)  # IT6 of r_D = 16 mm


def test_the_former_keys_give_both_cams_independent_sources() -> None:
    d = _with_tolerances('r = "IT6"\nrf = "IT6"\nl = "IT6"')
    sources = pair_sources(d)
    assert [s.key for s in sources] == ["r_a", "r_b", "rf_c", "rf_d", "l_a", "l_b"]
    assert {s.design_key for s in sources} == {"r", "rf", "l"}
    # cam A's single-contact analysis sees the same tolerances as before the pair keys
    cam_a = d.cams()[0].design
    assert [t.key for t in cam_a.tolerances] == ["r", "rf", "l"]


def test_sigma_of_df_is_the_rss_of_its_sensitivities() -> None:
    """THEORY §4.1 (CW11 eqs. 14-17): σ_Δf(θ) = sqrt(Σ (s_k σ_k)²), shares (s_k σ_k)²/Σ."""
    res = pair_monte_carlo(PAIR, 64, step_deg=1.0)
    study = prepare_pair(PAIR, step_deg=1.0)
    fac = conjugate_factors(PAIR, study.theta_rad)
    s = df_sensitivities(fac)
    dists = zip(study.plan.labels, study.plan.distributions, strict=True)
    sig = {lab: math.sqrt(d.variance()) for lab, d in dists}
    terms = {lab: (s[lab] * sig[lab]) ** 2 for lab in study.plan.labels}
    total = sum(terms.values())
    np.testing.assert_allclose(res.df.std, np.sqrt(total), rtol=1e-12)
    for lab, t in terms.items():
        np.testing.assert_allclose(res.df.shares[lab], t / total, rtol=1e-10, atol=1e-15)
    assert sum(res.df_contributions.values()) == pytest.approx(1.0)


def test_df_sensitivities_agree_with_the_exact_fixture() -> None:
    """The linear Δf of each source against the exact fixture (THEORY §5) at a small error."""
    pair = PAIR.mechanism
    theta = np.radians(np.arange(0.0, 360.0, 5.0))
    fac = conjugate_factors(PAIR, theta)
    s = df_sensitivities(fac)
    a = AnalyticShape(pair.cam_a, PAIR.program)  # type: ignore[attr-defined]
    b = AnalyticShape(pair.cam_b, PAIR.program)  # type: ignore[attr-defined]
    xi0 = pair.initial_angle_rad  # type: ignore[attr-defined]

    def exact(sa: object, sb: object, errors: FixtureErrors) -> np.ndarray:
        res = simulate_fixture(theta, sa, sb, Fixture.of(pair, errors), initial_angle_rad=xi0)
        return np.asarray(res.extras["delta_f_mm"])

    base = exact(a, b, FixtureErrors())
    h = 1e-4
    cases = {
        "r_a": (a.with_errors(radial_error=FourierError(h)), b, FixtureErrors()),
        "r_b": (a, b.with_errors(radial_error=FourierError(h)), FixtureErrors()),
        "n_a": (a.with_errors(normal_error=FourierError(h)), b, FixtureErrors()),
        "rf_d": (a, b, FixtureErrors(drr_d_mm=h)),
        "l_a": (a, b, FixtureErrors(dl_a_mm=h)),
        "eta": (a, b, FixtureErrors(deta_rad=h * 1e-2)),
    }
    for key, (sa, sb, err) in cases.items():
        step = h * 1e-2 if key == "eta" else h
        got = (exact(sa, sb, err) - base) / step
        # second order: |exact − linear| ≤ C·h; 2 % of the largest sensitivity is far above
        np.testing.assert_allclose(got, s[key], atol=2e-2 * np.abs(s[key]).max(), err_msg=key)


def test_cam_a_alone_is_the_single_contact_study_of_cam_a() -> None:
    """With cam B's and the arms' tolerances zero, ΔS_A is today's result for cam A."""
    d = _with_tolerances('r_a = "IT6"\nrf_c = "IT6"')
    pair = prepare_pair(d, step_deg=0.5)
    single = prepare(d, step_deg=0.5)  # the single-cam study runs on cam A (r, rf)
    assert single.plan.labels == ("r", "rf")
    np.testing.assert_array_equal(pair.theta_rad, single.theta_rad)
    np.testing.assert_array_equal(pair.motion["A"], single.sens["lift"])
    np.testing.assert_array_equal(pair.plan.column_variance(), single.plan.column_variance())
    assert np.all(pair.motion["B"] == 0.0)
    res = pair_monte_carlo(d, 100, step_deg=0.5)
    var = (single.sens["lift"] ** 2) @ single.plan.column_variance()
    np.testing.assert_allclose(res.motion["A"].std, np.sqrt(var), rtol=1e-12)


def test_sampled_df_matches_the_deterministic_moments() -> None:
    res = pair_monte_carlo(PAIR, 40_000, step_deg=2.0)
    study = prepare_pair(PAIR, step_deg=2.0)
    x = study.plan.sample(chunk_uniforms(0, 0, 4096, study.plan.uniforms))
    df = x @ study.df.T
    # 4,096 samples: the sample σ is within 5 % of σ (about 4.5 standard errors)
    np.testing.assert_allclose(df.std(axis=0), res.df.std, rtol=0.05)


def test_interference_and_backlash_follow_the_centre_distance() -> None:
    """Only the centre distance toleranced: Δf ≡ 0 and Δf₀ = x_f; the sample of x_f shows."""
    d = _with_tolerances("f_um = 20")
    res = pair_monte_carlo(d, 5000, step_deg=2.0)
    # Δf − Δf₀ = −x_f: interference when x_f < 0, backlash when x_f > 0, never both
    assert res.interference_mm.max <= 0.020 + 1e-15
    assert res.backlash_mm.max <= 0.020 + 1e-15
    assert res.interference_mm.mean == pytest.approx(res.backlash_mm.mean, rel=0.1)
    assert np.all(res.df.std == 0.0)


def test_pair_yield_needs_both_limits() -> None:
    with pytest.raises(DesignError, match="both limits"):
        pair_monte_carlo(PAIR, 10, interference_max_mm=0.01)
    res = pair_monte_carlo(PAIR, 2000, interference_max_mm=1.0, backlash_max_mm=1.0)
    assert res.pair_yield is not None and res.pair_yield.value == 1.0


@pytest.mark.parametrize(
    "tolerances",
    [
        "r_a_um = 30\nr_b_um = 30",  # Δr alone: two angles decide every verdict
        "r_a_um = 20\nn_a_um = 15\nr_b_um = 30",  # Δr and Δn of cam A: a hull decides
    ],
)
def test_fixture_verdict_of_a_sampled_cam_is_camtol_conjugates(tolerances: str) -> None:
    """Each sampled cam judged as `camtol conjugate` judges that cam's measured Δf."""
    # uniform beyond the fixture's ±22 µm bands: a good part of the cams fails
    keys = [line.split("_um")[0] for line in tolerances.splitlines()]
    d = _with_tolerances(
        tolerances
        + "\n[statistics]\n"
        + "\n".join(f'{k} = {{ distribution = "uniform" }}' for k in keys)
    )
    study = prepare_pair(d, step_deg=0.5)
    spec = fixture_spec(d)
    assert spec is not None and study.bands is not None
    x = study.plan.sample(chunk_uniforms(7, 0, 24, study.plan.uniforms))
    theta_deg = np.degrees(study.theta_rad)
    verdicts = []
    for row in x:
        for cam in d.cams():
            dr_um = row @ study.radial[cam.letter].T * 1e3
            reading = fixture_reading_um(study.factors, spec, cam.letter, dr_um)
            ours = bool(study.bands.margin_um(cam.letter, reading).min() >= 0.0)
            keep = (np.diff(theta_deg, prepend=-1.0) > 0) & (theta_deg < 360.0)  # once each
            measured = dataclasses.replace(
                spec, df_mea=ErrorFunction.table(theta_deg[keep], reading[keep])
            )
            theirs = inspect_conjugate(d, measured, step_deg=0.5).verdicts[cam.letter].passed
            assert ours == theirs
            verdicts.append(ours)
    assert any(verdicts) and not all(verdicts)  # both verdicts occur
    res = pair_monte_carlo(d, 3000, step_deg=0.5)
    assert 0.0 < res.fixture_yield["A"].value < 1.0


def test_same_seed_same_numbers_at_any_block() -> None:
    a = pair_monte_carlo(PAIR, 5000, seed=3, step_deg=2.0)
    b = pair_monte_carlo(PAIR, 5000, seed=3, step_deg=2.0)
    assert a.to_dict() == b.to_dict()
    c = pair_monte_carlo(PAIR, 5001, seed=3, step_deg=2.0)  # one more sample, same first 5000
    assert c.interference_mm.max >= a.interference_mm.max


@pytest.mark.parametrize(
    "tolerances, message",
    [
        ('eta = "IT6"', "explicit deviation"),
        ('r = "IT6"\nr_a = "IT6"', "both set the 'r' source of cam A"),
    ],
)
def test_bad_pair_tolerances(tolerances: str, message: str) -> None:
    with pytest.raises(DesignError, match=message):
        _with_tolerances(tolerances)


def test_a_pair_source_on_a_single_cam_is_refused() -> None:
    d = load_example("cw06-translating")
    with pytest.raises(DesignError, match="not an error source"):
        dataclasses.replace(d, tolerances=(ToleranceSpec("r_a", grade="IT6"),))
    with pytest.raises(DesignError, match="conjugate design"):
        pair_monte_carlo(d, 10)


def test_exact_minus_linear_shrinks_four_times_when_tolerances_halve() -> None:
    """The exact pair (both cams and the fixture followed as made) against the linear one."""
    from camtol.pair.as_made import follow_pair_as_made

    study = prepare_pair(PAIR, step_deg=1.0)
    x = study.plan.sample(chunk_uniforms(0, 0, 3, study.plan.uniforms))
    gaps = []
    for k in (1.0, 0.5):
        worst = np.zeros(3)
        for row in x * k:
            values = dict(zip(study.plan.labels, row.tolist(), strict=True))
            out = follow_pair_as_made(PAIR, study.sources, values, study.theta_rad)
            worst = np.maximum(
                worst,
                [
                    np.abs(out.df_mm - row @ study.df.T).max(),
                    np.abs(out.motion["A"] - row @ study.motion["A"].T).max(),
                    np.abs(out.motion["B"] - row @ study.motion["B"].T).max(),
                ],
            )
        gaps.append(worst)
    ratio = gaps[0] / gaps[1]
    # second order: the gap falls by 4 when the deviations halve (3.5-4.5: higher orders)
    assert np.all((ratio > 3.5) & (ratio < 4.5)), ratio
    assert gaps[0][0] < 1e-2 * np.abs(x @ study.df.T).max()  # and it is small


def test_exact_mode_agrees_with_linear_on_the_sampled_figures() -> None:
    lin = pair_monte_carlo(PAIR, 12, step_deg=2.0, seed=5)
    ex = pair_monte_carlo(PAIR, 12, step_deg=2.0, seed=5, mode="exact")
    # the same samples: interference and backlash within the second-order gap (< 0.1 µm)
    assert ex.interference_mm.max == pytest.approx(lin.interference_mm.max, abs=1e-4)
    assert ex.backlash_mm.max == pytest.approx(lin.backlash_mm.max, abs=1e-4)
    assert {k: v.value for k, v in ex.fixture_yield.items()} == {
        k: v.value for k, v in lin.fixture_yield.items()
    }
    assert any("exact mode" in n for n in ex.notes)
    with pytest.raises(DesignError, match="mode"):
        pair_monte_carlo(PAIR, 2, mode="fast")


def test_deterministic_quantiles_of_a_symmetric_sum() -> None:
    """Symmetric sources: the median is the mean; the 99.865 % point lies within 3σ."""
    res = pair_monte_carlo(PAIR, 16, step_deg=2.0)
    for m in (res.df, res.motion["A"], res.motion["B"]):
        np.testing.assert_allclose(m.q50, m.mean, atol=float(m.tolerance.max()) + 1e-15)
        assert np.all(m.q99865 <= m.mean + 3.0 * m.std + m.tolerance + 1e-15)
        assert np.all(m.q00135 <= m.q50) and np.all(m.q50 <= m.q99865)
    cols = res.curves_columns()
    assert list(cols)[:6] == [
        "theta_deg",
        "df_mean_um",
        "df_std_um",
        "df_q00135_um",
        "df_q50_um",
        "df_q99865_um",
    ]
    assert "dS_A_q99865_deg" in cols and "dS_B_std_deg" in cols


def _without_inspection() -> object:
    raw = example_text("cw11-conjugate")
    head, _, _ = raw.partition("\n[inspection]")
    return design_from_mapping(parse_toml(head, "test design"))


def test_a_fixture_yield_without_inspection_bands_is_refused() -> None:
    """Issue 28, bad input: no [inspection] bands, no fixture yield, unless left out."""
    d = _without_inspection()
    with pytest.raises(DesignError, match=r"\[inspection\].*--no-fixture-yield"):
        pair_monte_carlo(d, 100, step_deg=2.0)
    res = pair_monte_carlo(d, 100, step_deg=2.0, fixture_yield=False)
    assert res.fixture_yield == {}
    assert any("left out" in n for n in res.notes)
    # leaving it out of a design that has the bands gives the same sampled figures
    a = pair_monte_carlo(PAIR, 2000, step_deg=2.0, fixture_yield=False)
    b = pair_monte_carlo(PAIR, 2000, step_deg=2.0)
    assert a.interference_mm == b.interference_mm and a.fixture_yield == {}
    assert set(b.fixture_yield) == {"A", "B"}


def test_cli_fixture_yield_without_inspection(
    tmp_path: object, capsys: pytest.CaptureFixture[str]
) -> None:
    from pathlib import Path

    from camtol.cli.app import main

    path = Path(str(tmp_path)) / "pair.toml"
    path.write_text(example_text("cw11-conjugate").partition("\n[inspection]")[0])
    assert main(["montecarlo", str(path), "-n", "100", "--step", "2"]) == 2
    err = capsys.readouterr().err
    assert "[inspection]" in err and "--no-fixture-yield" in err and "Traceback" not in err
    args = ["montecarlo", str(path), "-n", "100", "--step", "2", "--no-fixture-yield"]
    assert main(args) == 0
    assert "fixture yield: left out" in capsys.readouterr().out
    single = ["montecarlo", "--example", "cw06-translating", "-n", "10", "--no-fixture-yield"]
    assert main(single) == 2
    assert "applies to a conjugate pair" in capsys.readouterr().err
