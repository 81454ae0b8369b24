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

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from camtol.analysis import Analysis
    from camtol.design import CamDesign
    from camtol.inspection.fixture import FixtureInspection

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

_THETA_LABEL = "cam angle θ [°]"
_COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2")


def pretty_unit(unit: str) -> str:
    """Display form of a unit key: ``um/rad2`` → ``µm/rad²``, ``deg`` → ``°``.

    Parameters
    ----------
    unit : str
        ASCII unit key, e.g. ``"um/rad2"``; ``""`` or ``"-"`` for dimensionless.

    Returns
    -------
    str
        The unit for display; ``"-"`` for a dimensionless quantity.
    """
    if unit in ("-", ""):
        return "-"
    return unit.replace("um", "µm").replace("deg", "°").replace("rad2", "rad²").replace("s2", "s²")


def _label(quantity: str, unit: str) -> str:
    return f"{quantity} [{pretty_unit(unit)}]"


def _axes(ax: Axes | None, figsize: tuple[float, float] = (7.0, 4.0)) -> Axes:
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig.add_subplot()


def _theta_axis(ax: Axes) -> None:
    ax.set_xlabel(_THETA_LABEL)
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0.0, 361.0, 60.0))
    ax.grid(True, linewidth=0.4, alpha=0.6)


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
    ax = _axes(ax)
    t = _theta_deg(analysis)
    c = analysis.curves
    arts: list[Any] = []
    arts += ax.plot(t, c["shift_angle"], color=_COLOURS[0], label="shift angle λ")
    arts += ax.plot(t, c["pressure_angle"], color=_COLOURS[3], ls="--", label="pressure angle φ")
    ax.set_ylabel(_label("λ, φ", "deg"))
    _theta_axis(ax)
    handles = list(arts)
    if "face_contact" in c:
        ax2 = ax.twinx()
        line = ax2.plot(t, c["face_contact"], color=_COLOURS[2], ls="-.", label="contact on face u")
        ax2.set_ylabel(_label("u", "mm"))
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
    ax = _axes(ax)
    unit = next(q.unit for q in analysis.quantities if q.key == "radial_factor")
    symbol = "cos λ / cos φ" if analysis.design.mechanism.output == "translating" else "ΔS_r/Δr"
    arts = list(ax.plot(_theta_deg(analysis), analysis.curves["radial_factor"], color="k"))
    ax.set_ylabel(_label(symbol, unit))
    ax.set_title("Radial-error factor ΔS_r/Δr")
    _theta_axis(ax)
    return arts


def _error_plot(
    analysis: Analysis, prefix: str, unit: str, title: str, ax: Axes | None, combined: bool
) -> list[Any]:
    ax = _axes(ax)
    t = _theta_deg(analysis)
    arts: list[Any] = []
    for i, key in enumerate(_source_keys(analysis)):
        arts += ax.plot(
            t,
            analysis.curves[f"{prefix}_{key}"],
            color=_COLOURS[i % len(_COLOURS)],
            label=f"{prefix}_{_source_label(analysis, key)}".replace("d", "Δ", 1),
        )
    if combined:
        arts += ax.plot(t, analysis.curves[f"{prefix}_worst"], "k-", lw=1.6, label="worst case")
        arts += ax.plot(t, analysis.curves[f"{prefix}_rms"], "k--", lw=1.2, label="RMS")
    ax.axhline(0.0, color="0.5", lw=0.6)
    symbol = prefix.replace("d", "Δ", 1)
    ax.set_ylabel(_label(symbol, unit))
    ax.set_title(title)
    _theta_axis(ax)
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
def _segment(ax: Axes, p: FloatArray, q: FloatArray, **kw: Any) -> list[Any]:
    return list(ax.plot([p[0], q[0]], [p[1], q[1]], **kw))


