"""The terminal summary and the ``--curves`` CSV of a Monte Carlo study (display units).

The words and tables ``camtol montecarlo`` prints, and the per-angle CSV it writes, from
a :class:`~camtol.report.tolerancing_display.MonteCarloDisplay`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from camtol.report.csv_text import csv_text

__all__ = ["curves_csv", "montecarlo_lines"]


def curves_csv(shown: Any) -> str:
    """Return the ``--curves`` CSV text: one row per angle (docs/tolerancing.md).

    Parameters
    ----------
    shown : MonteCarloDisplay
        The study in display units (:func:`camtol.report.tolerancing_display.display_montecarlo`).

    Returns
    -------
    str
        The CSV text, ΔS columns in µm or degrees; linear mode adds the quantiles'
        tolerance per angle (``dS_tolerance_<unit>``) and, with a spec or band, the
        probability of leaving it (``p_out``).
    """
    result = shown.result
    s = shown.statistics["lift"]
    u = s.unit
    cols = ["theta_deg"] + [f"dS_{k}_{u}" for k in ("mean", "std", "q00135", "q50", "q99865")]
    cols += [f"share_{k}" for k in result.shares]
    arrays = [result.theta_deg, s.mean, s.std, s.q00135, s.q50, s.q99865, *result.shares.values()]
    if s.tolerance is not None:
        cols.append(f"dS_tolerance_{u}")
        arrays.append(s.tolerance)
    if result.outside is not None:
        cols.append("p_out")
        arrays.append(result.outside.value)
    return csv_text(cols, np.column_stack(arrays), digits=9)


def _interval(ci: tuple[float | None, float | None] | None) -> str:
    if ci is None:
        return ""
    lo, hi = ci
    return f" [{'-' if lo is None else f'{lo:.4g}'}, {'-' if hi is None else f'{hi:.4g}'}]"


def montecarlo_lines(shown: Any) -> list[str]:
    """Return the terminal summary of ``camtol montecarlo`` (docs/tolerancing.md).

    Parameters
    ----------
    shown : MonteCarloDisplay
        The study in display units (:func:`camtol.report.tolerancing_display.display_montecarlo`).

    Returns
    -------
    list of str
        One line each; every figure says whether it is deterministic (from the source
        distributions) or sampled (with its 95 % interval), and the exact − linear
        figures say that they are differences, not a distribution.
    """
    lines: list[str] = []
    add = lines.append
    result = shown.result
    s = shown.statistics["lift"]
    u = s.unit
    add(
        f"camtol montecarlo: {result.design_name}, {result.mode} mode, {result.samples} samples,"
        f" seed {result.seed}"
    )
    for k, v in shown.sources.items():
        add(f"  source {k:<10} {v}")
    i = shown.worst_index
    if s.method == "deterministic":
        how = f"deterministic, from the distributions; quantiles within ±{s.resolution:.3g} {u}"
    else:
        how = f"sampled, {result.samples} samples"
    add(
        f"  dS at θ = {result.theta_deg[i]:.2f}° (worst margin) [{u}] ({how}): mean"
        f" {s.mean[i]:.4g}, std {s.std[i]:.4g}, 0.135 % {s.q00135[i]:.4g}, median"
        f" {s.q50[i]:.4g}, 99.865 % {s.q99865[i]:.4g}"
    )
    o = result.outside
    if o is not None:
        j = o.worst
        add(
            f"  P(dS outside the limits) (deterministic): largest {o.value[j]:.4%} at θ ="
            f" {result.theta_deg[j]:.2f}° (bounds [{o.lower[j]:.4%}, {o.upper[j]:.4%}]),"
            f" so the yield is at most {1.0 - float(o.lower.max()):.4%}"
        )
    for q in ("velocity", "acceleration"):
        if q in shown.statistics:
            v = shown.statistics[q]
            add(
                f"  max |d{q[0].upper()}| [{v.unit}] (sampled): mean {v.max_abs.mean:.4g},"
                f" 99.865 % {v.max_abs.q99865:.4g}"
            )
    m = s.max_abs
    ci = m.ci95
    add(
        f"  max |dS| [{u}] (sampled, 95 % CI in brackets): mean {m.mean:.4g}"
        f"{_interval(ci.get('mean'))}, std {m.std:.4g}, 0.135 % {m.q00135:.4g}"
        f"{_interval(ci.get('q00135'))}, median {m.q50:.4g}{_interval(ci.get('q50'))},"
        f" 99.865 % {m.q99865:.4g}{_interval(ci.get('q99865'))}"
    )
    y = result.yield_estimate
    if y is not None:
        add(
            f"  yield ({shown.yield_spec}) (sampled): {y.value:.4%}"
            f"  95 % CI [{y.ci95[0]:.4%}, {y.ci95[1]:.4%}]"
        )
    add(f"  contributions at θ = {result.worst_angle_deg:.2f}° (variance share):")
    for c in result.contributions:
        add(f"    {c.source:<12}{c.variance_share:>8.1%}")
    add(f"  {'source':<12}{'worst case':>12}{'RSS':>10}{'MC 99.73 %':>12}   [{u}]")
    for r in shown.comparison:
        add(
            f"  {r.source:<12}{r.worst_case:>12.4g}{r.rss:>10.4g}{r.mc_9973:>12.4g}"
            f"   ({r.mc_9973_method})"
        )
    if shown.difference is not None:
        d = shown.difference
        add(
            f"  linearisation error, exact minus linear on the same samples [{u}] (differences,"
            " not a distribution):"
        )
        add(
            f"    largest |exact - linear| over θ of the per-angle mean {d.mean:.3g}, std"
            f" {d.std:.3g}, 0.135 % quantile {d.q00135:.3g}, 99.865 % quantile {d.q99865:.3g};"
        )
        add(
            f"    of the 99.865 % quantile of max |dS| {d.max_abs_q99865:.3g}; largest"
            f" |exact - linear| of one sample at one angle {d.max_sample:.3g}"
        )
    for n in shown.notes:
        add(f"  note: {n}")
    return lines
