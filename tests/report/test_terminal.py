"""Plain-text terminal output (camtol.report.terminal): fits the width, no trailing
blanks, colour only when asked, cells kept whole (issue 32: it replaces rich's tables)."""

from __future__ import annotations

import io

import pytest

from camtol.report.terminal import NO_BREAK, Column, Terminal, table_lines

COLUMNS = [
    Column("quantity", wrap=True),
    Column("unit"),
    Column("max", "right"),
    Column("at θ"),
]
ROWS = [
    ("pressure angle φ" + " >" + NO_BREAK + "10°" + NO_BREAK + "LIMIT", "°", "15.000", "0.00°"),
    ("radial dimension |O2A| of the cam measured from its centre", "mm", "61.250", "120.00°"),
    ("ΔV worst case", "µm/rad", "0", "120.00-190.00°\n290.00-360.00°"),
]


@pytest.mark.parametrize("width", [40, 60, 80, 120])
def test_a_table_fits_its_width_and_keeps_cells_whole(width: int) -> None:
    out = io.StringIO()
    Terminal(out, width=width).table(COLUMNS, ROWS, title="Extremes over 0-360°")
    text = out.getvalue()
    lines = text.splitlines()
    assert max(len(ln) for ln in lines) <= width
    assert all(ln == ln.rstrip() for ln in lines)
    assert "\x1b[" not in text and NO_BREAK not in text  # a file: plain text
    for whole in ("120.00-190.00°", "290.00-360.00°", "15.000"):
        assert whole in text  # a cell's own lines are never split
    if width >= 60:  # words joined by a no-break space stay on one line
        assert "> 10° LIMIT" in text
    heading = next(i for i, ln in enumerate(lines) if ln.startswith("quantity"))
    assert set(lines[heading + 1]) == {"─"}
    assert lines[0].strip() == "Extremes over 0-360°"
    assert lines[-1] == ""  # a blank line closes the table


def test_columns_align_and_the_wrapping_column_takes_what_is_left() -> None:
    lines = table_lines(COLUMNS, ROWS, 60, heading=True)
    head = lines[0]
    unit_at = head.index("unit")
    for ln in lines[2:]:
        if ln[:unit_at].strip() and len(ln) > unit_at:
            assert ln[unit_at - 2 : unit_at] == "  "  # the gap before the unit column
    maxes = [ln for ln in lines if "61.250" in ln or "15.000" in ln]
    ends = {ln.index("61.250") + 6 if "61.250" in ln else ln.index("15.000") + 6 for ln in maxes}
    assert len(ends) == 1  # right-aligned numbers end in one column
    # wrapped at words, each line as full as the column allows (28 characters here)
    assert lines[3].startswith("radial dimension |O2A| of ")
    assert lines[4] == "the cam measured from its"


def test_key_values_wrap_under_their_value_column() -> None:
    out = io.StringIO()
    long = "rise 22 mm cycloidal 0-120°, dwell 120-190°, return 22 mm cycloidal 190-290°"
    Terminal(out, width=50).key_values([("follower", "translating"), ("motion", long)])
    lines = out.getvalue().splitlines()
    assert lines[0].startswith("follower  translating")
    assert all(len(ln) <= 50 for ln in lines)
    value_at = lines[0].index("translating")
    assert all(ln[:value_at].strip() == "" for ln in lines[2:])  # continuation indented


def test_colour_only_when_asked() -> None:
    out = io.StringIO()
    Terminal(out, width=80, colour=True).paragraph("FAIL", "red")
    assert out.getvalue() == "\x1b[31mFAIL\x1b[0m\n"
    out = io.StringIO()
    Terminal(out, width=80).paragraph("FAIL", "red")  # a StringIO is not a terminal
    assert out.getvalue() == "FAIL\n"


def test_paragraphs_wrap_at_words_and_keep_their_own_lines() -> None:
    out = io.StringIO()
    Terminal(out, width=30).paragraph("one two three four five six seven eight\nnine")
    assert out.getvalue().splitlines() == ["one two three four five six", "seven eight", "nine"]


def test_a_pipe_is_80_columns_wide() -> None:
    assert Terminal(io.StringIO()).width == 80
