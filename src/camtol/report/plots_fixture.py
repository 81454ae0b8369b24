"""Figures of conjugate cams on the centre-distance fixture (THEORY §4; CW11 §3, Figs. 6-9).

Δf and its parts, the estimated profile errors with the tolerances (and, with an
indicator record, the estimates at Δf_mea ± u_f), and the acceptance bands with the
measured Δf and its uncertainty band. Every figure made here names the design and the
camtol version. Matplotlib is imported only when a figure is drawn.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, in *Wide Spectra of Quality Control*, InTech, 2011, ch. 20.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.jet import FloatArray
from camtol.report._figstyle import _legend_outside, _stamp
from camtol.report.plot_style import COLOURS as _COLOURS
from camtol.report.plot_style import axes as _axes
from camtol.report.plot_style import axis_label as _label
from camtol.report.plot_style import theta_axis as _theta_axis

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from camtol.pair.acceptance import CamVerdict
    from camtol.pair.fixture import FixtureInspection
    from camtol.pair.indicator import RecordEstimates

__all__ = [
    "acceptance_plot",
    "conjugate_variation_plot",
    "fixture_figure",
    "profile_error_estimate_plot",
]


# ---------------------------------------------------------------------------------------
def _fixture_theta(inspection: FixtureInspection) -> FloatArray:
    return np.asarray(np.degrees(inspection.theta_rad))


def conjugate_variation_plot(
    inspection: FixtureInspection, ax: Axes | None = None, *, design_name: str = "conjugate cams"
) -> list[Any]:
    """Centre-distance variation Δf and its components (THEORY §4.1, CW11 eqs. 14-18).

    With a measurement the components come from it (eq. 19) and their sum is Δf_mea; the
    Δf_est predicted from the known errors of both cams (eqs. 14-18) is drawn dashed
    beside it.

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.pair.fixture.inspect_conjugate`.
    ax : matplotlib Axes, optional
        Where to draw.
    design_name : str
        Named in the title of a figure made here.

    Returns
    -------
    list
        The artists drawn.
    """
    made_here = ax is None
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
    _legend_outside(ax)
    _stamp(ax, design_name, made_here)
    return arts


def profile_error_estimate_plot(
    inspection: FixtureInspection,
    ax: Axes | None = None,
    *,
    tolerance_a_um: tuple[float, float] | None = None,
    tolerance_b_um: tuple[float, float] | None = None,
    record: RecordEstimates | None = None,
    design_name: str = "conjugate cams",
) -> list[Any]:
    """Estimated profile errors Δr_A,est, Δr_B,est with tolerance lines (CW11 eqs. 19-21).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.pair.fixture.inspect_conjugate` with a measured Δf.
    ax : matplotlib Axes, optional
        Where to draw.
    tolerance_a_um, tolerance_b_um : tuple of float, optional
        (lower, upper) radial tolerances drawn as horizontal lines: cam A dotted, cam B
        dashed and labelled at opposite ends, so equal tolerances stay distinguishable. [µm]
    record : RecordEstimates, optional
        With an indicator record: the upper and lower estimates at Δf_mea ± u_f (THEORY
        §4.4), shaded between.
    design_name : str
        Named in the title of a figure made here.

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
    made_here = ax is None
    ax = _axes(ax)
    t = _fixture_theta(inspection)
    arts: list[Any] = []
    if record is not None:
        for cam, colour, up, lo in (
            ("A", _COLOURS[0], record.upper.dr_a_est_um, record.lower.dr_a_est_um),
            ("B", _COLOURS[1], record.upper.dr_b_est_um, record.lower.dr_b_est_um),
        ):
            arts.append(
                ax.fill_between(
                    t, lo, up, color=colour, alpha=0.18, lw=0, label=f"Δr_{cam},est at Δf_mea ± u_f"
                )
            )
            arts += ax.plot(t, up, color=colour, lw=0.7, ls="--")
            arts += ax.plot(t, lo, color=colour, lw=0.7, ls="--")
    arts += ax.plot(t, est.dr_a_est_um, color=_COLOURS[0], label="Δr_A,est (master B)")
    arts += ax.plot(t, est.dr_b_est_um, color=_COLOURS[1], label="Δr_B,est (master A)")
    for tol, colour, cam, style, width, x_text, ha in (
        (tolerance_a_um, _COLOURS[0], "A", (0, (1, 2)), 1.6, 1.0, "left"),
        (tolerance_b_um, _COLOURS[1], "B", (3, (5, 3)), 1.1, 359.0, "right"),
    ):
        if tol is None:
            continue
        for j, value in enumerate(tol):
            arts.append(
                ax.axhline(
                    value,
                    color=colour,
                    ls=style,
                    lw=width,
                    gid=f"tolerance_{cam}_{('lower', 'upper')[j]}",
                    label=f"tolerance of cam {cam}: {tol[0]:g} .. {tol[1]:g} µm"
                    if j == 0
                    else None,
                )
            )
            arts.append(
                ax.annotate(
                    f"{cam} {value:+g}",
                    (x_text, value),
                    xytext=(0, 3 if j == 1 else -10),
                    textcoords="offset points",
                    ha=ha,
                    color=colour,
                    fontsize="x-small",
                )
            )
    ax.set_ylabel(_label("Δr", "um"))
    ax.set_title("Estimated radial profile errors")
    _theta_axis(ax)
    _legend_outside(ax)
    _stamp(ax, design_name, made_here)
    return arts


