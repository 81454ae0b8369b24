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

Why one module: it is the panels of the ``camtol analyze --plot`` figure and
:func:`analysis_figure`, which lays them out; every panel draws the same
:class:`~camtol.analysis.result.Analysis` (or its cam drawing) in the display units of
:mod:`camtol.report.display`. The fixture's figures live in
:mod:`camtol.report.plots_fixture` and are only re-exported here.

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
from camtol.report._figstyle import _fit_grid_to_legends, _legend_outside, _stamp
from camtol.report.display import (
    DisplayUnits,
    accuracy_words,
    display_curves,
    display_extremes,
)
from camtol.report.plot_style import COLOURS as _COLOURS
from camtol.report.plot_style import axes, pretty_unit
from camtol.report.plot_style import axes as _axes
from camtol.report.plot_style import axis_label as _label
from camtol.report.plot_style import theta_axis as _theta_axis
from camtol.report.plots_fixture import (
    acceptance_plot,
    conjugate_variation_plot,
    fixture_figure,
    profile_error_estimate_plot,
)

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.gridspec import GridSpec

    from camtol.analysis.drawing import CamDrawing
    from camtol.analysis.result import Analysis
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
    "svaj_plot",
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
        Result of :func:`camtol.analysis.result.analyse`.
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
    made_here = ax is None
    ax = _axes(ax)
    t = _theta_deg(analysis)
    c = display_curves(analysis)
    arts: list[Any] = []
    arts += ax.plot(t, c["shift_angle"], color=_COLOURS[0], label="shift angle λ")
    arts += ax.plot(t, c["pressure_angle"], color=_COLOURS[3], ls="--", label="pressure angle φ")
    limit = analysis.design.pressure_angle_limit_deg
    if limit is not None:
        arts.append(
            ax.axhline(limit, color=_COLOURS[3], lw=1.0, ls=":", label=f"limit ±{limit:g}°")
        )
        arts.append(ax.axhline(-limit, color=_COLOURS[3], lw=1.0, ls=":"))
    ax.set_ylabel(_label("λ, φ", "deg"))
    _theta_axis(ax)
    handles = list(arts[:3])  # λ, φ and (one of) the limit lines
    if "face_contact" in c:
        ax2 = ax.twinx()
        line = ax2.plot(t, c["face_contact"], color=_COLOURS[2], ls="-.", label="contact on face u")
        ax2.set_ylabel(_label("u", "mm"))
        arts += line
        handles += line
    if "face_contact" in c:  # clear of the twin axis' labels
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.14, 1.0), fontsize="small")
    else:
        _legend_outside(ax, handles)
    ax.set_title("Shift angle, pressure angle" + (", u" if "face_contact" in c else ""))
    _stamp(ax, analysis.design.name, made_here)
    return arts


def radial_factor_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """ΔS_r/Δr: cos λ / cos φ (translating) or cos λ / u (oscillating), CW06 eqs. 29, 43.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyse`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn.
    """
    made_here = ax is None
    ax = _axes(ax)
    curves = display_curves(analysis)
    unit = curves.unit("radial_factor").unit
    symbol = "cos λ / cos φ" if analysis.design.mechanism.output == "translating" else "ΔS_r/Δr"
    arts = list(ax.plot(_theta_deg(analysis), curves["radial_factor"], color="k"))
    ax.set_ylabel(_label(symbol, unit))
    ax.set_title("Radial-error factor ΔS_r/Δr")
    _theta_axis(ax)
    _stamp(ax, analysis.design.name, made_here)
    return arts


def _error_plot(
    analysis: Analysis, prefix: str, unit: str, title: str, ax: Axes | None, combined: bool
) -> list[Any]:
    made_here = ax is None
    ax = _axes(ax)
    t = _theta_deg(analysis)
    arts: list[Any] = []
    curves = display_curves(analysis)
    worst = curves[f"{prefix}_worst"]
    if analysis.errors.sources and not combined:  # the worst-case envelope ±Σ|ΔX_p|
        arts.append(
            ax.fill_between(
                t, -worst, worst, color="0.85", lw=0, label="worst-case envelope ±Σ|ΔX_p|"
            )
        )
    for i, key in enumerate(_source_keys(analysis)):
        arts += ax.plot(
            t,
            curves[f"{prefix}_{key}"],
            color=_COLOURS[i % len(_COLOURS)],
            label=f"{prefix}_{_source_label(analysis, key)}".replace("d", "Δ", 1),
        )
    if combined:
        arts += ax.plot(t, worst, "k-", lw=1.6, label="worst case")
        arts += ax.plot(t, curves[f"{prefix}_rms"], "k--", lw=1.2, label="RMS")
    ax.axhline(0.0, color="0.5", lw=0.6)
    symbol = prefix.replace("d", "Δ", 1)
    ax.set_ylabel(_label(symbol, unit))
    ax.set_title(title)
    _theta_axis(ax)
    if arts:
        _legend_outside(ax)
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
    _stamp(ax, analysis.design.name, made_here)
    return arts


