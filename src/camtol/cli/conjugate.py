"""``camtol conjugate``: the conjugate-cam fixture analysis (THEORY §4; [CW11]).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 1 when an inspected
cam fails its acceptance band, 0 when both pass (or when there is no measured record), 2 on
bad input.
"""

from __future__ import annotations

from pathlib import Path

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
from camtol.cli.inspection_options import decision_option
from camtol.cli.options import Number, design_options, step_option
from camtol.cli.recording import add_records, check_store_options, fixture_prepared, store_options

__all__ = ["conjugate"]


def _file_arg(value: str | None) -> str | None:
    """Return the path of a VALUE|FILE.csv|FORMULA option naming a file, else None."""
    if value is None or not value.strip().lower().endswith(".csv"):
        return None
    return value.strip()


@click.command()
@design_options
@click.option(
    "--df-mea",
    "df_mea",
    metavar="VALUE|FILE.csv|FORMULA",
    help="Measured centre-distance variation Δf: '22 um', '0.022 mm', a CSV of theta_deg,um,"
    " or a formula in theta (rad) / theta_deg giving µm. Overrides inspection.df_mea_um.",
)
@click.option(
    "--record",
    "record_path",
    metavar="FILE.csv",
    help="Dial-indicator record (CSV columns df_um, index[, time_s]; THEORY §4.4): its mean"
    " over complete revolutions is Δf_mea, and the estimates at Δf_mea ± u_f are reported."
    " Not with --df-mea.",
)
@click.option(
    "--drop-bad-revolutions",
    is_flag=True,
    help="With --record: exclude revolutions with more than 1.5× or fewer than 0.67× the"
    " median number of samples (a missed or spurious index mark) and report them, instead"
    " of refusing the record.",
)
@click.option(
    "--master-a",
    metavar="VALUE|FILE.csv|FORMULA",
    help="Known radial error of master cam A (µm), as for --df-mea.",
)
@click.option(
    "--master-b",
    metavar="VALUE|FILE.csv|FORMULA",
    help="Known radial error of master cam B (µm), as for --df-mea.",
)
@step_option(
    help_text="Grid step [deg]; must divide 360° into a whole number of steps, 0.001° to 90°.",
    min_points=4,
    max_points=360_000,
)
@decision_option
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option(
    "--curves",
    metavar="FILE.csv",
    help="Write one row per angle: Δf parts, Δr_A,est, Δr_B,est and the four bands (µm).",
)
@click.option(
    "--plot",
    metavar="FILE.png",
    help="Write the fixture figure: Δf parts, estimated errors, acceptance bands (PNG/SVG/PDF).",
)
@click.option(
    "--cmm-a",
    metavar="SCAN.csv",
    help="CMM scan of cam A (with --cmm-b): the CMM errors become the masters and the"
    " fixture is compared with the CMM ([CW11] Table 4; docs/cmm-inspection.md).",
)
@click.option("--cmm-b", metavar="SCAN.csv", help="CMM scan of cam B (with --cmm-a).")
@click.option(
    "--cmm-plot",
    metavar="FILE.png",
    help="With --cmm-a/--cmm-b: write Δf predicted from the CMM profiles against the record"
    " and their differences (PNG/SVG/PDF).",
)
@click.option(
    "--cmm-stylus-radius-mm",
    "cmm_stylus_mm",
    type=Number(low=0, unit="mm"),
    default=0.0,
    show_default=True,
    help="Stylus radius of the CMM scans (0: surface points) [mm].",
)
@click.option(
    "--cmm-datum",
    default="fit",
    show_default=True,
    metavar="fit|fit-rotation|bore|centre:X,Y[,DEG]",
    help="Registration of the CMM scans (as `camtol inspect --datum`).",
)
@click.option("--quiet", "-q", is_flag=True, help="Print nothing (exit status only).")
@store_options
def conjugate(
    design: str | None,
    example: str | None,
    df_mea: str | None,
    record_path: str | None,
    drop_bad_revolutions: bool,
    master_a: str | None,
    master_b: str | None,
    step_deg: float,
    decision: str,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    cmm_a: str | None,
    cmm_b: str | None,
    cmm_plot: str | None,
    cmm_stylus_mm: float,
    cmm_datum: str,
    quiet: bool,
    **store_opts: str | None,
) -> None:
    """Conjugate-cam fixture: Δf parts, inverse analysis Δr_A,est / Δr_B,est, acceptance.

    The design's [inspection] table gives the tolerances, the follower's constant errors,
    the master cams' errors and the measured Δf (THEORY §4, §8.3); the options override
    them. Prints the extremes and a verdict per inspected cam with the cam-angle intervals
    where it fails. Exit status 1 when a cam fails.

    --decision chooses the conformance rule (ISO 14253-1): 'simple' accepts a cam whose
    Δf_mea is in its band; 'guard-band' (with --record) only when Δf_mea ± u_f is, i.e.
    the acceptance zone shrunk by the uncertainty. The rule is stated in the output.

    With --record the indicator record is processed (THEORY §4.4): its mean over complete
    revolutions is Δf_mea and the verdicts are taken on it; the inverse estimates at the
    statistical representatives Δf_mea ± u_f (u_f: 3 standard deviations over
    revolutions) are reported as upper and lower worst-case estimates. A revolution far
    longer or shorter than the median (a missed or spurious index mark) is an error, or
    with --drop-bad-revolutions excluded and reported.

    With --store DB each inspected cam (A and B) is recorded in an inspection store with
    the traceability options (see `camtol records`).
    """

    def body() -> int:
        guard_paths(
            {
                "DESIGN": design,
                "--record": record_path,
                "--df-mea": _file_arg(df_mea),
                "--master-a": _file_arg(master_a),
                "--master-b": _file_arg(master_b),
                "--cmm-a": cmm_a,
                "--cmm-b": cmm_b,
            },
            {"--curves": curves, "--plot": plot, "--cmm-plot": cmm_plot},
        )
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        check_output_path(cmm_plot, "--cmm-plot", [".png", ".svg", ".pdf"])
        if cmm_plot and cmm_a is None:
            fail("--cmm-plot needs the CMM scans: give --cmm-a and --cmm-b")
        from camtol.cli.inspection_options import command_fixture_inputs
        from camtol.pair.decision import decision_rule_text
        from camtol.pair.fixture_run import run_fixture
        from camtol.pair.kinematics import require_pair
        from camtol.report import conjugate as rep

        store = check_store_options(store_opts)
        d = load_input(design, example)
        require_pair(d, "`camtol conjugate` needs")
        inputs = command_fixture_inputs()
        run = run_fixture(d, inputs, who="`camtol conjugate` needs")
        res, spec, estimates, rule, comparison = (
            run.inspection,
            run.spec,
            run.record,
            run.decision,
            run.comparison,
        )
        prepared = None  # the records are checked before any output and stored after them
        if store is not None:
            prepared = fixture_prepared(store, store_opts, d, design, example, inputs, run)
        if curves:
            rep.write_fixture_curves_csv(res, curves, record=estimates)
        if plot:
            from camtol.files import atomic_output
            from camtol.report.finite import require_finite_columns
            from camtol.report.plots import fixture_figure

            require_finite_columns(
                rep.fixture_curves_columns(res, record=estimates),
                optional=rep.OPTIONAL_FIXTURE_COLUMNS,
                where=plot,
            )
            fig = fixture_figure(
                res,
                tolerance_a_um=spec.tolerance_a_um,
                tolerance_b_um=spec.tolerance_b_um,
                design_name=d.name,
                record=estimates,
                decision_rule=rule,
            )
            with atomic_output(plot) as tmp:
                fig.savefig(tmp, format=Path(plot).suffix.lstrip(".").lower())
        if cmm_plot and comparison is not None:
            from camtol.files import atomic_output
            from camtol.report.inspection_plots import cmm_fixture_figure

            with atomic_output(cmm_plot) as tmp:
                cmm_fixture_figure(comparison).savefig(
                    tmp, format=Path(cmm_plot).suffix.lstrip(".").lower()
                )
        stored = [] if prepared is None else add_records(store or "", prepared)
        if as_json:
            data = rep.fixture_json(res, spec, d.name, record=estimates)
            data["decision_rule"] = {"rule": rule, "statement": decision_rule_text(rule)}
            if comparison is not None:
                data["cmm_comparison"] = comparison.summary()
            data["record_ids"] = list(stored)  # ids of cams A, B in --store ([] without)
            echo_json(data, command="conjugate")
        elif not quiet:
            rep.print_fixture(res, spec, d.name, record=estimates)
            if res.verdicts:
                import textwrap

                click.echo(textwrap.fill(f"Decision rule: {decision_rule_text(rule)}.", 80))
            if comparison is not None:
                from camtol.cli.inspect import cmm_comparison_lines

                for line in cmm_comparison_lines(comparison.summary()):
                    click.echo(line)
        if stored and not quiet:
            click.echo(f"recorded cams A, B as ids {stored[0]}, {stored[1]}", err=as_json)
        return EXIT_FAIL if res.passed is False else EXIT_OK

    raise _Exit(run_guarded(body))
