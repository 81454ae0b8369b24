"""``camtol precision``, ``camtol cut`` and ``camtol derive``: manufacturing checks (THEORY §6).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 0 on success, 2 on bad
input (one line on stderr, nothing written). Output files go through
:func:`camtol.files.atomic_write`.

Why one module: the three commands are the command-line face of one concept, the
precision a cam is made and measured to (THEORY §6: table precision, cutting step,
derivatives of a measured lift); they share their option parsing and output helpers.
"""

from __future__ import annotations

import math
from typing import Any

import click

from camtol.cli.common import (
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    fail,
    guard_paths,
    load_checked,
    run_guarded,
)
from camtol.cli.options import MAX_TOOL_RADIUS_MM, Number, design_options

__all__ = ["cut", "derive", "precision"]

#: ``camtol cut --json`` layout: 1.1 chose ``coarsest_cut_step_deg`` among the listed
#: steps (1.0: a hidden candidate list) and added ``lift_tolerance_unit`` and the
#: velocity jumps (issue 32).
CUT_SCHEMA_VERSION = "1.1"
#: derive --json 1.1 (issue 32): A_uncertainty_* includes the smoothing bias; the noise
#: and the bias are given beside it (A_noise_*, A_smoothing_bias_*).
DERIVE_SCHEMA_VERSION = "1.1"


def _floats(text: str, option: str) -> list[float]:
    try:
        values = [float(v) for v in text.replace(";", ",").split(",") if v.strip()]
    except ValueError:
        fail(f"{option}={text!r} is not allowed; give comma-separated numbers, e.g. 1,2,5,10")
    if not values:
        fail(f"{option}={text!r} is not allowed; give at least one number")
    return values


def _wrapped_echo(text: str) -> None:
    """Print a line wrapped to 80 columns, its continuation indented under its text."""
    import textwrap

    lead = " " * (len(text) - len(text.lstrip(" ")) + 2)
    click.echo(textwrap.fill(text, 80, subsequent_indent=lead, break_on_hyphens=False))


def _ints(text: str, option: str) -> list[int]:
    values = _floats(text, option)
    if not all(math.isfinite(v) and v == int(v) for v in values):  # int(nan) would raise
        fail(f"{option}={text!r} is not allowed; give whole numbers of decimals, e.g. 3,4,5,6")
    return [int(v) for v in values]


# ---------------------------------------------------------------------------------------
# precision
# ---------------------------------------------------------------------------------------
_PRECISION_KEYS = (
    "max_abs_dV_central",
    "max_abs_dA_central",
    "max_abs_dA_spline",
    "bound_alternating",
    "bound_dip",
)


def _precision_json(st: Any) -> dict[str, Any]:
    u = st.lift_unit
    tables = []
    for r in st.rows:
        row: dict[str, Any] = {"decimals": r.decimals, f"quantum_{u}": r.quantum}
        row.update({k: getattr(r, k) for k in _PRECISION_KEYS})
        row["max_abs_dV_spline"] = r.max_abs_dV_spline
        row["bound_spline"] = r.bound_spline
        if st.speed_rad_s is not None:
            w = st.speed_rad_s
            for k in _PRECISION_KEYS:
                order = 1 if "dV" in k else 2
                row[f"{k}_{u}_per_s{order if order > 1 else ''}"] = getattr(r, k) * w**order
        tables.append(row)
    doc: dict[str, Any] = {
        "design": st.design_name,
        "table_step_deg": st.table_step_deg,
        "lift_unit": u,
        "derivative_units": {"V": f"{u}/rad", "A": f"{u}/rad2"},
        "speed_rad_s": st.speed_rad_s,
        "max_abs_A": st.max_abs_acceleration,
        "unrounded": {
            "max_abs_dV_central": st.truncation_dV_central,
            "max_abs_dA_central": st.truncation_dA_central,
            "truncation_estimate_dA": st.truncation_estimate_dA,
        },
        "tables": tables,
    }
    if st.accel_budget_pct is not None:
        doc["accel_budget_pct"] = st.accel_budget_pct
        doc["recommended_decimals"] = st.recommended_decimals
    return doc


