"""``camtol examples``: the built-in example designs, listed or printed as TOML."""

from __future__ import annotations

import click

from camtol.cli.common import EXIT_OK, _Exit, run_guarded

__all__ = ["examples"]


@click.group(invoke_without_command=True)
@click.pass_context
def examples(ctx: click.Context) -> None:
    """List the built-in example designs (`camtol examples show NAME` prints one)."""
    if ctx.invoked_subcommand is None:
        import textwrap

        from camtol.config.examples import example_names, example_summary

        for name in example_names():  # the summary wrapped under itself, 80 columns
            line = f"{name:18s} {example_summary(name)}"
            click.echo(textwrap.fill(line, 80, subsequent_indent=" " * 19))


@examples.command("show")
@click.argument("name")
def examples_show(name: str) -> None:
    """Print the TOML of a built-in example, to start a design from it."""

    def body() -> int:
        from camtol.config.examples import example_text

        click.echo(example_text(name), nl=False)
        return EXIT_OK

    raise _Exit(run_guarded(body))
