"""``camtol inspect``: a machined cam checked from a CMM scan (issue 12; THEORY §2, §3, §5).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 1 when the cam fails
its profile zone, 0 when it passes, 2 on bad input (nothing written then).

Why one module: the command and the parsers of its own options (``--datum``, ``--columns``,
``--tolerance-um``, the record grid of ``--store``), which ``camtol conjugate`` and
``camtol report`` reuse for their CMM scans.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import click

from camtol.cli.common import (
    EXIT_FAIL,
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    fail,
    load_input,
    run_guarded,
)
from camtol.cli.options import Number, decision_flag, design_options, step_option
from camtol.cli.recording import check_store_options, store_options

if TYPE_CHECKING:
    from camtol.inspection.deviations import CmmInspection
    from camtol.inspection.registration import Datum

__all__ = [
    "inspect",
    "parse_columns",
    "parse_datum",
    "parse_numbers",
    "parse_zone_option",
    "record_grid_points",
]


def parse_numbers(text: str, count: int, option: str, what: str) -> tuple[float, ...]:
    """Parse ``count`` comma-separated finite numbers, or end with a usage error.

    Parameters
    ----------
    text : str
        The option's value.
    count : int
        How many numbers.
    option : str
        The option's name, for the message.
    what : str
        What to give, e.g. ``"X,Y in mm"``.
    """
    try:
        vals = tuple(float(v) for v in text.split(","))
    except ValueError:
        vals = ()
    if len(vals) != count or not all(math.isfinite(v) for v in vals):
        fail(f"{option}={text!r} is not allowed; give {what}")
    return vals


def parse_zone_option(text: str | None) -> tuple[float, float] | None:
    """Parse ``--tolerance-um``: T (a zone T wide, ±T/2) or LO,HI; None when not given.

    Parameters
    ----------
    text : str or None
        The option's value. [µm]

    Returns
    -------
    (float, float) or None
        The zone's limits (lower, upper). [µm]
    """
    if text is None:
        return None
    if "," not in text:
        (t,) = parse_numbers(text, 1, "--tolerance-um", "T (zone width, µm) or LO,HI in µm")
        if not 0 < t <= 20_000:
            fail(f"--tolerance-um={text!r} is not allowed; give a zone width T > 0 µm (≤ 20000)")
        return -0.5 * t, 0.5 * t
    lo, hi = parse_numbers(text, 2, "--tolerance-um", "T (zone width, µm) or LO,HI in µm")
    if not lo < hi:
        fail(f"--tolerance-um={text!r} is not allowed; give LO,HI with LO < HI (µm)")
    return lo, hi


#: Record grids a CMM record may use, finest first (points over 360°).
RECORD_GRIDS = (3600, 1800, 1440, 720, 360, 180, 72, 36)


def record_grid_points(insp: CmmInspection) -> int:
    """Return the finest record grid the scan's largest polar gap allows (any ``--step``).

    The store's resampling rule (:func:`camtol.records.lots.scan_on_grid`) allows a gap of
    :data:`~camtol.records.lots.MAX_GAP_STEPS` grid steps; a 720-point scan is stored on a
    0.25° grid, a 3600-point one on 0.1°.

    Parameters
    ----------
    insp : CmmInspection
        The inspection (its kept points' polar angles).

    Returns
    -------
    int
        Points n of the record grid.
    """
    from camtol.records.lots import MAX_GAP_STEPS, largest_polar_gap

    gap, _ = largest_polar_gap(insp.theta_deg[insp.kept])
    for n in RECORD_GRIDS:
        if gap <= MAX_GAP_STEPS * 360.0 / n:
            return n
    return RECORD_GRIDS[-1]  # refused by the store's rule, with its message


def parse_columns(text: str | None) -> dict[str, str] | None:
    """Parse ``--columns X=x_mm,Y=y_mm`` into a header mapping.

    Parameters
    ----------
    text : str or None
        The option's value (None: no mapping).
    """
    if text is None:
        return None
    out: dict[str, str] = {}
    for part in text.split(","):
        name, sep, target = part.partition("=")
        if not sep or not name.strip() or not target.strip():
            fail(f"--columns={text!r} is not allowed; give NAME=column pairs such as X=x_mm,Y=y_mm")
        out[name.strip()] = target.strip()
    return out


def parse_datum(
    text: str, angle: float | None, point: str | None, loss: str, keyway: float | None = None
) -> Datum:
    """Build the registration :class:`~camtol.inspection.registration.Datum` from options.

    Parameters
    ----------
    text : str
        ``--datum``: fit, fit-rotation, bore, centre:X,Y or centre:X,Y,DEG. [mm, deg]
    angle : float or None
        ``--datum-angle``. [deg]
    point : str or None
        ``--datum-point`` X,Y,DEG. [mm, mm, deg]
    loss : str
        ``--loss``.
    keyway : float or None
        ``--keyway-deg``: nominal polar angle of the keyway flagged in the scan. [deg]
    """
    from camtol.inspection.registration import Datum

    if keyway is not None and not math.isfinite(keyway):
        fail(f"--keyway-deg={keyway!r} must be a finite number of degrees")
    if keyway is not None and (angle is not None or point is not None):
        fail("--keyway-deg is the angular datum: leave out --datum-angle and --datum-point")

    centre = None
    mode = text
    if text.startswith("centre:") or text.startswith("center:"):
        values = text.split(":", 1)[1]
        if values.count(",") == 2:  # centre:X,Y,DEG: centre and stated angle at once
            x, y, a = parse_numbers(values, 3, "--datum", "centre:X,Y or centre:X,Y,DEG")
            if angle is not None:
                fail(f"--datum={text!r} states the angle already; leave out --datum-angle")
            angle = a
        else:
            x, y = parse_numbers(values, 2, "--datum", "centre:X,Y or centre:X,Y,DEG (mm, deg)")
        mode, centre = "centre", (x, y)
    if mode not in ("fit", "fit-rotation", "bore", "centre"):
        fail(f"--datum={text!r} is not allowed; use fit, fit-rotation, bore or centre:X,Y (mm)")
    pt = pt_angle = None
    if point is not None:
        x, y, a = parse_numbers(point, 3, "--datum-point", "X,Y,DEG (mm, mm, nominal degrees)")
        pt, pt_angle = (x, y), a
    if angle is not None and not math.isfinite(angle):
        fail(f"--datum-angle={angle!r} must be a finite number of degrees")
    return Datum(
        mode=mode,  # type: ignore[arg-type]
        centre_mm=centre,
        angle_deg=angle,
        point_mm=pt,
        point_angle_deg=pt_angle,
        loss=loss,  # type: ignore[arg-type]
        keyway_deg=keyway,
    )


@click.command()
@design_options
@click.option(
    "--points",
    "points_path",
    required=True,
    metavar="FILE.csv|.dmi|.dmo",
    help="CMM points: CSV with columns x_mm, y_mm [, z_mm, bore, cam] (units in names),"
    " or DMIS output (FA(label)=FEAT/POINT,CART,x,y,z,i,j,k with its UNITS).",
)
@click.option(
    "--cam",
    type=click.Choice(["A", "B"]),
    default="A",
    show_default=True,
    help="Which cam of a conjugate pair the scan is.",
)
@click.option(
    "--stylus-radius-mm",
    "stylus_mm",
    type=Number(low=0, unit="mm"),
    default=None,
    help="Stylus-ball radius: the points are ball centres, compensated along the"
    " local normal (0: surface points; default: the scan header's, else 0) [mm].",
)
@click.option(
    "--columns", metavar="NAME=col,...", help="Map the file's column names, e.g. X=x_mm,Y=y_mm."
)
@click.option(
    "--datum",
    "datum_text",
    default="fit",
    show_default=True,
    metavar="fit|fit-rotation|bore|centre:X,Y[,DEG]",
    help="Registration: best fit (rotation+translation), rotation only, bore circle"
    " (points flagged bore=1) or a given centre [mm] (and stated angle [deg]).",
)
@click.option(
    "--datum-angle",
    "datum_angle",
    type=float,
    metavar="DEG",
    help="Stated rotation of the cam's reference radial in the CMM frame [deg]"
    " (with bore or centre).",
)
@click.option(
    "--datum-point",
    "datum_point",
    metavar="X,Y,DEG",
    help="A datum point (keyway) in CMM mm at this nominal polar angle [deg].",
)
@click.option(
    "--keyway-deg",
    "keyway_deg",
    type=float,
    metavar="DEG",
    help="Feature datum: the points flagged keyway=1 lie at this nominal polar angle [deg]"
    " (with bore or centre).",
)
@click.option(
    "--loss",
    type=click.Choice(["soft_l1", "huber", "linear"]),
    default="soft_l1",
    show_default=True,
    help="Robust loss of the best fit.",
)
@click.option(
    "--tolerance-um",
    "tolerance",
    metavar="T|LO,HI",
    help="Profile zone [µm]: T, a zone T wide (ISO 1101: ±T/2 about the nominal), or the"
    " limits LO,HI (default: the design's [inspection] zone).",
)
@click.option(
    "--tolerance-on",
    "tolerance_on",
    type=click.Choice(["dn", "dr"]),
    help="Deviation the zone bounds: dn (normal, ISO 1101; default) or dr (a radial band,"
    " not ISO 1101).",
)
@decision_flag(
    "Decision rule (ISO 14253-1): 'simple' judges the deviations against the zone;"
    " 'guard-band' against the zone shrunk by U on both sides (needs --u-cmm-um)."
)
@click.option(
    "--u-cmm-um",
    "u_cmm_um",
    type=Number(low=0, unit="µm"),
    help="The CMM's expanded uncertainty U (k = 2) [µm], combined with a bore datum's.",
)
@click.option(
    "--harmonics",
    type=Number(low=1, integer=True),
    default=100,
    show_default=True,
    help="Fourier cut-off smoothing Δn for the follower error.",
)
@step_option(help_text="Cam-angle step of the follower error [deg].", min_points=4)
@click.option(
    "--spec-um",
    type=float,
    help="Motion spec: largest allowed max |ΔS| measured of a lift [µm]; the cam fails above it.",
)
@click.option(
    "--spec-deg",
    type=float,
    help="Motion spec: largest allowed max |ΔS| measured of a swing [deg].",
)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option(
    "--curves",
    metavar="FILE.csv",
    help="Write x_mm, y_mm, theta_deg, dn_um, dr_um per measured point.",
)
@click.option(
    "--motion",
    metavar="FILE.csv",
    help="Write theta_deg, dS_measured_<unit>, dS_linear_<unit> per cam angle.",
)
@click.option("--plot", metavar="FILE.png", help="Write the inspection figure (PNG/SVG/PDF).")
@click.option("--report", "report_path", metavar="FILE.html", help="Write an HTML report.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing (exit status only).")
@store_options
def inspect(
    design: str | None,
    example: str | None,
    points_path: str,
    cam: str,
    stylus_mm: float | None,
    columns: str | None,
    datum_text: str,
    datum_angle: float | None,
    datum_point: str | None,
    keyway_deg: float | None,
    loss: str,
    tolerance: str | None,
    tolerance_on: str | None,
    decision: str,
    u_cmm_um: float | None,
    harmonics: int,
    step_deg: float,
    spec_um: float | None,
    spec_deg: float | None,
    as_json: bool,
    curves: str | None,
    motion: str | None,
    plot: str | None,
    report_path: str | None,
    quiet: bool,
    **store_opts: str | None,
) -> None:
    """Inspect a machined cam from CMM points: registration, deviations, follower error.

    Registers the scan to the nominal profile (datum frame or robust best fit, with
    random and form uncertainties), computes the normal deviation Δn of every point to
    the exact analytic profile, the radial deviation Δr, the form and minimum zone, the
    verdict against the profile zone (ISO 1101: the design's [inspection]
    profile_tolerance_um, or --tolerance-um; floating without a datum, located with
    one) with the failing stretches, and the follower's motion error on the measured cam
    (exact, and linear from Δn), judged against the motion spec (--spec-um/--spec-deg)
    when given. Exit status 1 when the cam fails either.

    The traceability options (--part-number, --serial, --date, ...) go into --report and
    --json; with --store DB the inspected cam is recorded with them (see `camtol
    records`): its Δr on the finest record grid (0.1° to 10°) that the scan's largest
    gap allows, whatever --step (docs/cmm-inspection.md).
    """

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(motion, "--motion", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        check_output_path(report_path, "--report", [".html", ".htm"])
        aliases = parse_columns(columns)
        datum = parse_datum(datum_text, datum_angle, datum_point, loss, keyway_deg)
        tol = parse_zone_option(tolerance)
        if decision == "guard-band" and u_cmm_um is None:
            fail(
                "--decision guard-band needs the measurement uncertainty: give --u-cmm-um U"
                " (the CMM's expanded uncertainty, µm), or use --decision simple"
            )
        store = check_store_options(store_opts)
        from camtol.cli.recording import report_traceability
        from camtol.inspection.cmm import header_stylus_radius_mm
        from camtol.inspection.cmm_run import CmmInputs, run_cmm
        from camtol.inspection.deviations import cam_profile
        from camtol.report import inspection_report as rep

        d = load_input(design, example)
        prof = cam_profile(d, cam)  # type: ignore[arg-type]
        from camtol.cli.tolerancing import parse_motion_spec

        spec = parse_motion_spec(prof.mechanism.output, spec_um, spec_deg)
        kind = None if tolerance_on is None else ("normal" if tolerance_on == "dn" else "radial")
        header_r = header_stylus_radius_mm(points_path)
        stylus_note = None
        stylus = stylus_mm
        if stylus is None:
            stylus = header_r or 0.0
            if header_r:
                stylus_note = f"stylus radius {header_r:g} mm from the scan's header"
        elif header_r is not None and header_r != stylus and not quiet:
            click.echo(
                f"camtol: warning: the scan's header says stylus {header_r:g} mm;"
                f" --stylus-radius-mm {stylus:g} is used",
                err=True,
            )
        inputs = CmmInputs(
            points_path=points_path,
            cam=cam,  # type: ignore[arg-type]
            stylus_radius_mm=stylus,
            aliases=aliases,
            datum=datum,
            tolerance_um=tol,
            tolerance_kind=kind,  # type: ignore[arg-type]
            harmonics=harmonics,
            step_deg=step_deg,
            spec=spec,
            decision=decision,
            u_cmm_um=u_cmm_um,
        )
        run = run_cmm(d, inputs, profile=prof)
        if run.functional_error is not None:
            import warnings

            warnings.warn(f"follower error not computed: {run.functional_error}", stacklevel=1)
        insp, func = run.inspection, run.functional
        data = rep.inspection_json(insp, func, design=d.name, stylus_radius_mm=stylus)
        if stylus_note is not None:
            data["stylus_radius_source"] = "header"
        data["traceability"] = rep.traceability_json(
            report_traceability(store_opts), design=d, scan_path=points_path
        )
        for opt, wanted in (("--motion", motion), ("--spec-um/--spec-deg", spec)):
            if wanted is not None and func is None:
                fail(f"{opt}: the follower error could not be computed (see the warning)")
        prepared = None
        if store is not None:  # the record (gap rule, duplicates) is checked before any output
            from camtol.cli.recording import cmm_prepared

            n_record = record_grid_points(insp)

            prepared = cmm_prepared(
                store,
                store_opts,
                d,
                design,
                example,
                inputs,
                run,
                n_points=n_record,
                spec_um=spec_um,
                spec_deg=spec_deg,
            )
        fig = None
        if plot or report_path:
            from camtol.report.inspection_plots import inspection_figure

            fig = inspection_figure(insp, prof, func)
        if curves:
            rep.write_curves_csv(insp, curves)
        if motion and func is not None:
            rep.write_motion_csv(func, motion)
        if plot and fig is not None:
            from camtol.files import atomic_output

            with atomic_output(plot) as tmp:
                fig.savefig(tmp, format=Path(plot).suffix.lstrip(".").lower())
        if report_path and fig is not None:
            from camtol.files import atomic_write
            from camtol.report.inline_svg import figure_svg

            atomic_write(
                report_path, rep.inspection_report_html(data, figure_svg(fig, prefix="insp"))
            )
        record_id = None
        if store is not None and prepared is not None:  # after every output file
            from camtol.cli.recording import add_records

            record_id = add_records(store, prepared)[0]
        for w in () if quiet else insp.registration.warnings:  # -q: exit status only
            for line in rep.wrap_line(f"camtol: warning: {w}"):
                click.echo(line, err=True)
        if as_json:
            data["record_ids"] = [] if record_id is None else [record_id]  # in --store
            echo_json(data, command="inspect", schema_version=rep.INSPECT_SCHEMA_VERSION)
        elif not quiet:
            for line in rep.inspection_text(data):
                click.echo(line)
        if record_id is not None and not quiet:
            click.echo(f"recorded as id {record_id}", err=as_json)
        return EXIT_OK if data["verdict"] == "pass" else EXIT_FAIL

    raise _Exit(run_guarded(body))


def cmm_comparison_lines(summary: dict[str, float]) -> list[str]:
    """Text lines of the CMM-fixture comparison ([CW11] Table 4 figures, µm)."""
    lines = [
        f"CMM: rms Δr_A {summary['rms_dr_A_cmm_um']:.2f} µm,"
        f" rms Δr_B {summary['rms_dr_B_cmm_um']:.2f} µm; fixture predicted from the CMM"
        f" profiles: rms Δf {summary['rms_df_twin_um']:.2f} µm (exact),"
        f" {summary['rms_df_est_um']:.2f} µm (eqs. 14-18)"
    ]
    if "rms_df_mea_um" in summary:
        lines.append(
            f"against Δf_mea (rms {summary['rms_df_mea_um']:.2f} µm): rms(Δf_est − Δf_mea)"
            f" {summary['rms_df_est_minus_mea_um']:.2f} µm"
            f" ({100 * summary['relative_deviation_df_est']:.2f}%), rms(Δf_twin − Δf_mea)"
            f" {summary['rms_df_twin_minus_mea_um']:.2f} µm"
            f" ({100 * summary['relative_deviation_df_twin']:.2f}%)"
        )
    if "rms_dr_A_est_minus_cmm_um" in summary:
        lines.append(
            "fixture estimates against the CMM (each with the other cam's CMM error as"
            f" master): rms(Δr_A,est − Δr_A,CMM) {summary['rms_dr_A_est_minus_cmm_um']:.2f} µm,"
            f" rms(Δr_B,est − Δr_B,CMM) {summary['rms_dr_B_est_minus_cmm_um']:.2f} µm"
        )
    return lines
