"""The table reader's additions for long files and mixed columns (issue 9 item 13)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import camtol.tables
from camtol.exceptions import InputFileError
from camtol.tables import parse_table, read_table


def test_ignore_other_columns_reads_only_the_named_ones() -> None:
    text = "x_mm; label; y_mm\n1; a; 2\n3; b; 4\n"
    t = parse_table(text, required=["x_mm", "y_mm"], ignore_other_columns=True)
    assert t.names == ("x_mm", "y_mm")
    np.testing.assert_array_equal(t.data, [[1.0, 2.0], [3.0, 4.0]])
    with pytest.raises(InputFileError, match="line 2, column label: 'a' is not a number"):
        parse_table(text, required=["x_mm", "y_mm"])  # by default every column is numeric
    with pytest.raises(InputFileError, match="line 3, column y_mm: 'z' is not a number"):
        parse_table(
            "x_mm,label,y_mm\n1,a,2\n3,b,z\n",
            required=["x_mm"],
            optional=["y_mm"],
            ignore_other_columns=True,
        )


def test_streaming_path_matches_and_falls_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    p = tmp_path / "t.csv"
    rows = np.column_stack([np.arange(2000.0), np.arange(2000.0) ** 0.5])
    body = "\n".join(f"{a:g},{b:.17g}" for a, b in rows)
    p.write_text("# comment\ntheta_deg,dr_um\n" + body + "\n")
    whole = read_table(p, required=["theta_deg", "dr_um"])
    monkeypatch.setattr(camtol.tables, "_KEEP_TEXT_CHARS", 16)
    streamed = read_table(p, required=["theta_deg", "dr_um"])
    np.testing.assert_array_equal(streamed.data, whole.data)
    assert streamed.line_of(5) == 8  # line numbers are still found (file read again)
    # more comment lines than the head holds: read whole instead, same numbers
    monkeypatch.setattr(camtol.tables, "_HEAD_BYTES", 8)
    np.testing.assert_array_equal(read_table(p, required=["theta_deg"]).data, whole.data)
