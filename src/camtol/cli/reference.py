"""The Commands page of the documentation, generated from the real command tree.

``docs/commands.md`` holds the marker :data:`MARKER`; the site's hook (docs/_hooks.py)
replaces it with :func:`commands_markdown`. The commands are read through the group's own
``list_commands``/``get_command``, so the lazily registered ones (cli/commands.py) are
imported and documented like the others, and every default is the one click applies
(``--help`` and this page cannot drift apart). A test renders the page through the hook
and fails when a command or subcommand is missing.

Why not mkdocs-click: it documents a group from its ``commands`` attribute as soon as one
command is loaded (so a lazy group showed 2 of its commands), and prints click 8.2's
"no default" marker as ``Sentinel.UNSET``.
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Iterator
from typing import Any

import click

__all__ = ["MARKER", "command_paths", "commands_markdown", "metavar", "root_command", "walk"]

#: The line of docs/commands.md that the hook replaces with the generated reference.
MARKER = "<!-- commands:reference -->"


def walk(cmd: click.Command, ctx: click.Context) -> Iterator[tuple[click.Command, click.Context]]:
    """Yield every visible command below ``cmd`` (depth first, sorted) with its context.

    Parameters
    ----------
    cmd : click.Command
        A group (a plain command has nothing below it).
    ctx : click.Context
        Its context.
    """
    if not isinstance(cmd, click.Group):
        return
    for name in cmd.list_commands(ctx):
        sub = cmd.get_command(ctx, name)
        if sub is None or sub.hidden:
            continue
        sub_ctx = click.Context(sub, info_name=name, parent=ctx)
        yield sub, sub_ctx
        yield from walk(sub, sub_ctx)


def root_command() -> tuple[click.Command, click.Context]:
    """Return the ``camtol`` group and its context (the top of the command tree)."""
    from camtol.cli.app import cli

    return cli, click.Context(cli, info_name="camtol")


def command_paths() -> list[str]:
    """Return the path of every command and subcommand, e.g. ``camtol records list``.

    Returns
    -------
    list of str
        Command paths, in the order of the page.
    """
    root, ctx = root_command()
    return [c.command_path for _, c in walk(root, ctx)]


def _escape(text: str) -> str:
    """Escape what Markdown would read as markup in plain help text (code spans kept)."""
    parts = re.split(r"(`[^`]*`)", text)
    out = []
    for part in parts:
        if part.startswith("`"):
            out.append(part)
        else:
            part = part.replace("\\", "\\\\").replace("<", "&lt;")
            out.append(re.sub(r"([*_|\[\]])", r"\\\1", part))
    return "".join(out)


def _description(help_text: str | None) -> list[str]:
    """Return the command's help as Markdown paragraphs (click's no-rewrap blocks verbatim)."""
    if not help_text:
        return []
    lines: list[str] = []
    for para in re.split(r"\n\s*\n", inspect.cleandoc(help_text)):
        if para.lstrip().startswith("\b"):
            body = para.lstrip()[1:].strip("\n")
            lines += ["```text", *body.splitlines(), "```", ""]
        else:
            lines += [_escape(" ".join(para.split())), ""]
    return lines


def metavar(param: click.Parameter, ctx: click.Context) -> str:
    """Return an option's metavar as ``--help`` shows it (click 8.1 and 8.2 alike).

    Parameters
    ----------
    param : click.Parameter
        The option.
    ctx : click.Context
        Its command's context.
    """
    make: Any = param.make_metavar  # its signature changed in click 8.2
    try:
        return str(make(ctx))
    except TypeError:  # pragma: no cover - click 8.1 takes no context
        return str(make())


def _type(param: click.Option, ctx: click.Context) -> str:
    if param.is_flag:
        return "flag"
    kind = param.type
    if isinstance(kind, click.Choice):
        return " \\| ".join(f"`{c}`" for c in kind.choices)
    if isinstance(kind, (click.IntRange, click.FloatRange)):
        lo, hi = kind.min, kind.max
        bounds = [f"≥ {lo}" if lo is not None else "", f"≤ {hi}" if hi is not None else ""]
        return f"{kind.name} ({', '.join(b for b in bounds if b)})"
    return _escape(metavar(param, ctx).strip("[]."))


def _unset(value: object) -> bool:
    """Tell "no default": None, click 8.2's UNSET sentinel, or an empty multiple."""
    return value is None or type(value).__name__ == "Sentinel" or value == ()


