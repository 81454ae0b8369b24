"""The as-made cam at speed: a cut cam and a scanned cam against the nominal (THEORY §9.6)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.dynamics.lift import cut_lift, nominal_lift, scan_lift
from camtol.dynamics.run import DynamicsInputs, run_dynamics
from camtol.dynamics.steady import as_made_bound, steady_state
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError


def _elastic() -> FollowerTrain:
    return FollowerTrain(
        "translating", mass=1e-3, spring_rate=10.0, preload=100.0, stiffness=1e4, damping_ratio=0.05
    )


@pytest.mark.parametrize("name", ["popa-eccentric", "roller-translating"])
def test_a_cut_cam_at_0_1_deg_gives_the_nominal_forces_within_the_bound(name: str) -> None:
    # The flat tool every 0.1° leaves a polygon whose lift error is ≤ ρδ²/8 (1.1e-5 mm on
    # Popa's 30 mm circle): the force changes by at most (1 + ‖h‖₁)(k_f E + c ω ΔV).
    d = load_example(name)
    train = _elastic()
    rpm, step = (1200.0, 0.005) if name == "popa-eccentric" else (300.0, 0.01)
    nominal = steady_state(train, nominal_lift(d, step), rpm)
    cut = cut_lift(d, step, 0.1)
    made = steady_state(train, cut, rpm)
    bound = as_made_bound(train, cut, rpm)
    assert bound is not None
    diff = float(np.max(np.abs(made.train_force - nominal.train_force)))
    assert 0 < diff <= bound
    assert bound < 0.2 * float(np.min(nominal.train_force))  # small against the force
    if name == "popa-eccentric":  # r (sec(δ/2) − 1), the exact flat-tool error on a circle
        assert cut.lift_error_max == pytest.approx(
            30.0 * (1 / np.cos(np.radians(0.05)) - 1), rel=1e-3
        )


def test_the_bound_shrinks_with_the_cutting_step() -> None:
    d = load_example("popa-eccentric")
    train = _elastic()
    bounds = [as_made_bound(train, cut_lift(d, s / 20, s), 1200.0) for s in (2.0, 1.0, 0.5)]
    assert bounds[0] > bounds[1] > bounds[2]  # type: ignore[operator]


def test_a_rigid_train_refuses_a_cut_cam() -> None:
    d = load_example("popa-eccentric")
    train = FollowerTrain("translating", mass=1e-3, spring_rate=10.0, preload=100.0)
    with pytest.raises(DesignError, match="follower_stiffness_n_per_mm.*infinite force"):
        steady_state(train, cut_lift(d, 0.05, 1.0), 600.0)


def test_the_grid_must_resolve_the_cut() -> None:
    with pytest.raises(DesignError, match=r"--step=0\.5 is not allowed with --cut-step=2"):
        cut_lift(load_example("popa-eccentric"), 0.5, 2.0)


@pytest.mark.parametrize("stiffness", [None, 1e4])
def test_a_scan_of_the_nominal_cam_gives_the_nominal_forces(
    stiffness: float | None, tmp_path: Path
) -> None:
    # A noiseless scan of the nominal profile, registered by best fit as `inspect` does:
    # the follower's motion on it is the design's to the registration's precision.
    from camtol.inspection.twin import scan_csv_text, simulate_scan

    d = load_example("roller-translating")
    path = tmp_path / "scan.csv"
    path.write_text(scan_csv_text(simulate_scan(d, points=3600, noise_um=0.0)))
    overrides = {"mass_kg": 1.0, "spring_rate_n_per_mm": 10.0, "preload_n": 100.0}
    if stiffness is not None:
        overrides["follower_stiffness_n_per_mm"] = stiffness
    nominal = run_dynamics(d, DynamicsInputs(overrides=overrides))
    made = run_dynamics(d, DynamicsInputs(overrides=overrides, points_path=str(path)))
    assert made.lift.source == "scan" and made.lift.lift_error_max < 1e-5
    np.testing.assert_allclose(
        made.contact_force_n, nominal.contact_force_n, atol=1e-3 * nominal.contact_force_n.max()
    )
    assert made.jump_speed_rpm == pytest.approx(nominal.jump_speed_rpm, rel=1e-3)


def test_a_scan_with_a_profile_error_moves_the_force_by_its_acceleration() -> None:
    # A 20 µm normal error of harmonic 5 (a flat face: ΔS ≈ Δn): a rigid train's force
    # changes by k_s ΔS + m ω² ΔA, with ΔS, ΔA of the scanned cam's exact motion.
    from camtol.contact import FourierError

    d = load_example("popa-eccentric")
    err = FourierError(0.0, cos_mm=(0.0, 0.0, 0.0, 0.0, 0.02))  # 20 µm of harmonic 5
    lift = scan_lift(d, 0.1, err, harmonics=5)
    nominal = nominal_lift(d, 0.1)
    train = FollowerTrain("translating", mass=1e-3, spring_rate=10.0, preload=100.0)
    rpm = 1200.0
    a = steady_state(train, lift, rpm).train_force - steady_state(train, nominal, rpm).train_force
    w = rpm * np.pi / 30
    da = lift.smooth_acceleration - nominal.smooth_acceleration
    ds = lift.lift - nominal.lift
    np.testing.assert_allclose(a, 10.0 * ds + 1e-3 * w * w * da, rtol=1e-12, atol=1e-9)
    assert float(np.max(np.abs(ds))) == pytest.approx(0.02, rel=0.05)
