"""``camtol simulate``: digital twins that write input files with known truth (issue 12).

``camtol simulate cmm`` writes a CMM scan of a cam with a known profile error, placement
error, probe noise, stylus radius and outliers, and ``<scan>.truth.json`` beside it.
Registered on the ``camtol`` group by :mod:`camtol.cli.app`.
"""

from __future__ import annotations

import json
from pathlib import Path

import click

from camtol.cli.common import EXIT_OK, _Exit, check_output_path, fail, load_input, run_guarded
from camtol.cli.options import Number, design_options, seed_option

__all__ = ["simulate"]


@click.group()
def simulate() -> None:
    """Digital twins: simulated measurement files with their truth beside them."""


@simulate.command("cmm")
@design_options
@click.option(
    "--output",
    "-o",
    "output",
    required=True,
    metavar="SCAN.csv",
    help="Scan file to write (x_mm, y_mm); the truth goes to SCAN.truth.json.",
)
@click.option(
    "--cam",
    type=click.Choice(["A", "B"]),
    default="A",
    show_default=True,
    help="Which cam of a conjugate pair.",
)
@click.option(
    "--n-points",
    "points",
    type=Number(low=36, integer=True),  # camtol.inspection.cmm.MIN_POINTS
    default=3600,
    show_default=True,
    help="Profile points.",
)
@click.option("--points", "old_points", type=int, hidden=True)
@click.option(
    "--bore-points",
    type=Number(low=0, high=100_000, integer=True),
    default=0,
    show_default=True,
    help="Also write this many points on the bore (flagged bore=1; at least 3).",
)
@click.option(
    "--bore-radius-mm",
    type=Number(low=0, unit="mm"),
    help="Bore radius (default: 40 % of the cam's smallest radius) [mm].",
)
@click.option(
    "--keyway",
    "keyway_deg",
    type=Number(low=-360, high=360, unit="deg"),
    metavar="DEG",
    help="Also write a keyway point (keyway=1) at this nominal polar angle [deg];"
    " inspect with --datum bore --keyway-deg DEG.",
)
@click.option(
    "--noise-um",
    type=Number(low=0, high=1_000, unit="µm"),  # camtol.inspection.twin.MAX_NOISE_UM
    default=1.0,
    show_default=True,
    help="Probe noise along the normal (standard deviation) [µm].",
)
@seed_option
@click.option(
    "--stylus-radius-mm",
    "stylus_mm",
    type=Number(low=0, high=1_000, unit="mm"),  # twin.MAX_STYLUS_RADIUS_MM
    default=0.0,
    show_default=True,
    help="Write stylus-ball centres of this radius (0: surface points) [mm].",
)
@click.option(
    "--eccentricity-um",
    type=Number(low=-1e7, high=1e7, unit="µm"),  # twin.MAX_ECCENTRICITY_UM: 10 m
    default=0.0,
    show_default=True,
    help="Placement offset of the cam centre on the machine [µm].",
)
@click.option(
    "--eccentricity-deg",
    type=Number(low=-360, high=360, unit="deg"),
    default=0.0,
    show_default=True,
    help="Direction of the offset [deg].",
)
@click.option(
    "--rotation-deg",
    type=Number(low=-360, high=360, unit="deg"),
    default=0.0,
    show_default=True,
    help="Placement rotation of the cam on the machine [deg].",
)
@click.option(
    "--outliers",
    type=Number(low=0, integer=True),
    default=0,
    show_default=True,
    help="Points thrown off the surface by 50-100 µm.",
)
@click.option(
    "--error-rms-um",
    type=Number(low=0, unit="µm"),
    default=0.0,
    show_default=True,
    help="rms of a random Fourier profile error (harmonics 2-20, amplitude ∝ 1/k) [µm].",
)
@click.option(
    "--error-mean-um",
    type=Number(unit="µm"),
    default=0.0,
    show_default=True,
    help="Constant part of the profile error (material added) [µm].",
)
@click.option(
    "--error-kind",
    type=click.Choice(["radial", "normal"]),
    default="radial",
    show_default=True,
    help="Profile error along O2A (radial) or along the normal.",
)
def simulate_cmm(
    design: str | None,
    example: str | None,
    output: str,
    cam: str,
    points: int,
    old_points: int | None,
    bore_points: int,
    bore_radius_mm: float | None,
    keyway_deg: float | None,
    noise_um: float,
    seed: int,
    stylus_mm: float,
    eccentricity_um: float,
    eccentricity_deg: float,
    rotation_deg: float,
    outliers: int,
    error_rms_um: float,
    error_mean_um: float,
    error_kind: str,
) -> None:
    """Simulate a CMM scan of a cam (digital twin) with its truth in SCAN.truth.json."""

    def body() -> int:
        nonlocal points
        check_output_path(output, "--output", [".csv", ".txt"])
        if old_points is not None:  # the old name of --n-points (a count, not a file)
            ctx = click.get_current_context()
            if ctx.get_parameter_source("points") is click.core.ParameterSource.COMMANDLINE:
                fail("--points is the old name of --n-points: give --n-points once")
            if old_points < 36:
                fail(f"--points={old_points} is not allowed; give --n-points ≥ 36")
            click.echo("camtol: warning: --points is renamed --n-points", err=True)
            points = old_points
        if keyway_deg is not None and bore_points < 3:
            fail("--keyway is cut in the bore: give --bore-points N (N ≥ 3) as well")
        if 0 < bore_points < 3:
            fail(f"--bore-points={bore_points} is not allowed; give 0 or at least 3")
        if outliers > points // 10:  # camtol.inspection.twin: a tenth of the points at most
            fail(
                f"--outliers={outliers} is not allowed; give a whole number from 0 to"
                f" {points // 10} (a tenth of --n-points)"
            )
        from camtol.files import atomic_write
        from camtol.inspection.twin import random_profile_error, scan_csv_text, simulate_scan

        d = load_input(design, example)
        err = None
        if error_rms_um > 0 or error_mean_um != 0:
            err = random_profile_error(error_rms_um, seed=seed, mean_um=error_mean_um)
        sim = simulate_scan(
            d,
            cam=cam,  # type: ignore[arg-type]
            points=points,
            noise_um=noise_um,
            seed=seed,
            stylus_radius_mm=stylus_mm,
            eccentricity_um=eccentricity_um,
            eccentricity_deg=eccentricity_deg,
            rotation_deg=rotation_deg,
            outliers=outliers,
            profile_error=err,
            error_kind=error_kind,  # type: ignore[arg-type]
            bore_points=bore_points,
            bore_radius_mm=bore_radius_mm,
            keyway_deg=keyway_deg,
        )
        p = Path(output)
        truth = p.with_name(p.stem + ".truth.json")
        atomic_write(p, scan_csv_text(sim))
        atomic_write(truth, json.dumps(sim.truth.to_json(), indent=2) + "\n")
        click.echo(f"wrote {p} ({points} points) and {truth}")
        return EXIT_OK

    raise _Exit(run_guarded(body))


