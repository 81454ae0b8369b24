"""docs/file-formats.md documents what the commands really write.

Every CSV column and every JSON key that a command writes for the built-in examples must
be named (in backticks) in docs/file-formats.md, so that a new output cannot land
undocumented. Templates in the page stand for families of names: ``dS_<source>_<u>``
matches ``dS_phi_um``. Columns per second (``_per_s``, ``_per_s2``, written when a design
gives a cam speed) are documented with their per-radian form.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path
from typing import Any

import pytest

from camtol.cli import main
from camtol.config import example_names

PAGE = Path(__file__).resolve().parent.parent / "docs" / "file-formats.md"


def _documented() -> tuple[set[str], list[re.Pattern[str]]]:
    text = re.sub(r"^```.*?^```", "", PAGE.read_text(encoding="utf-8"), flags=re.M | re.S)
    names = set(re.findall(r"`([^`\n]+)`", text))
    words = {w for n in names for w in re.split(r"[,\s{}\[\]]+", n) if w}
    templates = [  # a placeholder is one name chunk: dS_<source>_<u> matches dS_phi_um
        re.compile("".join(_chunk(part) for part in re.split(r"(<[^>]+>)", w)) + r"\Z")
        for w in words
        if "<" in w and not w.startswith("<")
    ]
    return words, templates


def _chunk(part: str) -> str:
    return "[A-Za-z0-9]+" if part.startswith("<") else re.escape(part)


def _is_documented(name: str) -> bool:
    words, templates = _documented()
    name = re.sub(r"_per_s(2?)$", r"_per_rad\1", name)
    return name in words or any(t.match(name) for t in templates)


def _run(args: list[str]) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(args)
    return code, out.getvalue()


def _keys(obj: Any, skip: frozenset[str] = frozenset({"parameters"})) -> set[str]:
    """Dict keys at every depth (the display-name keys of ``parameters`` excepted)."""
    if isinstance(obj, dict):
        found = set(obj)
        for k, v in obj.items():
            if k not in skip:
                found |= _keys(v, skip)
        return found
    if isinstance(obj, list):
        return {k for v in obj for k in _keys(v, skip)}
    return set()


def test_templates_match_families() -> None:
    assert _is_documented("dS_phi_um") and _is_documented("dA_rms_deg_per_rad2")
    assert _is_documented("dV_worst_um_per_s")
    assert not _is_documented("an_undocumented_column_mm")


@pytest.mark.parametrize("example", example_names())
def test_analyze_outputs_are_documented(example: str, tmp_path: Path) -> None:
    csv_path = tmp_path / "curves.csv"
    code, out = _run(["analyze", "--example", example, "--json", "--curves", str(csv_path)])
    assert code == 0
    header = csv_path.read_text(encoding="utf-8").splitlines()[0].split(",")
    missing = sorted(c for c in header if not _is_documented(c))
    assert not missing, f"analyze --curves columns not in docs/file-formats.md: {missing}"
    keys = _keys(json.loads(out))
    missing = sorted(k for k in keys if not _is_documented(k))
    assert not missing, f"analyze --json keys not in docs/file-formats.md: {missing}"


def test_conjugate_outputs_are_documented(tmp_path: Path) -> None:
    from camtol.inspection import simulate_record, write_indicator_csv

    record = tmp_path / "record.csv"
    write_indicator_csv(simulate_record(lambda t: 22.0 + 0.0 * t, revolutions=2), record)
    for extra in ([], ["--record", str(record)]):
        csv_path = tmp_path / "fixture.csv"
        args = ["conjugate", "--example", "cw11-conjugate", "--json", "--curves", str(csv_path)]
        code, out = _run(args + extra)
        assert code in (0, 1)
        header = csv_path.read_text(encoding="utf-8").splitlines()[0].split(",")
        missing = sorted(c for c in header if not _is_documented(c))
        assert not missing, f"conjugate --curves columns not documented: {missing}"
        missing = sorted(k for k in _keys(json.loads(out)) if not _is_documented(k))
        assert not missing, f"conjugate --json keys not documented: {missing}"


@pytest.mark.parametrize(
    "args",
    [
        ["verify", "--example", "cw06-translating", "--json"],
        ["verify", "--example", "cw11-conjugate", "--json", "--no-polyline"],
        ["size", "--example", "roller-translating", "--json"],
        ["profile", "--example", "roller-translating", "-o", "{tmp}/p.csv", "--json"],
        ["report", "--example", "cw06-translating", "-o", "{tmp}/r.html", "--json"],
    ],
    ids=lambda a: " ".join(a[:2]),
)
def test_other_json_outputs_are_documented(args: list[str], tmp_path: Path) -> None:
    code, out = _run([a.replace("{tmp}", str(tmp_path)) for a in args])
    assert code == 0
    missing = sorted(k for k in _keys(json.loads(out)) if not _is_documented(k))
    assert not missing, f"camtol {args[0]} --json keys not in docs/file-formats.md: {missing}"


def test_profile_csv_columns_are_documented(tmp_path: Path) -> None:
    path = tmp_path / "p.csv"
    assert _run(["profile", "--example", "cw11-conjugate", "-o", str(path), "--quiet"])[0] == 0
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    layers = {c.removesuffix("_x_mm").removesuffix("_y_mm").upper() for c in header[1:]}
    words, _ = _documented()
    missing = sorted(layer for layer in layers if layer not in words)
    assert header[0] == "theta_deg" and not missing, f"layers not documented: {missing}"