def acceptance_plot(
    inspection: FixtureInspection,
    ax: Axes | None = None,
    *,
    cam: str = "A",
    record: RecordEstimates | None = None,
    verdict: CamVerdict | None = None,
    design_name: str = "conjugate cams",
) -> list[Any]:
    """Draw the acceptance band of an inspected cam and the measured Δf (THEORY §4.3).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.pair.fixture.inspect_conjugate`.
    ax : matplotlib Axes, optional
        Where to draw.
    cam : {"A", "B"}
        Inspected cam (the other one is the master).
    record : RecordEstimates, optional
        With an indicator record: the band Δf_mea ± u_f is shaded around Δf_mea (THEORY
        §4.4), the measurement uncertainty of the ISO 14253-1 decision rule.
    verdict : CamVerdict, optional
        The verdict to show (e.g. under the guard-band rule); the inspection's own
        verdict (simple acceptance) otherwise.
    design_name : str
        Named in the title of a figure made here.

    Returns
    -------
    list
        The artists drawn; failing intervals are shaded red.

    Raises
    ------
    ValueError
        If ``cam`` is not "A" or "B".
    """
    up, lo = inspection.bands.band_um(cam)
    master = inspection.bands.master_of(cam)
    made_here = ax is None
    ax = _axes(ax)
    t = _fixture_theta(inspection)
    arts: list[Any] = [ax.fill_between(t, lo, up, color="#9ecae1", alpha=0.5, label="band")]
    arts += ax.plot(t, up, color="#08519c", lw=1.0, label=f"Δf_{cam}(u),est")
    arts += ax.plot(t, lo, color="#08519c", lw=1.0, ls="--", label=f"Δf_{cam}(l),est")
    if inspection.estimate is not None:
        mea = inspection.estimate.df_mea_um
        if record is not None:
            arts.append(
                ax.fill_between(
                    t, mea - record.u_f_um, mea + record.u_f_um, color="#fd8d3c", alpha=0.55, lw=0,
                    label="Δf_mea ± u_f",
                )
            )  # fmt: skip
        arts += ax.plot(t, mea, "k-", lw=1.4, label="Δf measured")
    if verdict is None:
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
    _legend_outside(ax)
    _stamp(ax, design_name, made_here)
    return arts


def fixture_figure(
    inspection: FixtureInspection,
    *,
    tolerance_a_um: tuple[float, float] | None = None,
    tolerance_b_um: tuple[float, float] | None = None,
    design_name: str = "conjugate cams",
    record: RecordEstimates | None = None,
    verdicts: dict[str, CamVerdict] | None = None,
    decision_rule: str | None = None,
) -> Figure:
    """All fixture panels: Δf components, estimated errors, both acceptance bands (CW11).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.pair.fixture.inspect_conjugate`.
    tolerance_a_um, tolerance_b_um : tuple of float, optional
        Radial tolerances of cams A and B. [µm]
    design_name : str
        The design's name, in the figure title with the camtol version.
    record : RecordEstimates, optional
        Indicator-record estimates: draws u_f and the upper/lower estimates (THEORY §4.4).
    verdicts : dict of str to CamVerdict, optional
        Verdicts to show (e.g. the guard-band rule's); the inspection's otherwise.
    decision_rule : str, optional
        The conformance rule in force, stated in the title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    from camtol._version import __version__

    fig = Figure(figsize=(14.0, 9.5), layout="constrained")
    axs = fig.subplots(2, 2)
    conjugate_variation_plot(inspection, ax=axs[0, 0])
    if inspection.estimate is not None:
        profile_error_estimate_plot(
            inspection,
            ax=axs[0, 1],
            tolerance_a_um=tolerance_a_um,
            tolerance_b_um=tolerance_b_um,
            record=record,
        )
    else:
        axs[0, 1].set_axis_off()
    for j, cam in enumerate(("A", "B")):
        acceptance_plot(
            inspection,
            ax=axs[1, j],
            cam=cam,
            record=record,
            verdict=None if verdicts is None else verdicts.get(cam),
        )
    rule = f"; decision rule: {decision_rule}" if decision_rule else ""
    fig.suptitle(
        f"{design_name}: conjugate cams on the centre-distance fixture{rule} (camtol {__version__})"
    )
    return fig