def cam_plot(design: CamDesign, theta_deg: float, ax: Axes | None = None) -> list[Any]:
    """Draw the cam with its base circle and the follower at cam angle ``theta_deg``.

    Parameters
    ----------
    design : CamDesign
        The design (any follower type; both cams of a conjugate pair).
    theta_deg : float
        Cam angle at which the follower is drawn. [deg]
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
    """
    from camtol.kinematics import analysis_grid, kinematics

    ax = _axes(ax, (6.0, 6.0))
    mech = design.mechanism
    theta_rad = math.radians(float(theta_deg) % 360.0)
    grid, left = analysis_grid(0.25, design.program.boundaries_rad)
    arts: list[Any] = []
    conj = mech.kind == "conjugate"
    if conj:
        from camtol.mechanisms.conjugate import cam_design

        cams = [("cam A", cam_design(design, "A")), ("cam B", cam_design(design, "B"))]
    else:
        cams = [("cam profile", design)]
    here = []
    for i, (label, d) in enumerate(cams):
        k = kinematics(d, grid, left_limit=left, check=False)
        arts += ax.plot(
            k.contact_x_mm, k.contact_y_mm, color=("k", "#1f4e9c")[i], lw=1.5, label=label
        )
        here.append((d, kinematics(d, np.array([theta_rad]), check=False)))
    rb = getattr(mech, "base_radius_mm", None)
    if rb is not None:
        phi = np.linspace(0.0, 2.0 * math.pi, 361)
        arts += ax.plot(
            rb * np.cos(phi), rb * np.sin(phi), color="0.55", lw=0.8, ls=":", label="base circle"
        )
    arts += ax.plot([0.0], [0.0], "k+", ms=10, mew=1.5)
    arts.append(ax.annotate("O2", (0.0, 0.0), xytext=(4, 4), textcoords="offset points"))
    scale = float(rb if rb is not None else np.max(here[0][1].radius_mm))
    for d, k in here:
        arts += _draw_follower(ax, d, k, theta_rad, scale)
    k0 = here[0][1]
    a = np.array([k0.contact_x_mm[0], k0.contact_y_mm[0]])
    qv = np.array([k0.centre_x_mm[0], k0.centre_y_mm[0]])
    arts += _segment(ax, a, qv, color="#d62728", lw=0.8, ls="--", label="common normal AQ")
    arts += ax.plot([qv[0]], [qv[1]], "o", color="#d62728", ms=4)
    arts.append(ax.annotate("Q", tuple(qv), xytext=(4, -10), textcoords="offset points"))
    for _d, k in here:
        arts += ax.plot([k.contact_x_mm[0]], [k.contact_y_mm[0]], "ko", ms=4)
    arts.append(ax.annotate("A", tuple(a), xytext=(4, 4), textcoords="offset points"))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.set_title(f"{design.name}: follower at θ = {float(theta_deg):g}° (cam frame)")
    ax.grid(True, linewidth=0.3, alpha=0.5)
    ax.legend(loc="best", fontsize="small")
    return arts


def _draw_follower(ax: Axes, design: CamDesign, k: Any, theta: float, scale: float) -> list[Any]:
    """Draw the follower of a single-contact design at one angle (cam frame)."""
    mech: Any = design.mechanism
    kind = mech.kind
    t = np.array([math.cos(theta), math.sin(theta)])
    w = np.array([-math.sin(theta), math.cos(theta)])
    a = np.array([k.contact_x_mm[0], k.contact_y_mm[0]])
    style: dict[str, Any] = {"color": "#2c7f2c", "lw": 2.0}
    arts: list[Any] = []
    if kind == "flat_translating":
        phi = mech.face_angle_rad
        big_l = mech.base_radius_mm / math.cos(phi) - mech.offset_mm * math.tan(phi) + k.lift[0]
        p = mech.offset_mm * w + big_l * t
        d = np.array([-math.sin(theta + phi), math.cos(theta + phi)])
        arts += _face(ax, a, p, d, scale, style)
        arts += _segment(ax, p, p + 0.8 * scale * t, **style)
        base = mech.offset_mm * w
        arts += _segment(ax, base, base + 2.0 * scale * t, color="0.5", lw=0.6, ls="-.")
        arts.append(ax.annotate("P", tuple(p), xytext=(4, -10), textcoords="offset points"))
    elif kind == "flat_oscillating":
        o3 = mech.pivot_distance_mm * t
        xi = float(k.follower_angle_rad[0])
        psi = theta + math.pi / 2.0 - xi
        d = np.array([-math.sin(psi), math.cos(psi)])
        foot = a + float(np.dot(o3 - a, d)) * d
        arts += _face(ax, a, foot, d, scale, style)
        arts += _segment(ax, o3, foot, **style)
        arts += _pivot(ax, o3)
    elif "pitch_x" in _extras(design, theta, k):
        ex = _extras(design, theta, k)
        c = np.array([float(ex["pitch_x"]), float(ex["pitch_y"])])
        rf = mech.roller_radius_mm
        phi = np.linspace(0.0, 2.0 * math.pi, 121)
        arts += ax.plot(c[0] + rf * np.cos(phi), c[1] + rf * np.sin(phi), **style)
        if kind == "roller_translating":
            arts += _segment(ax, c, c + 0.8 * scale * t, **style)
        else:
            o3 = mech.pivot_distance_mm * t
            arts += _segment(ax, o3, c, **style)
            if kind != "conjugate_cam_b":  # the pair's pivot is drawn once, with cam A
                arts += _pivot(ax, o3)
    return arts


