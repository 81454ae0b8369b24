"""The ``camtol`` command group and its entry points (STYLE point 15).

It parses arguments, calls the public API, prints or writes, and maps camtol's errors to
one line on stderr. Exit codes: 0 ok, 1 out of tolerance (an inspected part fails), 2 usage
error, bad input or a design that cannot work. Files are written only after the analysis
succeeded, and atomically (no half-written output).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Mapping, Sequence
from typing import Any

import click

from camtol._version import __version__
from camtol.cli.commands import short_help
from camtol.cli.common import EXIT_OK, EXIT_USAGE, _Exit, _one_line

__all__ = ["cli", "console_main", "main"]


#: Other spellings accepted on the command line and not listed in the help (issue 8: one
#: spelling, ``analyze``, with the British ``analyse`` kept as an alias).
COMMAND_ALIASES: dict[str, str] = {"analyse": "analyze"}


class LazyGroup(click.Group):
    """A click group whose commands from other modules are imported only when run.

    ``camtol --help`` lists them from :data:`LAZY_COMMANDS` (module, attribute, short
    help) without importing their modules; a test checks that each short help is the
    command's own.
    """

    def __init__(
        self, *args: Any, lazy_commands: Mapping[str, tuple[str, str, str]], **kwargs: Any
    ) -> None:
        super().__init__(*args, **kwargs)
        self.lazy_commands = dict(lazy_commands)

    def list_commands(self, ctx: click.Context) -> list[str]:
        """Eager and lazy command names, sorted."""
        return sorted(set(super().list_commands(ctx)) | set(self.lazy_commands))

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        """Return a command, importing its module the first time it is asked for."""
        cmd_name = COMMAND_ALIASES.get(cmd_name, cmd_name)
        if cmd_name in self.lazy_commands and cmd_name not in self.commands:
            module, attr, _ = self.lazy_commands[cmd_name]
            self.add_command(getattr(importlib.import_module(module), attr), cmd_name)
        return super().get_command(ctx, cmd_name)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """Write the command table of ``--help`` without importing the lazy commands."""
        rows = []
        for name in self.list_commands(ctx):
            cmd = self.commands.get(name)
            if cmd is None:
                limit = formatter.width - 6 - len(name)
                rows.append((name, short_help(self.lazy_commands[name][2], limit)))
            elif not cmd.hidden:
                rows.append((name, cmd.get_short_help_str(formatter.width - 6 - len(name))))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


#: Commands living in their own modules: name -> (module, attribute, help summary, i.e.
#: the first paragraph of the command's docstring; tests/cli/test_lazy_commands.py checks it).
#: Registered in :func:`_register_subcommands`.
LAZY_COMMANDS: dict[str, tuple[str, str, str]] = {}


@click.group(
    cls=LazyGroup,
    lazy_commands=LAZY_COMMANDS,
    context_settings={"help_option_names": ["-h", "--help"]},
)
@click.version_option(__version__, prog_name="camtol")
def cli() -> None:
    """Precision disk cams: design, tolerance, inspection and manufacturing.

    Exit status: 0 ok, 1 out of tolerance, 2 usage error or invalid input/design.
    """


def _register_subcommands() -> None:
    """Add the commands that live in their own modules; each is imported when it runs."""
    from camtol.cli.commands import COMMANDS

    LAZY_COMMANDS.update(COMMANDS)
    cli.lazy_commands.update(LAZY_COMMANDS)


_register_subcommands()


def main(args: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status (0 ok, 1 out of tolerance, 2 usage).

    Parameters
    ----------
    args : sequence of str, optional
        Command-line arguments without the program name; by default ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status.
    """
    from camtol.textfile import tracking_inputs

    try:
        with tracking_inputs():
            cli.main(args=list(args) if args is not None else None, standalone_mode=False)
    except _Exit as e:
        return e.code
    except click.ClickException as e:
        click.echo(f"camtol: error: {_one_line(e.format_message())}", err=True)
        return EXIT_USAGE
    except click.exceptions.Abort:
        click.echo("camtol: aborted", err=True)
        return EXIT_USAGE
    except click.exceptions.Exit as e:
        return int(e.exit_code)
    return EXIT_OK


def console_main() -> None:
    """Entry point of the ``camtol`` console script."""
    sys.exit(main())
