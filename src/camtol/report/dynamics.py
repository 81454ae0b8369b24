"""What ``camtol dynamics`` shows: JSON, curves, terminal text and the figure (THEORY §9).

Everything here formats a :class:`~camtol.dynamics.run.DynamicsResult` it is given; the
display units (µm or degrees for the lift's errors, m/s or °/s for impact velocities) are
chosen here. The ``--json`` keys and the ``--curves`` columns are fixed (issue 33):
scripts rely on them. Matplotlib is imported only when the figure is drawn.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camtol.report.csv_text import csv_text

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from camtol.dynamics.run import DynamicsResult

__all__ = [
    "curves_columns",
    "dynamics_figure",
    "dynamics_section",
    "dynamics_json",
    "dynamics_text",
    "write_curves_csv",
]


def _round(x: float | None, digits: int = 10) -> float | None:
    """Return a finite number to ``digits`` significant digits, else None."""
    if x is None or not math.isfinite(x):
        return None
    return float(f"{x:.{digits}g}") if x != 0 else 0.0


def _units(result: DynamicsResult) -> tuple[str, float, str, float, str, float]:
    """(lift unit, factor, error unit, factor, velocity unit, factor) from internal."""
    if result.oscillating:
        deg = 180.0 / math.pi
        return "deg", deg, "deg", deg, "deg_per_s", deg
    return "mm", 1.0, "um", 1e3, "m_per_s", 1e-3


def dynamics_json(result: DynamicsResult) -> dict[str, Any]:
    """Return the ``camtol dynamics --json`` document (without its envelope).

    Parameters
    ----------
    result : DynamicsResult
        The study.

    Returns
    -------
    dict
        Exactly the keys of issue 33: ``rpm``, ``contact_force_min_n``,
        ``contact_force_min_at_deg``, ``contact_force_max_n``, ``jump_speed_rpm``,
        ``torque_min_nm``, ``torque_max_nm``, ``hertz_stress_max_mpa``,
        ``residual_vibration_um`` (``_deg`` for an oscillating follower) and
        ``separation`` (``start_deg``, ``end_deg``, ``impact_velocity_m_per_s`` or
        ``_deg_per_s``).
    """
    _, _, err_unit, err_k, vel_unit, vel_k = _units(result)
    force = result.contact_force_n
    i = int(np.argmin(force))
    stress = result.hertz_stress_mpa
    resid = result.residual_vibration
    return {
        "rpm": _round(result.rpm),
        "contact_force_min_n": _round(float(force[i])),
        "contact_force_min_at_deg": round(math.degrees(float(result.steady.theta_rad[i])), 4),
        "contact_force_max_n": _round(float(np.max(force))),
        "jump_speed_rpm": _round(result.jump_speed_rpm),
        "torque_min_nm": _round(float(np.min(result.torque_nm))),
        "torque_max_nm": _round(float(np.max(result.torque_nm))),
        "hertz_stress_max_mpa": None if stress is None else _round(float(np.max(stress))),
        f"residual_vibration_{err_unit}": None if resid is None else _round(resid * err_k),
        "separation": [
            {
                "start_deg": round(s.start_deg, 4),
                "end_deg": None if s.end_deg is None else round(s.end_deg, 4),
                f"impact_velocity_{vel_unit}": (
                    None if s.impact_velocity is None else _round(s.impact_velocity * vel_k)
                ),
            }
            for s in result.separations
        ],
    }


def curves_columns(result: DynamicsResult) -> dict[str, np.ndarray]:
    """Return the ``--curves`` columns over 0-360° (the first row repeated at 360°).

    Parameters
    ----------
    result : DynamicsResult
        The study.

    Returns
    -------
    dict of str to ndarray
        ``theta_deg``, ``lift_mm``, ``mass_mm``, ``dynamic_error_um``,
        ``contact_force_n``, ``torque_nm``, ``hertz_stress_mpa`` (``lift_deg``,
        ``mass_deg``, ``dynamic_error_deg`` for an oscillating follower; the stress
        empty without a face width).
    """
    lift_unit, lift_k, err_unit, err_k, _, _ = _units(result)
    s = result.steady

    def closed(a: np.ndarray) -> np.ndarray:
        return np.append(a, a[0])

    stress = result.hertz_stress_mpa
    return {
        "theta_deg": np.append(np.degrees(s.theta_rad), 360.0),
        f"lift_{lift_unit}": closed(s.lift * lift_k),
        f"mass_{lift_unit}": closed(s.mass * lift_k),
        f"dynamic_error_{err_unit}": closed(s.dynamic_error * err_k),
        "contact_force_n": closed(result.contact_force_n),
        "torque_nm": closed(result.torque_nm),
        "hertz_stress_mpa": closed(np.full(s.theta_rad.size, np.nan) if stress is None else stress),
    }


def write_curves_csv(result: DynamicsResult, path: str) -> None:
    """Write the ``--curves`` CSV atomically.

    Parameters
    ----------
    result : DynamicsResult
        The study.
    path : str
        The file.
    """
    from camtol.files import atomic_write

    cols = curves_columns(result)
    text = csv_text(
        list(cols),
        np.column_stack(list(cols.values())),
        comment=f"camtol dynamics: {result.design_name} at {result.rpm:g} rpm,"
        f" {result.lift.description}",
        blank_nonfinite=True,
    )
    atomic_write(path, text)


def dynamics_text(result: DynamicsResult) -> list[str]:
    """Return the terminal lines of ``camtol dynamics`` (80 columns).

    Parameters
    ----------
    result : DynamicsResult
        The study.

    Returns
    -------
    list of str
    """
    _, _, err_unit, err_k, vel_unit, vel_k = _units(result)
    t = result.train
    osc = result.oscillating
    shown_err = "µm" if err_unit == "um" else "°"
    lines = [
        f"design             {result.design_name}",
        f"cam                {result.lift.description}",
        f"speed              {result.rpm:g} rpm",
    ]
    if osc:
        m = f"I = {t.mass * 1e6:g} kg·mm², k_s = {t.spring_rate:g} N·m/rad,"
        m += f" P = {t.preload:g} N·m"
    else:
        m = f"m = {t.mass * 1e3:g} kg, k_s = {t.spring_rate:g} N/mm, P = {t.preload:g} N"
    if t.form_closed:
        m = f"form-closed pair, I = {t.mass * 1e6:g} kg·mm²"
    lines.append(f"train              {m}")
    wn = t.natural_frequency_rad_s
    unit_k = "N·m/rad" if osc else "N/mm"
    lines.append(
        "                   rigid (no follower stiffness)"
        if wn is None
        else f"                   k_f = {t.stiffness:g} {unit_k}, ζ = {t.damping_ratio:g},"
        f" f_n = {wn / (2 * math.pi):.4g} Hz"
    )
    force = result.contact_force_n
    i, j = int(np.argmin(force)), int(np.argmax(force))
    deg = np.degrees(result.steady.theta_rad)
    lines.append(
        f"contact force      min {force[i]:.4g} N at {deg[i]:.2f}°,"
        f" max {force[j]:.4g} N at {deg[j]:.2f}°"
    )
    if len(result.contacts) > 1:
        for c in result.contacts:
            f = c.normal_force_n
            k = int(np.argmax(f))
            lines.append(f"  on roller {c.label:<7s} max {f[k]:.4g} N at {deg[k]:.2f}°")
    if t.form_closed:
        lines.append("jump speed         none: the pair is form-closed")
    elif result.jump_speed_rpm is None:
        lines.append("jump speed         none found (up to 16 × the rigid train's)")
    else:
        margin = result.jump_speed_rpm / result.rpm
        lines.append(
            f"jump speed         {result.jump_speed_rpm:.6g} rpm ({margin:.3g} × the speed)"
        )
        if margin < 1 and float(np.min(force)) >= 0:
            lines.append("                   (a resonance below this speed: here contact is kept)")
    tq = result.torque_nm
    lines.append(f"camshaft torque    min {tq.min():.4g} N·m, max {tq.max():.4g} N·m")
    stress = result.hertz_stress_mpa
    lines.append(
        "Hertz stress       not computed: give dynamics.face_width_mm"
        if stress is None
        else f"Hertz stress       max {stress.max():.4g} MPa at {deg[int(np.argmax(stress))]:.2f}°"
    )
    if result.residual and t.rigid:
        lines.append("residual vibration none: a rigid train does not vibrate")
    for r in () if t.rigid else result.residual:
        lines.append(
            f"residual vibration {r.amplitude * err_k:.4g} {shown_err} in the dwell"
            f" {math.degrees(r.start_rad):g}-{math.degrees(r.end_rad):g}°"
        )
    vel = "m/s" if vel_unit == "m_per_s" else "°/s"
    for s in result.separations:
        end = "not within 1 revolution" if s.end_deg is None else f"{s.end_deg:.2f}°"
        imp = "" if s.impact_velocity is None else f", impact {s.impact_velocity * vel_k:.4g} {vel}"
        lines.append(f"separation         {s.start_deg:.2f}° to {end}{imp}")
    if result.lift.source != "nominal":
        unit = "°" if osc else "µm"
        scale = 180 / math.pi if osc else 1e3
        lines.append(
            f"as made            lift error ≤ {result.lift.lift_error_max * scale:.3g} {unit}"
            + (
                ""
                if result.as_made_bound is None
                else f"; it moves the train force by ≤ {result.as_made_bound:.3g}"
                f" {'N·m' if osc else 'N'}"
            )
        )
    b = result.steady.truncation_bound
    if b > 0:
        unit = "N·m" if osc else "N"
        lines.append(
            f"series             {result.lift.angles // 2} harmonics"
            f" ({result.lift.step_deg:g}° grid); truncation bound {b:.2g} {unit}"
            " on the train force"
        )
    if float(np.min(force)) < 0 and not t.form_closed:
        lines.append(
            "note               the contact force goes negative: the curves are the"
            " contact-kept motion"
        )
    return lines


def dynamics_figure(result: DynamicsResult) -> Figure:
    """Draw lift and dynamic error, contact force with its zero line, and torque.

    Parameters
    ----------
    result : DynamicsResult
        The study.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    from camtol.report.plot_style import theta_axis

    lift_unit, lift_k, err_unit, err_k, _, _ = _units(result)
    s = result.steady
    deg = np.append(np.degrees(s.theta_rad), 360.0)

    def closed(a: np.ndarray) -> np.ndarray:
        return np.append(a, a[0])

    fig = Figure(figsize=(7.5, 8.0), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1, sharex=True)
    shown = "°" if lift_unit == "deg" else "mm"
    ax1.plot(deg, closed(s.lift * lift_k), color="C0", lw=1.0, label="cam lift S")
    ax1.set_ylabel(f"lift S [{shown}]")
    twin = ax1.twinx()
    err = "µm" if err_unit == "um" else "°"
    twin.plot(deg, closed(s.dynamic_error * err_k), color="C1", lw=0.8, label="x − S")
    twin.set_ylabel(f"dynamic error x − S [{err}]")
    ax1.set_title(f"{result.design_name} at {result.rpm:g} rpm: {result.lift.description}")
    h1, l1 = ax1.get_legend_handles_labels()
    h2, l2 = twin.get_legend_handles_labels()
    ax1.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper right")
    if len(result.contacts) > 1:
        for c in result.contacts:
            ax2.plot(deg, closed(c.normal_force_n), lw=1.0, label=f"roller {c.label}")
        ax2.legend(fontsize=7)
    else:
        ax2.plot(deg, closed(result.contact_force_n), color="C2", lw=1.0)
    ax2.axhline(0.0, color="k", lw=0.8)
    for sep in result.separations:
        a = sep.start_deg
        b = 360.0 if sep.end_deg is None else sep.end_deg
        spans = [(a, b)] if b >= a else [(a, 360.0), (0.0, b)]
        for s0, s1 in spans:
            ax2.axvspan(s0, s1, color="C3", alpha=0.15)
    jump = result.jump_speed_rpm
    ax2.set_title(
        "normal contact force" + ("" if jump is None else f" (jump speed {jump:.5g} rpm)")
    )
    ax2.set_ylabel("contact force [N]")
    ax3.plot(deg, closed(result.torque_nm), color="C4", lw=1.0)
    ax3.axhline(0.0, color="k", lw=0.5)
    ax3.set_ylabel("camshaft torque [N·m]")
    for ax in (ax1, ax2, ax3):
        theta_axis(ax)
    for ax in (ax1, ax2):
        ax.set_xlabel("")
    return fig


