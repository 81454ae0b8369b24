"""Figures of a CMM inspection: deviation around the nominal, Δn(θ), functional ΔS.

Drawn as inspectors expect them: the nominal profile with the measured deviation
magnified along the normal and the tolerance zone around it; the normal deviation against
the polar angle with the tolerance limits and the outliers marked; and the follower-motion
error of the measured cam, exact and linear (:mod:`camtol.inspection.functional`).
For a conjugate pair, the fixture's Δf predicted from the two CMM profiles against the
record ([CW11] Table 4, :mod:`camtol.pair.cmm_fixture`). Matplotlib is imported
only when a figure is drawn (no pyplot).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from camtol.inspection.deviations import CamProfile, CmmInspection
    from camtol.inspection.functional import FunctionalDeviation
    from camtol.pair.cmm_fixture import CmmFixtureComparison

__all__ = ["cmm_fixture_figure", "inspection_figure"]


def _magnification(insp: CmmInspection, r_max_mm: float) -> float:
    """Choose a round magnification that draws the largest deviation at about 8% of the cam."""
    span_um = max(abs(insp.tolerance_um[0]), abs(insp.tolerance_um[1]), 1e-3)
    span_um = max(span_um, float(np.max(np.abs(insp.dn_um[insp.kept]))))
    raw = 0.08 * r_max_mm / (span_um * 1e-3)
    return float(10 ** math.floor(math.log10(raw))) if raw >= 1 else 1.0


def inspection_figure(
    insp: CmmInspection,
    profile: CamProfile,
    functional: FunctionalDeviation | None = None,
    *,
    magnification: float | None = None,
) -> Figure:
    """Draw the inspection figure: magnified deviation, Δn against θ, functional ΔS.

    Parameters
    ----------
    insp : CmmInspection
        The registered scan and its deviations.
    profile : CamProfile
        The inspected cam (its nominal profile is drawn).
    functional : FunctionalDeviation, optional
        The follower-motion error; its panel is left out when None.
    magnification : float, optional
        Scale of the deviations in the profile panel (default: a power of ten that draws
        the tolerance zone or the largest deviation at about 8% of the cam's size).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    table = profile.table
    t = np.linspace(0.0, 2 * math.pi, 3601)
    x, y, dx, dy, _, _ = table.evaluate(t)
    sp = np.hypot(dx, dy)
    nx, ny = dy / sp, -dx / sp
    r_max = float(np.max(np.hypot(x, y)))
    mag = _magnification(insp, r_max) if magnification is None else magnification
    lo, hi = insp.tolerance_um
    ncols = 3 if functional is not None else 2
    fig = Figure(figsize=(5.2 * ncols, 5.0), layout="constrained")
    axs = fig.subplots(1, ncols)
    ax = axs[0]
    ax.plot(x, y, color="0.3", lw=0.8, label="nominal")
    radial = insp.tolerance_kind == "radial"
    if radial:  # the zone is along O2A
        r = np.hypot(x, y)
        zx, zy = x / r, y / r
    else:
        zx, zy = nx, ny
    for v, style in ((lo, "--"), (hi, "--")):
        ax.plot(x + mag * v * 1e-3 * zx, y + mag * v * 1e-3 * zy, "C2", ls=style, lw=0.8)
    ax.plot([], [], "C2--", lw=0.8, label=f"tolerance [{lo:g}, {hi:g}] µm")
    px, py, pdx, pdy, _, _ = table.evaluate(insp.param_rad)
    ps = np.hypot(pdx, pdy)
    pnx, pny = pdy / ps, -pdx / ps
    k = insp.kept
    mx = px + mag * insp.dn_um * 1e-3 * pnx
    my = py + mag * insp.dn_um * 1e-3 * pny
    order = np.argsort(insp.param_rad[k])
    ax.plot(mx[k][order], my[k][order], "C0", lw=0.8, label=f"measured, Δn × {mag:g}")
    if np.any(~k):
        ax.plot(mx[~k], my[~k], "rx", ms=5, label="outliers")
    ax.plot([0], [0], "k+")
    ax.set_aspect("equal")
    ax.set_title(f"Cam {insp.cam}: deviation magnified {mag:g}×")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(fontsize=7, loc="upper right")
    ax = axs[1]
    dev, name = (insp.dr_um, "Δr") if radial else (insp.dn_um, "Δn")
    order = np.argsort(insp.theta_deg[k])
    ax.plot(insp.theta_deg[k][order], dev[k][order], "C0", lw=0.7, label=name)
    if np.any(~k):
        ax.plot(insp.theta_deg[~k], dev[~k], "rx", ms=5, label="outliers")
    ax.axhline(lo, color="C2", ls="--", lw=0.8)
    ax.axhline(hi, color="C2", ls="--", lw=0.8, label="tolerance")
    for a, b in insp.failing_intervals_deg:
        spans = [(a, b)] if b >= a else [(a, 360.0), (0.0, b)]
        for s0, s1 in spans:
            ax.axvspan(s0, s1, color="C3", alpha=0.15)
    ax.set_xlim(0, 360)
    ax.set_xticks(range(0, 361, 60))
    ax.set_xlabel("polar angle θ [deg]")
    ax.set_ylabel(f"{'radial' if radial else 'normal'} deviation {name} [µm]")
    verdict = "pass" if insp.passed else "FAIL"
    ax.set_title(f"{name} (tolerance on it): form {insp.form_um:.3g} µm, {verdict}")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    if functional is not None:
        ax = axs[2]
        deg = np.degrees(functional.theta_rad)
        # One unit per quantity (issue 31): µm for a lift, degrees for a swing, as the
        # terminal, JSON, CSV and the store show it.
        scale, unit = (1e3, "µm") if functional.unit == "mm" else (180 / math.pi, "deg")
        ax.plot(deg, functional.ds_measured * scale, "C0", lw=1.0, label="ΔS exact (contact)")
        ax.plot(deg, functional.ds_linear * scale, "C1--", lw=0.8, label="ΔS linear, (∂S/∂n)Δn")
        title = f"Functional error (Fourier ≤ {functional.harmonics} harmonics)"
        if functional.spec is not None:
            ax.axhline(-functional.spec * scale, color="C2", ls="--", lw=0.8)
            ax.axhline(functional.spec * scale, color="C2", ls="--", lw=0.8, label="motion spec")
            title += ", " + ("pass" if functional.passed else "FAIL")
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 60))
        ax.set_xlabel("cam angle θ [deg]")
        ax.set_ylabel(f"follower error ΔS [{unit}]")
        ax.set_title(title)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    return fig


