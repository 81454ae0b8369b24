"""One CSV format for every numeric table camtol writes (camtol.report.csv_text)."""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from camtol.report.csv_text import csv_text


def test_numbers_ten_digits_and_no_negative_zero() -> None:
    data = np.array([[0.0, -0.0, 1.0 / 3.0], [-1e-300, 123456789012.5, -2.5]])
    text = csv_text(["theta_deg", "v_mm_per_rad", "dS_um"], data)
    assert text == (
        "theta_deg,v_mm_per_rad,dS_um\n"
        "0,0,0.3333333333\n"  # -0.0 is written as 0: no sign where there is none
        "-1e-300,1.23456789e+11,-2.5\n"  # .10g drops trailing zeros
    )
    rows = list(csv.reader(io.StringIO(text)))
    np.testing.assert_allclose(np.array(rows[1:], float), data + 0.0, rtol=1e-9)


def test_comment_digits_and_blank_nonfinite() -> None:
    data = np.array([[1.0 / 7.0, math.nan, math.inf]])
    text = csv_text(["a", "b", "c"], data, comment="camtol test", digits=12, blank_nonfinite=True)
    assert text == "# camtol test\na,b,c\n0.142857142857,,\n"


def test_header_names_are_quoted_as_csv_requires() -> None:
    text = csv_text(["x, mm", 'say "y"'], np.zeros((1, 2)))
    assert next(csv.reader(io.StringIO(text))) == ["x, mm", 'say "y"']
