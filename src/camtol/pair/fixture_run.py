"""One inspection of a conjugate pair on the measuring fixture, from its inputs (THEORY §4).

:class:`FixtureInputs` gathers what an inspection is judged with besides the design: the
measured centre-distance variation (a number, formula or CSV, or a dial-indicator
record), the master cams' known errors, the CMM scans of both cams when the masters come
from them ([CW11]'s validation loop), and the decision rule (ISO 14253-1).
:func:`run_fixture` applies them to the design's ``[inspection]`` table and returns the
:class:`FixtureRun`: the inspection, the specification it used, the record's estimates
and the verdicts under the rule. ``camtol conjugate`` and ``camtol report`` are this one
call; the Python API gets the same.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.registration import Datum
from camtol.pair.acceptance import CamVerdict
from camtol.pair.cmm_fixture import CmmFixtureComparison, masters_from_scans
from camtol.pair.decision import DecisionRule, decide
from camtol.pair.fixture import FixtureInspection, inspect_conjugate
from camtol.pair.fixture_spec import FixtureSpec, fixture_spec
from camtol.pair.indicator import (
    RecordEstimates,
    process_record,
    read_indicator_csv,
    record_estimates,
    to_error_function,
)
from camtol.pair.kinematics import require_pair

__all__ = ["FixtureInputs", "FixtureRun", "run_fixture"]


@dataclass(frozen=True)
class FixtureInputs:
    """What a fixture inspection is judged with, besides the design (THEORY §4, §4.4).

    Every field is optional: what is not given comes from the design's ``[inspection]``
    table. Field names follow the command-line options they come from, and so do the
    messages of a refused combination.

    Attributes
    ----------
    df_mea : str, optional
        The measured Δf: a number of µm, a formula in theta or a CSV path (``--df-mea``).
    record_path : str, optional
        A dial-indicator record (CSV) to take Δf_mea and u_f from (``--record``).
    drop_bad_revolutions : bool
        Leave out the record's revolutions that disagree (``--drop-bad-revolutions``).
    master_a, master_b : str, optional
        Known radial errors of the master cams, as ``df_mea`` (``--master-a/-b``). [µm]
    decision : {"simple", "guard-band"}
        Conformance rule (ISO 14253-1); guard bands need a record's u_f.
    cmm_a, cmm_b : str, optional
        CMM scans of cams A and B: their radial errors become the masters (unless given)
        and the fixture is compared with them (``--cmm-a/--cmm-b``).
    cmm_stylus_radius_mm : float
        Stylus radius of the CMM scans (0: surface points). [mm]
    cmm_datum : Datum, optional
        Registration of the CMM scans (default: a robust best fit).
    step_deg : float
        θ grid step of the analysis. [deg]
    """

    df_mea: str | None = None
    record_path: str | None = None
    drop_bad_revolutions: bool = False
    master_a: str | None = None
    master_b: str | None = None
    decision: DecisionRule = "simple"
    cmm_a: str | None = None
    cmm_b: str | None = None
    cmm_stylus_radius_mm: float = 0.0
    cmm_datum: Datum | None = None
    step_deg: float = 0.1

    def __post_init__(self) -> None:
        if self.record_path is not None and self.df_mea is not None:
            raise DesignError(
                f"--record={self.record_path!r} and --df-mea={self.df_mea!r} are mutually"
                " exclusive; give the measured Δf one way"
            )
        if self.drop_bad_revolutions and self.record_path is None:
            raise DesignError("--drop-bad-revolutions applies to --record; give the record too")
        if self.decision == "guard-band" and self.record_path is None:
            raise DesignError(
                "--decision=guard-band needs the measurement uncertainty u_f of an indicator"
                " record; give --record FILE.csv, or use --decision simple"
            )
        if (self.cmm_a is None) != (self.cmm_b is None):
            raise DesignError("--cmm-a and --cmm-b go together: give the scans of both cams")


@dataclass(frozen=True)
class FixtureRun:
    """A fixture inspection with the inputs it was judged with.

    Attributes
    ----------
    inspection : FixtureInspection
        The inspection, its verdicts those of the decision rule.
    spec : FixtureSpec
        The specification used (inputs applied).
    record : RecordEstimates or None
        Estimates at Δf_mea ± u_f, with a dial-indicator record.
    decision : {"simple", "guard-band"}
        The decision rule in force.
    comparison : CmmFixtureComparison or None
        The fixture predicted from the two CMM scans, when they were given.
    """

    inspection: FixtureInspection
    spec: FixtureSpec
    record: RecordEstimates | None
    decision: DecisionRule
    comparison: CmmFixtureComparison | None = None

    @property
    def verdicts(self) -> dict[str, CamVerdict]:
        """Verdicts per inspected cam under the decision rule."""
        return self.inspection.verdicts

    @property
    def passed(self) -> bool | None:
        """True when every inspected cam passes, False if one fails, None without Δf_mea."""
        if not self.verdicts:
            return None
        return all(v.passed for v in self.verdicts.values())


def run_fixture(
    design: CamDesign, inputs: FixtureInputs, *, who: str = "the fixture inspection needs"
) -> FixtureRun:
    """Apply the inputs to the design's ``[inspection]`` table and run the fixture analysis.

    Parameters
    ----------
    design : CamDesign
        A conjugate design with an ``[inspection]`` table.
    inputs : FixtureInputs
        Measured Δf or record, masters, CMM scans, decision rule and grid.
    who : str
        Who needs a conjugate design, for the message when it is not one (e.g. "the
        inspection options of `camtol report` need").

    Returns
    -------
    FixtureRun
        The inspection with the verdicts of the decision rule.

    Raises
    ------
    DesignError
        Not a conjugate design, or no ``[inspection]`` table.
    InputFileError
        A record, CSV or scan that cannot be read.
    """
    require_pair(design, who)
    spec = fixture_spec(design)
    if spec is None:
        raise DesignError(
            "the design has no [inspection] table; give at least"
            " inspection.tolerance_a_um = [lower, upper] (see"
            " `camtol examples show cw11-conjugate`)"
        )

    def given(value: str | None, name: str, default: ErrorFunction) -> ErrorFunction:
        return default if value is None else parse_error_function(value, field=name)

    df_mea = (
        spec.df_mea
        if inputs.df_mea is None
        else parse_error_function(inputs.df_mea, field="--df-mea")
    )
    spec = dataclasses.replace(
        spec,
        df_mea=df_mea,
        master_a=given(inputs.master_a, "--master-a", spec.master_a),
        master_b=given(inputs.master_b, "--master-b", spec.master_b),
    )
    processed = None
    if inputs.record_path is not None:
        processed = process_record(
            read_indicator_csv(inputs.record_path),
            drop_bad_revolutions=inputs.drop_bad_revolutions,
        )
        spec = dataclasses.replace(spec, df_mea=to_error_function(processed))
    comparison = None
    if inputs.cmm_a is not None and inputs.cmm_b is not None:
        spec, comparison = masters_from_scans(
            design,
            spec,
            {"A": inputs.cmm_a, "B": inputs.cmm_b},
            stylus_radius_mm=inputs.cmm_stylus_radius_mm,
            datum=inputs.cmm_datum if inputs.cmm_datum is not None else Datum(loss="soft_l1"),
            keep_masters=(inputs.master_a is not None, inputs.master_b is not None),
            step_deg=inputs.step_deg,
        )
    res = inspect_conjugate(design, spec, step_deg=inputs.step_deg)
    estimates = None
    if processed is not None:
        estimates = record_estimates(design, spec, processed, res.theta_rad)
    verdicts = decide(res, inputs.decision, None if estimates is None else estimates.u_f_um)
    res = dataclasses.replace(res, verdicts=verdicts)
    return FixtureRun(res, spec, estimates, inputs.decision, comparison)
