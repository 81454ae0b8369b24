"""Every command's ``--json`` output validates against its shipped JSON Schema (issue 13.6).

The commands are enumerated from the CLI: a command with a ``--json`` flag but no schema
file in ``camtol/data/schemas`` or no invocation in tests/cli/json_invocations.py fails.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from importlib.resources import files
from pathlib import Path
from typing import Any

import click
import pytest
from json_invocations import INVOCATIONS, prepare

from camtol import __version__
from camtol.cli.app import cli, main

jsonschema = pytest.importorskip("jsonschema")

SCHEMAS = files("camtol") / "data" / "schemas"


def _json_commands() -> list[str]:
    """Commands with --json, a group's subcommands as "group sub" (e.g. "records list")."""
    ctx = click.Context(cli)
    out = []
    for name in cli.list_commands(ctx):
        cmd = cli.get_command(ctx, name)
        assert cmd is not None
        subs = (
            [(f"{name} {s}", cmd.get_command(ctx, s)) for s in cmd.list_commands(ctx)]
            if isinstance(cmd, click.Group)
            else [(name, cmd)]
        )
        for full, sub in subs:
            assert sub is not None
            if any("--json" in getattr(p, "opts", ()) for p in sub.params):
                out.append(full)
    return out


COMMANDS = _json_commands()


def test_the_cli_has_json_commands() -> None:
    assert {"analyze", "conjugate", "size", "verify", "records list", "records stats"} <= set(
        COMMANDS
    )


@pytest.fixture(scope="module")
def subs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    tmp = tmp_path_factory.mktemp("json")
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return prepare(str(tmp))


def _keys(obj: Any) -> set[str]:
    if isinstance(obj, dict):
        return set(obj) | {k for v in obj.values() for k in _keys(v)}
    if isinstance(obj, list):
        return {k for v in obj for k in _keys(v)}
    return set()


@pytest.mark.parametrize("command", COMMANDS)
def test_json_output_matches_schema(command: str, subs: dict[str, str]) -> None:
    if command.startswith("records "):
        pytest.importorskip("sqlalchemy", reason="the store needs camtol[store] (SQLAlchemy)")
    schema_file = SCHEMAS / f"{command.replace(' ', '-')}.schema.json"
    assert schema_file.is_file(), f"`camtol {command} --json` has no schema {schema_file}"
    assert command in INVOCATIONS, f"no invocation of `camtol {command} --json` to validate"
    schema = json.loads(schema_file.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    for args in INVOCATIONS[command]:
        argv = [a.format(**subs) for a in args]
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            code = main(argv)
        assert code in (0, 1), (argv, code)
        text = out.getvalue()
        data = json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in strict JSON"))
        errors = [f"{list(e.absolute_path)}: {e.message}" for e in validator.iter_errors(data)]
        assert not errors, f"{' '.join(argv)}:\n" + "\n".join(errors[:10])
        assert list(data)[:3] == ["schema_version", "command", "camtol_version"]
        assert data["command"] == command and data["camtol_version"] == __version__
        assert all(k.isascii() for k in _keys(data)), "keys are ASCII"
        assert not re.search(r"\d\.\d*9{8,}\d|\d\.\d*0{8,}[1-9]", text), "floats rounded"


def test_analyze_keys_are_snake_case_with_numbers(subs: dict[str, str]) -> None:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        assert main(INVOCATIONS["analyze"][4]) == 0  # the conjugate pair: nested cams
    data = json.loads(out.getvalue())
    bad = [k for k in _keys(data) if not re.fullmatch(r"[a-z][a-z0-9_]*", k)]
    assert not bad, bad
    params = data["design"]["parameters"].values()
    assert all(v is None or isinstance(v, (int, float)) for v in params)


def test_schemas_are_package_data() -> None:
    text = (Path(__file__).resolve().parents[2] / "pyproject.toml").read_text()
    assert "data/schemas/*.schema.json" in text


@pytest.mark.parametrize("command", ["analyze", "allocate", "report"])
def test_accuracy_beyond_the_grade_table_and_not_assessed_match_the_schema(command: str) -> None:
    # A worst case finer than IT01 has no lower grade, one coarser than IT18 no upper
    # grade, and a design without tolerances no grade at all: each is valid output.
    from camtol.iso286 import GradeBracket
    from camtol.report.tables import accuracy_json

    schema = json.loads((SCHEMAS / f"{command}.schema.json").read_text(encoding="utf-8"))
    # a command whose document has several shapes (a single cam, a conjugate pair)
    properties = (
        schema["$defs"]["single_cam"]["properties"] if "$defs" in schema else schema["properties"]
    )
    validator = jsonschema.Draft202012Validator(properties["accuracy"])
    cases = [
        GradeBracket(None, "IT01", None, 0.6),
        GradeBracket("IT18", None, 3900.0, None),
        GradeBracket("IT7", "IT8", 21.0, 33.0),
        None,
    ]
    for b in cases:
        data = accuracy_json(b)
        errors = [e.message for e in validator.iter_errors(data)]
        assert not errors, (b, errors)
    assert accuracy_json(None) == {
        "lower_grade": None,
        "lower_um": None,
        "upper_grade": None,
        "upper_um": None,
        "text": "not assessed: the design gives no tolerances",
    }


_EVERY_EXAMPLE = {  # cheap commands whose keys depend on the follower: every example
    "analyze": ["--step", "1"],
    "verify": ["--step", "2"],
    "size": [],
    "precision": ["--decimals", "4"],
    "cut": ["--cut-step", "2"],
}


@pytest.mark.parametrize("command", sorted(_EVERY_EXAMPLE))
def test_every_example_matches_the_schema(command: str) -> None:
    # Keys carry units (um or deg) and a conjugate pair adds cam B's: the hand-picked
    # invocations missed four such outputs once; every built-in example covers them.
    from camtol.config.design_file import example_names

    schema = json.loads((SCHEMAS / f"{command}.schema.json").read_text(encoding="utf-8"))
    validator = jsonschema.Draft202012Validator(schema)
    for name in example_names():
        argv = [command, "-e", name, *_EVERY_EXAMPLE[command], "--json"]
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            code = main(argv)
        assert code in (0, 1), argv
        errors = [
            f"{list(e.absolute_path)}: {e.message}"
            for e in validator.iter_errors(json.loads(out.getvalue()))
        ]
        assert not errors, f"{' '.join(argv)}:\n" + "\n".join(errors[:5])
