"""Strict, bounded design-file schema (issue 9 items 10-12; issue 8 one union).

A string is not a number, a boolean is not a length; every physical quantity has a
plausible range stated in the schema; messages name the field as the file writes it,
shorten the value and stay within a few hundred characters.
"""

from __future__ import annotations

import sys
from typing import Any

import pytest

from camtol.config.design_file import (
    design_from_mapping,
    example_text,
    follower_types,
)
from camtol.config.fields import MESSAGE_CHARS, VALUE_CHARS
from camtol.exceptions import ConfigError
from camtol.mechanisms import MECHANISMS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib


def _data(name: str) -> dict[str, Any]:
    return tomllib.loads(example_text(name))


def _error(data: dict[str, Any]) -> str:
    with pytest.raises(ConfigError) as exc:
        design_from_mapping(data)
    msg = str(exc.value)
    assert "\n" not in msg
    assert len(msg) <= MESSAGE_CHARS + 200  # one problem may exceed the soft cap a little
    return msg


@pytest.mark.parametrize(
    ("example", "table", "key", "value", "expect"),
    [
        (
            "roller-translating",
            "follower",
            "roller_radius_mm",
            True,
            "follower.roller_radius_mm=True",
        ),
        ("roller-translating", "follower", "base_radius_mm", "40", "follower.base_radius_mm='40'"),
        ("roller-translating", "follower", "base_radius_mm", 1e300, "≤ 100000 mm"),
        ("roller-translating", "follower", "offset_mm", float("nan"), "finite number"),
        ("cw11-conjugate", "follower", "arm_b_mm", 1e300, "follower.arm_b_mm=1e+300"),
        ("cw11-conjugate", "follower", "arm_a_mm", 5.0, "follower.arm_a_mm=5"),
        ("cw06-translating", "operation", "speed_rpm", 1e300, "operation.speed_rpm=1e+300"),
        ("cw06-translating", "operation", "speed_rpm", "300", "operation.speed_rpm='300'"),
        ("cw06-translating", "tolerances", "r_um", 1e300, "tolerances.r_um=1e+300"),
        ("cw06-translating", "tolerances", "r_um", True, "tolerances.r_um=True"),
    ],
)
def test_bad_values_name_the_field(
    example: str, table: str, key: str, value: Any, expect: str
) -> None:
    data = _data(example)
    data.setdefault(table, {})[key] = value
    if table == "tolerances":
        data["tolerances"].pop("r", None)
    msg = _error(data)
    assert expect in msg, msg


def test_conjugate_arm_message_uses_the_file_name() -> None:
    data = _data("cw11-conjugate")
    data["follower"]["arm_a_mm"] = 5.0
    msg = _error(data)
    assert "follower.arm_a_mm" in msg and "arm_length_mm" not in msg


@pytest.mark.parametrize("bad", [["a"], 3, True, {"x": 1}, "knife"])
def test_follower_type_must_be_a_known_name(bad: Any) -> None:
    data = _data("roller-translating")
    data["follower"]["type"] = bad
    msg = _error(data)
    assert msg.startswith("follower.type=")
    assert "allowed: flat_translating, flat_oscillating, roller_translating" in msg


def test_missing_type() -> None:
    data = _data("roller-translating")
    del data["follower"]["type"]
    assert _error(data).startswith("follower.type is missing")


def test_table_step_must_be_a_number() -> None:
    data = _data("cw06-translating")
    data["motion"] = {"table_step_deg": "1", "table_lift_mm": [0.0] * 360}
    assert "motion.table_step_deg='1'" in _error(data)


def test_huge_nested_lift_table_gives_a_short_message() -> None:
    data = _data("cw06-translating")
    data["motion"] = {"table_step_deg": 1.0, "table_lift_mm": [[1.0] * 100] * 360}
    msg = _error(data)
    assert len(msg) <= MESSAGE_CHARS + VALUE_CHARS
    assert "more problem" in msg


def test_long_values_are_shortened() -> None:
    data = _data("cw06-translating")
    data["follower"]["base_radius_mm"] = "x" * 10_000
    msg = _error(data)
    assert "…" in msg and len(msg) < 300


def test_schema_is_derived_from_every_registered_type() -> None:
    types = follower_types()
    assert set(types) == {k for k, c in MECHANISMS.items() if c.parameters}
    for cls in types.values():
        for p in cls.parameters:
            assert p.minimum < p.maximum
            assert p.unit in ("mm", "deg")
            assert p.name.endswith("_" + p.unit)