def dynamics_section(result: DynamicsResult | None, *, note: str = "") -> str:
    """HTML section of the report: the follower at speed (``camtol report``, THEORY §9).

    Parameters
    ----------
    result : DynamicsResult or None
        The study of the design's ``[dynamics]`` table at its ``operation.speed_rpm``;
        None when it could not be made (then ``note`` says why).
    note : str
        Why there is no result (e.g. the design gives no speed).

    Returns
    -------
    str
        An ``<h2>`` section: the figures of ``camtol dynamics`` as a table, and its figure
        as inline SVG.
    """
    from html import escape

    parts = ["<h2>Dynamics at speed</h2>"]
    if result is None:
        parts.append(f"<p>Not computed: {escape(note)} (THEORY §9).</p>")
        return "\n".join(parts)
    from camtol.report.inline_svg import figure_svg

    rows = []
    for line in dynamics_text(result):
        name, value = line[:19].strip(), line[19:].strip()
        rows.append(
            f"<tr><td>{escape(name)}</td><td>{escape(value)}</td></tr>"
            if name
            else f"<tr><td></td><td>{escape(value)}</td></tr>"
        )
    parts.append(
        '<p class="meta">The follower train of the design\'s [dynamics] table at its'
        " operation.speed_rpm: periodic steady state through the frequency domain, normal"
        " contact force, jump speed, camshaft torque, Hertz stress, residual vibration"
        " (THEORY §9).</p>"
    )
    parts.append("<table><tbody>" + "".join(rows) + "</tbody></table>")
    fig = dynamics_figure(result)
    parts.append(
        f'<figure class="figure" id="figure-dynamics">{figure_svg(fig, prefix="dyn")}'
        "<figcaption>Lift and dynamic error, normal contact force (its zero line; flights"
        " shaded) and camshaft torque at the design's speed (THEORY §9).</figcaption></figure>"
    )
    return "\n".join(parts)