def cmm_fixture_figure(comparison: CmmFixtureComparison) -> Figure:
    """Draw Δf predicted from the CMM profiles of both cams against the record ([CW11] Table 4).

    Top: Δf of the exact fixture twin on the two CMM profiles, Δf_est of [CW11] eqs. 14-18
    with the CMM errors, and the measured Δf_mea when there is one. Bottom: their
    differences from Δf_mea (from the twin without a measurement), rms in the legend.

    Parameters
    ----------
    comparison : CmmFixtureComparison
        The fixture compared with the CMM (:func:`~camtol.pair.compare_cmm_fixture`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    from camtol.pair.cmm_fixture import rms

    c = comparison
    deg = np.degrees(c.theta_rad)
    fig = Figure(figsize=(9.0, 6.4), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    if c.df_mea_um is not None:
        top.plot(deg, c.df_mea_um, "k", lw=1.2, label="Δf_mea (record)")
    top.plot(deg, c.df_twin_um, "C0", lw=0.9, label="Δf twin (exact, CMM profiles)")
    top.plot(deg, c.df_est_um, "C1--", lw=0.9, label="Δf_est (eqs. 14-18, CMM errors)")
    top.set_ylabel("centre-distance variation Δf [µm]")
    top.set_title("Fixture predicted from the CMM profiles of both cams")
    ref, name = (c.df_mea_um, "Δf_mea") if c.df_mea_um is not None else (c.df_twin_um, "twin")
    if c.df_mea_um is not None:
        d_twin = c.df_twin_um - ref
        bottom.plot(deg, d_twin, "C0", lw=0.9, label=f"twin − {name} (rms {rms(d_twin):.3g} µm)")
    d_est = c.df_est_um - ref
    bottom.plot(deg, d_est, "C1--", lw=0.9, label=f"Δf_est − {name} (rms {rms(d_est):.3g} µm)")
    bottom.axhline(0.0, color="0.5", lw=0.6)
    bottom.set_ylabel(f"difference from {name} [µm]")
    bottom.set_xlabel("cam angle θ [deg]")
    for ax in (top, bottom):
        ax.set_xlim(0, 360)
        ax.set_xticks(range(0, 361, 60))
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    return fig
