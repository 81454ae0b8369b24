"""Options that several ``camtol`` commands share, defined once.

``--step`` is checked as the command line is parsed, by the one rule of
:func:`camtol.grid.check_step`, so every command refuses a step that does not divide 360°
with the same one-line message naming the flag (``--step=0.7 is not allowed; ...``), before
any file is read. The module imports neither numpy nor the library: ``camtol --help`` stays
light (``tests/test_cli_lazy.py``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

__all__ = ["design_options", "step_option", "strict_option", "verbose_option"]

F = TypeVar("F", bound=Callable[..., Any])


def design_options(f: F) -> F:
    """Add the DESIGN argument and --example option.

    Parameters
    ----------
    f : callable
        The command function.

    Returns
    -------
    callable
        ``f`` with the option added.
    """
    f = click.option(
        "--example", "-e", metavar="NAME", help="Use a built-in example (see `camtol examples`)."
    )(f)
    f = click.argument("design", required=False, type=click.Path(dir_okay=False))(f)
    return f


def strict_option(f: F) -> F:
    """Add --strict: a pressure angle beyond the design limit makes the exit status 1.

    Parameters
    ----------
    f : callable
        The command function.

    Returns
    -------
    callable
        ``f`` with the option added.
    """
    return click.option(
        "--strict",
        is_flag=True,
        help="Exit with status 1 when a pressure angle exceeds the design limit"
        " (operation.pressure_angle_limit_deg).",
    )(f)


def verbose_option(f: F) -> F:
    """Add --verbose: also print the conventions in force.

    Parameters
    ----------
    f : callable
        The command function.

    Returns
    -------
    callable
        ``f`` with the option added.
    """
    return click.option(
        "--verbose", "-v", is_flag=True, help="Also print the IT-grade conventions in force."
    )(f)


def step_option(
    *, help_text: str = "Grid step [deg].", min_points: int = 1, max_points: int | None = None
) -> Callable[[F], F]:
    """Make the ``--step DEG`` option (default 0.1°), passed to the command as ``step_deg``.

    Parameters
    ----------
    help_text : str
        The option's help text.
    min_points : int
        Fewest grid steps over a revolution the command accepts (360°/min_points is the
        coarsest step).
    max_points : int, optional
        Most grid steps the command accepts; by default
        :data:`camtol.grid.MAX_GRID_POINTS` (0.0001°), the bound of :func:`camtol.analyse`.

    Returns
    -------
    callable
        The option decorator.
    """

    def check(ctx: click.Context, param: click.Parameter, value: float) -> float:
        from camtol.exceptions import DesignError
        from camtol.grid import MAX_GRID_POINTS, check_step

        most = MAX_GRID_POINTS if max_points is None else max_points
        try:
            check_step(value, name="--step", min_points=min_points, max_points=most)
        except DesignError as exc:  # a usage error: one line, exit status 2 (main())
            raise click.UsageError(str(exc), ctx=ctx) from None
        return value

    return click.option(
        "--step",
        "step_deg",
        type=float,
        default=0.1,
        show_default=True,
        metavar="DEG",
        callback=check,
        help=help_text,
    )