def _extras(design: CamDesign, theta: float, k: Any) -> dict[str, float]:
    from camtol import jet

    g = design.mechanism.contact(np.array([theta]), k.lift, k.velocity)
    return {key: float(np.asarray(jet.value(v)).ravel()[0]) for key, v in g.extras.items()}


def _face(
    ax: Axes, a: FloatArray, p: FloatArray, d: FloatArray, scale: float, style: dict[str, Any]
) -> list[Any]:
    s = [0.0, float(np.dot(p - a, d))]
    lo, hi = min(s) - 0.3 * scale, max(s) + 0.3 * scale
    return _segment(ax, a + lo * d, a + hi * d, **style)


def _pivot(ax: Axes, o3: FloatArray) -> list[Any]:
    arts: list[Any] = list(ax.plot([o3[0]], [o3[1]], "o", mfc="white", mec="k", ms=7))
    arts.append(ax.annotate("O3", tuple(o3), xytext=(5, 5), textcoords="offset points"))
    return arts


# ---------------------------------------------------------------------------------------
# The whole figure of `camtol analyze --plot`
# ---------------------------------------------------------------------------------------
def analysis_figure(analysis: Analysis, *, cam_angle_deg: float | None = None) -> Figure:
    """Draw the paper-like multi-panel figure of an analysis (CW06 Figs. 4-9).

    Panels: the cam and follower at a chosen angle (default: where the worst-case error
    is largest); λ, φ and u; the radial-error factor; ΔS per source with worst case and
    RMS; ΔV and ΔA per source.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.analyse`.
    cam_angle_deg : float, optional
        Cam angle at which to draw the cam and follower. [deg]

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
    at = round(worst.theta_deg, 2) if cam_angle_deg is None else cam_angle_deg
    cam_plot(analysis.design, at, ax=axs[0, 0])
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


# ---------------------------------------------------------------------------------------
# Conjugate cams on the measuring fixture (CW11 §3, Figs. 6-9)
# ---------------------------------------------------------------------------------------
def _fixture_theta(inspection: FixtureInspection) -> FloatArray:
    return np.asarray(np.degrees(inspection.theta_rad))


def conjugate_variation_plot(inspection: FixtureInspection, ax: Axes | None = None) -> list[Any]:
    """Centre-distance variation Δf and its components (THEORY §4.1, CW11 eqs. 14-18).

    With a measurement the components come from it (eq. 19) and their sum is Δf_mea; the
    Δf_est predicted from the known errors of both cams (eqs. 14-18) is drawn dashed
    beside it.

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.inspection.fixture.inspect_conjugate`.
    ax : matplotlib Axes, optional
        Where to draw.

    Returns
    -------
    list
        The artists drawn.
    """
    ax = _axes(ax)
    t = _fixture_theta(inspection)
    v = inspection.variation
    arts: list[Any] = []
    for i, (y, label) in enumerate(
        (
            (v.df_r_um, "Δf_r (profiles)"),
            (v.df_rf_um, "Δf_rf (roller radii)"),
            (v.df_l_um, "Δf_l (arm lengths)"),
            (v.df_eta_um, "Δf_η (arm angle)"),
        )
    ):
        arts += ax.plot(t, y, color=_COLOURS[i], label=label)
    arts += ax.plot(t, v.df_est_um, "k-", lw=1.6, label="Δf_est (sum)")
    if inspection.predicted is not None:  # beside the measurement: eqs. 14-18, known errors
        arts += ax.plot(
            t,
            inspection.predicted.df_est_um,
            "k--",
            lw=1.2,
            label="Δf_est from the known errors (eqs. 14-18)",
        )
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_ylabel(_label("Δf", "um"))
    ax.set_title("Centre-distance variation and its components")
    _theta_axis(ax)
    ax.legend(loc="best", fontsize="small")
    return arts


def profile_error_estimate_plot(
    inspection: FixtureInspection,
    ax: Axes | None = None,
    *,
    tolerance_a_um: tuple[float, float] | None = None,
    tolerance_b_um: tuple[float, float] | None = None,
) -> list[Any]:
    """Estimated profile errors Δr_A,est, Δr_B,est with tolerance lines (CW11 eqs. 19-21).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.inspection.fixture.inspect_conjugate` with a measured Δf.
    ax : matplotlib Axes, optional
        Where to draw.
    tolerance_a_um, tolerance_b_um : tuple of float, optional
        (lower, upper) radial tolerances drawn as horizontal lines. [µm]

    Returns
    -------
    list
        The artists drawn.

    Raises
    ------
    ValueError
        If the inspection has no measured Δf (nothing to estimate).
    """
    est = inspection.estimate
    if est is None:
        raise ValueError("the inspection has no measured Δf; there is no estimate to plot")
    ax = _axes(ax)
    t = _fixture_theta(inspection)
    arts: list[Any] = []
    arts += ax.plot(t, est.dr_a_est_um, color=_COLOURS[0], label="Δr_A,est (master B)")
    arts += ax.plot(t, est.dr_b_est_um, color=_COLOURS[1], label="Δr_B,est (master A)")
    for tol, colour, cam in (
        (tolerance_a_um, _COLOURS[0], "A"),
        (tolerance_b_um, _COLOURS[1], "B"),
    ):
        if tol is None:
            continue
        for j, value in enumerate(tol):
            arts.append(
                ax.axhline(
                    value,
                    color=colour,
                    ls=":",
                    lw=1.2,
                    label=f"tolerance of cam {cam}" if j == 0 else None,
                )
            )
    ax.set_ylabel(_label("Δr", "um"))
    ax.set_title("Estimated radial profile errors")
    _theta_axis(ax)
    ax.legend(loc="best", fontsize="small")
    return arts


def acceptance_plot(
    inspection: FixtureInspection, ax: Axes | None = None, *, cam: str = "A"
) -> list[Any]:
    """Draw the acceptance band of an inspected cam and the measured Δf (THEORY §4.3).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.inspection.fixture.inspect_conjugate`.
    ax : matplotlib Axes, optional
        Where to draw.
    cam : {"A", "B"}
        Inspected cam (the other one is the master).

    Returns
    -------
    list
        The artists drawn; failing intervals are shaded red.

    Raises
    ------
    ValueError
        If ``cam`` is not "A" or "B".
    """
    if cam not in ("A", "B"):
        raise ValueError(f"cam={cam!r} is not allowed; give 'A' or 'B'")
    ax = _axes(ax)
    t = _fixture_theta(inspection)
    b = inspection.bands
    up, lo = (
        (b.df_a_upper_um, b.df_a_lower_um) if cam == "A" else (b.df_b_upper_um, b.df_b_lower_um)
    )
    master = "B" if cam == "A" else "A"
    arts: list[Any] = [ax.fill_between(t, lo, up, color="#9ecae1", alpha=0.5, label="band")]
    arts += ax.plot(t, up, color="#08519c", lw=1.0, label=f"Δf_{cam}(u),est")
    arts += ax.plot(t, lo, color="#08519c", lw=1.0, ls="--", label=f"Δf_{cam}(l),est")
    if inspection.estimate is not None:
        arts += ax.plot(t, inspection.estimate.df_mea_um, "k-", lw=1.4, label="Δf measured")
    verdict = inspection.verdicts.get(cam)
    if verdict is not None:
        for start, end in verdict.failing_intervals_deg:
            spans = [(start, end)] if end >= start else [(start, 360.0), (0.0, end)]
            for s0, s1 in spans:
                arts.append(ax.axvspan(s0, s1, color="#d62728", alpha=0.2))
        state = "passes" if verdict.passed else "FAILS"
        ax.set_title(f"Acceptance of cam {cam} with master {master}: {state}")
    else:
        ax.set_title(f"Acceptance band of cam {cam} with master {master}")
    ax.set_ylabel(_label("Δf", "um"))
    _theta_axis(ax)
    ax.legend(loc="best", fontsize="small")
    return arts


def fixture_figure(
    inspection: FixtureInspection,
    *,
    tolerance_a_um: tuple[float, float] | None = None,
    tolerance_b_um: tuple[float, float] | None = None,
) -> Figure:
    """All fixture panels: Δf components, estimated errors, both acceptance bands (CW11).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.inspection.fixture.inspect_conjugate`.
    tolerance_a_um, tolerance_b_um : tuple of float, optional
        Radial tolerances of cams A and B. [µm]

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13.0, 9.0), layout="constrained")
    axs = fig.subplots(2, 2)
    conjugate_variation_plot(inspection, ax=axs[0, 0])
    if inspection.estimate is not None:
        profile_error_estimate_plot(
            inspection, ax=axs[0, 1], tolerance_a_um=tolerance_a_um, tolerance_b_um=tolerance_b_um
        )
    else:
        axs[0, 1].set_axis_off()
    acceptance_plot(inspection, ax=axs[1, 0], cam="A")
    acceptance_plot(inspection, ax=axs[1, 1], cam="B")
    fig.suptitle("Conjugate cams on the centre-distance fixture (THEORY §4)")
    return fig
