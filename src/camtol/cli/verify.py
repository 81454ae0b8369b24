"""``camtol verify``: check the analytic engine with exact contact geometry (THEORY §5).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 0 when every check
passes, 1 when one fails, 2 on bad input.
"""

from __future__ import annotations

import click

from camtol.cli.common import EXIT_FAIL, EXIT_OK, _Exit, echo_json, load_input, run_guarded
from camtol.cli.options import design_options, step_option
from camtol.report.units import pretty_unit

__all__ = ["verify"]


def _mark(ok: bool) -> str:
    return "ok" if ok else "FAILED"


def _print_summary(v: object) -> None:
    from camtol.verify import ROUNDTRIP_LIMIT, Verification

    assert isinstance(v, Verification)
    u = v.output_unit

    def echo(text: str) -> None:  # 80 columns; continuation lines indented
        import textwrap

        indent = " " * min(len(text) - len(text.lstrip()) + 2, 17)
        click.echo(textwrap.fill(text, width=80, subsequent_indent=indent))

    echo(f"camtol verify: {v.design_name} ({v.follower}), grid {v.step_deg:g}°")
    echo(
        f"  round trip     max |S_contact - S| = {v.roundtrip_max_error:.3g} {u}"
        f" (limit {ROUNDTRIP_LIMIT:g})  {_mark(v.roundtrip_ok)}"
    )
    acc = v.roundtrip_acceleration_max_error
    echo(
        f"                 V: {v.roundtrip_velocity_max_error:.3g} {u}/rad"
        + ("" if acc is None else f", A: {acc:.3g} {u}/rad²")
    )
    if "roundtrip_delta_f_max_mm" in v.extras:
        echo(f"                 fixture Δf: {v.extras['roundtrip_delta_f_max_mm']:.3g} mm")
    polys = [("", v.polyline)]
    if "polyline_b" in v.extras:
        polys = [("cam A ", v.polyline), ("cam B ", v.extras["polyline_b"])]
    for label, p in polys:
        if p is None:
            continue
        d = p if isinstance(p, dict) else p.__dict__
        echo(
            f"  polyline       {label}{d['points']} points (chordal tolerance"
            f" {d['chordal_tolerance_mm'] * 1e3:g} µm): max error {d['max_error']:.4g} {u},"
            f" expected from the chordal sag {d['expected_max_error']:.4g} {u}"
            f"  {_mark(bool(d['ok']))}"
        )
    if v.linearisation:
        unit = next(iter(v.linearisation.values())).unit
        what = (
            "Δf of the measuring fixture"
            if "linearisation_quantity" in v.extras
            else "ΔS at the design's tolerances"
        )
        shown = pretty_unit(unit)
        echo(f"  linearisation  closed form against exact re-simulation, {what} ({shown}):")
        click.echo(
            f"    {'source':<7}{'linear max':>13}{'exact max':>13}{'|diff| max':>13}"
            f"{'at half':>12}{'ratio':>7}"
        )
        for c in v.linearisation.values():
            ratio = "exact" if c.exact_to_rounding else f"{c.halving_ratio:.2f}"
            click.echo(
                f"    {c.key:<7}{c.linear_max:>13.6g}{c.exact_max:>13.6g}"
                f"{c.max_difference:>13.3g}{c.half_difference:>12.3g}{ratio:>7}  {_mark(c.ok)}"
            )
        echo(
            "    (|diff| must stay within 1 % of the linear max and fall by about 4 when the"
            " tolerance is halved: second order)"
        )
    for n in v.notes:
        echo(f"  note: {n}")
    echo("result: all checks passed" if v.ok else "result: CHECKS FAILED")


@click.command()
@design_options
@step_option(min_points=4, max_points=360_000)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--no-polyline", is_flag=True, help="Skip the exported-polyline check (faster).")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing (exit status only).")
def verify(
    design: str | None,
    example: str | None,
    step_deg: float,
    as_json: bool,
    no_polyline: bool,
    quiet: bool,
) -> None:
    """Verify a design's analytic results with the exact contact engine (THEORY §5).

    Round trip of the synthesised profile, the exported polyline against its chordal sag,
    and the closed-form error of every toleranced source against exact re-simulation of
    the perturbed mechanism (for conjugate designs: of the measuring fixture).
    """

    def body() -> int:
        from camtol.verify import verify as run

        result = run(load_input(design, example), step_deg=step_deg, polyline=not no_polyline)
        if as_json:
            echo_json(result.to_dict(), command="verify")
        elif not quiet:
            _print_summary(result)
        return EXIT_OK if result.ok else EXIT_FAIL

    raise _Exit(run_guarded(body))
