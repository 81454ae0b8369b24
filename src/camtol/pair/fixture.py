"""The whole conjugate-cam fixture analysis on a θ grid (THEORY §4; [CW11]).

:func:`inspect_conjugate` puts the parts together: the pair's factors and the forward
variation (:mod:`camtol.pair.variation`, THEORY §4.1), the inverse analysis from a
measured Δf (§4.2), the acceptance bands and a verdict per inspected cam with its failing
intervals (:mod:`camtol.pair.acceptance`, §4.3), and the refined extremes of every
curve. Its inputs are a :class:`~camtol.pair.fixture_spec.FixtureSpec`, usually the design's
own (:attr:`camtol.design.cam_design.CamDesign.inspection`).

The concepts live in their own modules: :mod:`~camtol.inspection.formula` (the bounded
formula evaluator), :mod:`~camtol.inspection.units` (lengths),
:mod:`~camtol.inspection.error_functions`, :mod:`~camtol.pair.variation`,
:mod:`~camtol.pair.acceptance`, :mod:`~camtol.pair.fixture_spec` and
:mod:`~camtol.pair.indicator`. Their names are also importable from here, as before
the split.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camtol.analysis.extremes import Extreme, find_extremes
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.grid import check_step
from camtol.inspection.error_functions import ErrorFunction as ErrorFunction
from camtol.inspection.error_functions import parse_error_function as parse_error_function
from camtol.inspection.units import parse_length_um as parse_length_um
from camtol.jet import FloatArray
from camtol.pair.acceptance import AcceptanceBands as AcceptanceBands
from camtol.pair.acceptance import CamVerdict as CamVerdict
from camtol.pair.acceptance import acceptance_bands as acceptance_bands
from camtol.pair.acceptance import failing_intervals as failing_intervals
from camtol.pair.acceptance import merge_intervals as merge_intervals
from camtol.pair.fixture_spec import FixtureErrors as FixtureErrors
from camtol.pair.fixture_spec import FixtureSpec as FixtureSpec
from camtol.pair.fixture_spec import fixture_spec
from camtol.pair.variation import ConjugateFactors as ConjugateFactors
from camtol.pair.variation import ConjugateVariation as ConjugateVariation
from camtol.pair.variation import InverseEstimate as InverseEstimate
from camtol.pair.variation import conjugate_factors as conjugate_factors
from camtol.pair.variation import conjugate_variation as conjugate_variation
from camtol.pair.variation import constant_parts
from camtol.pair.variation import inverse_estimate as inverse_estimate

__all__ = ["MAX_FIXTURE_POINTS", "FixtureInspection", "fixture_curves", "inspect_conjugate"]

#: Fewest grid points of a fixture analysis (a 90° step).
_MIN_POINTS = 4
#: Most grid points of a fixture analysis (a 0.001° step): failing-interval ends are
#: refined to 1e-4° and extremes to step/1000 regardless, so a finer grid only costs
#: memory (about 2.5 GB and 100 s at 0.0001°).
MAX_FIXTURE_POINTS = 360_000


@dataclass(frozen=True)
class FixtureInspection:
    """Result of :func:`inspect_conjugate` on a θ grid.

    Attributes
    ----------
    theta_rad : ndarray
        Uniform grid over [0, 2π). [rad]
    factors : ConjugateFactors
        Geometry of the pair.
    variation : ConjugateVariation
        Forward variation; Δf_r from the measurement (eq. 19) when there is one, otherwise
        from the master cams' errors (the master pair on the fixture). [µm]
    estimate : InverseEstimate or None
        Δr_A,est and Δr_B,est (None without a measurement). [µm]
    bands : AcceptanceBands
        The four bands. [µm]
    verdicts : dict of str to CamVerdict or None
        ``"A"``, ``"B"``; empty without a measurement.
    extremes : dict of str to (Extreme, Extreme)
        Global (max, min) of every curve of :func:`fixture_curves`, refined to step/1000;
        a value held over an angle range is reported as that range. [µm]
    predicted : ConjugateVariation or None
        With a measurement: the forward variation of CW11 eqs. 14-18 from the known errors
        of both cams (``master_a``, ``master_b``), whose ``df_est_um`` is the Δf_est to
        compare with Δf_mea (the paper's validation, THEORY §4.1, §8.4); None without a
        measurement (then ``variation`` is that forward variation). [µm]
    """

    theta_rad: FloatArray
    factors: ConjugateFactors
    variation: ConjugateVariation
    estimate: InverseEstimate | None
    bands: AcceptanceBands
    verdicts: dict[str, CamVerdict]
    extremes: dict[str, tuple[Extreme, Extreme]]
    predicted: ConjugateVariation | None = None

    @property
    def df_est_minus_mea_um(self) -> FloatArray | None:
        """Δf_est (eqs. 14-18, known errors) − Δf_mea over θ; None without both. [µm]"""
        if self.predicted is None or self.estimate is None:
            return None
        return np.asarray(self.predicted.df_est_um - self.estimate.df_mea_um)

    @property
    def passed(self) -> bool | None:
        """True if both inspected cams pass, False if one fails, None without a record."""
        if not self.verdicts:
            return None
        return all(v.passed for v in self.verdicts.values())


def inspect_conjugate(
    design: CamDesign, spec: FixtureSpec | None = None, *, step_deg: float = 0.1
) -> FixtureInspection:
    """Run the whole fixture analysis of THEORY §4 on a conjugate design.

    Parameters
    ----------
    design : CamDesign
        A conjugate design (mechanism :class:`~camtol.mechanisms.conjugate.ConjugatePair`).
    spec : FixtureSpec, optional
        Errors, tolerances, master cams and the measured Δf; default: the design's own
        ``[inspection]`` table (:attr:`~camtol.design.cam_design.CamDesign.inspection`).
    step_deg : float
        Grid step; 360 must be a whole multiple of it, between 0.001° and 90°
        (:func:`camtol.grid.check_step`). Failing-interval ends are refined by bisection
        on the continuous functions to 1e-4° regardless. [deg]

    Returns
    -------
    FixtureInspection
        Variation, estimates, bands, verdicts and extremes.

    Raises
    ------
    DesignError
        A step that is not allowed, a design that is not a conjugate pair, or no spec.
    """
    if spec is None:
        spec = fixture_spec(design)
        if spec is None:
            raise DesignError(
                f"design {design.name!r} has no [inspection] table; give at least"
                " inspection.tolerance_a_um = [lower, upper], or pass a FixtureSpec"
            )
    return _inspect(design, spec, step_deg)


def _inspect(design: CamDesign, spec: FixtureSpec, step_deg: float) -> FixtureInspection:
    n = check_step(step_deg, name="step_deg", min_points=_MIN_POINTS, max_points=MAX_FIXTURE_POINTS)
    theta: FloatArray = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)  # both cams, whatever the grid (issue 9)
    fac, variation, est, bands, predicted = _fixture_parts(design, spec, theta)

    def evaluate(t: FloatArray, names: frozenset[str]) -> dict[str, FloatArray]:
        _, var_t, est_t, bands_t, pred_t = _fixture_parts(design, spec, t)
        return fixture_curves(var_t, est_t, bands_t, predicted=pred_t)

    extremes = find_extremes(
        theta,
        fixture_curves(variation, est, bands, predicted=predicted),
        evaluate,
        step_deg=step_deg,
    )
    if spec.df_mea is None or est is None:
        return FixtureInspection(theta, fac, variation, None, bands, {}, extremes)
    df_mea = spec.df_mea

    def margin_fn(cam: str) -> Callable[[FloatArray], FloatArray]:
        def margin(t: FloatArray) -> FloatArray:
            f = conjugate_factors(design, t)
            b = acceptance_bands(
                f,
                spec.tolerance_a_um,
                spec.tolerance_b_um,
                spec.master_a,
                spec.master_b,
                spec.errors,
            )
            return b.margin_um(cam, df_mea(t))

        return margin

    verdicts = {}
    for cam in design.cams():
        m = bands.margin_um(cam.letter, est.df_mea_um)
        intervals = failing_intervals(theta, margin_fn(cam.letter))
        verdicts[cam.letter] = CamVerdict(cam.letter, not intervals, intervals, float(m.min()))
    return FixtureInspection(theta, fac, variation, est, bands, verdicts, extremes, predicted)


def _fixture_parts(
    design: CamDesign, spec: FixtureSpec, theta: FloatArray
) -> tuple[
    ConjugateFactors,
    ConjugateVariation,
    InverseEstimate | None,
    AcceptanceBands,
    ConjugateVariation | None,
]:
    """Geometry, variation, estimate, bands and (with a measurement) the prediction."""
    fac = conjugate_factors(design, theta)
    bands = acceptance_bands(
        fac, spec.tolerance_a_um, spec.tolerance_b_um, spec.master_a, spec.master_b, spec.errors
    )
    forward = conjugate_variation(fac, spec.master_a, spec.master_b, spec.errors)
    if spec.df_mea is None:
        return fac, forward, None, bands, None
    est = inverse_estimate(fac, spec.df_mea, spec.master_a, spec.master_b, spec.errors)
    rf, ll, eta = constant_parts(fac, spec.errors)
    return fac, ConjugateVariation(theta, est.df_r_um, rf, ll, eta), est, bands, forward


def fixture_curves(
    variation: ConjugateVariation,
    estimate: InverseEstimate | None,
    bands: AcceptanceBands,
    *,
    predicted: ConjugateVariation | None = None,
) -> dict[str, FloatArray]:
    """Collect the fixture's curves by name; the estimates only with a measurement.

    Parameters
    ----------
    variation : ConjugateVariation
        The Δf parts. [µm]
    estimate : InverseEstimate or None
        Δf_mea, Δr_A,est, Δr_B,est, when there is a measurement. [µm]
    bands : AcceptanceBands
        The four acceptance bands. [µm]
    predicted : ConjugateVariation, optional
        With a measurement: the forward prediction from the known errors (eqs. 14-18).

    Returns
    -------
    dict of str to ndarray
        ``df_r``, ``df_rf``, ``df_l``, ``df_eta``, ``df_est`` (then ``df_mea``,
        ``dr_A_est``, ``dr_B_est``, and ``df_est_pred`` with a prediction) and the bands
        ``df_A_upper`` ... ``df_B_lower``. [µm]
    """
    out = {
        "df_r": variation.df_r_um,
        "df_rf": variation.df_rf_um,
        "df_l": variation.df_l_um,
        "df_eta": variation.df_eta_um,
        "df_est": variation.df_est_um,
    }
    if estimate is not None:
        out |= {
            "df_mea": estimate.df_mea_um,
            "dr_A_est": estimate.dr_a_est_um,
            "dr_B_est": estimate.dr_b_est_um,
        }
        if predicted is not None:
            out["df_est_pred"] = predicted.df_est_um
    out |= {
        "df_A_upper": bands.df_a_upper_um,
        "df_A_lower": bands.df_a_lower_um,
        "df_B_upper": bands.df_b_upper_um,
        "df_B_lower": bands.df_b_lower_um,
    }
    return {k: np.asarray(v, dtype=float) for k, v in out.items()}
