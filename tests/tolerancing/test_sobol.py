"""Sobol indices of tolerance studies (issue 28 item 6)."""

from __future__ import annotations

import numpy as np
import pytest

from camtol.config import load_example
from camtol.exceptions import DesignError
from camtol.tolerancing.sobol import exact_sobol, sobol_indices
from camtol.tolerancing.study import prepare

CW06 = load_example("cw06-translating")


def test_a_linear_output_has_its_variance_shares_as_indices() -> None:
    """Y = Σ g_i x_i of independent sources: S_i = T_i = (g_i σ_i)² / Var Y."""
    study = prepare(CW06, step_deg=2.0)
    g = study.sens["lift"]
    i = int(np.argmax((g * g) @ study.plan.column_variance()))
    shares = g[i] ** 2 * study.plan.column_variance()
    shares /= shares.sum()
    res = sobol_indices(lambda x: x @ g[i], study.plan, 4000, seed=1)["output"]
    # N = 4,000: the estimators' standard error is about 0.01; 0.04 is four of them
    np.testing.assert_allclose(res.first, shares, atol=0.04)
    np.testing.assert_allclose(res.total, shares, atol=0.04)
    assert np.all((res.first_ci95[:, 0] <= res.first + 1e-12) & (res.first <= res.first_ci95[:, 1]))


def test_exact_indices_at_one_angle_are_the_linear_shares() -> None:
    """ΔS at one angle followed exactly is linear to second order: its S_i are the shares."""
    study = prepare(CW06, step_deg=5.0)
    g = study.sens["lift"]
    shares = g**2 * study.plan.column_variance()[None, :]
    worst = int(np.argmax(shares.sum(axis=1)))
    expected = shares[worst] / shares[worst].sum()
    res = exact_sobol(CW06, 256, step_deg=5.0, seed=2)
    at = res["ds_at_worst_angle"]
    # N = 256: standard error about 0.05; the bootstrap interval widened by 0.03 covers
    lo, hi = at.first_ci95[:, 0] - 0.03, at.first_ci95[:, 1] + 0.03
    assert np.all((lo <= expected) & (expected <= hi)), (at.first, expected)
    assert set(res) == {"max_abs_ds", "ds_at_worst_angle"}


def test_same_seed_same_indices() -> None:
    a = exact_sobol(CW06, 64, step_deg=10.0, seed=4)["max_abs_ds"]
    b = exact_sobol(CW06, 64, step_deg=10.0, seed=4)["max_abs_ds"]
    np.testing.assert_array_equal(a.first, b.first)
    np.testing.assert_array_equal(a.total_ci95, b.total_ci95)


def test_too_few_samples() -> None:
    with pytest.raises(DesignError, match="at least 64"):
        exact_sobol(CW06, 10)


def test_montecarlo_sobol_from_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    """`camtol montecarlo --sobol N` prints the library's indices (same seed, same N)."""
    import json

    from camtol.cli import main

    args = ["montecarlo", "-e", "cw06-translating", "-n", "1000", "--sobol", "64", "--json"]
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)["sobol"]
    lib = exact_sobol(CW06, 64, step_deg=1.0, seed=0)
    for name, indices in lib.items():
        firsts = [doc[name][lab]["first"] for lab in indices.labels]
        np.testing.assert_allclose(firsts, indices.first, rtol=1e-9)
