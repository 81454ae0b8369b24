"""``camtol profile`` and ``camtol report``: CAD/CAM exports and the HTML report.

Registered on the ``camtol`` group by :mod:`camtol.cli`. Exit status 0 on success, 2 on
bad input or a design that cannot be made; nothing is written unless everything succeeded.
"""

from __future__ import annotations

from pathlib import Path

import click

from camtol.cli import (
    EXIT_OK,
    _Exit,
    check_output_path,
    design_options,
    echo_json,
    fail,
    guard_paths,
    load_input,
    run_guarded,
)

__all__ = ["profile", "report"]


@click.command()
@design_options
@click.option(
    "--output",
    "-o",
    "output",
    metavar="FILE",
    required=True,
    help="Output file; the suffix chooses the format: .csv, .dxf or .svg.",
)
@click.option(
    "--tolerance",
    "tolerance_um",
    type=float,
    default=0.1,
    show_default=True,
    help="Largest deviation of a polyline chord from the analytic profile [µm].",
)
@click.option(
    "--cutter-radius",
    "cutter_radius_mm",
    type=float,
    default=None,
    metavar="MM",
    help="Also write the cutter-centre path for a cutter of this radius [mm].",
)
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def profile(
    design: str | None,
    example: str | None,
    output: str,
    tolerance_um: float,
    cutter_radius_mm: float | None,
    as_json: bool,
    quiet: bool,
) -> None:
    """Export the cam profile for CAD/CAM (CSV, DXF or SVG, chosen by the suffix of -o).

    The polylines' vertices lie on the analytic profile and every chord deviates from it
    by less than --tolerance. DXF layers: CAM_PROFILE, PITCH_CURVE (roller followers),
    CUTTER_PATH (with --cutter-radius); a conjugate pair has CAM_A_* and CAM_B_* layers.
    Coordinates in mm in the cam frame (origin at the cam pivot).
    """

    def body() -> int:
        from camtol.report.export import EXPORT_SUFFIXES, write_profile

        guard_paths({"DESIGN": design}, {"--output": output})
        check_output_path(output, "--output", list(EXPORT_SUFFIXES))
        if not (tolerance_um > 0):
            fail(f"--tolerance={tolerance_um:g} is not allowed; give a positive value in µm")
        if cutter_radius_mm is not None and not (cutter_radius_mm > 0):
            fail(
                f"--cutter-radius={cutter_radius_mm:g} is not allowed; give a positive radius in mm"
            )
        pts = write_profile(
            load_input(design, example),
            output,
            tolerance_mm=tolerance_um * 1e-3,
            cutter_radius_mm=cutter_radius_mm,
        )
        if as_json:
            doc = {
                "path": str(output),
                "design": pts.design_name,
                "tolerance_um": pts.tolerance_mm * 1e3,
                "cutter_radius_mm": pts.cutter_radius_mm,
                "curves": [
                    {
                        "layer": c.layer,
                        "description": c.description,
                        "vertices": int(c.theta_rad.size),
                        "max_deviation_um": c.max_deviation_mm * 1e3,
                    }
                    for c in pts.curves
                ],
            }
            echo_json(doc)
        elif not quiet:
            for c in pts.curves:
                click.echo(
                    f"{c.layer:20s} {c.theta_rad.size:6d} vertices,"
                    f" max chord deviation {c.max_deviation_mm * 1e3:.3f} µm"
                )
            click.echo(f"wrote {output}")
        return EXIT_OK

    raise _Exit(run_guarded(body))


@click.command()
@design_options
@click.option(
    "--output", "-o", "output", metavar="FILE.html", required=True, help="Report file (.html)."
)
@click.option(
    "--step", "step_deg", type=float, default=0.1, show_default=True, help="Grid step [deg]."
)
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def report(
    design: str | None,
    example: str | None,
    output: str,
    step_deg: float,
    as_json: bool,
    quiet: bool,
) -> None:
    """Write a self-contained HTML report: inputs, conventions, verdicts, extremes, figures.

    One file with inline SVG figures and no scripts: it opens offline. For a conjugate
    design with an [inspection] table it also shows the fixture analysis (THEORY §4).
    The exit status is 0 once the report is written, whatever its verdicts (use
    `camtol analyze` or `camtol conjugate` as a gate).
    """

    def body() -> int:
        from camtol.analysis import analyse
        from camtol.report.html import write_report

        guard_paths({"DESIGN": design}, {"--output": output})
        check_output_path(output, "--output", [".html", ".htm"])
        a = analyse(load_input(design, example), step_deg=step_deg)
        base_dir = Path(design).parent if design is not None else None
        write_report(a, output, base_dir=base_dir)
        worst = a.extremes["dS_worst"][0]
        if as_json:
            doc = {
                "path": str(output),
                "design": a.design.name,
                "max_worst_case": {"value": worst.value, "unit": a.error_unit},
                "accuracy": a.accuracy.describe(),
            }
            echo_json(doc)
        elif not quiet:
            click.echo(f"wrote {output} ({a.design.name}: {a.accuracy.describe()})")
        return EXIT_OK

    raise _Exit(run_guarded(body))
