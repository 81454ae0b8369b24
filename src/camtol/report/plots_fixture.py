"""Figures of the conjugate measuring fixture (THEORY §4; CW11 Figs. 6-9).

Each function takes the result of :func:`camtol.inspection.fixture.inspect_conjugate`,
draws on an optional ``ax`` and returns the artists.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray
from camtol.report.plot_style import COLOURS, axes, axis_label, theta_axis

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from camtol.inspection.fixture import FixtureInspection

__all__ = [
    "acceptance_plot",
    "conjugate_variation_plot",
    "fixture_figure",
    "profile_error_estimate_plot",
]


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
    ax = axes(ax)
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
        arts += ax.plot(t, y, color=COLOURS[i], label=label)
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
    ax.set_ylabel(axis_label("Δf", "um"))
    ax.set_title("Centre-distance variation and its components")
    theta_axis(ax)
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
    ax = axes(ax)
    t = _fixture_theta(inspection)
    arts: list[Any] = []
    arts += ax.plot(t, est.dr_a_est_um, color=COLOURS[0], label="Δr_A,est (master B)")
    arts += ax.plot(t, est.dr_b_est_um, color=COLOURS[1], label="Δr_B,est (master A)")
    for tol, colour, cam in (
        (tolerance_a_um, COLOURS[0], "A"),
        (tolerance_b_um, COLOURS[1], "B"),
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
    ax.set_ylabel(axis_label("Δr", "um"))
    ax.set_title("Estimated radial profile errors")
    theta_axis(ax)
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
    ax = axes(ax)
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
    ax.set_ylabel(axis_label("Δf", "um"))
    theta_axis(ax)
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
