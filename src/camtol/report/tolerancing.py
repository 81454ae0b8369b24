"""HTML section of a Monte Carlo study for the report (``camtol report --montecarlo N``)."""

from __future__ import annotations

from typing import Any

from camtol.report.html import _e, _table, figure_svg

__all__ = ["draw_limits", "montecarlo_section"]


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
        An ``<h2>`` section with the source distributions, max |ΔS| statistics, the
        contributor table, the worst-case / RSS / Monte Carlo comparison and the band
        figure (inline SVG).
    """
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    from camtol.report.tolerancing_display import display_montecarlo

    shown = display_montecarlo(result, design)
    s = shown.statistics["lift"]
    u = "µm" if s.unit == "um" else "°"
    parts = [
        f"<h2>Monte Carlo ({_e(result.mode)} mode, {result.samples} samples,"
        f" seed {result.seed})</h2>",
        _table(["source", "distribution"], [[k, v] for k, v in shown.sources.items()]),
    ]
    m = s.max_abs
    parts.append(
        f"<p>max |ΔS| over the cycle [{u}]: mean {m.mean:.4g}, σ {m.std:.4g},"
        f" 0.135 % {m.q00135:.4g}, median {m.q50:.4g}, 99.865 % {m.q99865:.4g}.</p>"
    )
    if result.yield_estimate is not None:
        y = result.yield_estimate
        parts.append(
            f"<p>Yield ({_e(shown.yield_spec)}): {y.value:.4%}, 95 % interval"
            f" [{y.ci95[0]:.4%}, {y.ci95[1]:.4%}] (Clopper-Pearson).</p>"
        )
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
            ["source", "worst case", "RSS", "Monte Carlo 99.73 %"],
            [
                [r.source, f"{r.worst_case:.4g}", f"{r.rss:.4g}", f"{r.mc_9973:.4g}"]
                for r in shown.comparison
            ],
            {1, 2, 3},
        )
    )
    fig = Figure(figsize=(8, 3.6))
    ax = fig.add_subplot()
    t = result.theta_deg
    ax.fill_between(t, s.q00135, s.q99865, alpha=0.3, label="0.135-99.865 % band")
    ax.plot(t, s.mean, label="mean")
    draw_limits(ax, shown)
    ax.set_xlim(0, 360)
    ax.set_xlabel("cam angle θ [deg]")
    ax.set_ylabel(f"ΔS [{s.unit}]")
    ax.legend(loc="best")
    fig.tight_layout()
    parts.append(
        f'<figure class="figure">{figure_svg(fig, prefix="mc")}<figcaption>Monte Carlo band'
        " of the displacement error ΔS(θ).</figcaption></figure>"
    )
    plt.close("all")
    return "\n".join(parts)


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
