"""The usage block of the README, generated from the command line itself.

``python -m camtol.cli.usage`` prints it; ``python -m camtol.cli.usage --write README.md``
replaces the block between the ``<!-- usage:begin -->`` and ``<!-- usage:end -->`` markers.
A test checks that the README agrees with the commands, so the two cannot drift apart.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import click

from camtol.cli.reference import metavar, root_command, walk

__all__ = ["BEGIN", "END", "usage_block", "write_readme"]

BEGIN = "<!-- usage:begin -->"
END = "<!-- usage:end -->"
_WIDTH = 92


def _piece(param: click.Parameter, ctx: click.Context) -> str | None:
    if isinstance(param, click.Argument):
        return None
    if not isinstance(param, click.Option) or param.hidden:
        return None
    names = sorted(param.opts, key=lambda o: (not o.startswith("--"), o))
    name = names[0]
    if name in ("--help", "-h") or name == "--example":
        return None
    text = name if param.is_flag else f"{name} {metavar(param, ctx)}"
    return text if param.required else f"[{text}]"


def _command_lines(path: str, cmd: click.Command, ctx: click.Context) -> list[str]:
    head = [path]
    args = [p for p in cmd.params if isinstance(p, click.Argument)]
    names = {o for p in cmd.params for o in getattr(p, "opts", ())}
    for a in args:
        meta = a.human_readable_name.upper()
        if a.name == "design" and "--example" in names:
            head.append(f"{meta}.toml | --example NAME")
        else:
            head.append(meta if a.required else f"[{meta}]")
    pieces = [p for p in (_piece(q, ctx) for q in cmd.params) if p]
    indent = " " * (len(path) + 1)
    lines = [" ".join(head)]
    for piece in pieces:  # wrap between options, never inside one
        if len(lines[-1]) + 1 + len(piece) > _WIDTH:
            lines.append(indent + piece)
        else:
            lines[-1] += " " + piece
    return lines


def usage_block() -> str:
    """Return the usage of every ``camtol`` command, one wrapped entry per command.

    Returns
    -------
    str
        Plain text, one line (or a few wrapped lines) per command and subcommand.
    """
    lines: list[str] = []
    for cmd, ctx in walk(*root_command()):
        if not isinstance(cmd, click.Group):
            lines += _command_lines(ctx.command_path, cmd, ctx)
        elif cmd.invoke_without_command:  # the group runs alone too (``camtol examples``)
            lines.append(ctx.command_path)
    return "\n".join(lines) + "\n"


def write_readme(path: str | Path) -> bool:
    """Replace the usage block of a README; return True when it changed.

    Parameters
    ----------
    path : str or Path
        README with the markers :data:`BEGIN` and :data:`END` around a ```text block.

    Returns
    -------
    bool
        Whether the file was rewritten.
    """
    p = Path(path)
    text = p.read_text(encoding="utf-8")
    start, end = text.index(BEGIN) + len(BEGIN), text.index(END)
    new = text[:start] + "\n```text\n" + usage_block() + "```\n" + text[end:]
    if new == text:
        return False
    p.write_text(new, encoding="utf-8")
    return True


def _main(argv: Sequence[str]) -> int:
    if len(argv) == 2 and argv[0] == "--write":
        changed = write_readme(argv[1])
        print(f"{argv[1]}: {'updated' if changed else 'already up to date'}")  # noqa: T201
        return 0
    sys.stdout.write(usage_block())
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(_main(sys.argv[1:]))
