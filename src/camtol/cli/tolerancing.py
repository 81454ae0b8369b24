"""``camtol montecarlo`` and ``camtol allocate``: statistical tolerance design (issue 11).

Registered on the ``camtol`` group by :mod:`camtol.cli.app`. Exit status 0 ok, 2 on bad input
(one line on stderr, nothing written). Files and keys: docs/tolerancing.md; a conjugate
pair is handed to :mod:`camtol.cli.pair_tolerancing` (docs/pair-tolerancing.md).

Why one module: the two commands are one command group's options over one study: the
spec or band of ΔS, the seed, the grid and the progress display are parsed and checked
by the same helpers here, and both hand a conjugate pair over at the same point.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import click

from camtol.cli.common import (
    EXIT_OK,
    _Exit,
    check_output_path,
    echo_json,
    fail,
    load_input,
    run_guarded,
)
from camtol.cli.dynamics import train_options, train_overrides
from camtol.cli.options import Number, design_options, seed_option, step_option

__all__ = ["allocate", "band_option", "montecarlo", "parse_motion_spec"]


@contextmanager
def _progress(label: str, enabled: bool) -> Iterator[Callable[[int, int], None] | None]:
    """Show a rich progress bar on stderr, only when stderr is a terminal."""
    if not (enabled and sys.stderr.isatty()):
        yield None
        return
    from rich.console import Console
    from rich.progress import Progress

    with Progress(console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(label, total=None)

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield update


def parse_motion_spec(
    output: str, spec_um: float | None, spec_deg: float | None, *, flag: str = "--spec"
) -> float | None:
    """Return the spec on max |ΔS| from ``<flag>-um`` / ``<flag>-deg``, or fail.

    One rule for every command that takes a motion spec (``montecarlo``, ``allocate``,
    ``inspect``, and ``report --mc-spec-um/-deg``): a lift in µm, a swing in degrees.

    Parameters
    ----------
    output : str
        The follower's output, ``"translating"`` or ``"oscillating"``.
    spec_um, spec_deg : float or None
        The flags' values. [µm, deg]
    flag : str
        The flags' common prefix, for the messages.

    Returns
    -------
    float or None
        The spec in mm (translating) or rad (oscillating); None when neither was given.
    """
    um, deg = f"{flag}-um", f"{flag}-deg"
    if spec_um is not None and spec_deg is not None:
        fail(f"give {um} or {deg}, not both")
    if spec_um is not None:
        if output == "oscillating":
            fail(f"{um}={spec_um:g} is not allowed: the output of this cam is an angle; use {deg}")
        if not (math.isfinite(spec_um) and spec_um > 0):
            fail(f"{um}={spec_um!r} is not allowed; give a number of µm > 0")
        return spec_um * 1e-3
    if spec_deg is not None:
        if output != "oscillating":
            fail(f"{deg}={spec_deg:g} is not allowed: the output of this cam is a lift; use {um}")
        if not (math.isfinite(spec_deg) and spec_deg > 0):
            fail(f"{deg}={spec_deg!r} is not allowed; give a number of degrees > 0")
        return math.radians(spec_deg)
    return None


def band_option(
    design: Any,
    band: str | None,
    spec: float | None,
    *,
    flag: str = "--band",
    spec_flag: str = "--spec",
) -> Any:
    """Read a band file option (None without it); refuse it together with a spec.

    Parameters
    ----------
    design : CamDesign
        The design (its output decides the file's unit: µm or degrees).
    band : str or None
        The option's value: a CSV file (docs/file-formats.md).
    spec : float or None
        The spec given by the ``<spec_flag>`` options, if any. [mm or rad]
    flag, spec_flag : str
        The option names, for the messages.

    Returns
    -------
    ToleranceBand or None
    """
    if band is None:
        return None
    if spec is not None:
        fail(f"give {flag} or {spec_flag}-um/{spec_flag}-deg, not both")
    from camtol.tolerancing.band import read_band_csv

    return read_band_csv(band, design.mechanism.output)


def _plot(shown: Any, path: str) -> None:
    from pathlib import Path

    from camtol.files import atomic_output
    from camtol.report.tolerancing import montecarlo_figure

    fig = montecarlo_figure(shown)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format=Path(path).suffix.lstrip(".").lower())


@click.command()
@design_options
@click.option(
    "--samples",
    "-n",
    type=Number(low=1, integer=True),
    required=True,
    help="Number of sampled mechanisms.",
)
@click.option("--mode", type=click.Choice(["linear", "exact"]), default="linear", show_default=True)
@seed_option
@click.option("--spec-um", type=float, help="Spec on max |dS| of a lift [um] (gives the yield).")
@click.option("--spec-deg", type=float, help="Spec on max |dS| of a swing [deg].")
@click.option(
    "--band",
    metavar="FILE.csv",
    help="Band lower <= dS <= upper (theta_deg, lower_um, upper_um or _deg) for the yield.",
)
@step_option()
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--curves", metavar="FILE.csv", help="Write per-angle statistics and shares.")
@click.option("--plot", metavar="FILE.png", help="Write the band figure (PNG, SVG, PDF).")
@click.option("--scheduler", metavar="ADDR", help="Dask scheduler, e.g. tcp://host:8786.")
@click.option(
    "--workers",
    type=Number(low=1, integer=True),
    default=1,
    show_default=True,
    help="Local workers: threads (linear mode), processes (exact mode).",
)
@click.option(
    "--derivatives", is_flag=True, help="Also sample ΔV and ΔA (linear mode; JSON max_abs_dV/dA)."
)
@click.option(
    "--interference-max-um",
    type=float,
    metavar="UM",
    help="Conjugate pair: largest interference of the pair yield [µm].",
)
@click.option(
    "--backlash-max-um",
    type=float,
    metavar="UM",
    help="Conjugate pair: largest backlash of the pair yield [µm].",
)
@click.option(
    "--no-fixture-yield",
    is_flag=True,
    help="Conjugate pair: leave out the fixture's yield (needs no [inspection] bands).",
)
@click.option(
    "--sobol",
    type=Number(low=64, high=100_000, integer=True),
    metavar="N",
    help="Exact Sobol indices with N rows (max |ΔS|, ΔS at its worst angle; a pair's Δf).",
)
@click.option(
    "--dynamics",
    "at_speed",
    is_flag=True,
    help="Also run every sample at speed: contact forces, vibration (THEORY §9.7).",
)
@click.option(
    "--rpm", type=Number(low=0, low_open=True, unit="rpm"), metavar="RPM", help="--dynamics speed."
)
@train_options
@click.option("--force-min-n", type=float, metavar="N", help="--dynamics: least contact force.")
@click.option("--force-max-n", type=float, metavar="N", help="--dynamics: largest contact force.")
@click.option(
    "--jump-margin",
    type=Number(low=1, low_open=True),
    metavar="X",
    help="--dynamics: contact kept at X times the speed.",
)
def montecarlo(
    design: str | None,
    example: str | None,
    samples: int,
    mode: str,
    seed: int,
    spec_um: float | None,
    spec_deg: float | None,
    band: str | None,
    step_deg: float,
    as_json: bool,
    curves: str | None,
    plot: str | None,
    scheduler: str | None,
    workers: int,
    derivatives: bool,
    interference_max_um: float | None,
    backlash_max_um: float | None,
    no_fixture_yield: bool,
    sobol: int | None,
    at_speed: bool,
    rpm: float | None,
    force_min_n: float | None,
    force_max_n: float | None,
    jump_margin: float | None,
    **train: Any,
) -> None:
    """Monte Carlo tolerance analysis: ΔS band, max |ΔS|, yield, contributions.

    A conjugate pair is toleranced as a pair (docs/pair-tolerancing.md): both cams'
    motion errors, the conjugate variation Δf, interference and backlash against the
    machine's centre distance (the pair yield with --interference-max-um and
    --backlash-max-um), and the fixture's yield of each cam.
    """

    def body() -> int:
        check_output_path(curves, "--curves", [".csv"])
        check_output_path(plot, "--plot", [".png", ".svg", ".pdf"])
        d = load_input(design, example)
        from camtol.cli.pair_tolerancing import (
            pair_montecarlo,
            refuse_pair_flags,
            refuse_single_cam_flags,
        )
        from camtol.pair.kinematics import is_pair

        speed_flags = (rpm, force_min_n, force_max_n, jump_margin, *train.values())
        if not at_speed and any(v is not None for v in speed_flags):
            fail("--rpm, the train options and the force specs go with --dynamics")
        if is_pair(d):
            refuse_pair_flags(
                {
                    "--spec-um": spec_um,
                    "--spec-deg": spec_deg,
                    "--band": band,
                    "--plot": plot,
                    "--scheduler": scheduler,
                    "--derivatives": derivatives or None,
                    "--dynamics": at_speed or None,
                }
            )
            return pair_montecarlo(
                d,
                samples=samples,
                mode=mode,
                seed=seed,
                step_deg=step_deg,
                interference_max_um=interference_max_um,
                backlash_max_um=backlash_max_um,
                fixture_yield=not no_fixture_yield,
                sobol=sobol,
                as_json=as_json,
                curves=curves,
            )
        refuse_single_cam_flags(interference_max_um, backlash_max_um, d.mechanism.kind)
        if no_fixture_yield:
            fail(
                f"--no-fixture-yield applies to a conjugate pair; the design's follower is"
                f" {d.mechanism.kind}"
            )
        spec = parse_motion_spec(d.mechanism.output, spec_um, spec_deg)
        limits = band_option(d, band, spec)
        from camtol.tolerancing import monte_carlo

        with _progress("Monte Carlo", not as_json) as progress:
            res = monte_carlo(
                d,
                samples,
                mode=mode,  # type: ignore[arg-type]
                seed=seed,
                spec=spec,
                band=limits,
                quantities=("lift", "velocity", "acceleration") if derivatives else ("lift",),
                step_deg=step_deg,
                workers=workers,
                scheduler=scheduler,
                progress=progress,
            )
        from camtol.report.tolerancing_display import display_montecarlo

        shown = display_montecarlo(res, d)
        sobol_doc = None
        if sobol is not None:
            from camtol.tolerancing.sobol import exact_sobol

            found = exact_sobol(d, sobol, seed=seed, step_deg=1.0)
            sobol_doc = {k: v.to_dict() for k, v in found.items()}
        speed_doc = None
        if at_speed:
            from camtol.tolerancing.dynamics_study import monte_carlo_dynamics

            speed_doc = monte_carlo_dynamics(
                d,
                samples,
                rpm=rpm,
                overrides=train_overrides(train),
                seed=seed,
                step_deg=step_deg,
                force_min_n=force_min_n,
                force_max_n=force_max_n,
                jump_margin=jump_margin,
            )
        import textwrap

        for w in res.warnings:  # 80 columns, continuations indented
            click.echo(textwrap.fill(f"warning: {w}", 80, subsequent_indent="  "), err=True)
        from camtol.report.tolerancing_text import curves_csv, montecarlo_lines

        if curves:
            from camtol.files import atomic_write

            atomic_write(curves, curves_csv(shown))
        if plot:
            _plot(shown, plot)
        if as_json:
            doc = shown.to_dict()
            if speed_doc is not None:
                doc["dynamics"] = speed_doc
            if sobol_doc is not None:
                doc["sobol"] = sobol_doc
            echo_json(doc, command="montecarlo")
        else:
            for line in montecarlo_lines(shown):
                click.echo(line)
            if speed_doc is not None:
                for line in _speed_lines(speed_doc):
                    click.echo(line)
            for key, indices in (sobol_doc or {}).items():
                firsts = ", ".join(f"{k} {v['first']:.2f}" for k, v in indices.items())
                click.echo(f"Sobol first-order, {key} (exact): {firsts}")
        return EXIT_OK

    raise _Exit(run_guarded(body))


def _speed_lines(doc: dict[str, Any]) -> list[str]:
    """Return the ``--dynamics`` part of the terminal summary (80 columns)."""
    peak, least = doc["peak_force_n"], doc["min_force_n"]
    out = [
        f"at {doc['rpm']:g} rpm, over {doc['samples']:,} samples (THEORY §9.7):",
        f"  peak contact force  mean {peak['mean']:.4g} N, 99.865 % {peak['q99865']:.4g} N",
        f"  least contact force mean {least['mean']:.4g} N, 0.135 % {least['q00135']:.4g} N",
    ]
    for key, unit in (("residual_vibration_um", "µm"), ("residual_vibration_deg", "°")):
        vib = doc.get(key)
        if vib is not None:
            out.append(f"  residual vibration  mean {vib['mean']:.4g}, max {vib['max']:.4g} {unit}")
    y = doc["yield"]
    if y is not None:
        lo, hi = y["ci95"]
        out.append(f"  yield at speed      {y['value']:.2%} (95 % CI {lo:.2%} .. {hi:.2%})")
    return out


def _warn_unmet(res: Any) -> None:
    """One line on stderr when the verified yield's interval lies below the target."""
    if not res.met:
        y = res.verified
        click.echo(
            f"warning: the allocation does not meet the {100 * res.target_yield:.6g} % yield"
            f" target: verified {100 * y.value:.6g} %",
            err=True,
        )


