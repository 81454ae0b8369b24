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
import os
import sys
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import click

from camtol import __version__
from camtol.cli_commands import short_help
from camtol.cli_options import design_options, step_option, strict_option, verbose_option
from camtol.exceptions import CamtolError

__all__ = [
    "main",
    "cli",
    "echo_json",
    "guard_paths",
    "analyse_with_hint",
    "load_input",
    "run_guarded",
    "strict_status",
    "EXIT_OK",
    "EXIT_FAIL",
    "EXIT_USAGE",
]

EXIT_OK = 0
EXIT_FAIL = 1
EXIT_USAGE = 2


class _Exit(Exception):
    """Carry an exit status out of a command without click's SystemExit."""

    def __init__(self, code: int) -> None:
        self.code = code


def fail(message: str, code: int = EXIT_USAGE) -> None:
    """Print one error line to stderr and leave with ``code``."""
    click.echo(f"camtol: error: {_one_line(message)}", err=True)
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


def load_checked(design: str | None, example: str | None) -> Any:
    """Load a design (as :func:`load_input`) and check that every cam can work.

    For commands that go straight to manufacturing (``cut``, ``precision``, G-code): the
    grid-independent geometry check of :func:`camtol.validity.check_design_geometry`.

    Parameters
    ----------
    design : str or None
        Path of a design file (TOML), or None when ``example`` is given.
    example : str or None
        Name of a built-in example, or None when ``design`` is given.

    Returns
    -------
    CamDesign
        The loaded, checked design.
    """
    from camtol.validity import check_design_geometry

    d = load_input(design, example)
    check_design_geometry(d)
    return d


def check_output_path(path: str | None, option: str, suffixes: Sequence[str]) -> None:
    """Reject an output path before any work: wrong suffix, a directory, not writable.

    Parameters
    ----------
    path : str or None
        The output file (None: the option was not given).
    option : str
        The option as the user wrote it, e.g. ``--curves``.
    suffixes : sequence of str
        Allowed lower-case suffixes, e.g. ``[".csv"]``.
    """
    if path is None:
        return
    from camtol.files import check_writable

    p = Path(path)
    if p.is_dir():
        fail(f"{option}={path!r} is a directory; give a file name")
    if p.suffix.lower() not in suffixes:
        fail(f"{option}={path!r}: the file name must end in {' or '.join(suffixes)}")
    if not p.parent.exists():
        fail(f"{option}={path!r}: directory {str(p.parent)!r} does not exist")
    try:
        check_writable(p)
    except CamtolError as exc:
        fail(f"{option}={path!r}: {exc}")


