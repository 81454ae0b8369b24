"""Fuzz the command line (issue 9, "keep it fixed"); the property is in :mod:`fuzz_harness`.

Four strategies, each in a fast profile (every test run, a few dozen cases each) and a long
one (``pytest -m fuzz``, ``CAMTOL_FUZZ_EXAMPLES`` cases each, default 2500):

* every field of every built-in example mutated (delete, zero, negative, NaN, ±inf, huge,
  tiny, wrong type, wrong unit), run through every command;
* random designs of every follower type and motion law (the refused constant velocity and
  very short segments included); the accepted outputs are checked independently: no cusp or
  self-intersection in the exported profile, pressure angle below 90° recomputed from the
  exported pitch curve, no NaN in any output;
* random bytes and encodings of a design file;
* random command-line flags and option values.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Any

import pytest
from fuzz_harness import (
    COMMANDS,
    EXAMPLES,
    FAST_COMMANDS,
    MUTATIONS,
    example_mapping,
    example_text,
    judge,
    leaf_paths,
    mutate,
    problems_of,
    run_cli,
    run_design,
    to_toml,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

LONG = int(os.environ.get("CAMTOL_FUZZ_EXAMPLES", "2500"))
FAST = settings(
    max_examples=12,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    database=None,
)
LONG_SETTINGS = settings(
    max_examples=LONG,
    deadline=None,
    derandomize=False,
    suppress_health_check=list(HealthCheck),
    database=None,
    print_blob=True,
)

_PATHS = {name: leaf_paths(example_mapping(name)) for name in EXAMPLES}


# --- strategies ------------------------------------------------------------------------------
@st.composite
def mutated_example(draw: st.DrawFn) -> tuple[str, str, str]:
    """(description, TOML text, command): one to three fields of an example mutated."""
    name = draw(st.sampled_from(EXAMPLES))
    doc = example_mapping(name)
    what = []
    for _ in range(draw(st.integers(1, 3))):
        paths = leaf_paths(doc)
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        kind = draw(st.sampled_from(MUTATIONS))
        doc = mutate(doc, path, kind)
        what.append(f"{'.'.join(map(str, path))}:{kind}")
    command = draw(st.sampled_from(COMMANDS))
    return f"{name} {' '.join(what)}", to_toml(doc), command


def _segments(draw: st.DrawFn, unit: str, travel: float) -> list[dict[str, Any]]:
    laws = [
        "cycloidal",
        "simple_harmonic",
        "polynomial_345",
        "polynomial_4567",
        "modified_trapezoid",
        "modified_sine",
        "modified_constant_velocity",
        "constant_velocity",  # refused by name (issue 32): the refusal is fuzzed too
    ]
    n_moves = draw(st.sampled_from([2, 2, 3]))
    heights = [draw(st.floats(0.05, 1.0)) * travel for _ in range(n_moves - 1)]
    heights.append(sum(heights))
    kinds = ["rise"] * (n_moves - 1) + ["return"]
    # Cut 0..360 into moves with optional dwells; some pieces very short.
    pieces = []
    for _ in range(n_moves):
        pieces.append(("move", draw(st.sampled_from([1e-6, 0.01, 1.0, 5.0, 30.0, 60.0, 120.0]))))
        if draw(st.booleans()):
            pieces.append(("dwell", draw(st.floats(1e-3, 90.0))))
    total = sum(w for _, w in pieces)
    scale = 360.0 / total
    segs, start, move = [], 0.0, 0
    for i, (kind, w) in enumerate(pieces):
        end = 360.0 if i == len(pieces) - 1 else start + w * scale
        if kind == "dwell":
            segs.append({"kind": "dwell", "start_deg": start, "end_deg": end})
        else:
            segs.append(
                {
                    "kind": kinds[move],
                    "law": draw(st.sampled_from(laws)),
                    "start_deg": start,
                    "end_deg": end,
                    f"lift_{unit}": heights[move],
                }
            )
            move += 1
        start = end
    return segs


@st.composite
def random_design(draw: st.DrawFn) -> tuple[str, str]:
    """(description, TOML text) of a random design of a random follower type."""
    name = draw(st.sampled_from(EXAMPLES))
    doc = example_mapping(name)
    follower = doc["follower"]
    for key, value in list(follower.items()):
        if isinstance(value, float | int) and not isinstance(value, bool):
            factor = draw(st.sampled_from([0.2, 0.5, 0.8, 1.0, 1.0, 1.25, 2.0, 5.0]))
            follower[key] = float(value) * factor
    oscillating = follower["type"] in ("flat_oscillating", "roller_oscillating", "conjugate")
    unit = "deg" if oscillating else "mm"
    travel = (
        draw(st.sampled_from([1.0, 10.0, 30.0, 60.0]))
        if oscillating
        else draw(st.sampled_from([0.5, 5.0, 20.0, 60.0]))
    )
    doc["motion"] = {"segments": _segments(draw, unit, travel)}
    return f"{name} {follower} {doc['motion']}", to_toml(doc)


ENCODINGS = ["utf-8", "utf-8-sig", "utf-16", "utf-16-le", "utf-32", "latin-1", "cp1252"]


@st.composite
def design_bytes(draw: st.DrawFn) -> bytes:
    """Random bytes, or an example in a random encoding, perhaps damaged."""
    choice = draw(st.integers(0, 3))
    if choice == 0:
        return draw(st.binary(max_size=400))
    text = example_text(draw(st.sampled_from(EXAMPLES)))
    if draw(st.booleans()):
        text = text.replace('name = "', 'name = "Übergröße ', 1)
    data = text.encode(draw(st.sampled_from(ENCODINGS)), errors="replace")
    if choice == 2:  # truncate
        data = data[: draw(st.integers(0, len(data)))]
    if choice == 3:  # overwrite a byte
        i = draw(st.integers(0, len(data) - 1))
        data = data[:i] + bytes([draw(st.integers(0, 255))]) + data[i + 1 :]
    return data


NUMBERS = ["0", "-1", "nan", "inf", "-inf", "1e-9", "1e-300", "1e300", "abc", "7", "0.1", "45"]
FORMULAS = [
    "1.2.3 um",
    ".",
    "..",
    "+" * 20000 + "1",
    "-" * 100000 + "1",
    "(" * 500 + "1" + ")" * 500,
    "22 um",
    "3*sin(theta)",
    "__import__('os')",
    "1e400",
    "theta_deg/0",
    "",
]


@st.composite
def flag_line(draw: st.DrawFn, tmp: Path) -> list[str]:
    """A command line with random options and values (files inside ``tmp``)."""
    design = tmp / "d.toml"
    command = draw(st.sampled_from(["analyze", "profile", "report", "verify", "conjugate"]))
    args = [command]
    source = draw(st.sampled_from(["example", "file", "both", "none", "missing", "dir"]))
    example = draw(st.sampled_from([*EXAMPLES, "nope"]))
    if source in ("example", "both"):
        args += ["--example", example]
    if source in ("file", "both"):
        args.append(str(design))
    if source == "missing":
        args.append(str(tmp / "missing.toml"))
    if source == "dir":
        args.append(str(tmp))
    outs = [
        str(tmp / "o.csv"),
        str(tmp / "o.dxf"),
        str(tmp / "o.svg"),
        str(tmp / "o.html"),
        str(tmp / "o.png"),
        str(tmp / "o.txt"),
        str(tmp),
        str(design),
        str(tmp / "m.csv"),
        str(tmp / "nodir" / "o.csv"),
        "/proc/x.dxf",
    ]
    options = {
        "analyze": ["--step", "--curves", "--plot", "--plot-angle", "--json", "--quiet"],
        "profile": ["-o", "--tolerance", "--cutter-radius", "--json", "--quiet"],
        "report": ["-o", "--step", "--json", "--quiet"],
        "verify": ["--step", "--json", "--no-polyline", "--quiet"],
        "conjugate": ["--df-mea", "--record", "--master-a", "--step", "--curves", "--json"],
    }[command]
    for opt in draw(st.lists(st.sampled_from(options), max_size=4)):
        if opt in ("--json", "--quiet", "--no-polyline"):
            args.append(opt)
        elif opt in ("-o", "--curves", "--plot"):
            args += [opt, draw(st.sampled_from(outs))]
        elif opt in ("--df-mea", "--master-a", "--record"):
            args += [opt, draw(st.sampled_from([*FORMULAS, str(tmp / "m.csv"), str(design)]))]
        else:
            args += [opt, draw(st.sampled_from(NUMBERS))]
    if command in ("profile", "report") and "-o" not in args and draw(st.booleans()):
        args += ["-o", str(tmp / ("o.csv" if command == "profile" else "o.html"))]
    if command in ("verify", "analyze", "report") and "--step" not in args:
        args += ["--step", "2"]  # keep the fuzz fast (validity does not depend on it)
    return args


def flag_inputs(args: list[str], tmp: Path) -> set[str]:
    """Names of the files in ``tmp`` that the command line reads (never to be modified)."""
    used = set()
    for i, a in enumerate(args):
        prev = args[i - 1] if i else ""
        if prev in ("-o", "--curves", "--plot"):
            continue
        if prev.startswith("--") and prev not in ("--df-mea", "--record", "--master-a"):
            continue
        p = Path(a)
        if p.parent == tmp and p.exists() and p.is_file():
            used.add(p.name)
    return used


def _flag_outputs(args: list[str]) -> dict[str, Path]:
    out = {}
    for opt in ("-o", "--curves"):
        if opt in args:  # the last occurrence wins (click)
            p = Path(args[len(args) - 1 - args[::-1].index(opt) + 1])
            if p.suffix == ".csv":
                out["profile" if args[0] == "profile" else "curves"] = p
    return out


# --- properties ------------------------------------------------------------------------------
def check_mutated(case: tuple[str, str, str]) -> None:
    what, text, command = case
    problems = problems_of(run_design(text, command))
    assert not problems, f"{what}: {problems}"


def check_random_design(case: tuple[str, str], commands: tuple[str, ...]) -> None:
    what, text = case
    for command in commands:
        problems = problems_of(run_design(text, command))
        assert not problems, f"{what}: {problems}"


def check_bytes(data: bytes) -> None:
    outcomes = run_design(data, "analyze")
    problems = problems_of(outcomes)
    assert not problems, f"{data[:80]!r}: {problems}"


def check_flags(draw_args: Any) -> None:
    with tempfile.TemporaryDirectory(prefix="camtol-fuzz-") as d:
        tmp = Path(d)
        (tmp / "d.toml").write_text(example_text("cw11-conjugate"), encoding="utf-8")
        (tmp / "m.csv").write_text("theta_deg,um\n0,20\n180,22\n", encoding="utf-8")
        before = {p.name: p.read_bytes() for p in tmp.iterdir()}
        args = draw_args(tmp)
        o = run_cli(args, _flag_outputs(args))
        problems = judge(o)
        for name, content in before.items():
            if name in flag_inputs(args, tmp) and (tmp / name).read_bytes() != content:
                problems.append(f"input {name} was modified")
        assert not problems, f"{args}: {problems}"


# --- fast profile (every test run) -------------------------------------------------------------
@FAST
@given(mutated_example())
def test_mutated_examples(case: tuple[str, str, str]) -> None:
    check_mutated(case)


@FAST
@given(random_design())
def test_random_designs(case: tuple[str, str]) -> None:
    check_random_design(case, FAST_COMMANDS[:2])


@FAST
@given(design_bytes())
def test_random_bytes(data: bytes) -> None:
    check_bytes(data)


@FAST
@given(st.data())
def test_cli_flags(data: st.DataObject) -> None:
    check_flags(lambda tmp: data.draw(flag_line(tmp)))


# --- long profile (pytest -m fuzz) ---------------------------------------------------------------
@pytest.mark.fuzz
@LONG_SETTINGS
@given(mutated_example())
def test_long_mutated_examples(case: tuple[str, str, str]) -> None:
    check_mutated(case)


@pytest.mark.fuzz
@LONG_SETTINGS
@given(random_design())
def test_long_random_designs(case: tuple[str, str]) -> None:
    check_random_design(case, COMMANDS[:3])


@pytest.mark.fuzz
@LONG_SETTINGS
@given(design_bytes())
def test_long_random_bytes(data: bytes) -> None:
    check_bytes(data)


@pytest.mark.fuzz
@LONG_SETTINGS
@given(st.data())
def test_long_cli_flags(data: st.DataObject) -> None:
    check_flags(lambda tmp: data.draw(flag_line(tmp)))
