"""The cam and its follower drawn in the cam frame (THEORY §0, §2): ``cam_plot``.

Matplotlib is imported only when a figure is drawn.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray
from camtol.report._figstyle import _axes, _legend_outside, _stamp

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

    from camtol.design import CamDesign

__all__ = ["cam_plot"]


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

    made_here = ax is None
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
        pitch = _pitch_curve(d, k)
        if pitch is not None:
            arts += ax.plot(
                pitch[0],
                pitch[1],
                color=("k", "#1f4e9c")[i],
                lw=0.8,
                ls="-.",
                label=f"pitch curve{' ' + label[-1] if conj else ''}",
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
    _legend_outside(ax)
    _stamp(ax, design.name, made_here)
    return arts


def _pitch_curve(design: CamDesign, k: Any) -> tuple[FloatArray, FloatArray] | None:
    """Return the roller centre path in the cam frame (THEORY §2.3), None without a roller."""
    from camtol import jet

    g = design.mechanism.contact(k.theta_rad, k.lift, k.velocity)
    if "pitch_x" not in g.extras:
        return None
    x = np.asarray(jet.value(g.extras["pitch_x"]), dtype=float)
    y = np.asarray(jet.value(g.extras["pitch_y"]), dtype=float)
    return x, y


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