def _default(param: click.Option, ctx: click.Context) -> str:
    """Return the default as the user gets it, or "required" / "—" (none)."""
    if param.required:
        return "required"
    if isinstance(param.show_default, str):
        return _escape(param.show_default)
    value = param.get_default(ctx, call=False)
    if callable(value):
        return "computed"
    if param.is_flag and param.secondary_opts:  # --x/--no-x: name the one that is default
        return f"`{(param.opts if value else param.secondary_opts)[0]}`"
    if param.is_flag and not param.is_bool_flag:  # flag_value options: off unless given
        return "—"
    if param.is_flag:
        return "on" if value else "off"
    if _unset(value):
        return "—"
    if isinstance(value, (list, tuple)):
        return ", ".join(f"`{v}`" for v in value)
    return f"`{value}`"


def _options_table(cmd: click.Command, ctx: click.Context) -> list[str]:
    rows = []
    for param in cmd.get_params(ctx):
        if not isinstance(param, click.Option) or param.hidden:
            continue
        if "--help" in param.opts:
            continue
        names = ", ".join(f"`{o}`" for o in param.opts)
        if param.secondary_opts:
            names += " / " + ", ".join(f"`{o}`" for o in param.secondary_opts)
        text = _escape(" ".join((param.help or "").split())) or "—"
        rows.append(f"| {names} | {_type(param, ctx)} | {text} | {_default(param, ctx)} |")
    if not rows:
        return []
    head = ["**Options**", "", "| Option | Value | Description | Default |", "|---|---|---|---|"]
    return [*head, *rows, ""]


def _section(cmd: click.Command, ctx: click.Context) -> list[str]:
    depth = ctx.command_path.count(" ") + 1  # camtol cut: ##, camtol records list: ###
    lines = [f"{'#' * depth} {ctx.command_path}", ""]
    lines += _description(cmd.help)
    usage = " ".join(cmd.collect_usage_pieces(ctx))
    lines += [f"**Usage:** `{ctx.command_path} {usage}`", ""]
    if isinstance(cmd, click.Group):
        lines += ["**Subcommands**", ""]
        for sub, sub_ctx in walk(cmd, ctx):
            if sub_ctx.parent is ctx:
                anchor = sub_ctx.command_path.replace(" ", "-")
                short = _escape(sub.get_short_help_str(limit=120))
                lines.append(f"- [`{sub_ctx.info_name}`](#{anchor}): {short}")
        lines.append("")
    lines += _options_table(cmd, ctx)
    return lines


def commands_markdown() -> str:
    """Return the Markdown reference of every command and subcommand of ``camtol``.

    An index (one line per command, linked), then per command its help, usage line and a
    table of its options with the defaults click applies.

    Returns
    -------
    str
        Markdown for docs/commands.md.
    """
    root, ctx = root_command()
    commands = list(walk(root, ctx))
    lines = ["| Command | What it does |", "|---|---|"]
    for cmd, sub_ctx in commands:
        anchor = sub_ctx.command_path.replace(" ", "-")
        short = _escape(cmd.get_short_help_str(limit=120))
        lines.append(f"| [`{sub_ctx.command_path}`](#{anchor}) | {short} |")
    lines.append("")
    lines += _options_table(root, ctx)
    for cmd, sub_ctx in commands:
        lines += _section(cmd, sub_ctx)
    return "\n".join(lines) + "\n"
