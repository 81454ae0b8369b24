"""The typed tables of a design file (camtol.config.fields): strict, bounded, every problem
named by its path with what is allowed (issue 32: they replace pydantic)."""

from __future__ import annotations

import math

import pytest

from camtol.config.fields import (
    AnyOf,
    AnyTable,
    Choice,
    Field,
    Flag,
    Integer,
    ListOf,
    Number,
    Table,
    Text,
    describe_problem,
    describe_problems,
    location,
)
from camtol.exceptions import ConfigError, FieldErrors

LENGTH = Number(0.001, 1e5, unit="mm")
SEGMENT = Table(
    {
        "kind": Field(Choice(("rise", "dwell"), explain={"coast": "a coast is a dwell here"})),
        "lift_mm": Field(Number(0.0, 100.0, exclusive_minimum=True, unit="mm"), None),
    }
)
TABLE = Table(
    {
        "name": Field(Text(min_chars=1, max_chars=8)),
        "r_mm": Field(LENGTH),
        "speed_rpm": Field(Number(0.0, exclusive_minimum=True, unit="rpm"), None),
        "order": Field(Integer(minimum=1), 1),
        "gravity": Field(Flag(), False),
        "master_um": Field(AnyOf((Number(), Text())), 0.0),
        "segments": Field(ListOf(SEGMENT), []),
        "extra": Field(AnyTable(), {}),
    }
)


def _problems(raw: object) -> FieldErrors:
    with pytest.raises(FieldErrors) as exc:
        TABLE.validate(raw)
    return exc.value


def test_a_valid_table_gets_its_defaults_and_floats() -> None:
    out = TABLE.validate({"name": "cam", "r_mm": 40})
    assert out == {
        "name": "cam",
        "r_mm": 40.0,
        "speed_rpm": None,
        "order": 1,
        "gravity": False,
        "master_um": 0.0,
        "segments": [],
        "extra": {},
    }
    assert isinstance(out["r_mm"], float)  # TOML's 40 is the length 40.0
    again = TABLE.validate({"name": "cam", "r_mm": 40})
    assert again["segments"] is not out["segments"]  # defaults are never shared


def test_none_counts_as_omitted() -> None:
    assert TABLE.validate({"name": "c", "r_mm": 1.0, "speed_rpm": None})["speed_rpm"] is None
    assert _problems({"name": "c", "r_mm": None}).problems[0].kind == "missing"


@pytest.mark.parametrize(
    ("value", "why"),
    [
        ("40", "a string is not a number"),
        (True, "a boolean is not a length"),
        (math.nan, "NaN"),
        (math.inf, "infinite"),
        (0.0, "below the minimum"),
        (1e300, "above the maximum"),
        ([40], "an array"),
    ],
)
def test_a_number_is_strict_finite_and_bounded(value: object, why: str) -> None:
    (problem,) = _problems({"name": "c", "r_mm": value}).problems
    assert problem.loc == ("r_mm",) and problem.kind == "value", why
    assert problem.allowed == "a finite number ≥ 0.001 and ≤ 100000 mm"


def test_open_bounds_and_whole_numbers() -> None:
    assert _problems({"name": "c", "r_mm": 1, "speed_rpm": 0}).problems[0].allowed == (
        "a finite number > 0 rpm"
    )
    for bad in (0, 1.0, True):
        (p,) = _problems({"name": "c", "r_mm": 1, "order": bad}).problems
        assert p.allowed == "a whole number ≥ 1"


def test_flags_texts_and_alternatives() -> None:
    (p,) = _problems({"name": "c", "r_mm": 1, "gravity": 1}).problems
    assert p.allowed == "true or false"
    (p,) = _problems({"name": "far too long", "r_mm": 1}).problems
    assert p.allowed == "a string of 1 to 8 characters"
    ok = TABLE.validate({"name": "c", "r_mm": 1, "master_um": "18 + 3*sin(theta)"})
    assert ok["master_um"] == "18 + 3*sin(theta)"
    (p,) = _problems({"name": "c", "r_mm": 1, "master_um": [1]}).problems
    assert p.allowed == "a finite number or a string"


def test_every_problem_is_found_with_its_path() -> None:
    raw = {
        "r_mm": -1,
        "colour": "red",
        "segments": [{"kind": "rise", "lift_mm": 5}, {"kind": "coast"}, {"lift_mm": 0}],
    }
    exc = _problems(raw)
    found = {(location(p.loc), p.kind) for p in exc.problems}
    assert found == {
        ("name", "missing"),
        ("r_mm", "value"),
        ("segments[1].kind", "explained"),
        ("segments[2].kind", "missing"),
        ("segments[2].lift_mm", "value"),
        ("colour", "unknown"),
    }
    message = str(exc)
    assert "\n" not in message and len(message) <= 400
    assert "segments[1].kind='coast': a coast is a dwell here" in message
    unknown = next(p for p in exc.problems if p.kind == "unknown")
    assert describe_problem(unknown, "t").startswith(
        "t.colour is not a known field; allowed: name, r_mm, speed_rpm,"
    )
    assert isinstance(exc, ConfigError)  # a user's mistake: one line, exit status 2


def test_messages_name_the_enclosing_table_and_stay_short() -> None:
    with pytest.raises(FieldErrors) as named:
        TABLE.validate({"name": "c", "r_mm": -1}, "follower")
    assert str(named.value) == (
        "follower.r_mm=-1 is not allowed; give a finite number ≥ 0.001 and ≤ 100000 mm"
    )
    assert named.value.problems[0].loc == ("r_mm",)  # relative to the table
    many = Table({f"f{i}": Field(Number()) for i in range(60)})
    with pytest.raises(FieldErrors) as caught:
        many.validate({})
    text = describe_problems(caught.value.problems, "t")
    assert len(text) <= 400 and text.endswith("more problem(s)")


def test_a_table_must_be_a_table() -> None:
    exc = _problems(["not", "a", "table"])
    (p,) = exc.problems
    assert p.loc == () and p.allowed == "a table"
    assert str(exc) == "['not', 'a', 'table'] is not allowed; give a table"
    (p,) = _problems({"name": "c", "r_mm": 1, "segments": "rise"}).problems
    assert p.loc == ("segments",) and p.allowed.startswith("an array of items")
