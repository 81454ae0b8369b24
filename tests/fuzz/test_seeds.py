"""The bad inputs of issue 32, run as fuzz seeds (:mod:`seeds`; also run by bench/fuzz.py)."""

from __future__ import annotations

from pathlib import Path

import pytest
from seeds import Seed, run_seed, seeds

SEEDS = seeds()


@pytest.mark.parametrize("seed", SEEDS, ids=[s.name for s in SEEDS])
def test_bad_input_is_refused_with_one_line(seed: Seed, tmp_path: Path) -> None:
    _, problems = run_seed(seed, tmp_path)
    assert not problems, problems


def test_every_command_reading_a_design_is_seeded_with_the_offset_0_grade() -> None:
    # Item 8: the same design refused the same way by every command (analyze, report,
    # montecarlo, profile, precision, cut, size): one seed per command.
    names = {s.name for s in SEEDS if s.name.startswith("it6-offset-0-")}
    wanted = {"analyze", "report", "montecarlo", "profile", "precision", "cut", "size"}
    assert names == {f"it6-offset-0-{c}" for c in wanted}