def _same_file(a: str, b: str) -> bool:
    """Tell whether two paths name one file (symlinks, ``..`` and hard links resolved)."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def guard_paths(inputs: Mapping[str, str | None], outputs: Mapping[str, str | None]) -> None:
    """Refuse an output that is an input or another output of the same command.

    Every command declares its file inputs and outputs, keyed by the option (or argument)
    as the user wrote it; this runs before any work. Paths are compared after resolving
    symbolic links and ``..`` (and as the same inode for existing files), so neither a
    link nor a relative detour can make camtol overwrite its own input. Inputs named
    inside a design file (lift tables, inspection tables) are protected at write time by
    :func:`camtol.files.atomic_output`.

    Parameters
    ----------
    inputs : mapping of str to str or None
        Input files by option name; None entries are ignored.
    outputs : mapping of str to str or None
        Output files by option name; None entries are ignored.
    """
    ins = [(k, v) for k, v in inputs.items() if v is not None]
    outs = [(k, v) for k, v in outputs.items() if v is not None]
    for i, (opt, path) in enumerate(outs):
        for in_opt, in_path in ins:
            if _same_file(path, in_path):
                fail(
                    f"{opt}={path!r} is the same file as the input {in_opt}={in_path!r};"
                    " camtol never overwrites an input: choose another output name"
                )
        for other_opt, other in outs[:i]:
            if _same_file(path, other):
                fail(
                    f"{opt}={path!r} is the same file as {other_opt}={other!r}; give each"
                    " output its own file name"
                )


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
        code: int | None = EXIT_USAGE  # until fn returns (fail() leaves by an exception)
        try:
            code = fn()
        except CamtolError as exc:
            click.echo(f"camtol: error: {_one_line(str(exc))}", err=True)
            code = EXIT_USAGE
        except BrokenPipeError:  # stdout's reader left (`| head`): quiet, status 1 as rich
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            code = EXIT_FAIL
        except OSError as exc:  # an input or output the OS refuses, in one line
            name = exc.filename if exc.filename is not None else "a file"
            click.echo(f"camtol: error: {name}: {exc.strerror or exc}", err=True)
            code = EXIT_USAGE
        except (ArithmeticError, MemoryError, RecursionError) as exc:
            click.echo(f"camtol: error: {_numerical_failure(exc)}", err=True)
            code = EXIT_USAGE
        except Exception as exc:
            from numpy.linalg import LinAlgError

            if not isinstance(exc, LinAlgError):
                raise
            click.echo(f"camtol: error: {_numerical_failure(exc)}", err=True)
            code = EXIT_USAGE
        finally:
            if code == EXIT_USAGE:  # the error says it: numpy's overflow chatter is noise
                caught = [w for w in caught if not issubclass(w.category, RuntimeWarning)]
            for message in dict.fromkeys(str(w.message) for w in caught):  # once each
                click.echo(f"camtol: warning: {message}", err=True)
    return EXIT_OK if code is None else code


#: Longest error line printed; longer messages are shortened in the middle. [characters]
MAX_MESSAGE_CHARS = 600


def _one_line(message: str) -> str:
    """One line of at most :data:`MAX_MESSAGE_CHARS` characters."""
    text = " ".join(message.split())
    if len(text) > MAX_MESSAGE_CHARS:
        half = MAX_MESSAGE_CHARS // 2 - 3
        text = f"{text[:half]} ... {text[-half:]}"
    return text


def _numerical_failure(exc: BaseException) -> str:
    """Message for a numerical failure no check caught (overflow, singular system...)."""
    what = {
        "OverflowError": "a number overflows",
        "ZeroDivisionError": "a division by zero",
        "FloatingPointError": "a floating-point error",
        "MemoryError": "the computation needs more memory than is available",
        "RecursionError": "an expression is nested too deeply",
        "LinAlgError": "a linear system is singular",
    }.get(type(exc).__name__, type(exc).__name__)
    return _one_line(
        f"numerical failure ({what}: {exc}); the design or option values are outside the"
        " range camtol can compute: check their magnitudes"
    )


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
@step_option()
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
@strict_option
@verbose_option
def analyze(
    design: str | None,
    example: str | None,
    step_deg: float,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    plot_angle_deg: float | None,
    quiet: bool,
    strict: bool,
    verbose: bool,
) -> None:
    """Analyse a design: profile, pressure and shift angles, and the follower's errors.

    Reports the nominal motion's peak V, A, J, each cam's pressure-angle range and
    smallest convex and concave radii, the extremes over 0-360° of every quantity, the
    error of each toleranced source, the worst case and RMS, and the accuracy grade of
    the output (THEORY §3). A pressure angle beyond the design limit is flagged; with
    --strict it makes the exit status 1.
    """

    def body() -> int:
        guard_paths({"DESIGN": design}, {"--curves": curves, "--plot": plot})
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
            echo_json(tables.analysis_json(a), command="analyze")
        elif not quiet:
            tables.print_analysis(a, verbose=verbose)
        if not quiet:
            for path in written:  # on stderr with --json, so stdout stays one JSON document
                click.echo(f"wrote {path}", err=as_json)
        return strict_status(a, strict)

    raise _Exit(run_guarded(body))


def echo_json(data: Any, *, command: str | None = None) -> None:
    """Print a command's JSON document on stdout: strict JSON, floats to 10 digits.

    Parameters
    ----------
    data : dict
        JSON-ready data; infinities and NaN become null, numpy scalars numbers.
    command : str, optional
        The command's name: the document then starts with ``schema_version``,
        ``command`` and ``camtol_version`` (the envelope of every ``--json`` output,
        described by ``camtol/data/schemas/<command>.schema.json``).
    """
    from camtol.report.finite import require_no_nan_json
    from camtol.report.units import json_ready

    # A NaN is a failed computation: an error naming its key (issue 9), never printed. An
    # infinity means "none" (e.g. no concave stretch) and is written as null.
    require_no_nan_json(data)
    if command is not None and isinstance(data, dict):
        from camtol.report.tables import SCHEMA_VERSION

        head = {"schema_version": SCHEMA_VERSION, "command": command, "camtol_version": __version__}
        data = {**head, **{k: v for k, v in data.items() if k not in head}}
    text = json.dumps(json_ready(data), indent=2, allow_nan=False, ensure_ascii=False)
    click.echo(text)


def strict_status(analysis: Any, strict: bool) -> int:
    """Exit status of a design command: 1 with ``--strict`` past the pressure-angle limit.

    Parameters
    ----------
    analysis : Analysis
        The design's analysis.
    strict : bool
        Whether ``--strict`` was given.

    Returns
    -------
    int
        :data:`EXIT_FAIL` or :data:`EXIT_OK`.
    """
    if strict and analysis.pressure_angle_exceeds_limit:
        click.echo(
            "camtol: error: the pressure angle exceeds the design limit"
            f" {analysis.design.pressure_angle_limit_deg:g}° (--strict)",
            err=True,
        )
        return EXIT_FAIL
    return EXIT_OK


def _save_figure(analysis: Any, path: str, *, cam_angle_deg: float | None = None) -> None:
    from camtol.drawing import analysis_drawing
    from camtol.files import atomic_output
    from camtol.report.finite import require_finite_columns
    from camtol.report.plots import analysis_figure
    from camtol.report.tables import curves_columns

    require_finite_columns(curves_columns(analysis), where=path)
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
    from camtol.cli_commands import COMMANDS

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
