"""The follower train from a design's [dynamics] table and overrides (THEORY §9.1)."""

from __future__ import annotations

import math

import pytest

from camtol.config.design_file import _parse_toml as parse_toml
from camtol.config.design_file import design_from_mapping, example_text, load_example
from camtol.dynamics.train import (
    GRAVITY_M_PER_S2,
    FollowerTrain,
    follower_train,
)
from camtol.exceptions import DesignError


def _design(name: str, table: str) -> object:
    return design_from_mapping(parse_toml(example_text(name) + "\n[dynamics]\n" + table, name))


def test_a_table_in_file_units_becomes_the_train() -> None:
    d = _design(
        "popa-eccentric",
        "mass_kg = 0.5\nspring_rate_n_per_mm = 12\npreload_n = 80\n"
        "follower_stiffness_n_per_mm = 2e4\nface_width_mm = 8\n",
    )
    t = follower_train(d)  # type: ignore[arg-type]
    assert (t.mass, t.spring_rate, t.preload, t.stiffness) == (0.5e-3, 12.0, 80.0, 2e4)
    assert t.damping_ratio == 0.05  # the default of an elastic train
    assert t.materials.face_width_mm == 8.0 and t.materials.youngs_modulus_cam_gpa == 210.0
    assert t.natural_frequency_rad_s == pytest.approx(math.sqrt(20012 / 0.5e-3))
    over = follower_train(d, {"mass_kg": 2.0, "damping_ratio": 0.0, "preload_n": None})  # type: ignore[arg-type]
    assert (over.mass, over.damping_ratio, over.preload) == (2e-3, 0.0, 80.0)


def test_an_oscillating_train_is_in_n_m() -> None:
    d = _design("cw06-oscillating", "inertia_kg_mm2 = 1500\nspring_rate_nm_per_rad = 30\n")
    t = follower_train(d)  # type: ignore[arg-type]
    assert (t.output, t.mass, t.spring_rate, t.preload, t.stiffness) == (
        "oscillating",
        1.5e-3,
        30.0,
        0.0,
        None,
    )
    assert t.damping_ratio == 0.0 and t.force_to_newton == 1e3 and t.torque_factor == 1.0


def test_gravity_adds_the_weight_along_the_lift() -> None:
    d = _design(
        "popa-eccentric",
        "mass_kg = 2\nspring_rate_n_per_mm = 1\npreload_n = 10\n"
        "gravity = true\ngravity_angle_deg = 60\n",
    )
    t = follower_train(d)  # type: ignore[arg-type]
    assert t.gravity_load == pytest.approx(2 * GRAVITY_M_PER_S2 * 0.5)
    assert t.preload == pytest.approx(10 + t.gravity_load)


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({}, r"dynamics\.mass_kg is missing: .* or as --mass-kg"),
        ({"mass_kg": 1.0}, r"dynamics\.spring_rate_n_per_mm is missing"),
        ({"mass_kg": 0.0, "spring_rate_n_per_mm": 1.0}, r"dynamics\.mass_kg=0\.0 .*> 0 kg"),
        ({"inertia_kg_mm2": 1.0}, r"dynamics\.inertia_kg_mm2 does not apply to a flat_translating"),
        ({"mass_kg": 1.0, "spring_rate_n_per_mm": 1.0, "damping_ratio": 2.0}, r"\[0, 2\)"),
        ({"mass_kg": 1.0, "spring_rate_n_per_mm": 1.0, "preload_n": -1.0}, r"preload_n=-1\.0"),
        ({"mass": 1.0}, r"dynamics\.mass is not a field"),
    ],
)
def test_bad_fields_are_named(overrides: dict[str, float], message: str) -> None:
    with pytest.raises(DesignError, match=message):
        follower_train(load_example("popa-eccentric"), overrides)


def test_a_pair_takes_no_spring_and_no_stiffness() -> None:
    d = load_example("cw11-conjugate")
    with pytest.raises(DesignError, match="form-closed"):
        follower_train(d, {"inertia_kg_mm2": 1.0, "spring_rate_nm_per_rad": 2.0}, form_closed=True)
    t = follower_train(d, {"inertia_kg_mm2": 1.0}, form_closed=True)
    assert t.form_closed and t.rigid and t.spring_rate == 0.0


def test_the_train_checks_itself() -> None:
    with pytest.raises(DesignError, match="FollowerTrain.stiffness=0"):
        FollowerTrain("translating", mass=1.0, spring_rate=1.0, preload=0.0, stiffness=0.0)
