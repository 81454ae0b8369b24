"""The G-code output of ``camtol profile -o cam.nc``: its options and its writer.

``camtol profile`` writes a CSV, DXF or SVG export itself and hands a G-code suffix here
(:data:`GCODE_SUFFIXES`): the machine's options (:func:`gcode_options`: arcs or lines, the
wire-EDM offset, the feed, the lead arcs, the Z moves) and the program written atomically
from :func:`camtol.manufacturing.gcode.write_gcode` (docs/manufacturing.md).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import click

from camtol.cli.common import EXIT_OK, check_output_path, echo_json, fail
from camtol.cli.options import MAX_TOOL_RADIUS_MM, Number

__all__ = ["GCODE_SUFFIXES", "gcode_options", "write_gcode_output"]


def gcode_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add the options that only G-code output takes (refused for CSV, DXF and SVG).

    Parameters
    ----------
    f : callable
        The command function (``camtol profile``).
    """
    for option in reversed(_OPTIONS):
        f = option(f)
    return f


_OPTIONS = [
    click.option(
        "--gcode",
        "gcode_mode",
        type=click.Choice(["arcs", "lines"]),
        default="arcs",
        show_default=True,
        help="G-code output: G02/G03 biarcs or G01 chords.",
    ),
    click.option(
        "--wire-radius",
        "wire_radius_mm",
        default=None,
        type=Number(low=0, high=MAX_TOOL_RADIUS_MM, unit="mm"),
        metavar="MM",
        help="G-code for wire EDM: wire radius [mm] (offset = wire radius + spark gap).",
    ),
    click.option(
        "--spark-gap",
        "spark_gap_mm",
        type=Number(low=0, unit="mm"),
        default=0.0,
        show_default=True,
        metavar="MM",
        help="Wire-EDM spark gap (overcut per side) [mm].",
    ),
    click.option(
        "--feed",
        "feed_mm_min",
        type=Number(low=0, low_open=True, high=1e6, unit="mm/min"),
        default=None,
        metavar="MM_PER_MIN",
        help="G-code: cutting feed [mm/min] (required for G-code).",
    ),
    click.option(
        "--lead-radius",
        "lead_radius_mm",
        type=Number(low=0, low_open=True, high=1e6, unit="mm"),
        default=None,
        metavar="MM",
        help="G-code: radius of the 90° lead-in/lead-out arcs [mm] (default: the tool offset,"
        " at least 1 mm).",
    ),
    click.option(
        "--safe-z",
        "safe_z_mm",
        type=Number(unit="mm"),
        default=None,
        metavar="MM",
        help="G-code with Z moves: retract height [mm] (with --cut-z; default: a 2D contour).",
    ),
    click.option(
        "--cut-z",
        "cut_z_mm",
        type=Number(unit="mm"),
        default=None,
        metavar="MM",
        help="G-code with Z moves: cutting depth [mm] (with --safe-z and --plunge-feed).",
    ),
    click.option(
        "--plunge-feed",
        "plunge_feed_mm_min",
        default=None,
        metavar="MM_PER_MIN",
        type=Number(low=0, low_open=True, high=1e6, unit="mm/min"),
        help="G-code with Z moves: feed of the plunge to --cut-z [mm/min].",
    ),
]


#: Output suffixes written as G-code by ``camtol profile``.
GCODE_SUFFIXES: tuple[str, ...] = (".nc", ".ngc", ".tap")


