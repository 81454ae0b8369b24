"""Figures and the HTML section of a Monte Carlo study (``--plot``, ``report --montecarlo N``).

:func:`montecarlo_figure` draws, in display units: the per-angle band of ΔS(θ) with its
mean, median and the limits (legend beside the axes, never over the band); a histogram
of max_θ |ΔS| over the samples against the limits; and a Pareto chart of the variance
shares at the angle of the worst margin. Each panel says whether its figures were
computed from the source distributions (deterministic) or sampled.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.report.html import _e, _table
from camtol.report.inline_svg import figure_svg

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["draw_limits", "montecarlo_figure", "montecarlo_section"]

#: Bars of the max |ΔS| histogram.
HISTOGRAM_BARS = 50


def _u(unit: str) -> str:
    return "µm" if unit == "um" else "°" if unit == "deg" else unit


def montecarlo_section(result: Any, design: Any) -> str:
    """HTML of a :class:`camtol.tolerancing.MonteCarloResult`: summary, tables and figure.

    Parameters
    ----------
    result : MonteCarloResult
        A finished study (internal units).
    design : CamDesign
        The studied design: it fixes the display units
        (:func:`camtol.report.tolerancing_display.display_montecarlo`).

    Returns
    -------
    str
        An ``<h2>`` section with the source distributions, max |ΔS| statistics with
        their 95 % intervals, the contributor table, the worst-case / RSS / Monte Carlo
        comparison and the figure of :func:`montecarlo_figure` (inline SVG).
    """
    import matplotlib.pyplot as plt

    from camtol.report.tolerancing_display import display_montecarlo

    shown = display_montecarlo(result, design)
    s = shown.statistics["lift"]
    u = _u(s.unit)
    parts = [
        f"<h2>Monte Carlo ({_e(result.mode)} mode, {result.samples} samples,"
        f" seed {result.seed})</h2>",
        _table(["source", "distribution"], [[k, v] for k, v in shown.sources.items()]),
    ]
    if s.method == "deterministic":
        parts.append(
            "<p>Per-angle mean, σ and quantiles of ΔS: computed from the source"
            f" distributions without sampling (within ±{s.resolution:.3g} {u}).</p>"
        )
    m = s.max_abs
    parts.append(
        f"<p>max |ΔS| over the cycle [{u}] (sampled): mean {m.mean:.4g}, σ {m.std:.4g},"
        f" 0.135 % {m.q00135:.4g}, median {m.q50:.4g}, 99.865 % {m.q99865:.4g}"
        f" (95 % interval {_interval(m.ci95.get('q99865'))}).</p>"
    )
    if result.yield_estimate is not None:
        y = result.yield_estimate
        parts.append(
            f"<p>Yield ({_e(shown.yield_spec)}): {y.value:.4%}, 95 % interval"
            f" [{y.ci95[0]:.4%}, {y.ci95[1]:.4%}] (sampled; Clopper-Pearson).</p>"
        )
    for w in result.warnings:
        parts.append(f"<p><strong>Warning:</strong> {_e(w)}.</p>")
    parts.append(f"<h3>Contributions at θ = {result.worst_angle_deg:.2f}°</h3>")
    parts.append(
        _table(
            ["source", "variance share"],
            [[c.source, f"{c.variance_share:.1%}"] for c in result.contributions],
            {1},
        )
    )
    parts.append(f"<h3>Worst case, RSS and Monte Carlo [{u}]</h3>")
    parts.append(
        _table(
            ["source", "worst case", "RSS", "Monte Carlo 99.73 %", "how"],
            [
                [
                    r.source,
                    f"{r.worst_case:.4g}",
                    f"{r.rss:.4g}",
                    f"{r.mc_9973:.4g}",
                    r.mc_9973_method,
                ]
                for r in shown.comparison
            ],
            {1, 2, 3},
        )
    )
    fig = montecarlo_figure(shown)
    parts.append(
        f'<figure class="figure">{figure_svg(fig, prefix="mc")}<figcaption>Band of the'
        " displacement error ΔS(θ), histogram of max |ΔS| against the limits and the"
        " contributions at the angle of the worst margin.</figcaption></figure>"
    )
    plt.close("all")
    return "\n".join(parts)


def _interval(ci: tuple[float | None, float | None] | None) -> str:
    if ci is None:
        return "n/a"
    lo, hi = ci
    return f"[{'-' if lo is None else f'{lo:.4g}'}, {'-' if hi is None else f'{hi:.4g}'}]"


def montecarlo_figure(shown: Any) -> Figure:
    """Draw the Monte Carlo figure: band of ΔS(θ), histogram of max |ΔS|, Pareto chart.

    Parameters
    ----------
    shown : MonteCarloDisplay
        The study in display units
        (:func:`camtol.report.tolerancing_display.display_montecarlo`).

    Returns
    -------
    matplotlib.figure.Figure
        Three panels; the band's legend stands to the right of its axes.
    """
    from matplotlib.figure import Figure

    result = shown.result
    s = shown.statistics["lift"]
    u = _u(s.unit)
    fig = Figure(figsize=(10, 7.5), layout="constrained")
    grid = fig.add_gridspec(2, 2, height_ratios=(1.25, 1.0))
    ax = fig.add_subplot(grid[0, :])
    t = result.theta_deg
    how = "deterministic" if s.method == "deterministic" else f"{result.samples} samples"
    ax.fill_between(t, s.q00135, s.q99865, alpha=0.3, label=f"0.135-99.865 % band ({how})")
    ax.plot(t, s.mean, label="mean")
    ax.plot(t, s.q50, ":", label="median")
    draw_limits(ax, shown)
    ax.set_xlabel("cam angle θ [deg]")
    ax.set_ylabel(f"ΔS [{u}]")
    ax.set_xlim(0, 360)
    ax.set_title(f"{result.design_name}: Monte Carlo ({result.mode}, {result.samples} samples)")
    from camtol.report._figstyle import _legend_outside

    _legend_outside(ax)
    _histogram(fig.add_subplot(grid[1, 0]), shown)
    _pareto(fig.add_subplot(grid[1, 1]), shown)
    return fig


def _histogram(ax: Any, shown: Any) -> None:
    """Draw the histogram of max |ΔS| over the samples against the limits (sampled)."""
    result = shown.result
    s = shown.statistics["lift"]
    u = _u(s.unit)
    hist = s.max_abs_histogram
    if hist is not None:
        edges, counts = hist
        occupied = np.flatnonzero(counts)
        top = float(edges[occupied[-1] + 1]) if occupied.size else float(edges[-1])
        if shown.limits is not None:
            top = max(top, float(np.max(np.maximum(shown.limits[1], -shown.limits[0]))))
        # Re-bin onto HISTOGRAM_BARS bars over [0, top] (counts moved whole, by centre).
        centres = 0.5 * (edges[:-1] + edges[1:])
        bars = np.linspace(0.0, top * 1.02 if top > 0 else 1.0, HISTOGRAM_BARS + 1)
        k = np.clip(np.searchsorted(bars, centres, side="right") - 1, 0, HISTOGRAM_BARS - 1)
        rebinned = np.bincount(k, weights=counts, minlength=HISTOGRAM_BARS)
        ax.bar(bars[:-1], rebinned, width=np.diff(bars), align="edge", color="tab:blue")
    ax.axvline(s.max_abs.q99865, color="0.2", linestyle=":", linewidth=1.0, label="99.865 %")
    if shown.limits is not None:
        lower, upper = shown.limits
        if result.yield_estimate is not None and result.yield_estimate.spec is not None:
            ax.axvline(float(upper[0]), color="tab:red", linestyle="--", label="spec")
        else:
            half = np.minimum(upper, -lower)
            ax.axvline(float(np.min(half)), color="tab:red", linestyle="--", label="band, tightest")
            ax.axvline(
                float(np.max(np.maximum(upper, -lower))),
                color="tab:red",
                linestyle=":",
                label="band, widest",
            )
    ax.set_xlabel(f"max |ΔS| over the cycle [{u}]")
    ax.set_ylabel("samples")
    ax.set_title(f"max |ΔS| (sampled, {result.samples} samples)", fontsize="medium")
    ax.legend(fontsize="small", loc="upper right")


def _pareto(ax: Any, shown: Any) -> None:
    """Draw the variance shares at the worst angle, largest first, and their sum."""
    result = shown.result
    contributions = list(result.contributions)
    names = [c.source for c in contributions]
    shares = np.array([c.variance_share for c in contributions]) * 100.0
    x = np.arange(len(names))
    ax.bar(x, shares, color="tab:green")
    ax.set_xticks(x, names, rotation=30 if len(names) > 4 else 0)
    ax.set_ylabel("variance share [%]")
    ax.set_ylim(0, 105)
    twin = ax.twinx()
    twin.plot(x, np.cumsum(shares), "o-", color="0.25", markersize=3)
    twin.set_ylim(0, 105)
    twin.set_ylabel("cumulative [%]")
    ax.set_title(
        f"contributions at θ = {result.worst_angle_deg:.1f}° (variance shares)", fontsize="medium"
    )


def draw_limits(ax: Any, shown: Any) -> None:
    """Draw the spec or band the yield was judged against, and the worst-margin angle.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes of ΔS(θ) in the display unit.
    shown : MonteCarloDisplay
        The study in display units: its ``limits`` (None: nothing drawn) and its
        result's ``worst_angle_deg``.
    """
    if shown.limits is None:
        return
    lower, upper = shown.limits
    result = shown.result
    t = result.theta_deg
    ax.plot(t, upper, "--", color="tab:red", linewidth=1.0, label="spec limits")
    ax.plot(t, lower, "--", color="tab:red", linewidth=1.0)
    ax.axvline(result.worst_angle_deg, color="0.4", linewidth=0.8, linestyle=":")
    ax.annotate(
        f"worst margin {result.worst_angle_deg:.1f}°",
        (result.worst_angle_deg, float(upper[int(abs(t - result.worst_angle_deg).argmin())])),
        textcoords="offset points",
        xytext=(4, -12),
        fontsize=8,
        color="0.3",
    )
