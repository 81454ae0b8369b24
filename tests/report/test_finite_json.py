"""A NaN in a JSON output is an error naming its key path (issue 9); infinities pass."""

from __future__ import annotations

import math

import numpy as np
import pytest

from camtol.exceptions import OutputError
from camtol.report.finite import require_no_nan_json


@pytest.mark.parametrize(
    ("doc", "where"),
    [
        ({"a": {"b": [1.0, 2.0, math.nan]}}, "a.b[2] is nan"),
        ({"parts": [{"id": 1, "x": 0.5}, {"id": 2, "x": np.float64("nan")}]}, "parts[1].x is nan"),
        ({"curve": np.array([0.0, np.nan])}, "curve holds NaN"),
        ([("s", math.nan)], "[0][1] is nan"),
        (math.nan, "value is nan"),
    ],
)
def test_the_first_nan_is_named_by_its_key_path(doc: object, where: str) -> None:
    with pytest.raises(OutputError, match=r"^" + where.replace("[", r"\[").replace("]", r"\]")):
        require_no_nan_json(doc)


def test_infinities_strings_and_integers_pass() -> None:
    doc = {"x": math.inf, "y": [-math.inf, "nan", 3, True, None], "z": np.array([1.0, np.inf])}
    require_no_nan_json(doc)  # no error
    with pytest.raises(OutputError, match=r"^top\.k is nan"):
        require_no_nan_json({"k": math.nan}, "top")
