r"""How precise must a lift table be? Rounding study of a tabulated lift (THEORY §6.1, §6.2).

The design's lift is tabulated every Δθ and rounded to k decimals (quantum Q = 10⁻ᵏ in
the table's unit: mm, or degrees for an oscillating follower). From each rounded table
camtol computes V and A the way a machine controller or a spreadsheet does (central
differences) and the way camtol itself does (its periodic cubic spline,
:class:`camtol.design.motion.LiftTable`), and compares them with the analytic V and A:

.. math::

    V_b ≈ \frac{y_c - y_a}{2Δθ},\qquad A_b ≈ \frac{y_a + y_c - 2y_b}{Δθ^2}

Deviations of at most s = Q/2 change the second difference by at most 4s/Δθ² (alternating
signs) or 2s/Δθ² (a single dip) ([CDH] eq. 10.4, THEORY §6.1); the spline amplifies
alternating deviations three times more, 6Q/Δθ² (:mod:`camtol.design.table_noise`). Without
rounding the second difference carries the truncation error
A_c − A = (Δθ²/12) S'''' + O(Δθ⁴); for s = e(1 − cos φ) exactly
A_c = A · 2(1 − cos Δθ)/Δθ², i.e. |A_c − A| ≤ e Δθ²/12 (THEORY §6.1; proved in
``tests/manufacturing/test_precision.py``).

All derivatives are per radian of cam angle (THEORY §0), in the table's lift unit
(mm/rad, mm/rad²; deg/rad, deg/rad² for an oscillating follower); multiply by ω, ω² for
time derivatives.

References
----------
.. [CDH] H. A. Rothbart (ed.), *Cam Design Handbook*, McGraw-Hill, 2004, §10, p. 298.
.. [Pop] D. Popa, "The influence of cams external groove in cam-follower mechanism
   functioning", University of Pitesti.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.design.motion import LiftTable
from camtol.design.table_noise import second_difference_gain, spline_acceleration_gain
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.jet import FloatArray

__all__ = ["DEFAULT_DECIMALS", "MAX_DECIMALS", "PrecisionRow", "PrecisionStudy", "table_precision"]

#: Decimals studied by default (Popa's 1e-3 ... 1e-6 mm). [-]
DEFAULT_DECIMALS: tuple[int, ...] = (3, 4, 5, 6)
#: Spline evaluation points per table interval (A is linear between knots; V is not). [-]
_SUBSAMPLES = 8


@dataclass(frozen=True)
class PrecisionRow:
    """Errors of one rounded table against the analytic V and A (THEORY §6.1).

    Attributes
    ----------
    decimals : int
        Decimals kept in the table. [-]
    quantum : float
        Rounding quantum Q = 10⁻ᵏ. [lift unit: mm or deg]
    max_abs_dV_central : float
        max |V_central − V| at the tabulated angles. [lift unit/rad]
    max_abs_dA_central : float
        max |A_central − A| at the tabulated angles. [lift unit/rad²]
    max_abs_dV_spline, max_abs_dA_spline : float
        The same for camtol's periodic spline, over the whole revolution (8 points per
        table interval). [lift unit/rad^k]
    bound_alternating : float
        4 s/Δθ², s = Q/2: largest change of a second difference ([CDH]). [lift unit/rad²]
    bound_dip : float
        2 s/Δθ²: a single dip of depth s. [lift unit/rad²]
    bound_spline : float
        ‖G‖∞ s/Δθ² ≈ 6Q/Δθ²: largest change of the spline's A. [lift unit/rad²]
    """

    decimals: int
    quantum: float
    max_abs_dV_central: float
    max_abs_dA_central: float
    max_abs_dV_spline: float
    max_abs_dA_spline: float
    bound_alternating: float
    bound_dip: float
    bound_spline: float


@dataclass(frozen=True)
class PrecisionStudy:
    """Table-precision study of a design (THEORY §6).

    Attributes
    ----------
    design_name : str
        Name of the design.
    table_step_deg : float
        Table spacing Δθ. [deg]
    lift_unit : str
        Unit of the tabulated lift: ``"mm"`` or ``"deg"``.
    speed_rad_s : float or None
        Cam speed ω when the design gives one. [rad/s]
    max_abs_acceleration : float
        max |A| of the design (the signal). [lift unit/rad²]
    truncation_dV_central, truncation_dA_central : float
        Errors of central differences of the *unrounded* table. [lift unit/rad^k]
    truncation_estimate_dA : float
        Leading-order truncation: the larger of Δθ²/12 · max |S''''| and Δθ/6 · max |ΔJ|
        (a jump ΔJ of J on a tabulated angle). [lift unit/rad²]
    rows : tuple of PrecisionRow
        One per number of decimals, in the order asked.
    accel_budget_pct : float or None
        Acceleration budget as a percentage of max |A|. [%]
    recommended_decimals : int or None
        Fewest decimals whose central-difference and spline acceleration errors both
        stay within the budget (None without a budget, or when none does).
    """

    design_name: str
    table_step_deg: float
    lift_unit: str
    speed_rad_s: float | None
    max_abs_acceleration: float
    truncation_dV_central: float
    truncation_dA_central: float
    truncation_estimate_dA: float
    rows: tuple[PrecisionRow, ...]
    accel_budget_pct: float | None
    recommended_decimals: int | None


#: Most decimals a lift table is rounded to (beyond, float64 holds no more digits).
MAX_DECIMALS = 12


def _central(y: FloatArray, step: float) -> tuple[FloatArray, FloatArray]:
    ya, yc = np.roll(y, 1), np.roll(y, -1)
    return (yc - ya) / (2.0 * step), (ya + yc - 2.0 * y) / step**2


def _check(table_step_deg: float, decimals: Sequence[int], budget: float | None) -> int:
    n = check_step(table_step_deg, name="table_step_deg", min_points=8)
    # Compared as numbers, never through int(): int(nan) and int(inf) raise.
    if not decimals or not all(
        not isinstance(d, bool)
        and isinstance(d, int | float | np.integer | np.floating)
        and d in range(MAX_DECIMALS + 1)
        for d in decimals
    ):
        raise DesignError(
            f"decimals={list(decimals)} is not allowed; give whole numbers between 0 and"
            f" {MAX_DECIMALS}"
        )
    if budget is not None and not (math.isfinite(budget) and budget > 0):
        raise DesignError(
            f"accel_budget_pct={budget:g} is not allowed; give a positive percentage of max |A|"
        )
    return n


def table_precision(
    design: CamDesign,
    *,
    table_step_deg: float = 1.0,
    decimals: Sequence[int] = DEFAULT_DECIMALS,
    accel_budget_pct: float | None = None,
) -> PrecisionStudy:
    """Tabulate the design's lift, round it, and measure what rounding does to V and A.

    Parameters
    ----------
    design : CamDesign
        The design whose analytic S, V, A are the truth (a design that is itself a lift
        table is compared with its own spline).
    table_step_deg : float
        Table spacing Δθ; must divide 360°. [deg]
    decimals : sequence of int
        Numbers of decimals to study, 0..12. [-]
    accel_budget_pct : float, optional
        Largest acceptable acceleration error, in percent of max |A|. [%]

    Returns
    -------
    PrecisionStudy

    Raises
    ------
    DesignError
        A step that does not divide 360°, decimals outside 0..12, a non-positive budget.

    Examples
    --------
    >>> from camtol.config.design_file import load_example
    >>> st = table_precision(load_example("popa-eccentric"), decimals=[3, 6])
    >>> [round(r.max_abs_dA_central, 1) for r in st.rows]
    [5.1, 0.0]
    """
    n = _check(table_step_deg, decimals, accel_budget_pct)
    oscillating = design.mechanism.output == "oscillating"
    scale = 180.0 / math.pi if oscillating else 1.0
    step = 2.0 * math.pi / n
    theta = np.arange(n, dtype=float) * step
    exact = design.program.evaluate(theta)
    s, v, a = exact.lift * scale, exact.velocity * scale, exact.acceleration * scale
    fine = np.arange(n * _SUBSAMPLES) * (step / _SUBSAMPLES)
    exact_fine = design.program.evaluate(fine)
    v_fine, a_fine = exact_fine.velocity * scale, exact_fine.acceleration * scale
    a_max = float(np.max(np.abs(a_fine)))

    vc, ac = _central(s, step)
    # S'''' ≈ dJ/dθ by a forward difference of the analytic J over 1e-5 rad: right limits
    # at the program's boundaries, so a jump of J is not mistaken for a huge S''''.
    eps = 1e-5
    j_ahead = design.program.evaluate(fine + eps).jerk * scale
    s4 = (j_ahead - exact_fine.jerk * scale) / eps
    # A jump ΔJ of J at a tabulated angle adds ΔJ·Δθ/6 to the second difference there.
    bounds = np.asarray(design.program.boundaries_rad, dtype=float)
    jump = 0.0
    if bounds.size:
        right = design.program.evaluate(bounds).jerk
        left = design.program.evaluate(bounds, left_limit=np.ones(bounds.size, bool)).jerk
        jump = float(np.max(np.abs(right - left))) * scale
    rows = []
    gain_spline = spline_acceleration_gain(n)
    for k in decimals:
        q = 10.0 ** -int(k)
        y = np.round(s, int(k))
        vc_k, ac_k = _central(y, step)
        spline = LiftTable(theta, y).evaluate(fine)
        half = 0.5 * q
        rows.append(
            PrecisionRow(
                decimals=int(k),
                quantum=q,
                max_abs_dV_central=float(np.max(np.abs(vc_k - v))),
                max_abs_dA_central=float(np.max(np.abs(ac_k - a))),
                max_abs_dV_spline=float(np.max(np.abs(spline.velocity - v_fine))),
                max_abs_dA_spline=float(np.max(np.abs(spline.acceleration - a_fine))),
                bound_alternating=second_difference_gain() * half / step**2,
                bound_dip=2.0 * half / step**2,
                bound_spline=gain_spline * half / step**2,
            )
        )
    recommended = None
    if accel_budget_pct is not None:
        limit = accel_budget_pct / 100.0 * a_max
        ok = [r.decimals for r in rows if max(r.max_abs_dA_central, r.max_abs_dA_spline) <= limit]
        recommended = min(ok) if ok else None
    return PrecisionStudy(
        design_name=design.name,
        table_step_deg=360.0 / n,
        lift_unit="deg" if oscillating else "mm",
        speed_rad_s=design.omega_rad_s,
        max_abs_acceleration=a_max,
        truncation_dV_central=float(np.max(np.abs(vc - v))),
        truncation_dA_central=float(np.max(np.abs(ac - a))),
        truncation_estimate_dA=max(float(step**2 / 12.0 * np.max(np.abs(s4))), jump * step / 6.0),
        rows=tuple(rows),
        accel_budget_pct=accel_budget_pct,
        recommended_decimals=recommended,
    )
