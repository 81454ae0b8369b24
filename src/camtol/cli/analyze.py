"""``camtol analyze``: everything the analytic engine says about a design (THEORY §2-3).

The profile, pressure and shift angles, curvature, and the follower's errors from the
design's tolerances, as a terminal summary, ``--json``, ``--curves`` CSV and a figure.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import click

from camtol.cli.common import (
    _Exit,
    check_output_path,
    echo_json,
    fail,
    guard_paths,
    load_input,
    run_guarded,
    strict_status,
)
from camtol.cli.options import design_options, step_option, strict_option, verbose_option

__all__ = ["analyse_with_hint", "analyze"]


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
        As :func:`camtol.analysis.result.analyse`.
    """
    from camtol.analysis.result import analyse
    from camtol.exceptions import GeometryError

    try:
        return analyse(design, step_deg=step_deg)
    except GeometryError as exc:
        from camtol.analysis.sizing import sizing_hint

        hint = sizing_hint(design)
        if hint is None:
            raise
        raise type(exc)(f"{exc}; {hint}") from None


@click.command()
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


def _save_figure(analysis: Any, path: str, *, cam_angle_deg: float | None = None) -> None:
    from camtol.analysis.drawing import analysis_drawing
    from camtol.files import atomic_output
    from camtol.report.finite import require_finite_columns
    from camtol.report.plots import analysis_figure
    from camtol.report.tables import curves_columns

    require_finite_columns(curves_columns(analysis), where=path)
    fig = analysis_figure(analysis, analysis_drawing(analysis, cam_angle_deg))
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=Path(path).suffix.lstrip(".").lower())
