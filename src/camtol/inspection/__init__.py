"""Inspection of machined cams (THEORY §4): the conjugate-cam measuring fixture and its record.

The public names below are what a user needs: the fixture's inputs (:class:`FixtureSpec`,
:class:`FixtureErrors`, :class:`ErrorFunction`), the whole analysis
(:func:`inspect_conjugate`), the equations of THEORY §4.1-4.3 one by one, and the
dial-indicator record (§4.4). Result types and helpers live in the concept modules:
:mod:`~camtol.inspection.formula`, :mod:`~camtol.inspection.units`,
:mod:`~camtol.inspection.error_functions`, :mod:`~camtol.inspection.conjugate`,
:mod:`~camtol.inspection.acceptance`, :mod:`~camtol.inspection.spec`,
:mod:`~camtol.inspection.fixture`, :mod:`~camtol.inspection.record` and
:mod:`~camtol.inspection.simulate`.
"""

from __future__ import annotations

from camtol.inspection.acceptance import acceptance_bands
from camtol.inspection.conjugate import (
    FixtureErrors,
    conjugate_factors,
    conjugate_variation,
    inverse_estimate,
)
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.fixture import FixtureInspection, inspect_conjugate
from camtol.inspection.record import (
    IndicatorRecord,
    process_record,
    read_indicator_csv,
    record_estimates,
    write_indicator_csv,
)
from camtol.inspection.simulate import simulate_record
from camtol.inspection.spec import FixtureSpec

__all__ = [
    "ErrorFunction",
    "FixtureErrors",
    "FixtureInspection",
    "FixtureSpec",
    "IndicatorRecord",
    "acceptance_bands",
    "conjugate_factors",
    "conjugate_variation",
    "inspect_conjugate",
    "inverse_estimate",
    "parse_error_function",
    "process_record",
    "read_indicator_csv",
    "record_estimates",
    "simulate_record",
    "write_indicator_csv",
]
