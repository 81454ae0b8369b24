"""``camtol size``: the smallest base radius (and best offset) that makes a design work.

With ``--jump-margin M`` it also proposes the return spring (rate and preload) that keeps
a force-closed follower on the cam up to M times the running speed (THEORY §9.8).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 0 when a size is
found, 2 on bad input or when no base radius can meet the requirements.
"""

from __future__ import annotations

import math
from typing import Any

import click

from camtol.cli.common import EXIT_OK, _Exit, echo_json, load_input, run_guarded
from camtol.cli.dynamics import train_options, train_overrides
from camtol.cli.options import Number, design_options, step_option

__all__ = ["size"]


#: How the text output names the linkage lengths (follower fields) of --linkage.
_DIMENSION_NAMES = {
    "pivot_distance_mm": "pivot distance f",
    "arm_length_mm": "arm length l",
    "arm_a_mm": "arm length l_A",
    "arm_b_mm": "arm length l_B",
    "face_offset_mm": "face offset e",
}


def _finite(x: float) -> float | None:
    return x if math.isfinite(x) else None


def spring_json(proposal: Any) -> dict[str, Any]:
    """JSON-ready dict of a :class:`~camtol.dynamics.spring.SpringProposal` (file units)."""
    osc = proposal.train.output == "oscillating"
    return {
        "spring_rate_nm_per_rad" if osc else "spring_rate_n_per_mm": proposal.spring_rate,
        "preload_nm" if osc else "preload_n": proposal.preload,
        "rpm": proposal.rpm,
        "jump_margin": proposal.margin,
        "jump_speed_rpm": proposal.jump_speed_rpm,
    }


def sizing_json(result: Any) -> dict[str, Any]:
    """JSON-ready dict of a :class:`~camtol.analysis.sizing.SizingResult` (units in the keys)."""
    return {
        "base_radius_mm": round(result.base_radius_mm, 6),
        "given_base_radius_mm": result.given_base_radius_mm,
        "offset_mm": None if result.offset_mm is None else round(result.offset_mm, 6),
        "limiting": result.limiting,
        "pressure_angle_limit_deg": result.pressure_angle_limit_deg,
        "min_radius_mm": result.min_radius_mm,
        "cutter_radius_mm": result.cutter_radius_mm,
        "tolerance_mm": result.tolerance_mm,
        "linkage": result.linkage,
        "dimensions_mm": {k: round(v, 6) for k, v in result.dimensions_mm.items()},
        "given_dimensions_mm": result.given_dimensions_mm,
        "cams": [
            {
                "cam": c.label or "cam",
                "max_abs_pressure_angle_deg": round(c.max_abs_pressure_angle_deg, 4),
                "pressure_angle_min_deg": round(c.pressure_angle_deg.min, 4),
                "pressure_angle_max_deg": round(c.pressure_angle_deg.max, 4),
                "min_convex_radius_mm": _finite(round(c.min_convex_radius_mm, 4)),
                "min_convex_radius_at_deg": _finite(c.min_convex_radius_at_deg),
                "min_concave_radius_mm": _finite(round(c.min_concave_radius_mm, 4)),
                "min_concave_radius_at_deg": _finite(c.min_concave_radius_at_deg),
            }
            for c in result.cams
        ],
    }


