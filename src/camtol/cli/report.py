"""``camtol profile`` and ``camtol report``: CAD/CAM exports and the HTML report.

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 0 on success, 2 on
bad input or a design that cannot be made; nothing is written unless everything succeeded.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from camtol.cli.common import (
    EXIT_FAIL,
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    fail,
    guard_paths,
    load_input,
    run_guarded,
)
from camtol.cli.gcode_output import GCODE_SUFFIXES, gcode_options, write_gcode_output
from camtol.cli.inspection_options import (
    check_cmm_options,
    command_fixture_inputs,
    has_inspection_input,
    inspection_options,
)
from camtol.cli.options import MAX_TOOL_RADIUS_MM, Number, design_options, step_option

__all__ = ["profile", "report"]


@click.command()
@design_options
@click.option(
    "--output",
    "-o",
    "output",
    metavar="FILE.csv|.dxf|.svg|.nc",
    required=True,
    help="Output file; the suffix chooses the format: .csv, .dxf, .svg, or G-code (.nc, .ngc,"
    " .tap: the cutter-centre path, needs --cutter-radius or --wire-radius).",
)
@click.option(
    "--tolerance",
    "tolerance_um",
    type=Number(low=1e-4, high=1000.0, unit="µm"),  # camtol.analysis.profile: 1e-7 to 1 mm
    default=0.1,
    show_default=True,
    metavar="UM",
    help="Largest deviation of a polyline chord from the analytic profile [µm].",
)
@click.option(
    "--cutter-radius",
    "cutter_radius_mm",
    type=Number(low=0, high=MAX_TOOL_RADIUS_MM, unit="mm"),
    default=None,
    metavar="MM",
    help="Also write the cutter-centre path for a cutter of this radius [mm].",
)
@gcode_options
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def profile(
    design: str | None,
    example: str | None,
    output: str,
    tolerance_um: float,
    cutter_radius_mm: float | None,
    gcode_mode: str,
    wire_radius_mm: float | None,
    spark_gap_mm: float,
    feed_mm_min: float | None,
    lead_radius_mm: float | None,
    safe_z_mm: float | None,
    cut_z_mm: float | None,
    plunge_feed_mm_min: float | None,
    as_json: bool,
    quiet: bool,
) -> None:
    """Export the cam profile for CAD/CAM (CSV, DXF or SVG, chosen by the suffix of -o).

    The polylines' vertices lie on the analytic profile and every chord deviates from it
    by less than --tolerance. DXF layers: CAM_PROFILE, CAM_PITCH_CURVE (roller followers),
    CAM_CUTTER_PATH (with --cutter-radius), CAM_CENTRE; a conjugate pair has CAM_A_* and
    CAM_B_* layers.
    Coordinates in mm in the cam frame (origin at the cam pivot). G-code (.nc, .ngc,
    .tap) is a program to run: units, plane, absolute mode, --feed, lead-in and lead-out
    arcs, a 2D contour unless --safe-z/--cut-z/--plunge-feed ask for Z moves.
    """

    def body() -> int:
        from camtol.export import write_profile
        from camtol.report.export import EXPORT_SUFFIXES

        guard_paths({"DESIGN": design}, {"--output": output})
        machine = {
            "feed_mm_min": feed_mm_min,
            "lead_radius_mm": lead_radius_mm,
            "safe_z_mm": safe_z_mm,
            "cut_z_mm": cut_z_mm,
            "plunge_feed_mm_min": plunge_feed_mm_min,
        }
        if Path(output).suffix.lower() in GCODE_SUFFIXES:
            return write_gcode_output(
                load_input, design, example, output, tolerance_um, cutter_radius_mm,
                gcode_mode, wire_radius_mm, spark_gap_mm, as_json, quiet, machine,
            )  # fmt: skip
        if wire_radius_mm is not None or spark_gap_mm != 0.0:
            fail("--wire-radius and --spark-gap are only allowed for G-code output (-o FILE.nc)")
        given = [k for k, v in machine.items() if v is not None]
        if given:
            flag = "--" + given[0].rsplit("_mm", 1)[0].replace("_", "-")
            fail(f"{flag} is only allowed for G-code output (-o FILE.nc, .ngc or .tap)")
        check_output_path(output, "--output", list(EXPORT_SUFFIXES) + list(GCODE_SUFFIXES))
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
            echo_json(doc, command="profile")
        elif not quiet:
            for c in pts.curves:
                click.echo(
                    f"{c.layer:20s} {c.theta_rad.size:6d} vertices,"
                    f" max chord deviation {c.max_deviation_mm * 1e3:.3f} µm"
                )
            click.echo(f"wrote {output}")
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _traceability_options(f: Any) -> Any:
    from camtol.report.qa import TRACEABILITY_FIELDS

    for key, label in reversed(TRACEABILITY_FIELDS):
        f = click.option(
            f"--{key.replace('_', '-')}",
            key,
            metavar="TEXT",
            help=f"Traceability: {label} (overrides the design's [traceability] table).",
        )(f)
    return f


def _cmm_part(
    design: Any,
    scan: str,
    stylus_mm: float,
    datum_text: str,
    decision: str,
    u_cmm_um: float | None,
    step_deg: float,
    traceability: dict[str, str | None],
) -> tuple[Any, str]:
    """Inspect a single cam's scan for ``camtol report --cmm`` (as ``camtol inspect``).

    The scan header's stylus radius is used when ``--cmm-stylus-radius-mm`` is not given.

    Returns
    -------
    (CmmPart, str)
        The inspection's JSON-ready data (with traceability), and its report section
        (:func:`camtol.report.inspection_report.cmm_section_html`, with the figure).
    """
    from camtol.cli.inspect import parse_datum
    from camtol.inspection.cmm import header_stylus_radius_mm
    from camtol.inspection.cmm_run import CmmInputs, run_cmm
    from camtol.report import inspection_report as rep
    from camtol.report.qa import CmmPart

    header = header_stylus_radius_mm(scan)
    stylus = header if (stylus_mm == 0.0 and header) else stylus_mm
    inputs = CmmInputs(
        points_path=scan,
        stylus_radius_mm=stylus,
        datum=parse_datum(datum_text, None, None, "soft_l1"),
        step_deg=step_deg,
        decision=decision,
        u_cmm_um=u_cmm_um,
    )
    run = run_cmm(design, inputs)
    data = rep.inspection_json(
        run.inspection, run.functional, design=design.name, stylus_radius_mm=stylus
    )
    given = {k: v for k, v in traceability.items() if v is not None}
    data["traceability"] = rep.traceability_json(given, design=design, scan_path=scan)
    from camtol.report.inline_svg import figure_svg
    from camtol.report.inspection_plots import inspection_figure

    fig = inspection_figure(run.inspection, run.profile, run.functional)
    return CmmPart(data), rep.cmm_section_html(data, figure_svg(fig, prefix="cmm"))


def dynamics_report_section(design: Any) -> str:
    """HTML section of a design's ``[dynamics]`` table at its speed (THEORY §9).

    A table the report cannot study (no ``operation.speed_rpm``, no mass) gives a section
    that says why; the report is still written.

    Parameters
    ----------
    design : CamDesign
        A design with a ``[dynamics]`` table.

    Returns
    -------
    str
        The section (:func:`camtol.report.dynamics.dynamics_section`).
    """
    from camtol.dynamics.run import DynamicsInputs, run_dynamics
    from camtol.exceptions import DesignError
    from camtol.report.dynamics import dynamics_section

    if design.speed_rpm is None:
        return dynamics_section(None, note="the design gives no operation.speed_rpm")
    try:
        return dynamics_section(run_dynamics(design, DynamicsInputs()))
    except DesignError as exc:
        return dynamics_section(None, note=str(exc))


@click.command()
@design_options
@click.option(
    "--output", "-o", "output", metavar="FILE.html", required=True, help="Report file (.html)."
)
@step_option()
@inspection_options
@click.option(
    "--cmm",
    "cmm",
    metavar="SCAN.csv|.dmi",
    help="CMM scan of a single cam (as `camtol inspect --points`): its inspection against"
    " the design's [inspection] zone goes into the report (a pair: --cmm-a/--cmm-b).",
)
@click.option(
    "--u-cmm-um",
    "u_cmm_um",
    type=Number(low=0, unit="µm"),
    help="With --cmm and --decision guard-band: the CMM's expanded uncertainty U [µm].",
)
@click.option(
    "--no-fail",
    is_flag=True,
    help="Exit 0 once the report is written, even when the inspected part fails.",
)
@_traceability_options
@click.option(
    "--radius-table",
    is_flag=True,
    help="Append the cam drawing's radius table (profile radius every 1° of polar angle).",
)
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
@click.option(
    "--montecarlo",
    "mc_samples",
    type=Number(low=1, integer=True),
    metavar="N",
    help="Add a linear Monte Carlo section with N samples (docs/tolerancing.md).",
)
@click.option(
    "--mc-spec-um", type=float, help="With --montecarlo: spec on max |dS| of a lift [um]."
)
@click.option(
    "--mc-spec-deg", type=float, help="With --montecarlo: spec on max |dS| of a swing [deg]."
)
@click.option(
    "--mc-band",
    metavar="FILE.csv",
    help="With --montecarlo: band lower <= dS <= upper (as `camtol montecarlo --band`).",
)
def report(
    design: str | None,
    example: str | None,
    output: str,
    step_deg: float,
    df_mea: str | None,
    record_path: str | None,
    drop_bad_revolutions: bool,
    master_a: str | None,
    master_b: str | None,
    cmm_a: str | None,
    cmm_b: str | None,
    cmm_stylus_mm: float,
    cmm_datum: str,
    decision: str,
    cmm: str | None,
    u_cmm_um: float | None,
    no_fail: bool,
    radius_table: bool,
    as_json: bool,
    quiet: bool,
    mc_samples: int | None,
    mc_spec_um: float | None,
    mc_spec_deg: float | None,
    mc_band: str | None,
    **traceability: str | None,
) -> None:
    """Write a self-contained HTML report: verdict, inputs, conventions, extremes, figures.

    One file with inline SVG figures and no scripts: it opens offline and prints to a clean
    PDF (A4; tables and figures are not split). The verdict comes first, in the terminal
    line and as a PASS/FAIL banner at the top of the report.

    A measured conjugate pair gets an inspection report: the design's [inspection] table,
    with the same inputs as `camtol conjugate` (--df-mea, --record, --master-a/-b,
    --cmm-a/-b, --decision). Exit status 1 when the inspected part fails (after the report is
    written), 0 when it passes or when there is no measurement (a design-only report shows
    the design checks but never fails the command); --no-fail always exits 0 once the
    file is written. Traceability fields come from the design's [traceability] table or
    the options.
    """

    def body() -> int:
        from camtol.analysis.result import analyse
        from camtol.report.html import write_report
        from camtol.report.qa import InspectionReport, overall_verdict

        csv_inputs = {
            flag: value
            for flag, value in (
                ("--df-mea", df_mea),
                ("--master-a", master_a),
                ("--master-b", master_b),
                ("--record", record_path),
                ("--cmm-a", cmm_a),
                ("--cmm-b", cmm_b),
                ("--cmm", cmm),
                ("--mc-band", mc_band),
            )
            if value is not None and Path(value).exists()
        }
        guard_paths({"DESIGN": design, **csv_inputs}, {"--output": output})
        from camtol.cli.recording import check_trace_text
        from camtol.pair.kinematics import is_pair

        check_trace_text({f"--{k.replace('_', '-')}": v for k, v in traceability.items()})
        d = load_input(design, example)  # the kind of design decides which scans apply
        check_cmm_options(cmm_a, cmm_b, cmm_stylus_mm, cmm_datum, cmm=cmm, pair=is_pair(d))
        if decision == "guard-band" and cmm is not None and u_cmm_um is None:
            fail(
                "--decision guard-band needs the measurement uncertainty: give --u-cmm-um U"
                " (the CMM's expanded uncertainty, µm), or use --decision simple"
            )
        check_output_path(output, "--output", [".html", ".htm"])
        mc_limits = {"--mc-spec-um": mc_spec_um, "--mc-spec-deg": mc_spec_deg, "--mc-band": mc_band}
        mc_given = [k for k, v in mc_limits.items() if v is not None]
        if mc_given and mc_samples is None:
            fail(f"{mc_given[0]} is only allowed with --montecarlo N")
        mc_spec = mc_curves = None
        if mc_samples is not None:
            from camtol.cli.tolerancing import band_option, parse_motion_spec

            mc_spec = parse_motion_spec(
                d.mechanism.output, mc_spec_um, mc_spec_deg, flag="--mc-spec"
            )
            mc_curves = band_option(d, mc_band, mc_spec, flag="--mc-band", spec_flag="--mc-spec")
        a = analyse(d, step_deg=step_deg)
        sections: list[str] = []
        if mc_samples is not None:
            from camtol.report.tolerancing import montecarlo_section
            from camtol.tolerancing import monte_carlo

            study = monte_carlo(d, mc_samples, spec=mc_spec, band=mc_curves, step_deg=step_deg)
            sections.append(montecarlo_section(study, d))
        if d.extras.get("dynamics") is not None:  # the design's [dynamics] table (issue 33)
            sections.append(dynamics_report_section(d))
        fixture = None
        cmm_part = None
        if cmm is not None:
            cmm_part, section = _cmm_part(
                d, cmm, cmm_stylus_mm, cmm_datum, decision, u_cmm_um, step_deg, traceability
            )
            sections.insert(0, section)
        if is_pair(d) and (
            d.inspection is not None
            or has_inspection_input(df_mea, record_path, master_a, master_b, cmm_a, cmm_b)
        ):
            from camtol.grid import check_step
            from camtol.pair.fixture import MAX_FIXTURE_POINTS
            from camtol.pair.fixture_run import run_fixture  # a pair's only (start-up)

            check_step(step_deg, name="--step", min_points=4, max_points=MAX_FIXTURE_POINTS)
            inputs = command_fixture_inputs()
            run = run_fixture(d, inputs, who="the inspection options of `camtol report` need")
            fixture = InspectionReport(run.inspection, run.spec, run.record, run.decision)
        elif has_inspection_input(df_mea, record_path, master_a, master_b, cmm_a, cmm_b) or (
            decision != "simple" and cmm is None
        ):
            fail(
                f"follower.type={d.mechanism.kind!r}: --df-mea, --record, --master-a/-b,"
                " --cmm-a/-b, --decision need a conjugate design (follower.type = 'conjugate')"
            )
        from camtol.analysis.drawing import analysis_drawing
        from camtol.analysis.radius_table import radius_table as make_radius_table
        from camtol.study import Study

        given = {k: v for k, v in traceability.items() if v is not None}
        write_report(
            Study(a, analysis_drawing(a)),  # the fixture results are passed in below
            output,
            fixture=fixture,
            traceability=given,
            radius_table=make_radius_table(d) if radius_table else None,
            sections=sections,
            cmm=cmm_part,
        )
        verdict = overall_verdict(a, fixture, cmm=cmm_part)
        from camtol.report.display import display_analysis

        shown = display_analysis(a)
        worst = shown.extremes["dS_worst"][0]
        status = EXIT_FAIL if verdict.inspected and not verdict.passed and not no_fail else EXIT_OK
        if as_json:
            from camtol.report.tables import accuracy_json

            doc: dict[str, Any] = {
                "path": str(output),
                "design": a.design.name,
                "verdict": {
                    "status": verdict.status,
                    "inspected": verdict.inspected,
                    "reasons": list(verdict.reasons),
                },
                "max_worst_case": {"value": worst.value, "unit": shown.error_unit},
                "accuracy": accuracy_json(a.accuracy),
            }
            if fixture is not None and fixture.inspection.verdicts:
                from camtol.pair.decision import decision_rule_text

                doc["decision_rule"] = {
                    "rule": fixture.decision,
                    "statement": decision_rule_text(fixture.decision),
                }
            echo_json(doc, command="report")
        elif not quiet:
            import textwrap

            click.echo(textwrap.fill(verdict.headline, 80, subsequent_indent="  "))
            click.echo(f"wrote {output}")
        return status

    raise _Exit(run_guarded(body))
