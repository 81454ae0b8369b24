"""Lazy imports: ``import camtol`` and ``camtol --help`` stay light (issue 8, speed).

Speed itself is measured by ``bench/run.py``; these tests check the mechanism (which
modules a fresh interpreter has imported), not a time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import camtol
from camtol.cli.app import LAZY_COMMANDS, cli, main
from camtol.cli.commands import short_help as make_default_short_help

SRC = str(Path(camtol.__file__).resolve().parent.parent)
HEAVY = [
    "numpy",
    "scipy",
    "matplotlib",
    "rich",
    "camtol.analysis.result",
    "camtol.config.design_file",
]


def _modules_after(code: str) -> set[str]:
    """Names in sys.modules after running ``code`` in a fresh interpreter."""
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run(
        [sys.executable, "-c", f"{code}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))"],
        capture_output=True,
        text=True,
        check=True,
        env=env,
    ).stdout
    return set(json.loads(out.splitlines()[-1]))


@pytest.mark.parametrize(
    "code",
    [
        "import camtol",
        "import camtol.cli.app",
        "from camtol.cli.app import main\nmain(['--help'])",
        "from camtol.cli.app import main\nmain(['examples'])",
    ],
)
def test_light_entry_points_import_no_heavy_module(code: str) -> None:
    loaded = _modules_after(code)
    assert "camtol" in loaded
    assert sorted(m for m in HEAVY if m in loaded) == []


def test_public_names_resolve_lazily() -> None:
    from camtol.analysis.result import analyse
    from camtol.config.design_file import load_example

    assert camtol.analyse is analyse
    assert camtol.load_example is load_example
    assert set(camtol.__all__) <= set(dir(camtol))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        camtol.nope  # noqa: B018


@pytest.mark.parametrize("name", sorted(LAZY_COMMANDS))
def test_lazy_short_help_is_the_commands_own(name: str) -> None:
    import importlib

    module, attr, summary = LAZY_COMMANDS[name]
    command = getattr(importlib.import_module(module), attr)
    for limit in (30, 45, 200):
        assert make_default_short_help(summary, limit) == command.get_short_help_str(limit)


def test_help_lists_every_command(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    names = set(cli.list_commands(None))  # type: ignore[arg-type]
    assert {"analyze", "examples", *LAZY_COMMANDS} <= names
    table = out.split("Commands:")[1].splitlines()
    listed = {line.split()[0] for line in table if line.startswith("  ") and line[2] != " "}
    assert names <= listed
