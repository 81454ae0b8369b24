"""What every ``camtol`` command shares: exit codes, one-line errors, input and output guards.

A command's body runs under :func:`run_guarded`, which turns camtol's errors (and a
numerical failure) into one line on stderr and exit status 2; :func:`fail` leaves with a
message; :func:`guard_paths` and :func:`check_output_path` refuse an output that would
overwrite an input or that cannot be written, before anything is computed; and
:func:`echo_json` prints a ``--json`` document with its envelope. Exit codes: 0 ok,
1 out of tolerance, 2 usage error, bad input or a design that cannot work.
"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import click

from camtol._version import __version__
from camtol.exceptions import CamtolError

__all__ = [
    "EXIT_FAIL",
    "EXIT_OK",
    "EXIT_USAGE",
    "check_output_path",
    "echo_json",
    "fail",
    "guard_paths",
    "load_checked",
    "load_input",
    "run_guarded",
    "strict_status",
]


EXIT_OK = 0


EXIT_FAIL = 1


EXIT_USAGE = 2


class _Exit(Exception):
    """Carry an exit status out of a command without click's SystemExit."""

    def __init__(self, code: int) -> None:
        self.code = code


def fail(message: str, code: int = EXIT_USAGE) -> None:
    """Print one error line to stderr and leave with ``code``.

    Parameters
    ----------
    message : str
        What is wrong, naming the option or file, the value and what is allowed.
    code : int
        Exit status (2 for a usage error, 1 for a part out of tolerance).
    """
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
    from camtol.config.design_file import load_design, load_example

    if (design is None) == (example is None):
        fail("give either a DESIGN.toml file or --example NAME (see `camtol examples`)")
    return load_example(example) if example is not None else load_design(str(design))


def load_checked(design: str | None, example: str | None) -> Any:
    """Load a design (as :func:`load_input`) and check that every cam can work.

    For commands that go straight to manufacturing (``cut``, ``precision``, G-code): the
    grid-independent geometry check of :func:`camtol.analysis.validity.check_design_geometry`.

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
    from camtol.analysis.validity import check_design_geometry

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
        except BrokenPipeError:  # stdout's reader left (`| head`): quiet, status 1
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


def echo_json(data: Any, *, command: str | None = None, schema_version: str | None = None) -> None:
    """Print a command's JSON document on stdout: strict JSON, floats to 10 digits.

    Parameters
    ----------
    data : dict
        JSON-ready data; infinities and NaN become null, numpy scalars numbers.
    command : str, optional
        The command's name: the document then starts with ``schema_version``,
        ``command`` and ``camtol_version`` (the envelope of every ``--json`` output,
        described by ``camtol/data/schemas/<command>.schema.json``).
    schema_version : str, optional
        That document's own layout version, when it moved past the common
        ``SCHEMA_VERSION`` (a key changed meaning).
    """
    from camtol.report.finite import require_no_nan_json
    from camtol.report.units import json_ready

    # A NaN is a failed computation: an error naming its key (issue 9), never printed. An
    # infinity means "none" (e.g. no concave stretch) and is written as null.
    require_no_nan_json(data)
    if command is not None and isinstance(data, dict):
        from camtol.report.tables import SCHEMA_VERSION

        version = schema_version or SCHEMA_VERSION
        head = {"schema_version": version, "command": command, "camtol_version": __version__}
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