@simulate.command("record")
@design_options
@click.option(
    "--output",
    "-o",
    "output",
    required=True,
    metavar="RECORD.csv",
    help="Indicator record to write (time_s, df_um, index).",
)
@click.option(
    "--truth-a",
    required=True,
    metavar="SCAN_A.truth.json",
    help="Truth of the simulated CMM scan of cam A (its profile error).",
)
@click.option(
    "--truth-b",
    required=True,
    metavar="SCAN_B.truth.json",
    help="Truth of the simulated CMM scan of cam B.",
)
@click.option(
    "--noise-um",
    type=Number(low=0, unit="µm"),
    default=0.5,
    show_default=True,
    help="Indicator noise per sample (standard deviation) [µm].",
)
@click.option("--revolutions", type=Number(low=1, integer=True), default=10, show_default=True)
@click.option(
    "--samples",
    "samples",
    type=Number(low=3, integer=True),  # camtol.pair.indicator.MIN_SAMPLES_PER_REVOLUTION
    default=4500,
    show_default=True,
    help="Samples per revolution (4 rev/h at 5 Hz: 4500).",
)
@seed_option
def simulate_record_cmd(
    design: str | None,
    example: str | None,
    output: str,
    truth_a: str,
    truth_b: str,
    noise_um: float,
    revolutions: int,
    samples: int,
    seed: int,
) -> None:
    """Simulate the fixture's indicator record of the same parts as two simulated scans.

    The centre-distance variation is the exact fixture simulation (THEORY §5) of cams with
    the profile errors of SCAN_A.truth.json and SCAN_B.truth.json and the follower's
    constant errors of the design's [inspection] table (e.g. cw11-experiment: Table 2).
    """

    def body() -> int:
        check_output_path(output, "--output", [".csv"])
        from camtol.exceptions import InputFileError
        from camtol.inspection.twin import error_from_truth
        from camtol.pair.fixture_spec import FixtureErrors
        from camtol.pair.indicator import write_indicator_csv
        from camtol.pair.twin import fixture_delta_f, simulate_record

        d = load_input(design, example)
        errs = []
        kinds = set()
        for path in (truth_a, truth_b):
            try:
                raw = json.loads(Path(path).read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise InputFileError(f"{path}: cannot read the truth JSON ({exc})") from None
            err, kind = error_from_truth(raw, source=path)
            errs.append(err)
            kinds.add(kind)
        if len(kinds) > 1:
            fail("--truth-a and --truth-b apply their errors differently (radial/normal)")
        from camtol.pair.fixture_spec import fixture_spec

        spec = fixture_spec(d)
        errors = spec.errors if spec is not None else FixtureErrors()
        df = fixture_delta_f(d, errs[0], errs[1], errors, error_kind=kinds.pop())
        rec = simulate_record(
            df, revolutions=revolutions, samples_per_revolution=samples, noise_um=noise_um, rng=seed
        )
        write_indicator_csv(rec, output)
        click.echo(f"wrote {output} ({rec.df_um.size} samples, {revolutions} revolutions)")
        return EXIT_OK

    raise _Exit(run_guarded(body))