@click.command()
@design_options
@click.option(
    "--table-step", "table_step_deg", type=float, default=1.0, show_default=True, metavar="DEG",
    help="Spacing of the lift table [deg]; must divide 360.",
)  # fmt: skip
@click.option(
    "--decimals", "decimals_text", default="3,4,5,6", show_default=True, metavar="K,...",
    help="Numbers of decimals to round the table to, comma-separated.",
)  # fmt: skip
@click.option(
    "--accel-budget", "accel_budget_pct", type=Number(low=0, low_open=True, unit="%"),
    default=None, metavar="PCT",
    help="Acceptable acceleration error in % of max |A|: recommends the fewest decimals.",
)  # fmt: skip
@click.option("--json", "as_json", is_flag=True, help="Print the study as JSON.")
def precision(
    design: str | None,
    example: str | None,
    table_step_deg: float,
    decimals_text: str,
    accel_budget_pct: float | None,
    as_json: bool,
) -> None:
    """How precise must the lift table be? (THEORY §6.1, §6.2)

    Tabulates the design's lift every --table-step, rounds it to each number of decimals,
    and compares V and A from central differences and from camtol's periodic spline with
    the analytic V and A, beside the handbook bounds 4s/Δθ² (alternating) and 2s/Δθ²
    (single dip), s = Q/2, and the spline's exact bound 6Q/Δθ². Per radian of cam angle.
    """

    def body() -> int:
        from camtol.grid import check_step
        from camtol.manufacturing.precision import MAX_DECIMALS, table_precision

        decimals = _ints(decimals_text, "--decimals")
        if not all(0 <= k <= MAX_DECIMALS for k in decimals):
            fail(
                f"--decimals={decimals_text!r} is not allowed; give whole numbers from 0 to"
                f" {MAX_DECIMALS}"
            )
        check_step(table_step_deg, name="--table-step", min_points=8)
        st = table_precision(
            load_checked(design, example),
            table_step_deg=table_step_deg,
            decimals=decimals,
            accel_budget_pct=accel_budget_pct,
        )
        if as_json:
            echo_json(_precision_json(st), command="precision")
            return EXIT_OK
        u = st.lift_unit
        echo = click.echo
        echo(
            f"camtol precision: {st.design_name}, table every {st.table_step_deg:g}°,"
            f" max |A| = {st.max_abs_acceleration:.6g} {u}/rad²"
        )
        import textwrap

        def para(text: str) -> None:  # wrapped to 80 columns, indented
            echo(textwrap.fill(text, 78, initial_indent="  ", subsequent_indent="  "))

        para(
            f"unrounded: central differences err by {st.truncation_dV_central:.3g} {u}/rad"
            f" (V) and {st.truncation_dA_central:.3g} {u}/rad² (A); truncation estimate"
            f" max(Δθ²/12·max|S''''|, Δθ/6·max|ΔJ|) = {st.truncation_estimate_dA:.3g} {u}/rad²"
        )
        heads = ["max|dV|cd", "max|dA|cd", "4s/Δθ²", "2s/Δθ²", "max|dA|sp", "6Q/Δθ²"]
        echo(f"  {'dec':>3} {'Q ' + u:>7}" + "".join(f" {h:>9}" for h in heads))
        for r in st.rows:
            values = [
                r.max_abs_dV_central,
                r.max_abs_dA_central,
                r.bound_alternating,
                r.bound_dip,
                r.max_abs_dA_spline,
                r.bound_spline,
            ]
            echo(f"  {r.decimals:>3d} {r.quantum:>7.0e}" + "".join(f" {v:>9.4g}" for v in values))
        para(
            f"dec: decimals of the table; Q: its rounding step; dV in {u}/rad, dA and the"
            f" bounds in {u}/rad²; cd: central differences, sp: camtol's periodic spline;"
            " s is half of Q."
        )
        if st.accel_budget_pct is not None:
            rec = st.recommended_decimals
            echo(
                f"  budget {st.accel_budget_pct:g} % of max |A|: "
                + (
                    f"tabulate with {rec} decimals"
                    if rec is not None
                    else "no studied precision meets it (try more decimals or a finer table)"
                )
            )
        return EXIT_OK

    raise _Exit(run_guarded(body))


