"""Inspection inputs shared by ``camtol conjugate`` and ``camtol report`` (THEORY §4).

The options (``--df-mea``, ``--record``, ``--drop-bad-revolutions``, ``--master-a``,
``--master-b``, ``--decision``) and :func:`run_fixture`, which turns them and a conjugate
design into the fixture inspection, the record's estimates and the verdicts under the
chosen decision rule (ISO 14253-1, :mod:`camtol.inspection.decision`). Bad input ends in
``fail()`` (one line, exit 2).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, TypeVar

import click

from camtol.cli import fail
from camtol.cli_options import Number

if TYPE_CHECKING:  # pragma: no cover
    from camtol.design import CamDesign
    from camtol.inspection.acceptance import CamVerdict
    from camtol.inspection.decision import DecisionRule
    from camtol.inspection.fixture import FixtureInspection
    from camtol.inspection.record import RecordEstimates
    from camtol.inspection.spec import FixtureSpec

__all__ = [
    "FixtureRun",
    "check_cmm_options",
    "decision_option",
    "has_inspection_input",
    "inspection_options",
    "run_fixture",
]

F = TypeVar("F", bound=Callable[..., Any])


def decision_option(f: F) -> F:
    """Add ``--decision simple|guard-band`` (ISO 14253-1) to a command.

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with the option.
    """
    return click.option(
        "--decision",
        type=click.Choice(["simple", "guard-band"]),
        default="simple",
        show_default=True,
        help="Conformance rule (ISO 14253-1): 'simple' passes a cam when Δf_mea is in its"
        " band; 'guard-band' only when Δf_mea ± u_f is (the band shrunk by the record's"
        " uncertainty u_f; needs --record).",
    )(f)


def inspection_options(f: F) -> F:
    """Add the inspection inputs of ``camtol conjugate`` to a command (for ``report``).

    Parameters
    ----------
    f : callable
        The click command function.

    Returns
    -------
    callable
        ``f`` with ``--df-mea``, ``--record``, ``--drop-bad-revolutions``,
        ``--master-a/-b``, ``--cmm-a/-b``, ``--cmm-stylus-radius-mm``, ``--cmm-datum``
        and ``--decision``.
    """
    options = [
        click.option(
            "--df-mea",
            "df_mea",
            metavar="VALUE|FILE.csv|FORMULA",
            help="Measured centre-distance variation Δf, as for `camtol conjugate`"
            " (overrides inspection.df_mea_um).",
        ),
        click.option(
            "--record",
            "record_path",
            metavar="FILE.csv",
            help="Dial-indicator record (df_um, index[, time_s]; THEORY §4.4), as for"
            " `camtol conjugate`. Not with --df-mea.",
        ),
        click.option(
            "--drop-bad-revolutions",
            is_flag=True,
            help="With --record: exclude revolutions with a missed or spurious index mark.",
        ),
        click.option(
            "--master-a", metavar="VALUE|FILE.csv|FORMULA", help="Radial error of master cam A."
        ),
        click.option(
            "--master-b", metavar="VALUE|FILE.csv|FORMULA", help="Radial error of master cam B."
        ),
        click.option(
            "--cmm-a",
            metavar="SCAN.csv",
            help="CMM scan of cam A (with --cmm-b), as for `camtol conjugate`: the CMM errors"
            " become the masters.",
        ),
        click.option("--cmm-b", metavar="SCAN.csv", help="CMM scan of cam B (with --cmm-a)."),
        click.option(
            "--cmm-stylus-radius-mm",
            "cmm_stylus_mm",
            type=Number(low=0, unit="mm"),
            default=0.0,
            show_default=True,
            help="Stylus radius of the CMM scans (0: surface points) [mm].",
        ),
        click.option(
            "--cmm-datum",
            default="fit",
            show_default=True,
            metavar="fit|fit-rotation|bore|centre:X,Y[,DEG]",
            help="Registration of the CMM scans (as `camtol inspect --datum`).",
        ),
        decision_option,
    ]
    for option in reversed(options):
        f = option(f)
    return f


@dataclass(frozen=True)
class FixtureRun:
    """A fixture inspection run from the command line.

    Attributes
    ----------
    inspection : FixtureInspection
        The inspection, its verdicts those of the decision rule.
    spec : FixtureSpec
        The specification used (options applied).
    record : RecordEstimates or None
        Estimates at Δf_mea ± u_f, with ``--record``.
    decision : {"simple", "guard-band"}
        The decision rule in force.
    comparison : CmmFixtureComparison or None
        The fixture predicted from the two CMM scans, with ``--cmm-a/--cmm-b``.
    """

    inspection: FixtureInspection
    spec: FixtureSpec
    record: RecordEstimates | None
    decision: DecisionRule
    comparison: Any = None

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


def has_inspection_input(*values: str | None) -> bool:
    """Whether any inspection input (``--df-mea``, ``--record``, ...) was given."""
    return any(x is not None for x in values)


def check_cmm_options(
    cmm_a: str | None, cmm_b: str | None, cmm_stylus_mm: float, cmm_datum: str
) -> None:
    """Refuse CMM-scan options that cannot apply: one scan alone, or no scan at all.

    Without ``--cmm-a``/``--cmm-b`` a stylus radius or a datum would be silently ignored
    (a NaN radius included), so giving one ends the command with a usage error.

    Parameters
    ----------
    cmm_a, cmm_b : str or None
        ``--cmm-a`` and ``--cmm-b``: the CMM scans of cams A and B.
    cmm_stylus_mm : float
        ``--cmm-stylus-radius-mm`` (default 0). [mm]
    cmm_datum : str
        ``--cmm-datum`` (default ``fit``).
    """
    if (cmm_a is None) != (cmm_b is None):
        fail("--cmm-a and --cmm-b go together: give the scans of both cams")
    if cmm_a is not None:
        return
    for flag, value, default in (
        ("--cmm-stylus-radius-mm", cmm_stylus_mm, 0.0),
        ("--cmm-datum", cmm_datum, "fit"),
    ):
        if value != default:  # NaN too
            fail(f"{flag}={value!r} applies to CMM scans: give --cmm-a and --cmm-b as well")


def run_fixture(
    d: CamDesign,
    *,
    df_mea: str | None,
    record_path: str | None,
    drop_bad_revolutions: bool,
    master_a: str | None,
    master_b: str | None,
    decision: str,
    step_deg: float,
    command: str,
    cmm_a: str | None = None,
    cmm_b: str | None = None,
    cmm_stylus_mm: float = 0.0,
    cmm_datum: str = "fit",
) -> FixtureRun:
    """Apply the options to the design's [inspection] table and run the fixture analysis.

    Parameters
    ----------
    d : CamDesign
        A conjugate design.
    df_mea, record_path, master_a, master_b : str or None
        The option values (see ``camtol conjugate --help``).
    drop_bad_revolutions : bool
        ``--drop-bad-revolutions``.
    cmm_a : str or None
        ``--cmm-a``: CMM scan of cam A.
    cmm_b : str or None
        ``--cmm-b``: CMM scan of cam B.
    cmm_stylus_mm : float
        ``--cmm-stylus-radius-mm``. [mm]
    cmm_datum : str
        ``--cmm-datum``.
    decision : {"simple", "guard-band"}
        ``--decision``.
    step_deg : float
        Grid step. [deg]
    command : str
        The command's name, for messages.

    Returns
    -------
    FixtureRun
        The inspection with the verdicts of the decision rule.
    """
    from camtol.inspection.decision import decide
    from camtol.inspection.error_functions import ErrorFunction, parse_error_function
    from camtol.inspection.fixture import inspect_conjugate
    from camtol.mechanisms.conjugate import ConjugatePair

    if record_path is not None and df_mea is not None:
        fail(
            f"--record={record_path!r} and --df-mea={df_mea!r} are mutually exclusive;"
            " give the measured Δf one way"
        )
    if drop_bad_revolutions and record_path is None:
        fail("--drop-bad-revolutions applies to --record; give the record too")
    if decision == "guard-band" and record_path is None:
        fail(
            "--decision=guard-band needs the measurement uncertainty u_f of an indicator"
            " record; give --record FILE.csv, or use --decision simple"
        )
    if not isinstance(d.mechanism, ConjugatePair):
        fail(
            f"follower.type={d.mechanism.kind!r}: the inspection options of `camtol {command}`"
            " need a conjugate design (follower.type = 'conjugate')"
        )
    spec = d.inspection
    if spec is None:
        fail(
            "the design has no [inspection] table; give at least"
            " inspection.tolerance_a_um = [lower, upper] (see"
            " `camtol examples show cw11-conjugate`)"
        )
    assert spec is not None  # fail() does not return

    def option(value: str | None, name: str, default: ErrorFunction) -> ErrorFunction:
        return default if value is None else parse_error_function(value, field=name)

    spec = dataclasses.replace(
        spec,
        df_mea=spec.df_mea if df_mea is None else parse_error_function(df_mea, field="--df-mea"),
        master_a=option(master_a, "--master-a", spec.master_a),
        master_b=option(master_b, "--master-b", spec.master_b),
    )
    estimates = None
    processed = None
    comparison = None
    if record_path is not None:
        from camtol.inspection.record import process_record, read_indicator_csv, to_error_function

        processed = process_record(
            read_indicator_csv(record_path), drop_bad_revolutions=drop_bad_revolutions
        )
        spec = dataclasses.replace(spec, df_mea=to_error_function(processed))
    check_cmm_options(cmm_a, cmm_b, cmm_stylus_mm, cmm_datum)
    if cmm_a is not None and cmm_b is not None:
        from camtol.cli_inspect import cmm_pair_masters

        spec, comparison = cmm_pair_masters(
            d,
            spec,
            cmm_a,
            cmm_b,
            stylus_radius_mm=cmm_stylus_mm,
            datum_text=cmm_datum,
            master_given=(master_a is not None, master_b is not None),
            step_deg=step_deg,
        )
    res = inspect_conjugate(d, spec, step_deg=step_deg)
    if processed is not None:
        from camtol.inspection.record import record_estimates

        estimates = record_estimates(d, spec, processed, res.theta_rad)
    rule: DecisionRule = "guard-band" if decision == "guard-band" else "simple"
    verdicts = decide(res, rule, None if estimates is None else estimates.u_f_um)
    res = dataclasses.replace(res, verdicts=verdicts)
    return FixtureRun(res, spec, estimates, rule, comparison)
