"""The one table reader (issue 8: one reader for every CSV camtol reads) and the grid rule."""

from __future__ import annotations

import codecs
from pathlib import Path

import numpy as np
import pytest

from camtol.exceptions import DesignError, InputFileError
from camtol.grid import check_step, run_bounds, uniform_table_step
from camtol.tables import parse_table, read_table


@pytest.mark.parametrize(
    "text",
    [
        "theta_deg,lift_mm\n0,1.5\n10,2\n",
        "\ufefftheta_deg,lift_mm\r\n0,1.5\r\n10,2\r\n",
        "# made by a CMM\ntheta_deg; lift_mm\n0; 1.5 # first\n\n10;2\n",
        "theta_deg\tlift_mm\n0\t1.5\n10\t2\n",
        "theta_deg   lift_mm\n  0   1.5\n 10   2\n",
        '"theta_deg","lift_mm"\n"0","1.5"\n"10","2"\n',
    ],
    ids=["comma", "bom-crlf", "semicolon-comments", "tab", "blanks", "quoted"],
)
def test_forms_accepted(text: str) -> None:
    t = parse_table(text, source="f.csv", required=["theta_deg", "lift_mm"])
    np.testing.assert_array_equal(t.column("theta_deg"), [0.0, 10.0])
    np.testing.assert_array_equal(t.column("lift_mm"), [1.5, 2.0])


def test_utf16_with_bom(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_bytes(codecs.BOM_UTF16_LE + "a,b\n1,2\n".encode("utf-16-le"))
    assert read_table(p).data.tolist() == [[1.0, 2.0]]


def test_not_utf8_names_file_and_line(tmp_path: Path) -> None:
    p = tmp_path / "t.csv"
    p.write_bytes(b"a,b\n1,2\n3,\xff\n")
    with pytest.raises(InputFileError, match=r"t\.csv, line 3: is not UTF-8 text \(byte 0xff\)"):
        read_table(p)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("a,b\n1,2\n3,x\n", r"f\.csv, line 3, column b: 'x' is not a number"),
        ("a,b\n1,2\n3\n", r"f\.csv, line 3: expected 2 cells \(a, b\), got 1"),
        ("a,b\n1,2\n3,4,5\n", r"f\.csv, line 3: expected 2 cells"),
        ("a,b\n1,nan\n", r"line 2, column b: 'nan' is not allowed"),
        ("a,b\n1,inf\n", r"line 2, column b: 'inf' is not allowed"),
        ("a,a\n1,2\n", r"column 'a' is given twice"),
        ("", r"is empty"),
        ("# only a comment\n", r"is empty"),
        ("a,b\n", r"has no data rows"),
        ("c,d\n1,2\n", r"needs the columns a, b \(optional\); missing a; found: c, d"),
        ("1,2\n", r"needs a header line"),
    ],
)
def test_errors_name_file_line_column(text: str, message: str) -> None:
    with pytest.raises(InputFileError, match=message):
        parse_table(text, source="f.csv", required=["a"], optional=["b"])


def test_headerless_default_names_and_aliases() -> None:
    t = parse_table("0, 3\n90, 4\n", source="e.csv", default_names=["theta_deg", "um"])
    assert t.names == ("theta_deg", "um")
    t = parse_table("X,Y\n1,2\n", source="s.csv", aliases={"x": "x_mm", "y": "y_mm"})
    assert t.names == ("x_mm", "y_mm")


def test_line_of_locates_rows_after_comments() -> None:
    t = parse_table("# c\na,b\n\n1,2\n# c\n3,4\n", source="f.csv")
    assert [t.line_of(0), t.line_of(1)] == [4, 6]


def test_missing_file_and_directory(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="cannot be read"):
        read_table(tmp_path / "missing.csv")
    with pytest.raises(InputFileError, match="is a directory"):
        read_table(tmp_path)


def test_large_table_is_vectorised(tmp_path: Path) -> None:
    n = 200_000
    p = tmp_path / "big.csv"
    rows = np.column_stack([np.arange(n) * 0.0018, np.sin(np.arange(n))])
    np.savetxt(p, rows, delimiter=",", header="theta_deg,df_um", comments="")
    t = read_table(p, required=["theta_deg", "df_um"])
    assert t.rows == n
    np.testing.assert_allclose(t.data, rows, rtol=1e-15)


@pytest.mark.parametrize("step", [1, 0.5, 0.1, 45, 360, 0.0001])
def test_check_step_accepts(step: float) -> None:
    assert check_step(step) == round(360 / step)


@pytest.mark.parametrize("step", [0, -1, float("nan"), float("inf"), 1e-9, 1e-300, 7, 400, True])
def test_check_step_refuses(step: float) -> None:
    with pytest.raises(DesignError, match=r"--step=.* is not allowed; .*divide 360°"):
        check_step(step)


def test_uniform_table_step() -> None:
    assert uniform_table_step(np.arange(360.0), source="t.csv") == (1.0, 360)
    # the closing 360° row is dropped before (drop_closing_row); the gap is named
    with pytest.raises(
        InputFileError, match=r"row 4: theta_deg jumps from 2° to 4°; 1 row missing"
    ):
        uniform_table_step(np.r_[0.0, 1.0, 2.0, 4.0, np.arange(5.0, 360.0)], source="t.csv")
    with pytest.raises(InputFileError, match=r"row 361: theta_deg=360° is beyond one revolution"):
        uniform_table_step(np.arange(361.0), source="t.csv")
    with pytest.raises(InputFileError, match="must start at 0°"):
        uniform_table_step(np.arange(1.0, 361.0), source="t.csv")


def test_run_bounds_split_a_grid_into_runs_of_equal_values() -> None:
    """The one run finder of the engine, the motion program and the extremes' plateaus."""
    values = np.array([3, 3, 1, 1, 1, 3, 2])
    bounds = run_bounds(values)
    assert bounds == [0, 2, 5, 6, 7]
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        assert np.all(values[a:b] == values[a])  # one value per run
        assert b == values.size or values[b] != values[a]  # and a change after it
    assert run_bounds(np.array([True])) == [0, 1]
    assert run_bounds(np.array([], dtype=bool)) == [0]
