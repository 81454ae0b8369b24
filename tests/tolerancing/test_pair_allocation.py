"""IT grades of a conjugate pair against its interference/backlash yield (issue 28)."""

from __future__ import annotations

import pytest

from camtol.config import load_example
from camtol.exceptions import DesignError
from camtol.pair.sources import pair_sources
from camtol.tolerancing.pair import pair_monte_carlo
from camtol.tolerancing.pair_allocation import allocate_pair

PAIR = load_example("cw11-conjugate")


def test_loose_limits_keep_the_coarsest_grades() -> None:
    a = allocate_pair(PAIR, interference_max_mm=1.0, backlash_max_mm=1.0, samples=500)
    assert set(a.grades.values()) == {"IT12"} and a.steps == () and a.met
    assert a.fixed == ("eta",)  # an explicit deviation is kept
    assert {s.key for s in pair_sources(a.design)} == set(a.grades) | {"eta"}


def test_the_chosen_grades_give_the_yield_they_claim() -> None:
    a = allocate_pair(
        PAIR,
        interference_max_mm=0.06,
        backlash_max_mm=0.06,
        target_yield=0.95,
        samples=1000,
        verify_samples=4000,
        step_deg=2.0,
    )
    assert a.steps  # something had to be tightened
    assert a.met == (a.yield_estimate.value >= 0.95)
    again = pair_monte_carlo(
        a.design, 4000, step_deg=2.0, interference_max_mm=0.06, backlash_max_mm=0.06
    )
    assert again.pair_yield is not None
    assert again.pair_yield.value == pytest.approx(a.yield_estimate.value)
    assert a.to_dict()["criterion"] == "pair_yield"


def test_an_unreachable_target_says_so() -> None:
    a = allocate_pair(PAIR, interference_max_mm=0.0, backlash_max_mm=0.0, samples=200, step_deg=5.0)
    assert not a.met and set(a.grades.values()) == {"IT5"}


def test_bad_target() -> None:
    with pytest.raises(DesignError, match="--yield"):
        allocate_pair(PAIR, interference_max_mm=0.01, backlash_max_mm=0.01, target_yield=1.0)