@click.command()
@design_options
@click.option(
    "--pressure-angle-limit",
    "limit_deg",
    type=Number(low=0, low_open=True, high=90, unit="deg"),
    metavar="DEG",
    help="Largest allowed |pressure angle| [deg] (default: the design's"
    " operation.pressure_angle_limit_deg, else 90).",
)
@click.option(
    "--min-radius",
    "min_radius_mm",
    type=Number(low=0, low_open=True, unit="mm"),
    metavar="MM",
    help="Smallest allowed convex radius of curvature of the profile [mm].",
)
@click.option(
    "--cutter-radius",
    "cutter_radius_mm",
    type=Number(low=0, low_open=True, unit="mm"),
    metavar="MM",
    help="Cutter or wheel radius; concave stretches must be at least this flat [mm].",
)
@click.option(
    "--optimise-offset",
    is_flag=True,
    help="Also choose the offset of a translating roller follower (smallest max |φ|).",
)
@click.option(
    "--linkage",
    type=click.Choice(["fixed", "pivot", "scale"]),
    default="fixed",
    show_default=True,
    help="Oscillating follower: keep the pivot distance and arm length (fixed), choose the"
    " pivot distance for the smallest max |φ| with the arm kept (pivot), or scale both"
    " with the base radius (scale).",
)
@step_option(max_points=360_000)
@click.option(
    "--jump-margin",
    "jump_margin",
    type=Number(low=1, low_open=True),
    metavar="M",
    help="Also propose the return spring (rate, preload) that keeps the follower on the"
    " cam up to M × the running speed (THEORY §9.8); the train from [dynamics].",
)
@click.option(
    "--rpm",
    type=Number(low=0, low_open=True, unit="rpm"),
    metavar="RPM",
    help="Running speed for --jump-margin [rpm] (default: operation.speed_rpm).",
)
@train_options
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def size(
    design: str | None,
    example: str | None,
    limit_deg: float | None,
    min_radius_mm: float | None,
    cutter_radius_mm: float | None,
    optimise_offset: bool,
    linkage: str,
    step_deg: float,
    jump_margin: float | None,
    rpm: float | None,
    as_json: bool,
    **train: Any,
) -> None:
    """Find the smallest base radius (offset, linkage) meeting pressure-angle and curvature limits.

    The motion is kept; every cam of the design is checked (both cams of a conjugate
    pair). A translating roller follower's offset is chosen with --optimise-offset; an
    oscillating follower's pivot distance (and arm length) with --linkage pivot (or
    scale); every other dimension is kept. With --jump-margin, also the return spring of a
    force-closed follower for that margin over the running speed (--rpm).
    """

    def body() -> int:
        from camtol.analysis.sizing import minimum_base_radius

        overrides = train_overrides(train)
        if jump_margin is None and (rpm is not None or overrides):
            from camtol.cli.common import fail

            fail("--rpm and the train's options are for --jump-margin: give it too")
        d = load_input(design, example)
        spring = None
        if jump_margin is not None:
            from camtol.dynamics.spring import size_spring

            spring = size_spring(d, rpm, jump_margin, overrides=overrides)
        r = minimum_base_radius(
            d,
            pressure_angle_limit_deg=limit_deg,
            min_radius_mm=min_radius_mm,
            cutter_radius_mm=cutter_radius_mm,
            optimise_offset=optimise_offset,
            step_deg=step_deg,
            linkage=linkage,
        )
        if as_json:
            doc = sizing_json(r)
            if spring is not None:
                doc["spring"] = spring_json(spring)
            echo_json(doc, command="size")
            return EXIT_OK
        click.echo(f"design             {d.name}")
        click.echo(
            f"base radius r_b    {r.base_radius_mm:.3f} mm minimum"
            f" (given {r.given_base_radius_mm:g} mm; resolution {r.tolerance_mm:g} mm)"
        )
        if r.offset_mm is not None:
            click.echo(f"offset e           {r.offset_mm:.3f} mm (smallest max |φ|)")
        how = {"pivot": "smallest max |φ|", "scale": "scaled with r_b"}.get(r.linkage, "")
        for key, value in r.dimensions_mm.items():
            given = r.given_dimensions_mm[key]
            note = "kept" if value == given else how
            click.echo(
                f"{_DIMENSION_NAMES.get(key, key):<18} {value:.3f} mm ({note}; given {given:g} mm)"
            )
        click.echo(f"limited by         {r.limiting}")
        for c in r.cams:
            name = f"cam {c.label}" if c.label else "cam"
            click.echo(
                f"{name:<18} max |φ| {c.max_abs_pressure_angle_deg:.2f}°; min convex ρ"
                f" {c.min_convex_radius_mm:.4g} mm"
            )
            click.echo(
                " " * 19
                + (
                    f"min concave ρ {c.min_concave_radius_mm:.4g} mm"
                    if math.isfinite(c.min_concave_radius_mm)
                    else "no concave stretch"
                )
            )
        if spring is not None:
            osc = spring.train.output == "oscillating"
            k_unit, p_unit = ("N·m/rad", "N·m") if osc else ("N/mm", "N")
            j = spring.jump_speed_rpm
            jump = "none found" if j is None else f"{j:.6g} rpm"
            click.echo(
                f"return spring      {spring.spring_rate:.4g} {k_unit},"
                f" preload {spring.preload:.4g} {p_unit}"
            )
            click.echo(
                f"                   jump speed {jump} ({spring.margin:g} × {spring.rpm:g} rpm"
                " wanted)"
            )
        return EXIT_OK

    raise _Exit(run_guarded(body))
