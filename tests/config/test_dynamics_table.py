"""The [dynamics] table of a design file: validated at load, kept as written (issue 33)."""

from __future__ import annotations

import pytest

from camtol.config.design_file import _parse_toml, design_from_mapping, example_text
from camtol.dynamics.train import DynamicsTable
from camtol.exceptions import ConfigError


def _load(name: str, table: str) -> object:
    return design_from_mapping(_parse_toml(example_text(name) + "\n[dynamics]\n" + table, "x"))


def test_the_table_is_kept_typed_and_as_written() -> None:
    d = _load("popa-eccentric", "mass_kg = 0.5\nspring_rate_n_per_mm = 10\ngravity = true\n")
    table = d.extras["dynamics"]  # type: ignore[attr-defined]
    assert isinstance(table, DynamicsTable)
    assert table.get("mass_kg") == 0.5 and table.get("gravity") is True
    assert table.to_mapping() == {"mass_kg": 0.5, "spring_rate_n_per_mm": 10.0, "gravity": True}


def test_the_hash_is_that_of_the_file_however_numbers_are_spelt() -> None:
    a = _load("popa-eccentric", "mass_kg = 0.5\nspring_rate_n_per_mm = 10\npreload_n = 50\n")
    b = _load("popa-eccentric", "mass_kg = 5e-1\nspring_rate_n_per_mm = 10.0\npreload_n = 5e1\n")
    c = _load("popa-eccentric", "mass_kg = 0.6\nspring_rate_n_per_mm = 10\npreload_n = 50\n")
    plain = design_from_mapping(_parse_toml(example_text("popa-eccentric"), "x"))
    hashes = [x.content_hash for x in (a, b, c, plain)]  # type: ignore[attr-defined]
    assert hashes[0] == hashes[1]
    assert len({hashes[0], hashes[2], hashes[3]}) == 3


@pytest.mark.parametrize(
    ("name", "table", "message"),
    [
        (
            "popa-eccentric",
            "mass_kg = 0\n",
            r"dynamics\.mass_kg=0 is not allowed; give a finite number > 0 kg",
        ),
        ("popa-eccentric", 'mass_kg = "1"\n', r"dynamics\.mass_kg='1'"),
        ("popa-eccentric", "damping_ratio = 2.5\n", r"dynamics\.damping_ratio=2\.5"),
        ("popa-eccentric", "poisson_ratio_cam = 0.5\n", r"dynamics\.poisson_ratio_cam=0\.5"),
        ("popa-eccentric", "speed = 3\n", r"dynamics\.speed is not a field"),
        ("popa-eccentric", "preload_nm = 3\n", r"dynamics\.preload_nm does not apply"),
        ("cw06-oscillating", "spring_rate_n_per_mm = 3\n", r"give spring_rate_nm_per_rad"),
        (
            "cw06-oscillating",
            "gravity = true\n",
            r"dynamics\.gravity = true applies to a translating",
        ),
        ("cw11-conjugate", "spring_rate_nm_per_rad = 3\n", r"form-closed"),
        ("popa-eccentric", "gravity_angle_deg = 30\n", r"needs gravity = true"),
    ],
)
def test_a_bad_table_is_refused_at_load(name: str, table: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        _load(name, table)


def test_a_design_with_the_table_round_trips_through_dump_design() -> None:
    import sys

    from camtol.config.design_file import dump_design

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    d = _load("roller-translating", "mass_kg = 0.5\nspring_rate_n_per_mm = 10\ngravity = true\n")
    again = design_from_mapping(tomllib.loads(dump_design(d)))  # type: ignore[arg-type]
    assert again.content_hash == d.content_hash  # type: ignore[attr-defined]
    assert again.extras["dynamics"] == d.extras["dynamics"]  # type: ignore[attr-defined]
