"""docs/file-formats.md documents what the commands really write.

Every CSV column and every JSON key that a command writes for the built-in examples must
be named (in backticks) in docs/file-formats.md, so that a new output cannot land
undocumented. Templates in the page stand for families of names: ``dS_<source>_<u>``
matches ``dS_phi_um``. Columns per second (``_per_s``, ``_per_s2``, written when a design
gives a cam speed) are documented with their per-radian form.
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import re
from pathlib import Path
from typing import Any

import pytest

from camtol.cli.app import main
from camtol.config.design_file import example_names

PAGE = Path(__file__).resolve().parent.parent / "docs" / "file-formats.md"


@functools.cache
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
    from camtol.pair.indicator import write_indicator_csv
    from camtol.pair.twin import simulate_record

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


def _csv_header(path: Path) -> list[str]:
    """The column names of a CSV file written by camtol (``#`` comment lines skipped)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    return next(ln for ln in lines if ln and not ln.startswith("#")).split(",")


def _undocumented(names: set[str] | list[str]) -> list[str]:
    return sorted(n for n in names if not _is_documented(n))


def test_cmm_outputs_are_documented(tmp_path: Path) -> None:
    # Issue 12: camtol simulate cmm (scan + .truth.json), simulate record, inspect
    # (--json, --curves, --motion, for a swing and a lift, with a motion spec) and
    # conjugate --cmm-a/--cmm-b (--json, --curves).
    a, b, rec = tmp_path / "a.csv", tmp_path / "b.csv", tmp_path / "rec.csv"
    for cam, path in (("A", a), ("B", b)):
        args = ["simulate", "cmm", "-e", "cw11-experiment", "-o", str(path), "--cam", cam]
        args += ["--error-rms-um", "20", "--outliers", "2", "--stylus-radius-mm", "1"]
        assert _run(args)[0] == 0
        assert not _undocumented(_csv_header(path)), _csv_header(path)
        truth = json.loads(path.with_name(path.stem + ".truth.json").read_text())
        assert not _undocumented(_keys(truth)), f"truth JSON: {_undocumented(_keys(truth))}"
    args = ["simulate", "record", "-e", "cw11-experiment", "-o", str(rec)]
    args += [
        "--truth-a",
        str(tmp_path / "a.truth.json"),
        "--truth-b",
        str(tmp_path / "b.truth.json"),
    ]
    assert _run(args)[0] == 0
    assert not _undocumented(_csv_header(rec)), f"record: {_undocumented(_csv_header(rec))}"
    lift = tmp_path / "lift.csv"
    assert _run(["simulate", "cmm", "-e", "roller-translating", "-o", str(lift)])[0] == 0
    runs = [
        ("cw11-experiment", a, ["--cam", "A", "--stylus-radius-mm", "1", "--spec-deg", "1"]),
        ("roller-translating", lift, ["--spec-um", "1000"]),
    ]
    for example, scan, extra in runs:
        curves, motion = tmp_path / "c.csv", tmp_path / "m.csv"
        args = ["inspect", "-e", example, "--points", str(scan), "--json", *extra]
        code, out = _run([*args, "--curves", str(curves), "--motion", str(motion)])
        assert code in (0, 1)
        for what, names in (
            ("--json", _keys(json.loads(out))),
            ("--curves", _csv_header(curves)),
            ("--motion", _csv_header(motion)),
        ):
            missing = _undocumented(names)
            assert not missing, f"inspect {what} of {example} not documented: {missing}"
    curves = tmp_path / "fixture.csv"
    args = ["conjugate", "-e", "cw11-experiment", "--record", str(rec), "--json"]
    args += ["--cmm-a", str(a), "--cmm-b", str(b), "--cmm-stylus-radius-mm", "1"]
    args += ["--cmm-datum", "centre:0,0,0", "--curves", str(curves)]
    code, out = _run(args)
    assert code in (0, 1)
    missing = _undocumented(_keys(json.loads(out))) + _undocumented(_csv_header(curves))
    assert not missing, f"conjugate --cmm-a/--cmm-b outputs not documented: {missing}"
