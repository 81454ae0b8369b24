"""The ``camtol`` command: a thin layer over the library (STYLE point 15).

It parses arguments, calls the public API, prints or writes, and maps camtol's errors to
one line on stderr. Exit codes: 0 ok, 1 out of tolerance (an inspected part fails), 2 usage
error, bad input or a design that cannot work. Files are written only after the analysis
succeeded, and atomically (no half-written output).
"""

from __future__ import annotations

import importlib
import json
import math
import sys
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

import click
from click.utils import make_default_short_help

from camtol import __version__
from camtol.exceptions import CamtolError

__all__ = [
    "main",
    "cli",
    "analyse_with_hint",
    "load_input",
    "run_guarded",
    "EXIT_OK",
    "EXIT_FAIL",
    "EXIT_USAGE",
]

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_USAGE = 2

F = TypeVar("F", bound=Callable[..., Any])


class _Exit(Exception):
    """Carry an exit status out of a command without click's SystemExit."""

    def __init__(self, code: int) -> None:
        self.code = code


def fail(message: str, code: int = EXIT_USAGE) -> None:
    """Print one error line to stderr and leave with ``code``."""
    click.echo(f"camtol: error: {message}", err=True)
    raise _Exit(code)


def load_input(design: str | None, example: str | None) -> Any:
    """Load a design from a path or a built-in example name (exactly one of them).

    Parameters
    ----------
    design : str or None
        Path of a design file (TOML), or None when ``example`` is given.
    example : str or None
        Name of a built-in example, or None when ``design`` is given.

    Returns
    -------
    CamDesign
        The loaded design. Giving both or neither ends the command with a usage error.
    """
    from camtol.config import load_design, load_example

    if (design is None) == (example is None):
        fail("give either a DESIGN.toml file or --example NAME (see `camtol examples`)")
    return load_example(example) if example is not None else load_design(str(design))


def check_output_path(path: str | None, option: str, suffixes: Sequence[str]) -> None:
    """Reject an output path with a wrong suffix or a missing directory, before any work."""
    if path is None:
        return
    p = Path(path)
    if p.suffix.lower() not in suffixes:
        fail(f"{option}={path!r}: the file name must end in {' or '.join(suffixes)}")
    if not p.parent.exists():
        fail(f"{option}={path!r}: directory {str(p.parent)!r} does not exist")


