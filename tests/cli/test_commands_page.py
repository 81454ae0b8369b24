"""The Commands page of the documentation shows every command, with real defaults (issue 32).

The page is rendered the way the site builds it: docs/commands.md through the hook of
docs/_hooks.py, then Markdown with the site's table and toc extensions; the command tree
is walked independently here, so a command missing from the page fails the test.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path
from typing import Any

import click
import pytest

from camtol.cli.app import cli
from camtol.cli.commands import COMMANDS

DOCS = Path(__file__).resolve().parents[2] / "docs"


def _hooks() -> Any:
    spec = importlib.util.spec_from_file_location("docs_hooks", DOCS / "_hooks.py")
    assert spec is not None and spec.loader is not None
    hooks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hooks)
    return hooks


def _tree() -> dict[str, click.Command]:
    """Every command path of the real tree, walked here (not by the generator)."""
    out: dict[str, click.Command] = {}

    def walk(group: click.Group, ctx: click.Context) -> None:
        for name in group.list_commands(ctx):
            cmd = group.get_command(ctx, name)
            assert cmd is not None, name
            sub = click.Context(cmd, info_name=name, parent=ctx)
            out[sub.command_path] = cmd
            if isinstance(cmd, click.Group):
                walk(cmd, sub)

    walk(cli, click.Context(cli, info_name="camtol"))
    return out


@pytest.fixture(scope="module")
def page_html() -> str:
    markdown = pytest.importorskip("markdown")  # installed with MkDocs (the docs extra)

    class File:
        src_uri = "commands.md"

    class Page:
        file = File()

    text = (DOCS / "commands.md").read_text(encoding="utf-8")
    rendered = _hooks().on_page_markdown(text, page=Page(), config=None, files=None)
    html: str = markdown.markdown(rendered, extensions=["tables", "toc", "attr_list"])
    return html


def test_every_command_and_subcommand_has_a_section(page_html: str) -> None:
    tree = _tree()
    assert set(COMMANDS) <= {p.split()[1] for p in tree}  # the lazy ones are in the tree
    assert {"camtol records list", "camtol simulate cmm", "camtol examples show"} <= set(tree)
    ids = set(re.findall(r'<h[2-4] id="(camtol-[a-z-]+)"', page_html))
    missing = sorted(p for p in tree if p.replace(" ", "-") not in ids)
    assert not missing, f"commands missing from the Commands page: {missing}"


def test_every_option_is_listed_with_its_real_default(page_html: str) -> None:
    assert "Sentinel" not in page_html and "UNSET" not in page_html
    tree = _tree()
    cut = page_html.split('id="camtol-cut"')[1].split("<h2")[0]
    assert "<code>--cut-step</code>" in cut
    # the default the command applies, read from click (not typed into the test)
    default = next(p for p in tree["camtol cut"].params if p.name == "cut_steps_text").default
    assert f"<code>{default}</code>" in cut
    for path, cmd in tree.items():
        section = page_html.split(f'id="{path.replace(" ", "-")}"')[1]
        section = re.split(r"<h[2-4] ", section)[0]
        for param in cmd.params:
            if isinstance(param, click.Option) and not param.hidden:
                assert f"<code>{param.opts[0]}</code>" in section, (path, param.opts[0])


def test_the_hook_refuses_a_page_without_the_marker() -> None:
    class File:
        src_uri = "commands.md"

    class Page:
        file = File()

    with pytest.raises(ValueError, match="marker"):
        _hooks().on_page_markdown("# Commands\n", page=Page())