def write_gcode_output(
    load: Any,
    design: str | None,
    example: str | None,
    output: str,
    tolerance_um: float,
    cutter_radius_mm: float | None,
    mode: Any,
    wire_radius_mm: float | None,
    spark_gap_mm: float,
    as_json: bool,
    quiet: bool,
    machine: dict[str, float | None],
) -> int:
    """``camtol profile -o cam.nc``: the cutter-centre path as G-code (THEORY §6).

    Parameters
    ----------
    load : callable
        Loads the design from ``design`` or ``example`` (the command's loader).
    design, example : str or None
        ``DESIGN.toml`` or ``--example NAME``.
    output : str
        The program's path (``.nc``, ``.ngc`` or ``.tap``).
    tolerance_um : float
        Largest chord or biarc deviation from the cutter-centre path. [µm]
    cutter_radius_mm, wire_radius_mm : float or None
        The milling cutter's radius, or the EDM wire's (exactly one). [mm]
    mode : str
        ``arcs`` (G02/G03 biarcs) or ``lines`` (G01 chords).
    spark_gap_mm : float
        Wire EDM overcut added to the wire radius. [mm]
    as_json : bool
        Print the summary as JSON.
    quiet : bool
        Print nothing but errors.
    machine : dict
        ``feed_mm_min``, ``lead_radius_mm``, ``safe_z_mm``, ``cut_z_mm``,
        ``plunge_feed_mm_min`` as given (None: not given). [mm, mm/min]

    Returns
    -------
    int
        Exit status.
    """
    from camtol.files import atomic_write
    from camtol.manufacturing.gcode import write_gcode

    check_output_path(output, "--output", list(GCODE_SUFFIXES))
    if (cutter_radius_mm is None) == (wire_radius_mm is None):
        fail("G-code output needs exactly one of --cutter-radius MM or --wire-radius MM")
    if wire_radius_mm is None and spark_gap_mm != 0.0:
        fail("--spark-gap is the wire-EDM overcut: give --wire-radius MM as well")
    if wire_radius_mm is not None and wire_radius_mm + spark_gap_mm > MAX_TOOL_RADIUS_MM:
        fail(
            f"--wire-radius + --spark-gap = {wire_radius_mm + spark_gap_mm:g} mm is not"
            f" allowed; the offset may be at most {MAX_TOOL_RADIUS_MM:g} mm"
        )
    feed = machine["feed_mm_min"]
    if feed is None:
        fail("G-code output needs --feed MM_PER_MIN, the cutting feed rate of the machine")
    assert feed is not None  # fail() has left
    from camtol.analysis.validity import check_design_geometry

    d = load(design, example)
    check_design_geometry(d)  # an impossible cam is not cut (issue 9)
    prog = write_gcode(
        d,
        tool_radius_mm=cutter_radius_mm,
        tolerance_mm=tolerance_um * 1e-3,
        mode=mode,
        wire_radius_mm=wire_radius_mm,
        spark_gap_mm=spark_gap_mm,
        feed_mm_min=feed,
        lead_radius_mm=machine["lead_radius_mm"],
        safe_z_mm=machine["safe_z_mm"],
        cut_z_mm=machine["cut_z_mm"],
        plunge_feed_mm_min=machine["plunge_feed_mm_min"],
    )
    atomic_write(output, prog.text)
    if as_json:
        doc = {
            "path": str(output),
            "format": "gcode",
            "mode": prog.mode,
            "tolerance_um": prog.tolerance_mm * 1e3,
            "tool_radius_mm": prog.tool_radius_mm,
            "blocks": prog.blocks,
            "max_fit_deviation_um": prog.max_fit_deviation_mm * 1e3,
            "feed_mm_min": prog.feed_mm_min,
            "lead_radius_mm": prog.lead_radius_mm,
            "safe_z_mm": prog.safe_z_mm,
            "cut_z_mm": prog.cut_z_mm,
            "plunge_feed_mm_min": prog.plunge_feed_mm_min,
        }
        echo_json(doc, command="profile")
    elif not quiet:
        click.echo(
            f"G-code ({prog.mode}): {prog.blocks} blocks, cutter-path offset"
            f" {prog.tool_radius_mm:g} mm,\n  fit within {prog.max_fit_deviation_mm * 1e3:.3g} µm"
            f" (tolerance {prog.tolerance_mm * 1e3:g} µm), feed {prog.feed_mm_min:g} mm/min,"
            f" {'Z moves' if prog.cut_z_mm is not None else '2D contour (no Z)'}"
        )
        click.echo(f"wrote {output}")
    return EXIT_OK
