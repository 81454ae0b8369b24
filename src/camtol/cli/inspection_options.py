"""Inspection inputs shared by ``camtol conjugate`` and ``camtol report`` (THEORY §4).

The options (``--df-mea``, ``--record``, ``--drop-bad-revolutions``, ``--master-a``,
``--master-b``, ``--decision``, the CMM scans) and :func:`fixture_inputs`, which turns
them into the one :class:`~camtol.pair.fixture_run.FixtureInputs` that
:func:`camtol.pair.fixture_run.run_fixture` takes. Bad input ends in one line, exit 2.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import click

from camtol.cli.common import fail
from camtol.cli.options import Number, decision_flag

if TYPE_CHECKING:  # pragma: no cover
    from camtol.pair.fixture_run import FixtureInputs

__all__ = [
    "check_cmm_options",
    "decision_option",
    "has_inspection_input",
    "inspection_options",
    "command_fixture_inputs",
    "fixture_inputs",
]

F = TypeVar("F", bound=Callable[..., Any])


#: ``--decision`` of ``camtol conjugate`` (the fixture's record).
decision_option = decision_flag(
    "Conformance rule (ISO 14253-1): 'simple' passes a cam when Δf_mea is in its"
    " band; 'guard-band' only when Δf_mea ± u_f is (the band shrunk by the record's"
    " uncertainty u_f; needs --record)."
)

#: ``--decision`` of ``camtol report``, whose rule judges a fixture record and a CMM scan.
_REPORT_DECISION = decision_flag(
    "Conformance rule (ISO 14253-1): 'simple' judges Δf_mea against each cam's band"
    " (fixture) and the deviations against the zone (--cmm); 'guard-band' shrinks the band"
    " by the record's u_f (needs --record) and the zone by the CMM's U (needs --u-cmm-um)."
)


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
        _REPORT_DECISION,
    ]
    for option in reversed(options):
        f = option(f)
    return f


def has_inspection_input(*values: str | None) -> bool:
    """Whether any inspection input (``--df-mea``, ``--record``, ...) was given."""
    return any(x is not None for x in values)


def check_cmm_options(
    cmm_a: str | None,
    cmm_b: str | None,
    cmm_stylus_mm: float,
    cmm_datum: str,
    *,
    cmm: str | None = None,
    pair: bool | None = None,
) -> None:
    """Refuse CMM-scan options that cannot apply: the wrong kind, one scan alone, none.

    The wrong kind is named first (issue 31): ``--cmm`` is a single cam's scan,
    ``--cmm-a``/``--cmm-b`` a conjugate pair's. Without a scan a stylus radius or a datum
    would be silently ignored (a NaN radius included), so giving one ends the command
    with a usage error.

    Parameters
    ----------
    cmm_a, cmm_b : str or None
        ``--cmm-a`` and ``--cmm-b``: the CMM scans of cams A and B.
    cmm_stylus_mm : float
        ``--cmm-stylus-radius-mm`` (default 0). [mm]
    cmm_datum : str
        ``--cmm-datum`` (default ``fit``).
    cmm : str or None
        ``--cmm``: the scan of a single cam (``camtol report``).
    pair : bool, optional
        Whether the design is a conjugate pair (None: not known yet).
    """
    if pair is False and (cmm_a is not None or cmm_b is not None):
        flag = "--cmm-a" if cmm_a is not None else "--cmm-b"
        fail(
            f"{flag} is a scan of a conjugate pair's cam; this design is a single cam:"
            " give its scan as --cmm SCAN"
        )
    if pair is True and cmm is not None:
        fail(
            "--cmm is a single cam's scan; this design is a conjugate pair: give --cmm-a and"
            " --cmm-b"
        )
    if cmm is not None and (cmm_a is not None or cmm_b is not None):
        fail("--cmm is a single cam's scan: leave out --cmm-a and --cmm-b")
    if (cmm_a is None) != (cmm_b is None):
        fail("--cmm-a and --cmm-b go together: give the scans of both cams")
    if cmm_a is not None or cmm is not None:
        return
    for flag, value, default in (
        ("--cmm-stylus-radius-mm", cmm_stylus_mm, 0.0),
        ("--cmm-datum", cmm_datum, "fit"),
    ):
        if value != default:  # NaN too
            fail(f"{flag}={value!r} applies to CMM scans: give --cmm-a and --cmm-b as well")


def fixture_inputs(
    *,
    df_mea: str | None,
    record_path: str | None,
    drop_bad_revolutions: bool,
    master_a: str | None,
    master_b: str | None,
    decision: str,
    step_deg: float,
    cmm_a: str | None = None,
    cmm_b: str | None = None,
    cmm_stylus_mm: float = 0.0,
    cmm_datum: str = "fit",
) -> FixtureInputs:
    """Build the fixture inspection's inputs from the options (one object for the library).

    Parameters
    ----------
    df_mea, record_path, master_a, master_b : str or None
        The option values (see ``camtol conjugate --help``).
    drop_bad_revolutions : bool
        ``--drop-bad-revolutions``.
    decision : {"simple", "guard-band"}
        ``--decision``.
    step_deg : float
        Grid step. [deg]
    cmm_a, cmm_b : str or None
        ``--cmm-a``, ``--cmm-b``: CMM scans of cams A and B.
    cmm_stylus_mm : float
        ``--cmm-stylus-radius-mm``. [mm]
    cmm_datum : str
        ``--cmm-datum``.

    Returns
    -------
    FixtureInputs
        For :func:`camtol.pair.fixture_run.run_fixture`.
    """
    from camtol.cli.inspect import parse_datum
    from camtol.pair.fixture_run import FixtureInputs

    check_cmm_options(cmm_a, cmm_b, cmm_stylus_mm, cmm_datum)
    return FixtureInputs(
        df_mea=df_mea,
        record_path=record_path,
        drop_bad_revolutions=drop_bad_revolutions,
        master_a=master_a,
        master_b=master_b,
        decision="guard-band" if decision == "guard-band" else "simple",
        cmm_a=cmm_a,
        cmm_b=cmm_b,
        cmm_stylus_radius_mm=cmm_stylus_mm,
        cmm_datum=None if cmm_a is None else parse_datum(cmm_datum, None, None, "soft_l1"),
        step_deg=step_deg,
    )


#: The options of :func:`inspection_options` (and ``--step``) that make the inputs.
_FIXTURE_OPTIONS = (
    "df_mea",
    "record_path",
    "drop_bad_revolutions",
    "master_a",
    "master_b",
    "decision",
    "step_deg",
    "cmm_a",
    "cmm_b",
    "cmm_stylus_mm",
    "cmm_datum",
)


def command_fixture_inputs() -> FixtureInputs:
    """Build the fixture inputs from the running command's own options.

    ``camtol conjugate`` and ``camtol report`` take the same options
    (:func:`inspection_options`); they are read from click's context, so that no
    command repeats them.

    Returns
    -------
    FixtureInputs
        As :func:`fixture_inputs` of the command's option values.
    """
    params = click.get_current_context().params
    return fixture_inputs(**{name: params[name] for name in _FIXTURE_OPTIONS})
