"""Monte Carlo samples at speed: linear in the samples, as a direct steady state says."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.montecarlo import column_responses, sample_dynamics, tolerance_columns
from camtol.dynamics.steady import residual_vibration, steady_state
from camtol.dynamics.stress import cam_contacts
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError


@pytest.mark.parametrize("stiffness", [None, 1e4])
def test_samples_equal_the_steady_state_of_their_lift(
    stiffness: float | None, rng: np.random.Generator
) -> None:
    d = load_example("roller-translating")
    train = FollowerTrain(
        "translating",
        mass=1e-3,
        spring_rate=10.0,
        preload=120.0,
        stiffness=stiffness,
        damping_ratio=0.05 if stiffness else 0.0,
    )
    step, rpm = 0.1, 600.0
    labels, ds, da, dev = tolerance_columns(d, step)
    assert labels == ("r", "rf", "e")
    resp = column_responses(d, train, rpm, labels, ds, da, step_deg=step, jump_margin=1.2)
    rows = rng.uniform(-1, 1, (40, 3)) * np.array(dev) * 50  # large, to see the effect
    out = sample_dynamics(resp, rows, force_min_spec_n=60.0)
    nominal = nominal_lift(d, step)
    for i in (0, 17, 39):
        dl, dacc = ds @ rows[i], da @ rows[i]
        lift = dataclasses.replace(
            nominal,
            lift=nominal.lift + dl,
            smooth_lift=nominal.smooth_lift + dl,
            smooth_acceleration=nominal.smooth_acceleration + dacc,
        )
        steady = steady_state(train, lift, rpm)
        (c,) = cam_contacts(d, nominal, train, steady.train_force)
        assert out.peak_force_n[i] == pytest.approx(c.normal_force_n.max(), rel=1e-10)
        assert out.min_force_n[i] == pytest.approx(c.normal_force_n.min(), rel=1e-10)
        assert out.residual_vibration is not None
        r = max(v.amplitude for v in residual_vibration(train, lift, steady))
        assert out.residual_vibration[i] == pytest.approx(r, rel=1e-8, abs=1e-15)
        margin = steady_state(train, lift, 1.2 * rpm)
        (cm,) = cam_contacts(d, nominal, train, margin.train_force)
        assert out.margin_min_force_n is not None
        assert out.margin_min_force_n[i] == pytest.approx(cm.normal_force_n.min(), rel=1e-10)
    expect = (out.min_force_n >= 60.0) & (out.margin_min_force_n > 0)
    np.testing.assert_array_equal(out.passed, expect)
    assert 0.0 < out.yield_fraction <= 1.0


def test_a_pair_and_bad_shapes_are_refused() -> None:
    d = load_example("cw11-conjugate")
    pair = FollowerTrain("oscillating", mass=1e-3, spring_rate=0.0, preload=0.0, form_closed=True)
    with pytest.raises(DesignError, match="not a pair"):
        column_responses(
            d, pair, 100.0, ["r"], np.zeros((360, 1)), np.zeros((360, 1)), step_deg=1.0
        )
    single = load_example("popa-eccentric")
    train = FollowerTrain("translating", mass=1e-3, spring_rate=1.0, preload=10.0)
    with pytest.raises(DesignError, match=r"need \(360, 1\)"):
        column_responses(
            single, train, 100.0, ["r"], np.zeros((36, 1)), np.zeros((36, 1)), step_deg=1.0
        )


def test_montecarlo_dynamics_from_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    """`camtol montecarlo --dynamics`: the forces of the sampled cams around the nominal."""
    import json

    from camtol.cli import main

    train = ["--rpm", "600", "--mass-kg", "0.5", "--spring-rate-n-per-mm", "10"]
    train += ["--preload-n", "50"]
    assert main(["dynamics", "-e", "popa-eccentric", *train, "--json"]) == 0
    nominal = json.loads(capsys.readouterr().out)
    args = ["montecarlo", "-e", "popa-eccentric", "-n", "2000", "--dynamics", *train]
    assert main([*args, "--force-min-n", "55", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)["dynamics"]
    peak, least = doc["peak_force_n"], doc["min_force_n"]
    # IT6 profile errors move the forces by a fraction of a newton around the nominal
    assert peak["min"] <= nominal["contact_force_max_n"] <= peak["max"]
    assert least["min"] <= nominal["contact_force_min_n"] <= least["max"]
    assert peak["max"] - peak["min"] < 1.0
    assert doc["yield"]["value"] == 1.0  # 55 N is far below the least force (≈ 59.9 N)
    no_flag = ["montecarlo", "-e", "popa-eccentric", "-n", "200", "--rpm", "600"]
    assert main(no_flag) == 2  # a speed without --dynamics
    assert "go with --dynamics" in capsys.readouterr().err
