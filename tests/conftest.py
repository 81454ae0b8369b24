"""Shared fixtures."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import settings

settings.register_profile("camtol", max_examples=40, deadline=None, derandomize=True)
settings.load_profile("camtol")


@pytest.fixture
def rng() -> np.random.Generator:
    """Seeded random generator (never unseeded randomness in tests)."""
    return np.random.default_rng(20061203)
