"""Design files: a test per validation message (field, value and what is allowed)."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import pytest

from camtol.config.design_file import (
    design_from_mapping,
    example_names,
    example_text,
    load_design,
    load_example,
)
from camtol.design.motion import LiftTable
from camtol.exceptions import ConfigError
from camtol.report.display import analysis_notes

try:
    import tomllib
except ImportError:  # pragma: no cover
    import tomli as tomllib  # type: ignore[no-redef]

BASE: dict[str, Any] = tomllib.loads(example_text("cw06-translating"))


def _with(path: str, value: Any) -> dict[str, Any]:
    data = copy.deepcopy(BASE)
    node: Any = data
    keys = path.split(".")
    for k in keys[:-1]:
        node = node[int(k)] if k.isdigit() else node[k]
    last = keys[-1]
    if value is _DELETE:
        del node[last]
    else:
        node[int(last) if last.isdigit() else last] = value
    return data


_DELETE = object()


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (
            "follower.base_radius_mm",
            -40.0,
            r"follower.base_radius_mm=-40.0 is not allowed; give a finite number ≥ 0.001"
            r" and ≤ 100000 mm",
        ),
        ("follower.base_radius_mm", _DELETE, r"follower.base_radius_mm is missing"),
        ("follower.type", "knife", r"follower.type='knife' is unknown; allowed: flat_translating"),
        (
            "follower.face_angle_deg",
            90.0,
            r"follower.face_angle_deg=90.0 is not allowed; give a finite number > -90 and < 90 deg",
        ),
        ("follower.colour", "red", r"follower.colour is not a known field"),
        (
            "motion.segments.0.law",
            "spline",
            r"motion.segments\[0\].law='spline' is not allowed; give a known motion law: cycloidal",
        ),
        ("motion.segments.3.end_deg", 350.0, r"cover 350°; they must cover exactly 360°"),
        ("motion.segments.0.lift_mm", _DELETE, r"motion.segments\[0\].lift_mm is missing"),
        ("motion.segments.2.lift_mm", 20.0, r"rises and returns must balance"),
        ("name", _DELETE, r"name is missing"),
        ("tolerances.r", "IT19", r"tolerances.r='IT19'"),
        ("tolerances.r", 19, r"tolerances.r=19: a bare key takes an IT grade"),
        (
            "tolerances.f",
            "IT6",
            r"tolerances.f is not an error source of a flat_translating follower; allowed: r",
        ),
        ("tolerances", {"phi_um": 5.0}, r"tolerances.phi_um: the unit suffix must be _deg"),
        ("tolerances", {"r": "IT6", "r_um": 3.0}, r"tolerances.r is given twice"),
        (
            "operation",
            {"speed_rpm": -3},
            r"operation.speed_rpm=-3 is not allowed; give a finite number > 0 and ≤ 1e\+06 rpm",
        ),
    ],
)
def test_validation_messages(path: str, value: Any, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        design_from_mapping(_with(path, value))


def test_translating_lift_must_be_mm() -> None:
    data = _with("motion.segments.0.lift_mm", _DELETE)
    data["motion"]["segments"][0]["lift_deg"] = 22.0
    with pytest.raises(
        ConfigError,
        match=r"lift_deg is not allowed: a translating follower's lift is given as lift_mm",
    ):
        design_from_mapping(data)


def test_zero_offset_with_grade_asks_for_explicit_deviation() -> None:
    # Issue 32: refused when the design is read, so that every command (not only those
    # that resolve tolerances, as analyze does) refuses it alike.
    with pytest.raises(ConfigError, match=r"tolerances.e='IT6' cannot be applied.*e_um"):
        design_from_mapping(_with("follower.offset_mm", 0.0))


def test_explicit_deviations_in_file_units() -> None:
    data = copy.deepcopy(BASE)
    data["tolerances"] = {"r_um": 19.0, "e_um": 9.0, "phi_deg": 0.011}
    d = design_from_mapping(data)
    tol = {t.key: t.deviation for t in d.resolve_tolerances(61.25)}
    assert tol == pytest.approx({"r": 0.019, "e": 0.009, "phi": math.radians(0.011)})


def test_missing_and_malformed_files(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"design file '.*nope.toml' cannot be read"):
        load_design(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = 'x'\n[follower\n")
    with pytest.raises(ConfigError, match=r"is not valid TOML"):
        load_design(bad)
    incomplete = tmp_path / "incomplete.toml"
    incomplete.write_text('[follower]\ntype = "flat_translating"\n')
    # Every field at fault, and the file they are missing from.
    with pytest.raises(ConfigError, match=r"^design file '.*incomplete.toml': name is missing"):
        load_design(incomplete)
    with pytest.raises(ConfigError) as caught:
        load_design(incomplete)
    assert "motion is missing" in str(caught.value)


def test_lift_table_from_csv(tmp_path: Path) -> None:
    import numpy as np

    design = load_example("cw06-translating")
    t = np.arange(360.0)
    lift = design.program.evaluate(np.radians(t)).lift
    csv = tmp_path / "lift.csv"
    csv.write_text(
        "theta_deg,lift_mm\n" + "".join(f"{a:g},{b:.9f}\n" for a, b in zip(t, lift, strict=True))
    )
    data = copy.deepcopy(BASE)
    data["motion"] = {"table_file": "lift.csv"}
    (tmp_path / "cam.toml").write_text("")
    d = design_from_mapping(data, base_dir=tmp_path)
    assert isinstance(d.program, LiftTable)
    assert d.program.evaluate(np.radians([60.0])).lift[0] == pytest.approx(11.0, abs=1e-6)
    data["motion"] = {"table_file": "missing.csv"}
    with pytest.raises(ConfigError, match=r"motion.table_file='.*missing.csv' cannot be read"):
        design_from_mapping(data, base_dir=tmp_path)


def test_inline_table_must_cover_360() -> None:
    data = copy.deepcopy(BASE)
    data["motion"] = {"table_step_deg": 1.0, "table_lift_mm": [0.0] * 300}
    with pytest.raises(ConfigError, match=r"covers 300°; the table must cover exactly 360°"):
        design_from_mapping(data)


def test_examples_load() -> None:
    assert {"cw06-translating", "cw06-oscillating"} <= set(example_names())
    for name in example_names():
        assert load_example(name).name == name
    with pytest.raises(ConfigError, match=r"example 'nope' does not exist; available: "):
        example_text("nope")


@pytest.mark.parametrize(("decimals", "reliable"), [(3, False), (6, True)])
def test_lift_table_precision_is_reported(tmp_path: Path, decimals: int, reliable: bool) -> None:
    """THEORY §1/§6.1: a table's derivatives depend on its precision; say so (Popa: 1e-3 mm
    distorts the acceleration badly, 1e-6 mm matches theory)."""
    import numpy as np

    from camtol.analysis.result import analyse

    design = load_example("cw06-translating")
    t = np.arange(360.0)
    lift = design.program.evaluate(np.radians(t)).lift
    rows = "".join(f"{a:g},{b:.{decimals}f}\n" for a, b in zip(t, lift, strict=True))
    (tmp_path / "lift.csv").write_text("theta_deg,lift_mm\n" + rows)
    data = copy.deepcopy(BASE)
    data["motion"] = {"table_file": "lift.csv"}
    a = analyse(design_from_mapping(data, base_dir=tmp_path), step_deg=1.0)
    assert isinstance(a.design.program, LiftTable)
    assert a.design.program.resolution == pytest.approx(10.0**-decimals)
    notes = analysis_notes(a)  # the report's words for a.lift_table
    assert any(f"rounded to {10.0**-decimals:g} mm" in n for n in notes)
    assert any("NOT reliable" in n for n in notes) is not reliable
    assert a.lift_table is not None and a.lift_table.derivatives_reliable is reliable