@click.command()
@design_options
@click.option("--spec-um", type=float, help="Spec on max |dS| of a lift [um].")
@click.option("--spec-deg", type=float, help="Spec on max |dS| of a swing [deg].")
@click.option(
    "--band",
    metavar="FILE.csv",
    help="Band lower <= dS <= upper (theta_deg, lower_um, upper_um or _deg) instead of a spec.",
)
@click.option(
    "--criterion",
    type=click.Choice(["worst_case", "rss", "monte_carlo", "pair_yield"]),
    default="worst_case",
    show_default=True,
    help="pair_yield: a conjugate pair's interference and backlash (with their limits).",
)
@click.option(
    "--interference-max-um", type=float, metavar="UM", help="pair_yield: largest interference."
)
@click.option("--backlash-max-um", type=float, metavar="UM", help="pair_yield: largest backlash.")
@click.option(
    "--yield",
    "target_yield",
    type=Number(low=0, low_open=True, high=1, high_open=True),
    default=0.9973,
    show_default=True,
    help="Yield target of the monte_carlo criterion and of the verification (0-1).",
)
@click.option("--grades", default="IT5-IT12", show_default=True, help="Grade range, e.g. IT5-IT12.")
@click.option(
    "--cost-exponent",
    type=Number(low=0, low_open=True),
    default=1.0,
    show_default=True,
    help="b in cost = sum a_k (T_coarsest/T_k)^b.",
)
@click.option(
    "--cost",
    "costs",
    multiple=True,
    metavar="KEY=A",
    help="Cost coefficient a_k of a source (default 1), repeatable.",
)
@click.option(
    "--samples",
    type=Number(low=1, integer=True),
    default=20000,
    show_default=True,
    help="Samples per candidate (monte_carlo), at most 1e10 as for montecarlo.",
)
@click.option(
    "--verify-samples", type=Number(low=1, integer=True), default=20000, show_default=True
)
@seed_option
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def allocate(
    design: str | None,
    example: str | None,
    spec_um: float | None,
    spec_deg: float | None,
    band: str | None,
    criterion: str,
    target_yield: float,
    grades: str,
    cost_exponent: float,
    costs: tuple[str, ...],
    samples: int,
    verify_samples: int,
    seed: int,
    as_json: bool,
    interference_max_um: float | None,
    backlash_max_um: float | None,
) -> None:
    """Choose the coarsest (cheapest) IT grade per source that meets a spec."""

    def body() -> int:
        from camtol import iso286
        from camtol.cli.pair_tolerancing import pair_allocate, refuse_single_cam_flags
        from camtol.tolerancing import allocate as run

        d = load_input(design, example)
        if criterion == "pair_yield":
            return pair_allocate(
                d,
                interference_max_um=interference_max_um,
                backlash_max_um=backlash_max_um,
                target_yield=target_yield,
                grades=grades,
                samples=samples,
                seed=seed,
                as_json=as_json,
            )
        refuse_single_cam_flags(interference_max_um, backlash_max_um, d.mechanism.kind)
        spec = parse_motion_spec(d.mechanism.output, spec_um, spec_deg)
        curves = band_option(d, band, spec)
        if spec is None and curves is None:
            fail(
                "give the spec on max |dS|: --spec-um (lift) or --spec-deg (swing), or a band"
                " (--band FILE.csv)"
            )
        lo, sep, hi = grades.partition("-")
        try:
            a, b = iso286.parse_grade(lo), iso286.parse_grade(hi if sep else lo)
        except ValueError as exc:
            fail(f"--grades={grades!r}: {exc}")
        i, j = iso286.GRADES.index(a), iso286.GRADES.index(b)
        if i > j:
            fail(f"--grades={grades!r}: the finer grade comes first (e.g. IT5-IT12)")
        coef: dict[str, float] = {}
        for c in costs:
            k, _, v = c.partition("=")
            try:
                coef[k] = float(v)
            except ValueError:
                fail(f"--cost={c!r}: give KEY=NUMBER, e.g. r=2")
        res = run(
            d,
            spec,
            band=curves,
            criterion=criterion,  # type: ignore[arg-type]
            grades=iso286.GRADES[i : j + 1],
            target_yield=target_yield,
            cost_exponent=cost_exponent,
            cost_coefficients=coef,
            samples=samples,
            verify_samples=verify_samples,
            seed=seed,
        )
        from camtol.report.display import DisplayUnits

        shown = DisplayUnits.of(d)
        unit, scale = shown.lift, shown.lift_scale
        spec_shown = None if res.spec is None else res.spec * scale
        # worst case and RSS in the display unit; a yield or a band ratio as it is
        achieved = res.achieved
        if res.criterion != "monte_carlo" and res.spec is not None:
            achieved = res.achieved * scale
        if as_json:
            from camtol.report.tables import accuracy_json

            out = {
                "grades": res.grades,
                "tolerances": [
                    {
                        "source": t.key,
                        f"deviation_{'um' if t.unit == 'mm' else 'deg'}": (
                            t.deviation * 1e3 if t.unit == "mm" else math.degrees(t.deviation)
                        ),
                        "origin": t.origin,
                    }
                    for t in res.deviations
                ],
                "criterion": res.criterion,
                "spec": spec_shown,
                "band": res.band,
                "unit": unit,
                "achieved": achieved,
                "cost": res.cost,
                "accuracy": accuracy_json(res.accuracy),
                "yield": {"value": res.verified.value, "ci95": list(res.verified.ci95)},
                "coarser_fails": res.coarser_fails,
                "evaluated": res.evaluated,
                "target_yield": res.target_yield,
                "met": res.met,
            }
            _warn_unmet(res)
            echo_json(out, command="allocate")
            return EXIT_OK
        echo = click.echo
        unit_shown = {"um": " µm", "deg": "°"}.get(unit, f" {unit}")  # as the terminal shows it
        what_spec = (
            f"band {res.band} (lower <= dS <= upper)"
            if res.spec is None
            else f"spec max |ΔS| ≤ {spec_shown:g}{unit_shown}"
        )
        echo(f"camtol allocate: {d.name}, {what_spec}, criterion {res.criterion}")
        for t in res.deviations:
            echo(f"  {t.key:<6}{res.grades[t.key]:<6}{t.display}")
        what = "yield" if res.criterion == "monte_carlo" else f"max {res.criterion}"
        if res.criterion == "monte_carlo":
            val = f"{100 * achieved:.6g} %"
        elif res.spec is None:
            what += " / band half-width"
            val = f"{achieved:.4g}"
        else:
            val = f"{achieved:.4g}{unit_shown}"
        echo(f"  {what}: {val}; cost {res.cost:.4g}; {res.evaluated} combinations evaluated")
        echo(f"  accuracy of the output (worst case): {res.accuracy.describe()}")
        y = res.verified
        echo(f"  verified by Monte Carlo ({y.samples} samples): yield {100 * y.value:.6g} %,")
        echo(
            f"    95 % interval {100 * y.ci95[0]:.6g} % to {100 * y.ci95[1]:.6g} %;"
            f" target {100 * res.target_yield:.6g} %: {res.verdict}"
        )
        if res.verdict == "inconclusive":
            echo(
                "  note: the verified yield is below the target but its 95 % interval reaches"
                " it; more --verify-samples would tell"
            )
        _warn_unmet(res)
        return EXIT_OK

    raise _Exit(run_guarded(body))
