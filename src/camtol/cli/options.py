"""Options that several ``camtol`` commands share, defined once, and number options.

``--step`` is checked as the command line is parsed, by the one rule of
:func:`camtol.grid.check_step`, so every command refuses a step that does not divide 360°
with the same one-line message naming the flag (``--step=0.7 is not allowed; ...``), before
any file is read. The module imports neither numpy nor the library: ``camtol --help`` stays
light (``tests/cli/test_lazy_commands.py``).

:class:`Number` is the type of a numeric option with bounds: a value that is not finite or
out of bounds is refused as the line is read, with the flag's name and what is allowed
(``--noise-um=-1 is not allowed; give a number ≥ 0 in µm``), never under the name of the
library parameter it becomes, and never after a unit conversion.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, TypeVar

import click

__all__ = [
    "MAX_TOOL_RADIUS_MM",
    "Number",
    "decision_flag",
    "design_options",
    "seed_option",
    "step_option",
    "strict_option",
    "verbose_option",
]

F = TypeVar("F", bound=Callable[..., Any])

#: Largest tool radius a command accepts: :data:`camtol.analysis.profile.MAX_TOOL_RADIUS_MM`,
#: written out so that ``--help`` imports no numpy (a test holds the two equal). [mm]
MAX_TOOL_RADIUS_MM = 100_000.0


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


#: ``--strict``: a pressure angle beyond the design limit makes the exit status 1.
strict_option = click.option(
    "--strict",
    is_flag=True,
    help="Exit with status 1 when a pressure angle exceeds the design limit"
    " (operation.pressure_angle_limit_deg).",
)

#: ``--verbose``: also print the conventions in force.
verbose_option = click.option(
    "--verbose", "-v", is_flag=True, help="Also print the IT-grade conventions in force."
)


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


class Number(click.ParamType):  # type: ignore[type-arg]  # generic from click 8.4 on
    """A finite number (or whole number) within bounds, checked as the line is read.

    Parameters
    ----------
    low : float, optional
        Smallest value allowed (``low_open``: values must exceed it).
    low_open : bool
        Exclude ``low`` itself.
    high : float, optional
        Largest value allowed (``high_open``: values must be below it).
    high_open : bool
        Exclude ``high`` itself.
    integer : bool
        Whole numbers only (an ``int``).
    unit : str
        Unit named in the message (``µm``, ``mm``, ``%``), or ``""``.
    """

    def __init__(
        self,
        *,
        low: float | None = None,
        low_open: bool = False,
        high: float | None = None,
        high_open: bool = False,
        integer: bool = False,
        unit: str = "",
    ) -> None:
        self.low, self.low_open, self.integer = low, low_open, integer
        self.high, self.high_open = high, high_open
        self.name = "integer" if integer else "float"  # the usage's INTEGER / FLOAT
        what = "a whole number" if integer else "a percentage" if unit == "%" else "a number"
        above = "" if low is None else f"{'>' if low_open else '≥'} {low:g}"
        below = "" if high is None else f"{'<' if high_open else '≤'} {high:g}"
        if low is not None and high is not None:
            bounds = (
                f" from {low:g} to {high:g}"
                if not (low_open or high_open)
                else f" {above} and {below}"
            )
        elif low is not None:
            bounds = f" {above}"
        else:
            bounds = "" if high is None else f" {below}"
        self.allowed = what + bounds + (f" in {unit}" if unit and unit != "%" else "")

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> Any:
        """Return the value as a number, or end the command with a one-line usage error.

        Parameters
        ----------
        value : Any
            The text given (or the default).
        param : click.Parameter or None
            The option, whose longest flag the message names.
        ctx : click.Context or None
            The command's context.

        Returns
        -------
        int or float
            The number.
        """
        flag = max(getattr(param, "opts", None) or ["value"], key=len)
        try:
            x = (int if self.integer else float)(value)
        except (TypeError, ValueError):
            kind = "a whole number" if self.integer else "a number"
            raise click.UsageError(f"{flag}={value!r} is not {kind}", ctx) from None
        low, high = self.low, self.high
        if (
            not math.isfinite(x)
            or (low is not None and (x <= low if self.low_open else x < low))
            or (high is not None and (x >= high if self.high_open else x > high))
        ):
            raise click.UsageError(f"{flag}={x:g} is not allowed; give {self.allowed}", ctx)
        return x


#: ``--seed``: the seed of a command's random streams (a whole number ≥ 0), default 0.
seed_option = click.option(
    "--seed",
    type=Number(low=0, integer=True),
    default=0,
    show_default=True,
    help="Seed of the random streams.",
)


def decision_flag(help_text: str) -> Callable[[F], F]:
    """Return the ``--decision simple|guard-band`` option (ISO 14253-1) with its help.

    The rule is one flag in every command; what it judges (a fixture record, a CMM scan,
    both) is the command's, and so is the help.

    Parameters
    ----------
    help_text : str
        What 'simple' and 'guard-band' judge in this command.

    Returns
    -------
    callable
        A decorator adding the option.
    """
    return click.option(
        "--decision",
        type=click.Choice(["simple", "guard-band"]),
        default="simple",
        show_default=True,
        help=help_text,
    )
