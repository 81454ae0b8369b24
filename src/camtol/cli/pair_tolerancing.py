"""``camtol montecarlo`` and ``camtol allocate`` on a conjugate pair (docs/pair-tolerancing.md).

The commands' options are parsed in :mod:`camtol.cli.tolerancing`; on a conjugate design
it hands them here: one library call (:func:`camtol.tolerancing.pair.pair_monte_carlo`,
:func:`camtol.tolerancing.pair_allocation.allocate_pair`), then the terminal summary
(80 columns), the ``--json`` document or the ``--curves`` CSV.
"""

from __future__ import annotations

import math
from typing import Any

import click

from camtol.cli.common import EXIT_OK, echo_json, fail
from camtol.design.cam_design import CamDesign

__all__ = ["pair_allocate", "pair_montecarlo", "refuse_pair_flags", "refuse_single_cam_flags"]


def _limits_mm(
    interference_max_um: float | None, backlash_max_um: float | None
) -> tuple[float | None, float | None]:
    """Return the pair yield's limits in mm (both or neither, each ≥ 0)."""
    if (interference_max_um is None) != (backlash_max_um is None):
        fail(
            "--interference-max-um and --backlash-max-um go together: the pair yield needs"
            " both limits"
        )
    out = []
    for flag, value in (
        ("--interference-max-um", interference_max_um),
        ("--backlash-max-um", backlash_max_um),
    ):
        if value is not None and not (math.isfinite(value) and 0.0 <= value <= 1e6):
            fail(f"{flag}={value!r} is not allowed; give a number of µm from 0 to 1e6")
        out.append(None if value is None else value * 1e-3)
    return out[0], out[1]


def refuse_pair_flags(given: dict[str, object]) -> None:
    """Refuse a single cam's ΔS options on a pair (one line naming the first given).

    Parameters
    ----------
    given : dict of str to object
        Flag -> its value (None when not given).
    """
    for flag, value in given.items():
        if value is not None:
            fail(
                f"{flag} applies to a single cam's ΔS; a pair's yield is"
                " --interference-max-um with --backlash-max-um"
            )


def refuse_single_cam_flags(
    interference_max_um: float | None, backlash_max_um: float | None, what: str
) -> None:
    """Refuse a pair's options on a single cam (one line naming them).

    Parameters
    ----------
    interference_max_um, backlash_max_um : float or None
        The options as given.
    what : str
        The design's follower type, for the message.
    """
    if interference_max_um is not None or backlash_max_um is not None:
        fail(
            f"--interference-max-um and --backlash-max-um apply to a conjugate pair; the"
            f" design's follower is {what}"
        )


def pair_montecarlo(
    design: CamDesign,
    *,
    samples: int,
    mode: str,
    seed: int,
    step_deg: float,
    interference_max_um: float | None,
    backlash_max_um: float | None,
    sobol: int | None,
    as_json: bool,
    curves: str | None,
    fixture_yield: bool = True,
) -> int:
    """Tolerance a pair as a pair and render it (see the module docstring).

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    samples : int
        ``--samples``.
    mode : {"linear", "exact"}
        ``--mode``.
    seed : int
        ``--seed``.
    step_deg : float
        ``--step``. [deg]
    interference_max_um, backlash_max_um : float or None
        The pair yield's limits. [µm]
    sobol : int or None
        ``--sobol N``: exact Sobol indices with N rows.
    as_json : bool
        ``--json``.
    curves : str or None
        ``--curves`` CSV path.
    fixture_yield : bool
        False with ``--no-fixture-yield``.

    Returns
    -------
    int
        Exit status.
    """
    from camtol.tolerancing.pair import pair_monte_carlo

    imax, bmax = _limits_mm(interference_max_um, backlash_max_um)
    res = pair_monte_carlo(
        design,
        samples,
        seed=seed,
        step_deg=step_deg,
        interference_max_mm=imax,
        backlash_max_mm=bmax,
        mode=mode,
        fixture_yield=fixture_yield,
    )
    doc = res.to_dict()
    if sobol is not None:
        from camtol.tolerancing.sobol import exact_sobol

        doc["sobol"] = {
            k: v.to_dict() for k, v in exact_sobol(design, sobol, seed=seed, step_deg=1.0).items()
        }
    if samples < 1000:
        click.echo(
            f"warning: {samples} samples, fewer than 1,000: the sampled figures are rough",
            err=True,
        )
    if curves:
        import numpy as np

        from camtol.files import atomic_write
        from camtol.report.csv_text import csv_text

        cols = res.curves_columns()
        atomic_write(curves, csv_text(list(cols), np.column_stack(list(cols.values()))))
    if as_json:
        echo_json(doc, command="montecarlo")
    else:
        for line in _lines(doc):
            click.echo(line)
    if curves and not as_json:
        click.echo(f"wrote {curves}")
    return EXIT_OK


def _yield_text(y: dict[str, Any]) -> str:
    lo, hi = y["ci95"]
    return f"{y['value']:.2%} (95 % CI {lo:.2%} .. {hi:.2%})"


