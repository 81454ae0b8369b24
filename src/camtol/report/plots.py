"""Figures of an analysis, drawn like the papers' figures (CW06 Figs. 4-9, CW11 Figs. 6-9).

Every function takes a result object (STYLE point 6), draws on an optional Matplotlib
``ax`` and returns the artists it made; without ``ax`` it makes a new
:class:`matplotlib.figure.Figure` (no pyplot, so no global state and no GUI backend:
``fig.savefig`` picks the Agg/SVG/PDF renderer from the file format). Matplotlib is only
imported when a figure is drawn; ``import camtol`` does not import it.

Axes carry the quantity and its unit, ``"ΔS [µm]"``; the cam angle is in degrees. The
analysis grid holds each segment boundary twice (left, then right limit), so a jump of a
velocity or acceleration error is drawn as a vertical step exactly at the boundary
(THEORY §3.5), never smeared over a grid step.

References
----------
.. [CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006.
.. [CW11] W.-T. Chang, L.-I. Wu, in *Wide Spectra of Quality Control*, InTech, 2011, ch. 20.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray
from camtol.report.plot_style import COLOURS, axes, axis_label, pretty_unit, theta_axis
from camtol.report.plots_fixture import (
    acceptance_plot,
    conjugate_variation_plot,
    fixture_figure,
    profile_error_estimate_plot,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from camtol.analysis import Analysis
    from camtol.drawing import CamDrawing
    from camtol.mechanisms.elements import Outline

__all__ = [
    "acceleration_error_plot",
    "acceptance_plot",
    "analysis_figure",
    "cam_plot",
    "conjugate_variation_plot",
    "fixture_figure",
    "lift_error_plot",
    "pretty_unit",
    "profile_error_estimate_plot",
    "radial_factor_plot",
    "shift_angle_plot",
    "velocity_error_plot",
]


def _theta_deg(analysis: Analysis) -> FloatArray:
    return np.asarray(np.degrees(analysis.kinematics.theta_rad))


def _source_keys(analysis: Analysis) -> list[str]:
    return list(analysis.errors.sources)


def _source_label(analysis: Analysis, key: str) -> str:
    for t in analysis.tolerances:
        if t.key == key:
            return f"{key} ({t.display})"
    return key


# ---------------------------------------------------------------------------------------
# Panels of an analysis (CW06 Figs. 4-9)
# ---------------------------------------------------------------------------------------
def shift_angle_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """Shift angle λ and pressure angle φ, and the contact position u on the face.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    ax : matplotlib Axes, optional
        Where to draw; a new figure otherwise. u (flat faces) goes on a twin y axis.

    Returns
    -------
    list
        The artists (lines) drawn.

    Notes
    -----
    λ is the angle between the radial line O2A and the common normal (THEORY §2.5,
    CW06 eqs. 38-42); u = |PA| of a flat face (THEORY §2.1-2.2).
    """
    ax = axes(ax)
    t = _theta_deg(analysis)
    c = analysis.curves
    arts: list[Any] = []
    arts += ax.plot(t, c["shift_angle"], color=COLOURS[0], label="shift angle λ")
    arts += ax.plot(t, c["pressure_angle"], color=COLOURS[3], ls="--", label="pressure angle φ")
    ax.set_ylabel(axis_label("λ, φ", "deg"))
    theta_axis(ax)
    handles = list(arts)
    if "face_contact" in c:
        ax2 = ax.twinx()
        line = ax2.plot(t, c["face_contact"], color=COLOURS[2], ls="-.", label="contact on face u")
        ax2.set_ylabel(axis_label("u", "mm"))
        arts += line
        handles += line
    ax.legend(handles=handles, loc="best", fontsize="small")
    ax.set_title("Shift angle, pressure angle" + (", u" if "face_contact" in c else ""))
    return arts


def radial_factor_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """ΔS_r/Δr: cos λ / cos φ (translating) or cos λ / u (oscillating), CW06 eqs. 29, 43.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn.
    """
    ax = axes(ax)
    unit = next(q.unit for q in analysis.quantities if q.key == "radial_factor")
    symbol = "cos λ / cos φ" if analysis.design.mechanism.output == "translating" else "ΔS_r/Δr"
    arts = list(ax.plot(_theta_deg(analysis), analysis.curves["radial_factor"], color="k"))
    ax.set_ylabel(axis_label(symbol, unit))
    ax.set_title("Radial-error factor ΔS_r/Δr")
    theta_axis(ax)
    return arts


def _error_plot(
    analysis: Analysis, prefix: str, unit: str, title: str, ax: Axes | None, combined: bool
) -> list[Any]:
    ax = axes(ax)
    t = _theta_deg(analysis)
    arts: list[Any] = []
    for i, key in enumerate(_source_keys(analysis)):
        arts += ax.plot(
            t,
            analysis.curves[f"{prefix}_{key}"],
            color=COLOURS[i % len(COLOURS)],
            label=f"{prefix}_{_source_label(analysis, key)}".replace("d", "Δ", 1),
        )
    if combined:
        arts += ax.plot(t, analysis.curves[f"{prefix}_worst"], "k-", lw=1.6, label="worst case")
        arts += ax.plot(t, analysis.curves[f"{prefix}_rms"], "k--", lw=1.2, label="RMS")
    ax.axhline(0.0, color="0.5", lw=0.6)
    symbol = prefix.replace("d", "Δ", 1)
    ax.set_ylabel(axis_label(symbol, unit))
    ax.set_title(title)
    theta_axis(ax)
    if arts:
        ax.legend(loc="best", fontsize="small")
    else:
        ax.text(
            0.5,
            0.5,
            "no toleranced error source",
            ha="center",
            va="center",
            transform=ax.transAxes,
            color="0.4",
        )
    return arts


def _unit_of(analysis: Analysis, key: str) -> str:
    return next(q.unit for q in analysis.quantities if q.key == key)


def lift_error_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """Displacement error ΔS of each source, worst case Σ|ΔS_p| and RMS (CW06 eqs. 44-47).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn.
    """
    return _error_plot(
        analysis, "dS", _unit_of(analysis, "dS_worst"), "Displacement errors ΔS", ax, True
    )


def velocity_error_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """Velocity error ΔV = ω dΔS/dθ of each source (THEORY §3.5, CW06 §3.4).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn; per radian of cam angle unless the design gives a speed.
    """
    return _error_plot(
        analysis, "dV", _unit_of(analysis, "dV_worst"), "Velocity errors ΔV", ax, False
    )


def acceleration_error_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """Acceleration error ΔA = ω² d²ΔS/dθ² of each source (THEORY §3.5, CW06 §3.4).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn; jumps at segment boundaries appear as vertical steps.
    """
    return _error_plot(
        analysis, "dA", _unit_of(analysis, "dA_worst"), "Acceleration errors ΔA", ax, False
    )


# ---------------------------------------------------------------------------------------
# The cam and its follower
# ---------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------
# The cam and follower at one angle
# ---------------------------------------------------------------------------------------
def _segment(ax: Axes, p: Any, q: Any, **kw: Any) -> list[Any]:
    return list(ax.plot([p[0], q[0]], [p[1], q[1]], **kw))


def cam_plot(drawing: CamDrawing, ax: Axes | None = None) -> list[Any]:
    """Draw the cam with its base circle and the follower at the drawing's cam angle.

    Parameters
    ----------
    drawing : CamDrawing
        From :func:`camtol.drawing.cam_drawing` (every cam of the design, both cams of a
        conjugate pair).
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn.

    Notes
    -----
    Drawn in the cam frame X-Y of THEORY §0 (origin O2 at the cam pivot): the cam is
    fixed and the follower stands where it is at θ, seen from the cam. Also marked: the
    contact point A, the instant centre Q = I23 and the common normal AQ (THEORY §2).
    The follower is the mechanism's own outline (rollers, faces, arms, pivots).
    """
    ax = axes(ax, (6.0, 6.0))
    arts: list[Any] = []
    labelled = len(drawing.cams) > 1
    for i, cam in enumerate(drawing.cams):
        name = f"cam {cam.label}" if labelled else "cam profile"
        arts += ax.plot(
            cam.profile_x_mm, cam.profile_y_mm, color=("k", "#1f4e9c")[i % 2], lw=1.5, label=name
        )
    rb = drawing.base_radius_mm
    phi = np.linspace(0.0, 2.0 * math.pi, 361)
    arts += ax.plot(
        rb * np.cos(phi), rb * np.sin(phi), color="0.55", lw=0.8, ls=":", label="base circle"
    )
    arts += ax.plot([0.0], [0.0], "k+", ms=10, mew=1.5)
    arts.append(ax.annotate("O2", (0.0, 0.0), xytext=(4, 4), textcoords="offset points"))
    style: dict[str, Any] = {"color": "#2c7f2c", "lw": 2.0}
    pivots: set[tuple[float, float]] = set()
    for cam in drawing.cams:
        arts += _draw_outline(ax, cam.outline, style, pivots)
    c0 = drawing.cams[0]
    a = (c0.contact_x_mm, c0.contact_y_mm)
    qv = (c0.centre_x_mm, c0.centre_y_mm)
    arts += _segment(ax, a, qv, color="#d62728", lw=0.8, ls="--", label="common normal AQ")
    arts += ax.plot([qv[0]], [qv[1]], "o", color="#d62728", ms=4)
    arts.append(ax.annotate("Q", qv, xytext=(4, -10), textcoords="offset points"))
    for cam in drawing.cams:
        arts += ax.plot([cam.contact_x_mm], [cam.contact_y_mm], "ko", ms=4)
    arts.append(ax.annotate("A", a, xytext=(4, 4), textcoords="offset points"))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.set_title(f"{drawing.design_name}: follower at θ = {drawing.theta_deg:g}° (cam frame)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    ax.legend(loc="best", fontsize="small")
    return arts


def _draw_outline(
    ax: Axes, outline: Outline, style: dict[str, Any], pivots: set[tuple[float, float]]
) -> list[Any]:
    """Draw a follower outline; a pivot shared by two cams is drawn once."""
    arts: list[Any] = []
    phi = np.linspace(0.0, 2.0 * math.pi, 121)
    for x, y, r in outline.circles:
        arts += ax.plot(x + r * np.cos(phi), y + r * np.sin(phi), **style)
    for p, q in outline.segments:
        arts += _segment(ax, p, q, **style)
    for p, q in outline.guides:
        arts += _segment(ax, p, q, color="0.5", lw=0.6, ls="-.")
    for text, x, y in outline.labels:
        arts.append(ax.annotate(text, (x, y), xytext=(4, -10), textcoords="offset points"))
    for o3 in outline.pivots:
        key = (round(o3[0], 9), round(o3[1], 9))
        if key in pivots:
            continue
        pivots.add(key)
        arts += ax.plot([o3[0]], [o3[1]], "o", mfc="white", mec="k", ms=7)
        arts.append(ax.annotate("O3", o3, xytext=(5, 5), textcoords="offset points"))
    return arts


# ---------------------------------------------------------------------------------------
# The whole figure of `camtol analyze --plot`
# ---------------------------------------------------------------------------------------
def analysis_figure(analysis: Analysis, drawing: CamDrawing | None = None) -> Figure:
    """Draw the paper-like multi-panel figure of an analysis (CW06 Figs. 4-9).

    Panels: the cam and follower (``drawing``, e.g. from
    :func:`camtol.drawing.analysis_drawing`, at the angle where the worst-case error is
    largest); λ, φ and u; the radial-error factor; ΔS per source with worst case and
    RMS; ΔV and ΔA per source.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    drawing : CamDrawing
        The cam and follower to draw in the first panel.

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save with ``fig.savefig(path)``.
    """
    from matplotlib.figure import Figure

    from camtol import __version__

    fig = Figure(figsize=(13.0, 15.0), layout="constrained")
    axs = fig.subplots(3, 2)
    worst = analysis.extremes["dS_worst"][0]
    if drawing is None:
        raise TypeError("analysis_figure needs the drawing (camtol.drawing.analysis_drawing)")
    cam_plot(drawing, ax=axs[0, 0])
    shift_angle_plot(analysis, ax=axs[0, 1])
    radial_factor_plot(analysis, ax=axs[1, 0])
    lift_error_plot(analysis, ax=axs[1, 1])
    velocity_error_plot(analysis, ax=axs[2, 0])
    acceleration_error_plot(analysis, ax=axs[2, 1])
    fig.suptitle(
        f"{analysis.design.name}: max worst-case ΔS {worst.value:.4g}"
        f" {pretty_unit(analysis.error_unit)} at θ = {worst.theta_deg:.2f}°,"
        f" {analysis.accuracy.describe()} (camtol {__version__})"
    )
    return fig