# ---------------------------------------------------------------------------------------
# cut
# ---------------------------------------------------------------------------------------
def _cut_json(res: Any) -> dict[str, Any]:
    u = res.lift_error_unit
    lu = "deg" if res.oscillating else "mm"
    scale = 180.0 / math.pi if res.oscillating else 1.0
    return {
        "cut_step_deg": res.cut.cut_step_deg,
        "tool": res.cut.tool,
        "read_step_deg": res.read_step_deg,
        f"max_abs_lift_error_{u}": float(abs(res.lift_error_display).max()),
        "max_abs_dA_central": float(abs(res.central_acceleration_error).max()) * scale,
        "scallop_height_um": float(res.scallop_height_mm.max()) * 1e3,
        "rule_rho_delta2_over_8_um": float(res.rule_mm.max()) * 1e3,
        "max_abs_dV_exact": float(abs(res.velocity_error).max()) * scale,
        "max_abs_dA_exact": float(abs(res.acceleration_error).max()) * scale,
        "velocity_jumps": int(res.velocity_jump.size),
        "max_velocity_jump": res.max_velocity_jump * scale,
        "derivative_units": {"V": f"{lu}/rad", "A": f"{lu}/rad2"},
    }


@click.command()
@design_options
@click.option(
    "--cut-step", "cut_steps_text", default="1,2,5,10", show_default=True, metavar="DEG,...",
    help="Cutting steps δ [deg], comma-separated; each must divide 360.",
)  # fmt: skip
@click.option(
    "--tool", type=click.Choice(["flat", "cylinder"]), default="flat", show_default=True,
    help="Flat tool (half-planes) or cylindrical tool (disks).",
)  # fmt: skip
@click.option(
    "--tool-radius", "tool_radius_mm", default=None, metavar="MM",
    type=Number(low=0, low_open=True, high=MAX_TOOL_RADIUS_MM, unit="mm"),
    help="Cylinder radius [mm] (wire EDM: wire radius + spark gap).",
)  # fmt: skip
@click.option(
    "--read-step", "read_step_deg", type=float, default=None, metavar="DEG",
    help="Reading step [deg] (default δ/20, never coarser than 0.1°).",
)  # fmt: skip
@click.option(
    "--cam", type=click.Choice(["A", "B"]), default="A", show_default=True,
    help="Which cam of a conjugate pair to cut.",
)  # fmt: skip
@click.option(
    "--lift-tolerance-um", "lift_tol_um", type=Number(low=0, low_open=True, unit="µm"),
    default=None, metavar="UM",
    help="Translating follower: the coarsest listed step whose lift error stays within UM.",
)  # fmt: skip
@click.option(
    "--lift-tolerance-deg", "lift_tol_deg", type=Number(low=0, low_open=True, unit="deg"),
    default=None, metavar="DEG",
    help="Oscillating follower: the coarsest listed step whose arm-angle error stays within"
    " DEG.",
)  # fmt: skip
@click.option(
    "--accel-budget", "accel_budget_pct", type=Number(low=0, low_open=True, unit="%"),
    default=None, metavar="PCT",
    help="The coarsest listed step whose second-difference A error stays within PCT % of"
    " max |A|.",
)  # fmt: skip
@click.option(
    "--curves", "curves_path", default=None, metavar="FILE.csv",
    help="Write the lift error of every cut step against θ.",
)  # fmt: skip
@click.option("--json", "as_json", is_flag=True, help="Print the results as JSON.")
def cut(
    design: str | None,
    example: str | None,
    cut_steps_text: str,
    tool: str,
    tool_radius_mm: float | None,
    read_step_deg: float | None,
    cam: str,
    lift_tol_um: float | None,
    lift_tol_deg: float | None,
    accel_budget_pct: float | None,
    curves_path: str | None,
    as_json: bool,
) -> None:
    """Simulate cutting at discrete cam angles and follow the cut cam exactly (THEORY §6.3).

    The tool is set at the angles kδ (flat: the cam is the intersection of half-planes;
    cylinder: the blank minus the tool's disks), the follower's motion on the cut cam is
    found with the contact engine at the reading step, and the lift, V and A errors, the
    scallop height and the rule ρδ²/8 are reported per cut step, with the follower's
    velocity jump at the cusps. With a lift tolerance or an A budget, the coarsest of the
    listed steps that meets it is recommended.
    """

    def body() -> int:
        import numpy as np

        from camtol.files import atomic_write
        from camtol.manufacturing.cut_study import CutStudyInputs, cut_study
        from camtol.report.csv_text import csv_text
        from camtol.report.finite import require_finite_columns

        if lift_tol_um is not None and lift_tol_deg is not None:
            fail("give --lift-tolerance-um (translating) or --lift-tolerance-deg (oscillating)")
        lift_tol = lift_tol_um if lift_tol_um is not None else lift_tol_deg
        inputs = CutStudyInputs(
            cut_steps_deg=tuple(_floats(cut_steps_text, "--cut-step")),
            tool="cylinder" if tool == "cylinder" else "flat",
            tool_radius_mm=tool_radius_mm,
            read_step_deg=read_step_deg,
            cam=cam,
            lift_tolerance=lift_tol,
            accel_budget_pct=accel_budget_pct,
            curves=curves_path is not None,
            lift_tolerance_unit=(
                None if lift_tol is None else "um" if lift_tol_um is not None else "deg"
            ),
        )
        guard_paths({"DESIGN": design}, {"--curves": curves_path})
        check_output_path(curves_path, "--curves", [".csv"])
        study = cut_study(load_checked(design, example), inputs)
        results, coarsest = study.results, study.coarsest_cut_step_deg
        oscillating = results[0].oscillating
        if curves_path is not None and study.curves_theta_deg is not None:
            u = results[0].lift_error_unit
            header = ["theta_deg"] + [f"lift_error_{u}_{s:g}deg" for s in inputs.cut_steps_deg]
            data = np.column_stack([study.curves_theta_deg, *study.curves_lift_error])
            require_finite_columns(dict(zip(header, data.T, strict=True)), where=curves_path)
            atomic_write(curves_path, csv_text(header, data))
        if as_json:
            doc: dict[str, Any] = {
                "design": study.design_name,
                "cam": study.cam,
                "tool": tool,
                "tool_radius_mm": tool_radius_mm,
                "cuts": [_cut_json(r) for r in results],
            }
            if inputs.has_criteria:
                doc["lift_tolerance"] = lift_tol
                doc["lift_tolerance_unit"] = inputs.lift_tolerance_unit
                doc["accel_budget_pct"] = accel_budget_pct
                doc["coarsest_cut_step_deg"] = coarsest
            echo_json(doc, command="cut", schema_version=CUT_SCHEMA_VERSION)
            return EXIT_OK
        u = results[0].lift_error_unit
        lu = "°" if oscillating else "mm"
        pretty = "µm" if u == "um" else "°"
        what = "flat tool" if tool == "flat" else f"cylinder R = {tool_radius_mm:g} mm"
        echo = click.echo
        echo(f"camtol cut: {study.design_name}, {what}")
        echo(
            f"  {'step°':>6} {'read°':>6} {'max|ΔS| ' + pretty:>11} {'scallop µm':>10}"
            f" {'ρδ²/8 µm':>9} {'V jump':>9} {'A 2nd diff':>11}"
        )
        for r in results:
            j = _cut_json(r)
            echo(
                f"  {r.cut.cut_step_deg:>6g} {r.read_step_deg:>6g}"
                f" {j[f'max_abs_lift_error_{u}']:>11.4g} {j['scallop_height_um']:>10.4g}"
                f" {j['rule_rho_delta2_over_8_um']:>9.4g} {j['max_velocity_jump']:>9.4g}"
                f" {j['max_abs_dA_central']:>11.4g}"
            )
        echo(f"  [V jump in {lu}/rad, A 2nd diff in {lu}/rad²]")
        if any(r.velocity_jump.size for r in results):
            echo(
                "  The follower's velocity jumps at each cusp (an impulse of A); second\n"
                "  differences read a jump ΔV as ΔV/Δθ_read, so 'A 2nd diff' grows as the\n"
                "  reading step shrinks: it measures the jumps, not the curve between them."
            )
        if inputs.has_criteria:
            import textwrap

            wanted = []
            if lift_tol is not None:
                wanted.append(f"max|ΔS| ≤ {lift_tol:g}{'' if u == 'deg' else ' '}{pretty}")
            if accel_budget_pct is not None:
                wanted.append(f"A 2nd diff ≤ {accel_budget_pct:g} % of max|A|")
            steps = ", ".join(f"{s:g}°" for s in inputs.cut_steps_deg)
            text = (
                f"coarsest listed step with {' and '.join(wanted)}: {coarsest:g}°"
                if coarsest is not None
                else f"none of the listed steps ({steps}) has {' and '.join(wanted)}; list"
                " finer steps with --cut-step"
            )
            echo(textwrap.fill(text, 78, initial_indent="  ", subsequent_indent="  "))
        if curves_path is not None:
            click.echo(f"wrote {curves_path}")
        return EXIT_OK

    raise _Exit(run_guarded(body))