def _lines(doc: dict[str, Any]) -> list[str]:
    """Terminal summary of a pair study, within 80 columns."""

    def um(s: dict[str, float]) -> str:
        return f"mean {s['mean']:.3g}, 99.865 % {s['q99865']:.3g}, max {s['max']:.3g} µm"

    out = [f"camtol montecarlo: {doc['design']} as a pair, {doc['samples']:,} pairs (sampled)"]
    out.append(f"  interference  {um(doc['interference_um'])}")
    out.append(f"  backlash      {um(doc['backlash_um'])}")
    for cam, s in doc["max_abs_ds_deg"].items():
        out.append(
            f"  max |ΔS_{cam.upper()}|    mean {s['mean']:.3g}, 99.865 % {s['q99865']:.3g},"
            f" max {s['max']:.3g}°"
        )
    if doc["fixture_yield"]:
        for cam, y in doc["fixture_yield"].items():
            out.append(f"  fixture accepts cam {cam.upper()}: {_yield_text(y)}")
    else:
        out.append("  fixture yield: left out (--no-fixture-yield)")
    if doc["pair_yield"] is not None:
        out.append(
            f"  pair yield (interference ≤ {doc['interference_max_um']:g} µm, backlash ≤"
            f" {doc['backlash_max_um']:g} µm): {_yield_text(doc['pair_yield'])}"
        )
    top = list(doc["df_contributions"].items())[:5]
    out.append(
        f"  Δf at {doc['df_worst_angle_deg']:.1f}° (deterministic), variance shares: "
        + ", ".join(f"{k} {v:.0%}" for k, v in top)
    )
    for key, s in doc.get("sobol", {}).items():
        firsts = ", ".join(f"{k} {v['first']:.2f}" for k, v in s.items())
        out.append(f"  Sobol first-order, {key}: {firsts}")
    out += [f"  note: {n}" for n in doc["notes"]]
    return _wrap(out)


def _wrap(lines: list[str], width: int = 80) -> list[str]:
    import textwrap

    out = []
    for line in lines:
        indent = " " * (len(line) - len(line.lstrip()) + 2)
        out += textwrap.wrap(line, width, subsequent_indent=indent) or [""]
    return out


def pair_allocate(
    design: CamDesign,
    *,
    interference_max_um: float | None,
    backlash_max_um: float | None,
    target_yield: float,
    grades: str,
    samples: int,
    seed: int,
    as_json: bool,
    step_deg: float = 0.5,
) -> int:
    """Allocate a pair's grades against its pair yield and render it.

    Parameters
    ----------
    design : CamDesign
        A conjugate design.
    interference_max_um, backlash_max_um : float or None
        The pair yield's limits (required). [µm]
    target_yield : float
        ``--yield``. [-]
    grades : str
        ``--grades``, a range such as ``IT5-IT12``.
    samples : int
        ``--samples``, per step (the verification uses five times as many).
    seed : int
        ``--seed``.
    step_deg : float
        ``--step``. [deg]
    as_json : bool
        ``--json``.

    Returns
    -------
    int
        Exit status.
    """
    from camtol import iso286
    from camtol.pair.kinematics import is_pair
    from camtol.tolerancing.pair_allocation import allocate_pair

    if not is_pair(design):
        fail(
            "--criterion pair_yield needs a conjugate pair; the design's follower is"
            f" {design.mechanism.kind}"
        )
    lo, _, hi = grades.partition("-")
    try:
        first = iso286.GRADES.index(iso286.parse_grade(lo))
        last = iso286.GRADES.index(iso286.parse_grade(hi or lo))
    except ValueError as exc:
        fail(f"--grades={grades!r}: {exc}")
    imax, bmax = _limits_mm(interference_max_um, backlash_max_um)
    if imax is None or bmax is None:
        fail(
            "--criterion pair_yield needs --interference-max-um and --backlash-max-um (the"
            " limits of the pair yield)"
        )
    assert imax is not None and bmax is not None
    res = allocate_pair(
        design,
        interference_max_mm=imax,
        backlash_max_mm=bmax,
        target_yield=target_yield,
        grades=iso286.GRADES[first : last + 1],
        samples=samples,
        verify_samples=5 * samples,
        seed=seed,
        step_deg=step_deg,
    )
    doc = {"design": design.name, **res.to_dict()}
    if not res.met:
        click.echo(
            f"warning: the verified pair yield {_yield_text(doc['pair_yield'])} is below the"
            f" target {target_yield:.2%}: the allocation does not meet it",
            err=True,
        )
    if as_json:
        echo_json(doc, command="allocate")
        return EXIT_OK
    lines = [
        f"camtol allocate: {design.name} as a pair, pair yield ≥ {target_yield:.2%} with"
        f" interference ≤ {interference_max_um:g} µm, backlash ≤ {backlash_max_um:g} µm",
        "  grades: " + ", ".join(f"{k} {g}" for k, g in res.grades.items()),
    ]
    if res.fixed:
        lines.append("  kept (explicit deviations): " + ", ".join(res.fixed))
    lines.append(f"  verified pair yield: {_yield_text(doc['pair_yield'])}")
    lines.append(f"  {len(res.steps)} tightening steps (see --json)")
    for line in _wrap(lines):
        click.echo(line)
    return EXIT_OK
