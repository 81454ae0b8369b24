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


#: The terminal's width: every line of the summary fits it (STYLE, issue 32).
WIDTH = 80
#: How units are shown (the result keeps the file spellings "um" and "deg").
_SHOWN = {"um": "µm", "deg": "°"}


def _interval(ci: tuple[float | None, float | None] | None) -> str:
    if ci is None:
        return ""
    lo, hi = ci
    return f" [{'-' if lo is None else f'{lo:.4g}'}, {'-' if hi is None else f'{hi:.4g}'}]"


def _pct(p: float, digits: int = 6) -> str:
    """Return a probability in percent with the significant digits it needs.

    6 for yields (99.9816 %, where the digits near 100 % matter), 3 for small
    probabilities (1.77e-07 %).
    """
    return f"{100.0 * p:.{digits}g} %"


def _wrap(text: str, indent: int, hang: int = 4) -> list[str]:
    """Lines of ``text`` within :data:`WIDTH`, indented, continuations indented further."""
    import textwrap

    return textwrap.wrap(
        text,
        WIDTH,
        initial_indent=" " * indent,
        subsequent_indent=" " * (indent + hang),
        break_on_hyphens=False,
        break_long_words=False,
    )


def montecarlo_lines(shown: Any) -> list[str]:
    """Return the terminal summary of ``camtol montecarlo`` (docs/tolerancing.md).

    Every line fits 80 columns: a figure's label and method on one line, its numbers on
    the next, notes wrapped under themselves.

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
    u = _SHOWN.get(s.unit, s.unit)
    lines += _wrap(
        f"camtol montecarlo: {result.design_name}, {result.mode} mode, {result.samples}"
        f" samples, seed {result.seed}",
        0,
    )
    for k, v in shown.sources.items():
        lines += _wrap(f"source {k:<10} {v}", 2, 18)
    i = shown.worst_index
    if s.method == "deterministic":
        how = f"deterministic (quantiles within ±{s.resolution:.3g} {u})"
    else:
        how = f"sampled, {result.samples} samples"
    add(f"  ΔS at θ = {result.theta_deg[i]:.2f}° (worst margin), {how}:")
    lines += _wrap(
        f"mean {s.mean[i]:.4g}, std {s.std[i]:.4g}, 0.135 % {s.q00135[i]:.4g}, median"
        f" {s.q50[i]:.4g}, 99.865 % {s.q99865[i]:.4g} {u}",
        4,
    )
    o = result.outside
    if o is not None:
        j = o.worst
        add("  P(ΔS outside the limits), deterministic:")
        lines += _wrap(
            f"largest {_pct(o.value[j], 3)} at θ = {result.theta_deg[j]:.2f}° (bounds"
            f" {_pct(o.lower[j], 3)} to {_pct(o.upper[j], 3)}), so the yield is at most"
            f" {_pct(1.0 - float(o.lower.max()))}",
            4,
        )
    for q in ("velocity", "acceleration"):
        if q in shown.statistics:
            v = shown.statistics[q]
            lines += _wrap(
                f"max |d{q[0].upper()}| [{v.unit}] (sampled): mean {v.max_abs.mean:.4g},"
                f" 99.865 % {v.max_abs.q99865:.4g}",
                2,
            )
    m = s.max_abs
    ci = m.ci95
    add("  max |ΔS|, sampled (95 % intervals in brackets):")
    lines += _wrap(
        f"mean {m.mean:.4g}{_interval(ci.get('mean'))}, std {m.std:.4g},"
        f" 0.135 % {m.q00135:.4g}{_interval(ci.get('q00135'))},"
        f" median {m.q50:.4g}{_interval(ci.get('q50'))},"
        f" 99.865 % {m.q99865:.4g}{_interval(ci.get('q99865'))} {u}",
        4,
    )
    y = result.yield_estimate
    if y is not None:
        lines += _wrap(
            f"yield ({shown.yield_spec}), sampled: {_pct(y.value)}, 95 % interval"
            f" {_pct(y.ci95[0])} to {_pct(y.ci95[1])}",
            2,
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
        add(f"  linearisation error, exact minus linear on the same samples [{u}]")
        add("  (differences, not a distribution):")
        add("    largest |exact - linear| over θ of the per-angle mean")
        lines += _wrap(
            f"{d.mean:.3g}, std {d.std:.3g}, 0.135 % quantile {d.q00135:.3g},"
            f" 99.865 % quantile {d.q99865:.3g}; of the 99.865 % quantile of max |ΔS|"
            f" {d.max_abs_q99865:.3g}; largest |exact - linear| of one sample at one angle"
            f" {d.max_sample:.3g}",
            6,
            0,
        )
    for n in shown.notes:
        lines += _wrap(f"note: {n}", 2, 6)
    return lines
