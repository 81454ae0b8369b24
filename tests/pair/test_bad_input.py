"""Bad inspection input gets one clear line (issue 9 items 8, 9, 11, 12; issue 8 item 3).

Regression tests of the reproductions: formulas that are too long or too deep, malformed
lengths, absurd magnitudes, lax types in ``[inspection]``, messages that named
``fixture.`` fields, and the conjugate command's ``--step``.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import design_from_mapping, example_text, load_design, load_example
from camtol.config.inspection_table import fixture_spec_from_mapping
from camtol.exceptions import ConfigError, DesignError, InputFileError
from camtol.inspection import ErrorFunction
from camtol.inspection.error_functions import parse_error_function
from camtol.inspection.formula import MAX_FORMULA_CHARS, Formula
from camtol.inspection.units import MAX_ERROR_UM, parse_length_um
from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    assert len(lines[0]) < 400, lines[0]  # a few hundred characters at most
    return lines[0]


# --- formulas: bounded (issue 9 item 9) -----------------------------------------------------
@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("-" * 100_000 + "1", "too long"),
        ("+".join(["1"] * 20_000), "too long"),
        ("+".join(["theta"] * 300), "too large|nested"),  # 1,799 characters: within the length
        ("-" * 500 + "1", "nested"),
        ("sin(" * 100 + "theta" + ")" * 100, "nested"),
        ("9" * 400, "not finite"),
    ],
    ids=["minus-chain", "20000-terms", "many-terms", "deep-unary", "deep-calls", "huge-int"],
)
def test_formula_bounds_give_one_design_error(text: str, pattern: str) -> None:
    with pytest.raises(DesignError, match=pattern) as info:
        ErrorFunction.formula(text)
    msg = str(info.value)
    assert "\n" not in msg and len(msg) < 400  # the formula is shortened in the message


def test_formula_within_bounds_still_works() -> None:
    # a 40-term Fourier series is well inside the bounds
    text = " + ".join(f"0.1*sin({k}*theta)" for k in range(1, 41))
    assert len(text) < MAX_FORMULA_CHARS
    f = Formula.parse(text)
    theta = np.linspace(0.0, 2 * math.pi, 7)
    expected = sum(0.1 * np.sin(k * theta) for k in range(1, 41))
    np.testing.assert_allclose(f(theta), expected, atol=1e-12)


def test_formula_beyond_bounds_on_the_check_grid() -> None:
    with pytest.raises(DesignError, match=r"reaches .* µm at θ=.*within ±10000 µm"):
        ErrorFunction.formula("1e300*sin(theta)")
    with pytest.raises(DesignError, match="not finite at θ=0.00°"):
        ErrorFunction.formula("1/theta")


@pytest.mark.parametrize(
    "flag",
    ["-" * 100_000 + "1", "+".join(["1"] * 20_000), "1.2.3 um", ".", "..", "1e300 um", "1e999"],
    ids=["minus-chain", "20000-terms", "1.2.3um", "dot", "dotdot", "1e300um", "inf"],
)
def test_cli_df_mea_bad_values(flag: str, capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = _run(["conjugate", "-e", "cw11-conjugate", "-q", "--df-mea", flag], capsys)
    assert code == 2
    assert "--df-mea" in _one_line(err)


# --- lengths (issue 9 item 9) ---------------------------------------------------------------
@pytest.mark.parametrize("text", ["1.2.3 um", ".", "..", "um", "1..2", "--1", "1e", ""])
def test_malformed_lengths(text: str) -> None:
    with pytest.raises(DesignError, match="number with unit um or mm"):
        parse_length_um(text, field="--df-mea")


@pytest.mark.parametrize("value", ["1e300 um", "11 mm", 1e300, -2e4, 10**400, math.nan, math.inf])
def test_lengths_are_bounded(value: str | float) -> None:
    with pytest.raises(DesignError, match=r"--df-mea=.*(within ±10000 µm|finite)"):
        parse_length_um(value, field="--df-mea")
    with pytest.raises(DesignError, match=r"--df-mea=.*(within ±10000 µm|finite)"):
        parse_error_function(value, field="--df-mea")


def test_lengths_accept_the_usual_forms() -> None:
    assert parse_length_um(".5 mm") == pytest.approx(500.0)
    assert parse_length_um("5. um") == pytest.approx(5.0)
    assert parse_length_um("-1e1um") == pytest.approx(-10.0)
    assert parse_length_um(f"{MAX_ERROR_UM:g}") == MAX_ERROR_UM


# --- the typed [inspection] table (issue 8 item 3, issue 9 items 11-12) ---------------------
def _cw11_mapping() -> dict[str, object]:
    return dict(tomllib.loads(example_text("cw11-conjugate")))


@pytest.mark.parametrize(
    ("key", "value", "pattern"),
    [
        ("dl_a_um", True, r"inspection\.dl_a_um=True is not allowed; give a number of µm"),
        ("dl_a_um", "19", r"inspection\.dl_a_um='19' is not allowed"),
        ("dl_a_um", 1e300, r"inspection\.dl_a_um=1e\+300 is not allowed.*±10000"),
        ("drr_d_um", math.nan, r"inspection\.drr_d_um=nan is not allowed"),
        ("deta_deg", 45.0, r"inspection\.deta_deg=45.0 is not allowed.*±10"),
        ("tolerance_a_um", 22, r"inspection\.tolerance_a_um=22 is not allowed; give \[lower, up"),
        ("tolerance_a_um", ["-22", 22], r"inspection\.tolerance_a_um=\['-22', 22\]"),
        ("tolerance_a_um", [22, -22], r"inspection\.tolerance_a_um=\[22, -22\].*lower < upper"),
        ("tolerance_b_um", [-1e300, 1e300], r"inspection\.tolerance_b_um=.*within ±10000"),
        ("tolerance_b_um", [1, 2, 3], r"inspection\.tolerance_b_um=\[1, 2, 3\]"),
        ("master_a_um", "1e300 um", r"inspection\.master_a_um='1e300 um' is not allowed"),
        ("master_b_um", True, r"inspection\.master_b_um=True is not allowed"),
        ("df_mea_um", [1, 2], r"inspection\.df_mea_um=\[1, 2\] is not allowed"),
        ("fixture", {}, r"inspection\.fixture is not a known field; allowed: tolerance_a_um"),
    ],
)
def test_inspection_table_is_strict_and_names_fields_as_written(
    key: str, value: object, pattern: str
) -> None:
    data = _cw11_mapping()
    table = dict(data["inspection"])  # type: ignore[call-overload]
    table[key] = value
    data["inspection"] = table
    with pytest.raises(ConfigError, match=pattern) as info:
        design_from_mapping(data)
    assert "fixture." not in str(info.value) and "\n" not in str(info.value)


def test_inspection_table_is_a_typed_spec_on_the_design() -> None:
    d = load_example("cw11-conjugate")
    assert isinstance(d.inspection, FixtureSpec)
    assert "inspection" not in d.extras  # no raw dict below the config layer
    assert d.inspection.tolerance_a_um == (-22.0, 22.0)
    assert d.inspection.errors.dl_a_mm == pytest.approx(0.019)
    assert d.inspection.errors.deta_rad == pytest.approx(math.radians(0.022))
    assert d.inspection.df_mea is not None
    assert d.inspection.to_mapping()["master_a_um"] == "18.5 + 3.5*sin(theta)"
    with pytest.raises(AttributeError):
        d.inspection.tolerance_a_um = (0.0, 1.0)  # type: ignore[misc]  # frozen
    # a single cam's [inspection] states only its CMM zone (issue 31): no fixture inputs
    from camtol.inspection.zone import ZoneTable
    from camtol.pair.fixture_spec import fixture_spec

    single = load_example("cw06-translating")
    assert isinstance(single.inspection, ZoneTable) and fixture_spec(single) is None


def test_missing_required_field_and_python_spec_messages() -> None:
    with pytest.raises(DesignError, match=r"inspection\.tolerance_a_um is missing; give \["):
        fixture_spec_from_mapping({"dl_a_um": 1})
    zero = ErrorFunction.constant(0.0)
    with pytest.raises(DesignError, match=r"^inspection\.tolerance_b_um=\[5, -5\]"):
        FixtureSpec(FixtureErrors(), (-1.0, 1.0), (5.0, -5.0), zero, zero)


def test_relative_csv_paths_are_resolved_at_load(tmp_path: Path) -> None:
    (tmp_path / "master.csv").write_text("theta_deg;dr_um\n0;1\n180;3\n")
    text = example_text("cw11-conjugate").replace(
        'master_a_um = "18.5 + 3.5*sin(theta)"', 'master_a_um = "master.csv"'
    )
    (tmp_path / "d.toml").write_text(text)
    d = load_design(tmp_path / "d.toml")
    assert d.inspection is not None
    assert d.inspection.master_a(np.radians([90.0])) == pytest.approx([2.0])
    assert d.inspection.to_mapping()["master_a_um"] == str(tmp_path / "master.csv")
    # a bad table is reported when the design is loaded, naming the file and line
    (tmp_path / "master.csv").write_text("theta_deg,dr_um\n0,1\n180,1e300\n")
    with pytest.raises(InputFileError, match=r"master\.csv: the error 1e\+300 µm"):
        load_design(tmp_path / "d.toml")


def test_error_table_forms(tmp_path: Path) -> None:
    p = tmp_path / "e.csv"
    p.write_bytes(b"\xef\xbb\xbf# deviations\r\n0 1\r\n180 3\r\n")  # BOM, CRLF, blanks, no header
    assert ErrorFunction.from_csv(p)(np.radians([90.0])) == pytest.approx([2.0])
    p.write_text("theta_deg,operator\n0,1\n180,3\n")
    with pytest.raises(InputFileError, match="needs a column in µm besides theta_deg"):
        ErrorFunction.from_csv(p)
    p.write_text("theta_deg,dr_um,dr_um\n0,1,1\n180,3,3\n")
    with pytest.raises(InputFileError, match="'dr_um' is given twice"):
        ErrorFunction.from_csv(p)


# --- the conjugate command's --step: the one grid rule (issue 9 item 8) ---------------------
@pytest.mark.parametrize(
    "step", ["0", "nan", "1e-9", "1e-300", "0.7", "-1", "inf", "180", "0.0001"]
)
def test_cli_conjugate_step_uses_the_grid_rule(
    step: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run(["conjugate", "-e", "cw11-conjugate", "--step", step], capsys)
    assert code == 2 and out == ""
    line = _one_line(err)
    assert "--step=" in line and "divide 360°" in line


def test_python_step_uses_the_grid_rule() -> None:
    from camtol.pair.fixture import inspect_conjugate
    from camtol.pair.indicator import process_record
    from camtol.pair.twin import simulate_record

    d = load_example("cw11-conjugate")
    for bad in (0.0, math.nan, 1e-9, 1e-300, 0.7):
        with pytest.raises(DesignError, match="step_deg=.*divide 360°"):
            inspect_conjugate(d, step_deg=bad)
        with pytest.raises(DesignError, match="step_deg=.*divide 360°"):
            process_record(simulate_record(np.sin, revolutions=2, noise_um=0.0), step_deg=bad)


def test_inspect_conjugate_uses_the_designs_spec() -> None:
    from camtol.pair.fixture import inspect_conjugate

    d = load_example("cw11-conjugate")
    assert d.inspection is not None
    a = inspect_conjugate(d, step_deg=1.0)
    b = inspect_conjugate(d, d.inspection, step_deg=1.0)
    np.testing.assert_array_equal(a.bands.df_a_upper_um, b.bands.df_a_upper_um)
    with pytest.raises(DesignError, match=r"has no \[inspection\] table"):
        inspect_conjugate(dataclasses.replace(d, inspection=None))


def test_verify_and_report_use_the_resolved_csv_paths(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before, `verify` re-parsed [inspection] without the design's directory: a relative
    master CSV was looked up in the working directory ("cannot read the error table")."""
    (tmp_path / "m.csv").write_text("theta_deg,dr_um\n0,18\n180,22\n")
    text = example_text("cw11-conjugate").replace(
        'master_a_um = "18.5 + 3.5*sin(theta)"', 'master_a_um = "m.csv"'
    )
    (tmp_path / "d.toml").write_text(text)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    code, out, err = _run(["verify", str(tmp_path / "d.toml")], capsys)
    assert code == 0, err
    assert "all checks passed" in out
    code, out, err = _run(["report", str(tmp_path / "d.toml"), "-o", "r.html", "-q"], capsys)
    assert code in (0, 1), err
    assert "m.csv" in (elsewhere / "r.html").read_text(encoding="utf-8")