# ---------------------------------------------------------------------------------------
# derive
# ---------------------------------------------------------------------------------------
@click.command()
@click.argument("lift_csv", metavar="LIFT.csv", type=click.Path(dir_okay=False))
@click.option(
    "--method", type=click.Choice(["spline", "savgol"]), default="spline", show_default=True,
    help="Periodic smoothing spline or Savitzky-Golay (cubic) filter.",
)  # fmt: skip
@click.option(
    "--smoothing", type=Number(low=0, low_open=True), default=None, metavar="X",
    help="Spline λ [rad³] or Savitzky-Golay window [samples]; default: by GCV or noise.",
)  # fmt: skip
@click.option(
    "--noise-um",
    type=Number(low=0, low_open=True, unit="µm"),
    default=None,
    metavar="UM",
    help="Known rms lift noise [µm] (lift_mm files).",
)
@click.option(
    "--noise-deg",
    type=Number(low=0, low_open=True, unit="deg"),
    default=None,
    metavar="DEG",
    help="Known rms lift noise [deg] (lift_deg files).",
)
@click.option(
    "--output", "-o", "output", default=None, metavar="FILE.csv", help="Write S, V, A, J."
)
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def derive(
    lift_csv: str,
    method: str,
    smoothing: float | None,
    noise_um: float | None,
    noise_deg: float | None,
    output: str | None,
    as_json: bool,
) -> None:
    """V, A and J of a measured or tabulated lift, with a stated smoothing (THEORY §6.1).

    LIFT.csv has the columns theta_deg and lift_mm (or lift_deg), one revolution in equal
    steps (a closing 360° row is dropped). Prints the smoothing chosen and the noise
    amplification: how many mm/rad² of A noise each µm of lift noise becomes.
    """

    def body() -> int:
        import numpy as np

        from camtol.exceptions import InputFileError
        from camtol.files import atomic_write
        from camtol.grid import drop_closing_row
        from camtol.manufacturing.derivatives import derive_lift
        from camtol.report.csv_text import csv_text
        from camtol.report.finite import require_finite_columns
        from camtol.tables import read_table

        guard_paths({"LIFT.csv": lift_csv}, {"--output": output})
        check_output_path(output, "--output", [".csv"])
        table = read_table(lift_csv, required=["theta_deg"], optional=["lift_mm", "lift_deg"])
        cols = [c for c in ("lift_mm", "lift_deg") if c in table]
        if len(cols) != 1:
            raise InputFileError(
                f"{lift_csv}: give exactly one lift column, lift_mm or lift_deg; found"
                f" {', '.join(table.names)}"
            )
        unit = cols[0].removeprefix("lift_")
        noise = None
        if noise_um is not None:
            if unit != "mm":
                fail("--noise-um is for lift_mm files; use --noise-deg for lift_deg")
            noise = noise_um * 1e-3
        if noise_deg is not None:
            if unit != "deg" or noise_um is not None:
                fail("--noise-deg is for lift_deg files; use --noise-um for lift_mm")
            noise = noise_deg
        theta = table.column("theta_deg")
        lift = table.column(cols[0])
        theta, lift = drop_closing_row(
            theta, lift, source=lift_csv, name=cols[0], line_of=table.line_of
        )
        kind: Any = method
        res = derive_lift(
            theta,
            lift,
            method=kind,
            smoothing=smoothing,
            noise=noise,
            source=lift_csv,
            line_of=table.line_of,
        )
        # Gains per µm of lift noise (mm files) or per 0.001° (deg files).
        per = 1e-3
        g = res.gains
        if output is not None:
            header = [
                "theta_deg",
                f"lift_{unit}",
                f"lift_smoothed_{unit}",
                f"V_{unit}_per_rad",
                f"A_{unit}_per_rad2",
                f"J_{unit}_per_rad3",
            ]
            data = np.column_stack(
                [theta, res.lift_measured, res.lift, res.velocity, res.acceleration, res.jerk]
            )
            names = ["theta_deg", "lift", "lift_smoothed", "V", "A", "J"]
            require_finite_columns(dict(zip(names, data.T, strict=True)), where=output)
            atomic_write(output, csv_text(header, data))
        noise_unit = "um" if unit == "mm" else "mdeg"
        doc = {
            "file": lift_csv,
            "lift_unit": unit,
            "samples": int(theta.size),
            "method": res.method,
            "smoothing_parameter": res.parameter,
            "smoothing_parameter_unit": "rad3" if res.method == "spline" else "samples",
            "selection": res.selection,
            "effective_dof": res.effective_dof,
            "residual_rms": res.residual_rms,
            "noise_estimate": res.noise_estimate,
            f"noise_gain_per_{noise_unit}": {
                "S": g[0] * per,
                f"V_{unit}_per_rad": g[1] * per,
                f"A_{unit}_per_rad2": g[2] * per,
                f"J_{unit}_per_rad3": g[3] * per,
            },
            f"A_uncertainty_{unit}_per_rad2": res.acceleration_uncertainty,
            f"A_noise_{unit}_per_rad2": res.acceleration_noise,
            f"A_smoothing_bias_{unit}_per_rad2": res.acceleration_bias,
            "max_abs_A": float(abs(res.acceleration).max()),
        }
        if as_json:
            echo_json(doc, command="derive", schema_version=DERIVE_SCHEMA_VERSION)
            return EXIT_OK
        nu = "µm" if unit == "mm" else "0.001°"
        how = {"gcv": "generalised cross-validation", "noise": "the given noise level",
               "given": "--smoothing"}[res.selection]  # fmt: skip
        par = (
            f"λ = {res.parameter:.4g} rad³"
            if res.method == "spline"
            else f"window = {res.parameter:g} samples (cubic)"
        )
        echo = _wrapped_echo  # 80 columns (issue 32)
        echo(f"camtol derive: {lift_csv}, {theta.size} samples every {360 / theta.size:g}°")
        echo(f"  smoothing: {res.method}, {par}, chosen by {how}; {res.effective_dof:.1f} dof")
        echo(
            f"  residual rms {res.residual_rms:.4g} {unit}; noise σ = {res.noise_estimate:.4g}"
            f" {unit} ({'given' if noise is not None else 'estimated'})"
        )
        echo(
            f"  noise amplification: 1 {nu} rms of lift noise gives {g[1] * per:.4g} {unit}/rad"
            f" in V, {g[2] * per:.4g} {unit}/rad² in A, {g[3] * per:.4g} {unit}/rad³ in J"
        )
        echo(
            f"  so A is uncertain by about ±{res.acceleration_uncertainty:.4g} {unit}/rad² (1σ)"
            f" against max |A| = {doc['max_abs_A']:.4g} {unit}/rad²"
        )
        echo(
            f"  = √(noise² + bias²): noise {res.acceleration_noise:.3g}, smoothing bias"
            f" {res.acceleration_bias:.3g} {unit}/rad²"
        )
        if output is not None:
            echo(f"wrote {output}")
        return EXIT_OK

    raise _Exit(run_guarded(body))