def run_guarded(fn: Callable[[], int | None]) -> int:
    """Run a command body; camtol errors become one stderr line and exit status 2.

    Warnings raised by ``fn`` are printed to stderr as ``camtol: warning:`` lines.

    Parameters
    ----------
    fn : callable
        Command body without arguments, returning an exit status or None (success).

    Returns
    -------
    int
        Exit status: that of ``fn``, 0 when it returned None, 2 on a camtol error.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            code = fn()
        except CamtolError as exc:
            click.echo(f"camtol: error: {exc}", err=True)
            code = EXIT_USAGE
        finally:
            for message in dict.fromkeys(str(w.message) for w in caught):  # once each
                click.echo(f"camtol: warning: {message}", err=True)
    return EXIT_OK if code is None else code


def analyse_with_hint(design: Any, *, step_deg: float) -> Any:
    """Analyse a design; an undercut or pressure-angle failure says which base radius works.

    Parameters
    ----------
    design : CamDesign
        The design.
    step_deg : float
        Grid step. [deg]

    Returns
    -------
    Analysis
        As :func:`camtol.analysis.analyse`.
    """
    from camtol.analysis import analyse
    from camtol.exceptions import GeometryError

    try:
        return analyse(design, step_deg=step_deg)
    except GeometryError as exc:
        from camtol.cli_size import sizing_hint

        hint = sizing_hint(design)
        if hint is None:
            raise
        raise type(exc)(f"{exc}; {hint}") from None


def design_options(f: F) -> F:
    """Add the DESIGN argument and --example option."""
    f = click.option(
        "--example", "-e", metavar="NAME", help="Use a built-in example (see `camtol examples`)."
    )(f)
    f = click.argument("design", required=False, type=click.Path(dir_okay=False))(f)
    return f


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
                rows.append((name, make_default_short_help(self.lazy_commands[name][2], limit)))
            elif not cmd.hidden:
                rows.append((name, cmd.get_short_help_str(formatter.width - 6 - len(name))))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


#: Commands living in their own modules: name -> (module, attribute, help summary, i.e.
#: the first paragraph of the command's docstring; tests/test_cli_lazy.py checks it).
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


@cli.command()
@design_options
@click.option(
    "--step",
    "step_deg",
    type=float,
    default=0.1,
    show_default=True,
    metavar="DEG",
    help="Grid step [deg].",
)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option(
    "--curves",
    metavar="FILE.csv",
    help="Write one row per angle: profile, angles and every error curve (units in columns).",
)
@click.option("--plot", metavar="FILE.png", help="Write the paper-style figure (PNG, SVG, PDF).")
@click.option(
    "--plot-angle",
    "plot_angle_deg",
    type=float,
    metavar="DEG",
    help="Cam angle at which the figure draws the cam and follower [deg]"
    " (default: where the worst-case error is largest).",
)
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success (exit status only).")
def analyze(
    design: str | None,
    example: str | None,
    step_deg: float,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    plot_angle_deg: float | None,
    quiet: bool,
) -> None:
    """Analyse a design: profile, pressure and shift angles, and the follower's errors.

    Reports the extremes over 0-360° of every quantity, the error of each toleranced
    source, the worst case and RMS, and the accuracy grade of the output (THEORY §3).
    """

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        if plot_angle_deg is not None:
            if plot is None:
                fail("--plot-angle draws on the figure: give --plot FILE.png as well")
            if not (math.isfinite(plot_angle_deg) and 0.0 <= plot_angle_deg < 360.0):
                fail(
                    f"--plot-angle={plot_angle_deg!r} is not allowed; give a cam angle from 0"
                    " up to (not including) 360 degrees"
                )
        from camtol.report import tables

        a = analyse_with_hint(load_input(design, example), step_deg=step_deg)
        written = []
        if curves:
            tables.write_curves_csv(a, curves)
            written.append(curves)
        if plot:
            _save_figure(a, plot, cam_angle_deg=plot_angle_deg)
            written.append(plot)
        if as_json:
            click.echo(json.dumps(tables.analysis_json(a), indent=2, default=_json_default))
        elif not quiet:
            tables.print_analysis(a)
        if not quiet:
            for path in written:  # on stderr with --json, so stdout stays one JSON document
                click.echo(f"wrote {path}", err=as_json)
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _json_default(o: Any) -> Any:
    if isinstance(o, float) and not math.isfinite(o):
        return None
    return str(o)


def _save_figure(analysis: Any, path: str, *, cam_angle_deg: float | None = None) -> None:
    from camtol.drawing import analysis_drawing
    from camtol.report.files import atomic_output
    from camtol.report.plots import analysis_figure

    fig = analysis_figure(analysis, analysis_drawing(analysis, cam_angle_deg))
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=Path(path).suffix.lstrip(".").lower())


@cli.group(invoke_without_command=True)
@click.pass_context
def examples(ctx: click.Context) -> None:
    """List the built-in example designs (`camtol examples show NAME` prints one)."""
    if ctx.invoked_subcommand is None:
        from camtol.examples import example_names, example_summary

        for name in example_names():
            click.echo(f"{name:20s} {example_summary(name)}")


@examples.command("show")
@click.argument("name")
def examples_show(name: str) -> None:
    """Print the TOML of a built-in example, to start a design from it."""

    def body() -> int:
        from camtol.examples import example_text

        click.echo(example_text(name), nl=False)
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _register_subcommands() -> None:
    """Add the commands that live in their own modules; each is imported when it runs."""
    LAZY_COMMANDS["conjugate"] = (
        "camtol.cli_conjugate",
        "conjugate",
        "Conjugate-cam fixture: Δf parts, inverse analysis Δr_A,est / Δr_B,est, acceptance.",
    )
    LAZY_COMMANDS["profile"] = (
        "camtol.cli_report",
        "profile",
        "Export the cam profile for CAD/CAM (CSV, DXF or SVG, chosen by the suffix of -o).",
    )
    LAZY_COMMANDS["report"] = (
        "camtol.cli_report",
        "report",
        "Write a self-contained HTML report: verdict, inputs, conventions, extremes, figures.",
    )
    LAZY_COMMANDS["verify"] = (
        "camtol.cli_verify",
        "verify",
        "Verify a design's analytic results with the exact contact engine (THEORY §5).",
    )
    LAZY_COMMANDS["size"] = (
        "camtol.cli_size",
        "size",
        "Find the smallest base radius (and offset) meeting the pressure-angle and curvature"
        " limits.",
    )
    LAZY_COMMANDS["precision"] = (
        "camtol.cli_manufacturing",
        "precision",
        "How precise must the lift table be? (THEORY §6.1, §6.2)",
    )
    LAZY_COMMANDS["cut"] = (
        "camtol.cli_manufacturing",
        "cut",
        "Simulate cutting at discrete cam angles and follow the cut cam exactly (THEORY §6.3).",
    )
    LAZY_COMMANDS["derive"] = (
        "camtol.cli_manufacturing",
        "derive",
        "V, A and J of a measured or tabulated lift, with a stated smoothing (THEORY §6.1).",
    )
    LAZY_COMMANDS["records"] = (
        "camtol.cli_records",
        "records",
        "Query stored inspection records: list, show one, lot statistics (SQLite, PostgreSQL).",
    )
    LAZY_COMMANDS["inspect"] = (
        "camtol.cli_inspect",
        "inspect",
        "Inspect a machined cam from CMM points: registration, deviations, follower error.",
    )
    LAZY_COMMANDS["simulate"] = (
        "camtol.cli_simulate",
        "simulate",
        "Digital twins: simulated measurement files with their truth beside them.",
    )
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
    try:
        cli.main(args=list(args) if args is not None else None, standalone_mode=False)
    except _Exit as e:
        return e.code
    except click.ClickException as e:
        click.echo(f"camtol: error: {e.format_message()}", err=True)
        return EXIT_USAGE
    except click.exceptions.Abort:
        click.echo("camtol: aborted", err=True)
        return EXIT_USAGE
    except click.exceptions.Exit as e:
        return int(e.exit_code)
    return EXIT_OK


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())


def console_main() -> None:
    """Entry point of the ``camtol`` console script."""
    sys.exit(main())
