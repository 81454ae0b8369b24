"""The return spring for a jump margin (THEORY §9.8)."""

from __future__ import annotations

import numpy as np
import pytest

from camtol.config.design_file import load_example
from camtol.dynamics.jump import minimum_force
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.spring import FLOOR_FRACTION, propose_spring
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError


@pytest.mark.parametrize("stiffness", [None, 1e4])
@pytest.mark.parametrize("name", ["roller-translating", "cw06-translating", "popa-eccentric"])
def test_the_proposed_spring_meets_the_margin(name: str, stiffness: float | None) -> None:
    d = load_example(name)
    lift = nominal_lift(d, 0.1)
    train = FollowerTrain(
        "translating",
        mass=1e-3,
        spring_rate=1.0,
        preload=1.0,
        stiffness=stiffness,
        damping_ratio=0.05 if stiffness else 0.0,
    )
    p = propose_spring(train, lift, 900.0, 1.3)
    assert p.spring_rate > 0 and p.preload >= 0
    assert p.jump_speed_rpm is not None and p.jump_speed_rpm >= 1.3 * 900.0 * (1 - 1e-9)
    floor = (
        FLOOR_FRACTION * 1e-3 * (900 * np.pi / 30) ** 2 * float(np.max(-lift.smooth_acceleration))
    )
    assert minimum_force(p.train, lift, 900.0)[0] >= floor * (1 - 1e-6)
    # a 10% weaker spring misses the margin: the proposal is not wastefully stiff
    weak = FollowerTrain(
        "translating",
        mass=1e-3,
        spring_rate=0.9 * p.spring_rate,
        preload=0.9 * p.preload,
        stiffness=stiffness,
        damping_ratio=0.05 if stiffness else 0.0,
    )
    assert (
        minimum_force(weak, lift, 1.3 * 900.0)[0] < 0 or minimum_force(weak, lift, 900.0)[0] < floor
    )


def test_a_margin_must_exceed_one() -> None:
    train = FollowerTrain("translating", mass=1e-3, spring_rate=1.0, preload=1.0)
    with pytest.raises(DesignError, match=r"--jump-margin=1 is not allowed"):
        propose_spring(train, nominal_lift(load_example("popa-eccentric"), 1.0), 900.0, 1.0)


def test_size_proposes_the_spring(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from camtol.cli.app import main

    args = ["size", "-e", "roller-translating", "--jump-margin", "1.3", "--mass-kg", "0.5"]
    assert main([*args, "--rpm", "600", "--json"]) == 0
    spring = json.loads(capsys.readouterr().out)["spring"]
    assert set(spring) == {
        "spring_rate_n_per_mm",
        "preload_n",
        "rpm",
        "jump_margin",
        "jump_speed_rpm",
    }
    assert spring["jump_speed_rpm"] >= 1.3 * 600 * (1 - 1e-9)
    assert main(["size", "-e", "roller-translating", "--rpm", "600"]) == 2
    assert "are for --jump-margin" in capsys.readouterr().err
    assert main([*args[:-2], "--rpm", "600"]) == 2  # no mass
    assert "dynamics.mass_kg is missing" in capsys.readouterr().err
    assert (
        main(
            [
                "size",
                "-e",
                "cw11-conjugate",
                "--jump-margin",
                "1.3",
                "--rpm",
                "60",
                "--inertia-kg-mm2",
                "10",
            ]
        )
        == 2
    )
    assert "form-closed" in capsys.readouterr().err
