"""``camtol dynamics``: the follower at speed, of the nominal or the as-made cam (issue 33).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Parses the options, builds one
:class:`~camtol.dynamics.run.DynamicsInputs`, calls
:func:`~camtol.dynamics.run.run_dynamics` and renders the result
(:mod:`camtol.report.dynamics`). Exit status 0, or 2 on bad input (nothing written then).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from camtol.cli.common import (
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    guard_paths,
    load_input,
    run_guarded,
)
from camtol.cli.options import Number, design_options

__all__ = ["dynamics"]

#: The train's options: (flag, table field, unit for the message, lower bound, open?).
_TRAIN_OPTIONS: tuple[tuple[str, str, str, float, bool], ...] = (
    ("--mass-kg", "mass_kg", "kg", 0.0, True),
    ("--spring-rate-n-per-mm", "spring_rate_n_per_mm", "N/mm", 0.0, True),
    ("--preload-n", "preload_n", "N", 0.0, False),
    ("--follower-stiffness-n-per-mm", "follower_stiffness_n_per_mm", "N/mm", 0.0, True),
    ("--inertia-kg-mm2", "inertia_kg_mm2", "kg·mm²", 0.0, True),
    ("--spring-rate-nm-per-rad", "spring_rate_nm_per_rad", "N·m/rad", 0.0, True),
    ("--preload-nm", "preload_nm", "N·m", 0.0, False),
    ("--follower-stiffness-nm-per-rad", "follower_stiffness_nm_per_rad", "N·m/rad", 0.0, True),
    ("--face-width-mm", "face_width_mm", "mm", 0.0, True),
)


def _step(ctx: click.Context, param: click.Parameter, value: float | None) -> float | None:
    if value is None:
        return None
    from camtol.exceptions import DesignError
    from camtol.grid import check_step

    try:
        check_step(value, name="--step", min_points=16)
    except DesignError as exc:
        raise click.UsageError(str(exc), ctx=ctx) from None
    return value


def train_options(f: Any) -> Any:
    """Add the ``[dynamics]`` overrides (``--mass-kg`` ... ``--damping-ratio``) to a command.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the options; each arrives as its table field's name.
    """
    f = click.option(
        "--damping-ratio",
        "damping_ratio",
        type=Number(low=0, high=2, high_open=True),
        metavar="ZETA",
        help="Override dynamics.damping_ratio, of the train's first mode [-].",
    )(f)
    for flag, name, unit, low, low_open in reversed(_TRAIN_OPTIONS):
        f = click.option(
            flag,
            name,
            type=Number(low=low, low_open=low_open, unit=unit),
            metavar="VALUE",
            help=f"Override dynamics.{name} [{unit}].",
        )(f)
    return f


def train_overrides(values: dict[str, Any]) -> dict[str, Any]:
    """Return the train fields given on the command line (None: not given).

    Parameters
    ----------
    values : dict
        The command's keyword arguments.

    Returns
    -------
    dict
        Table field → value, for the fields given.
    """
    names = [name for _, name, *_ in _TRAIN_OPTIONS] + ["damping_ratio"]
    return {k: values[k] for k in names if values.get(k) is not None}


@click.command()
@design_options
@click.option(
    "--rpm",
    type=Number(low=0, low_open=True, unit="rpm"),
    metavar="RPM",
    help="Cam speed [rpm] (default: the design's operation.speed_rpm).",
)
@train_options
@click.option(
    "--cut-step",
    "cut_step_deg",
    type=Number(low=0, low_open=True, unit="deg"),
    metavar="DEG",
    help="The cam as cut every DEG by a flat tool (THEORY §6.3); needs a follower stiffness.",
)
@click.option(
    "--tool-radius",
    "tool_radius_mm",
    type=Number(low=0, low_open=True, unit="mm"),
    metavar="MM",
    help="With --cut-step: a cylindrical tool of this radius instead of a flat one [mm].",
)
@click.option(
    "--points",
    "points_path",
    metavar="SCAN.csv",
    help="The cam as measured: a CMM scan, registered as `camtol inspect` does.",
)
@click.option(
    "--stylus-radius-mm",
    "stylus_mm",
    type=Number(low=0, unit="mm"),
    default=0.0,
    show_default=True,
    help="With --points: the stylus-ball radius (0: surface points) [mm].",
)
@click.option(
    "--harmonics",
    type=Number(low=1, integer=True),
    default=100,
    show_default=True,
    help="With --points: the Fourier cut-off smoothing the scan (THEORY §9.6).",
)
@click.option(
    "--step",
    "step_deg",
    type=float,
    callback=_step,
    metavar="DEG",
    help="Grid step [deg] (default 0.1, or the cutting step / 20 and at most 0.1).",
)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option(
    "--curves",
    metavar="FILE.csv",
    help="Write theta_deg, lift, mass, dynamic_error, contact_force_n, torque_nm,"
    " hertz_stress_mpa per grid angle.",
)
@click.option("--plot", metavar="FILE.png", help="Write the figure (PNG/SVG/PDF).")
def dynamics(
    design: str | None,
    example: str | None,
    rpm: float | None,
    cut_step_deg: float | None,
    tool_radius_mm: float | None,
    points_path: str | None,
    stylus_mm: float,
    harmonics: int,
    step_deg: float | None,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    **train: Any,
) -> None:
    """Follower dynamics at speed: contact force, jump, vibration, torque, contact stress.

    The follower train of the design's [dynamics] table (options override it) driven by
    the nominal cam, or by the cam as made: cut every --cut-step degrees, or measured
    (--points). Gives the periodic steady state (through the frequency domain), the
    normal contact force, the camshaft torque, the Hertz stress, the residual vibration
    in the dwells, the jump speed and, above it, the separations (THEORY §9).
    """

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        guard_paths(
            {"DESIGN": design, "--points": points_path}, {"--curves": curves, "--plot": plot}
        )
        from camtol.dynamics.run import DynamicsInputs, run_dynamics
        from camtol.report import dynamics as rep

        if tool_radius_mm is not None and cut_step_deg is None:
            from camtol.cli.common import fail

            fail("--tool-radius is for a cut cam: give --cut-step too")
        d = load_input(design, example)
        inputs = DynamicsInputs(
            rpm=rpm,
            overrides=train_overrides(train),
            step_deg=step_deg,
            cut_step_deg=cut_step_deg,
            tool="flat" if tool_radius_mm is None else "cylinder",
            tool_radius_mm=0.0 if tool_radius_mm is None else tool_radius_mm,
            points_path=points_path,
            stylus_radius_mm=stylus_mm,
            harmonics=harmonics,
        )
        result = run_dynamics(d, inputs)
        fig = rep.dynamics_figure(result) if plot else None
        if curves:
            rep.write_curves_csv(result, curves)
        if plot and fig is not None:
            from camtol.files import atomic_output

            with atomic_output(plot) as tmp:
                fig.savefig(tmp, format=Path(plot).suffix.lstrip(".").lower())
        if as_json:
            echo_json(rep.dynamics_json(result), command="dynamics")
        else:
            import textwrap

            for line in rep.dynamics_text(result):  # label column of 19, 80 columns
                click.echo(
                    textwrap.fill(line, 80, subsequent_indent=" " * 19, break_on_hyphens=False)
                )
        return EXIT_OK

    raise _Exit(run_guarded(body))
