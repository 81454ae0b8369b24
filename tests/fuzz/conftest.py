"""Fuzz profiles: a fast one in every test run, a long one with ``pytest -m fuzz``.

Tests marked ``fuzz`` run only when the marker is selected (``pytest -m fuzz``); their
number of cases per test is ``CAMTOL_FUZZ_EXAMPLES`` (default 2500).
"""

from __future__ import annotations

import pytest


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip the long fuzz profile unless ``-m`` selects it."""
    if "fuzz" in (config.getoption("-m") or ""):
        return
    skip = pytest.mark.skip(reason="long fuzz profile: run with `pytest -m fuzz`")
    for item in items:
        if item.get_closest_marker("fuzz") is not None:
            item.add_marker(skip)