def _unit_of(analysis: Analysis, key: str) -> str:
    return display_curves(analysis).unit(key).unit


def lift_error_plot(analysis: Analysis, ax: Axes | None = None) -> list[Any]:
    """Displacement error ΔS of each source, worst case Σ|ΔS_p| and RMS (CW06 eqs. 44-47).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyse`.
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
        Result of :func:`camtol.analysis.result.analyse`.
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
        Result of :func:`camtol.analysis.result.analyse`.
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
# The cam and follower at one angle
# ---------------------------------------------------------------------------------------
def _segment(ax: Axes, p: Any, q: Any, **kw: Any) -> list[Any]:
    return list(ax.plot([p[0], q[0]], [p[1], q[1]], **kw))


def cam_plot(drawing: CamDrawing, ax: Axes | None = None) -> list[Any]:
    """Draw the cam with its base circle and the follower at the drawing's cam angle.

    Parameters
    ----------
    drawing : CamDrawing
        From :func:`camtol.analysis.drawing.cam_drawing` (every cam of the design, both cams of a
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
    made_here = ax is None
    ax = axes(ax, (6.0, 6.0))
    arts: list[Any] = []
    labelled = len(drawing.cams) > 1
    for i, cam in enumerate(drawing.cams):
        name = f"cam {cam.label}" if labelled else "cam profile"
        colour = ("k", "#1f4e9c")[i % 2]
        arts += ax.plot(cam.profile_x_mm, cam.profile_y_mm, color=colour, lw=1.5, label=name)
        if cam.pitch_x_mm is not None and cam.pitch_y_mm is not None:
            arts += ax.plot(
                cam.pitch_x_mm,
                cam.pitch_y_mm,
                color=colour,
                lw=0.8,
                ls="-.",
                label=f"pitch curve {cam.label}".rstrip(),
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
    _legend_outside(ax)
    _stamp(ax, drawing.design_name, made_here)
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
def _motion_peaks(analysis: Analysis) -> Any:
    """Return the nominal-motion peaks: the analysis field when present, else computed."""
    peaks = getattr(analysis, "motion", None)
    if peaks is not None:
        return peaks
    from camtol.analysis.summary import motion_peaks

    return motion_peaks(
        analysis.kinematics,
        output=analysis.design.mechanism.output,
        omega_rad_s=analysis.design.omega_rad_s,
    )


def _svaj_scales(analysis: Analysis) -> list[tuple[str, str, float]]:
    """Return (symbol, display unit, factor from per-radian values) for S, V, A, J."""
    w = analysis.design.omega_rad_s
    if analysis.design.mechanism.output == "oscillating":
        s = [("ξ", "°", math.degrees(1.0))]
        if w is None:
            return s + [("V", "rad/rad", 1.0), ("A", "rad/rad²", 1.0), ("J", "rad/rad³", 1.0)]
        return s + [("V", "rad/s", w), ("A", "rad/s²", w**2), ("J", "rad/s³", w**3)]
    s = [("S", "mm", 1.0)]
    if w is None:
        return s + [("V", "mm/rad", 1.0), ("A", "mm/rad²", 1.0), ("J", "mm/rad³", 1.0)]
    return s + [("V", "m/s", w * 1e-3), ("A", "m/s²", w**2 * 1e-3), ("J", "m/s³", w**3 * 1e-3)]


def svaj_plot(analysis: Analysis, axs: list[Axes] | None = None) -> list[Any]:
    """Nominal follower motion S, V, A, J (the SVAJ diagram; THEORY §1).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyse`.
    axs : list of 4 matplotlib Axes, optional
        Where to draw S, V, A and J (top to bottom); a new figure otherwise.

    Returns
    -------
    list
        The artists drawn.

    Notes
    -----
    At the design speed ω the derivatives are time derivatives (V = ω dS/dθ, A = ω²
    d²S/dθ², J = ω³ d³S/dθ³) in m/s, m/s², m/s³ (rad/s… for an oscillating follower);
    without a speed they are per radian of cam angle. The peaks in each panel's label come
    from :func:`camtol.analysis.summary.motion_peaks`.
    """
    made_here = axs is None
    if axs is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(7.0, 8.0), layout="constrained")
        axs = list(fig.subplots(4, 1, sharex=True))
    k = analysis.kinematics
    t = _theta_deg(analysis)
    peaks = _motion_peaks(analysis)
    peak_of = {"V": peaks.velocity, "A": peaks.acceleration, "J": peaks.jerk}
    arts: list[Any] = []
    for i, (ax, y, (sym, unit, f)) in enumerate(
        zip(axs, (k.lift, k.velocity, k.acceleration, k.jerk), _svaj_scales(analysis), strict=True)
    ):
        arts += ax.plot(t, np.asarray(y) * f, color=_COLOURS[i], lw=1.2)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel(f"{sym} [{unit}]")
        _theta_axis(ax)
        if sym in peak_of:
            p = peak_of[sym]
            ax.set_title(
                f"peak |{sym}| = {p.abs_max * f:.4g} {unit}", fontsize="small", loc="right"
            )
        if i < 3:  # one θ axis label, under J
            ax.xaxis.label.set_visible(False)
            ax.tick_params(labelbottom=False)
    speed = analysis.design.speed_rpm
    axs[0].set_title(
        "Nominal motion (SVAJ)" + (f" at {speed:g} rpm" if speed else ", per radian"), loc="left"
    )
    _stamp(axs[0], analysis.design.name, made_here)
    return arts


def analysis_figure(analysis: Analysis, drawing: CamDrawing | None = None) -> Figure:
    """Draw the paper-like multi-panel figure of an analysis (CW06 Figs. 4-9).

    Panels: the cam (with the pitch curve of a roller) and follower at a chosen angle
    (default: where the worst-case error is largest); the nominal S, V, A, J (at speed
    when the design gives one); λ and φ with the pressure-angle limit, and u; the
    radial-error factor; ΔS per source with worst case and RMS; ΔV and ΔA per source
    inside their worst-case envelopes. Legends stand outside the axes so that they never
    hide a curve.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyse`.
    drawing : CamDrawing
        The cam and follower to draw in the first panel (e.g. from
        :func:`camtol.analysis.drawing.analysis_drawing`, at the angle where the worst-case error
        is largest).

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save with ``fig.savefig(path)``. Its title names the
        design and the camtol version.
    """
    import matplotlib

    if drawing is None:
        raise TypeError(
            "analysis_figure needs the drawing (camtol.analysis.drawing.analysis_drawing)"
        )
    # Titles at the top of their axes: no panel has tick labels above it, so matplotlib's
    # search for them (a third of the drawing time, issue 32) would find nothing.
    with matplotlib.rc_context({"axes.titley": 1.0}):
        fig, grid = _analysis_panels(analysis, drawing)
    _fit_grid_to_legends(fig, grid)
    return fig


def _analysis_panels(analysis: Analysis, drawing: CamDrawing) -> tuple[Figure, GridSpec]:
    from matplotlib.figure import Figure

    from camtol._version import __version__

    fig = Figure(figsize=(14.0, 20.0))  # laid out by _fit_grid_to_legends
    gs = fig.add_gridspec(4, 2, height_ratios=(1.4, 1.0, 1.0, 1.0))
    worst = display_extremes(analysis)["dS_worst"][0]
    cam_plot(drawing, ax=fig.add_subplot(gs[0, 0]))
    svaj = gs[0, 1].subgridspec(4, 1, hspace=0.2)  # room for each panel's peak
    svaj_axes = [fig.add_subplot(svaj[i]) for i in range(4)]
    svaj_plot(analysis, svaj_axes)
    shift_angle_plot(analysis, ax=fig.add_subplot(gs[1, 0]))
    radial_factor_plot(analysis, ax=fig.add_subplot(gs[1, 1]))
    lift_error_plot(analysis, ax=fig.add_subplot(gs[2, :]))
    velocity_error_plot(analysis, ax=fig.add_subplot(gs[3, 0]))
    acceleration_error_plot(analysis, ax=fig.add_subplot(gs[3, 1]))
    fig.suptitle(
        f"{analysis.design.name}: max worst-case ΔS {worst.value:.4g}"
        f" {pretty_unit(DisplayUnits.of(analysis.design).lift)} at θ = {worst.theta_deg:.2f}°,"
        f" {accuracy_words(analysis.accuracy)} (camtol {__version__})",
        y=1.0 - 0.12 / 20.0,
        va="top",
    )
    return fig, gs
