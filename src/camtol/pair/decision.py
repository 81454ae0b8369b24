"""Conformance decision rules with measurement uncertainty (ISO 14253-1; THEORY §4.3-4.4).

The fixture's acceptance test (THEORY §4.3) compares the measured centre-distance
variation Δf_mea with the band [Δf_lower, Δf_upper] of the inspected cam. A dial-indicator
record also gives the measurement uncertainty u_f(θ) (THEORY §4.4). Two rules decide
conformance:

* ``"simple"`` (shared risk): the cam passes when Δf_mea itself lies in the band, i.e. the
  estimate at Δf_mea is within tolerance; the uncertainty is reported but not used.
* ``"guard-band"`` (ISO 14253-1 proof of conformance): the acceptance zone is the band
  shrunk by u_f on both sides; the cam passes only when Δf_mea − u_f ≥ Δf_lower and
  Δf_mea + u_f ≤ Δf_upper at every θ, i.e. the estimates at Δf_mea ± u_f both stay within
  tolerance.

Because the inverse estimate is affine in Δf (THEORY §4.2), "the estimate at Δf_mea ± u_f
is within tolerance" and "Δf_mea ± u_f lies in the band" are the same statement.

References
----------
.. [ISO14253] ISO 14253-1:2017, Geometrical product specifications (GPS) — Inspection by
   measurement of workpieces and measuring equipment — Part 1: Decision rules for
   verifying conformity or nonconformity with specifications.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.pair.acceptance import CamVerdict, failing_intervals
from camtol.pair.fixture import FixtureInspection

__all__ = ["DECISION_RULES", "DecisionRule", "decide", "decision_rule_text"]

#: A conformance decision rule (ISO 14253-1).
DecisionRule = Literal["simple", "guard-band"]

#: The allowed decision rules, in the order the CLI lists them.
DECISION_RULES: tuple[DecisionRule, ...] = ("simple", "guard-band")


def decision_rule_text(rule: DecisionRule) -> str:
    """State a decision rule in one sentence, for the terminal, JSON and the report.

    Parameters
    ----------
    rule : {"simple", "guard-band"}
        The decision rule.

    Returns
    -------
    str
        The rule in words.

    Raises
    ------
    DesignError
        If ``rule`` is not one of :data:`DECISION_RULES`.
    """
    if rule == "simple":
        return (
            "simple acceptance (ISO 14253-1 shared risk): a cam passes when the measured"
            " Δf_mea lies within its acceptance band; the uncertainty u_f is not used"
        )
    if rule == "guard-band":
        return (
            "guard band (ISO 14253-1 proof of conformance): a cam passes only when"
            " Δf_mea ± u_f lies within its acceptance band, i.e. the acceptance zone is"
            " shrunk by u_f on both sides"
        )
    raise DesignError(f"decision={rule!r} is not allowed; give one of {', '.join(DECISION_RULES)}")


def decide(
    inspection: FixtureInspection, rule: DecisionRule, u_f_um: ArrayLike | None = None
) -> dict[str, CamVerdict]:
    """Verdicts of the inspected cams under a decision rule (ISO 14253-1).

    Parameters
    ----------
    inspection : FixtureInspection
        Result of :func:`camtol.pair.fixture.inspect_conjugate` with a measured Δf.
    rule : {"simple", "guard-band"}
        The decision rule (see the module docstring).
    u_f_um : array_like, optional
        Measurement uncertainty u_f on ``inspection.theta_rad`` (e.g.
        ``RecordEstimates.u_f_um``); required by ``"guard-band"``. [µm]

    Returns
    -------
    dict of str to CamVerdict
        One verdict per cam ("A", "B"). Under ``"simple"`` these are the inspection's own
        verdicts; under ``"guard-band"`` the margin is min(Δf_mea − u_f − Δf_lower,
        Δf_upper − Δf_mea − u_f) and the failing intervals are located on the grid
        curves, interpolated linearly and periodically. Empty without a measurement.

    Raises
    ------
    DesignError
        Unknown rule, ``"guard-band"`` without ``u_f_um``, or ``u_f_um`` of the wrong
        shape or with negative or non-finite values.
    """
    decision_rule_text(rule)  # validates the rule
    if rule == "simple" or inspection.estimate is None:
        return dict(inspection.verdicts)
    if u_f_um is None:
        raise DesignError(
            "decision='guard-band' needs the measurement uncertainty u_f; give an indicator"
            " record (--record), or use decision='simple'"
        )
    theta = np.asarray(inspection.theta_rad, dtype=float)
    u_f = np.asarray(u_f_um, dtype=float)
    if u_f.shape != theta.shape or not np.all(np.isfinite(u_f)) or np.any(u_f < 0):
        raise DesignError(
            f"u_f_um: {u_f.shape[0] if u_f.ndim == 1 else u_f.shape} values, must be"
            f" {theta.size} finite values ≥ 0 on the inspection grid"
        )
    mea = inspection.estimate.df_mea_um
    b = inspection.bands
    grid = np.append(theta, theta[0] + 2 * math.pi)
    out: dict[str, CamVerdict] = {}
    for cam, up, lo in (
        ("A", b.df_a_upper_um, b.df_a_lower_um),
        ("B", b.df_b_upper_um, b.df_b_lower_um),
    ):
        m = np.minimum(mea - u_f - lo, up - mea - u_f)
        closed = np.append(m, m[0])  # periodic: θ = 2π is θ = 0

        def margin(t: FloatArray, closed: FloatArray = closed) -> FloatArray:
            return np.asarray(np.interp(np.mod(t, 2 * math.pi), grid, closed))

        intervals = failing_intervals(theta, margin)
        out[cam] = CamVerdict(cam, not intervals, intervals, float(m.min()))
    return out
