"""Inspection of machined cams: the conjugate-cam fixture (THEORY §4) and CMM scans (§2, §3, §5).

The public names below are what a user needs: the fixture's inputs (:class:`FixtureSpec`,
:class:`FixtureErrors`, :class:`ErrorFunction`), the whole analysis
(:func:`inspect_conjugate`), the equations of THEORY §4.1-4.3 one by one, and the
dial-indicator record (§4.4); for a coordinate-measuring-machine scan (issue 12,
docs/cmm-inspection.md) the reader (:func:`read_scan`), the registration datum
(:class:`Datum`), the deviations (:func:`cam_profile`, :func:`inspect_scan`), the
follower-motion error (:func:`functional_deviation`), the fixture compared with the CMM
(:func:`compare_cmm_fixture`) and the scan twin (:func:`simulate_scan`), with their
result types. Result types and helpers live in the concept modules:
:mod:`~camtol.inspection.formula`, :mod:`~camtol.inspection.units`,
:mod:`~camtol.inspection.error_functions`, :mod:`~camtol.inspection.conjugate`,
:mod:`~camtol.inspection.acceptance`, :mod:`~camtol.inspection.spec`,
:mod:`~camtol.inspection.fixture`, :mod:`~camtol.inspection.record`,
:mod:`~camtol.inspection.simulate`, :mod:`~camtol.inspection.cmm`,
:mod:`~camtol.inspection.registration`, :mod:`~camtol.inspection.deviations`,
:mod:`~camtol.inspection.functional`, :mod:`~camtol.inspection.cmm_fixture` and
:mod:`~camtol.inspection.twin`.
"""

from __future__ import annotations

from camtol.inspection.acceptance import acceptance_bands
from camtol.inspection.cmm import Scan, read_scan
from camtol.inspection.cmm_fixture import CmmFixtureComparison, compare_cmm_fixture
from camtol.inspection.conjugate import (
    FixtureErrors,
    conjugate_factors,
    conjugate_variation,
    inverse_estimate,
)
from camtol.inspection.deviations import CamProfile, CmmInspection, cam_profile, inspect_scan
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.fixture import FixtureInspection, inspect_conjugate
from camtol.inspection.functional import FunctionalDeviation, functional_deviation
from camtol.inspection.record import (
    IndicatorRecord,
    process_record,
    read_indicator_csv,
    record_estimates,
    write_indicator_csv,
)
from camtol.inspection.registration import Datum, Registration
from camtol.inspection.simulate import simulate_record
from camtol.inspection.spec import FixtureSpec
from camtol.inspection.twin import SimulatedScan, simulate_scan

__all__ = [
    "CamProfile",
    "CmmFixtureComparison",
    "CmmInspection",
    "Datum",
    "ErrorFunction",
    "FixtureErrors",
    "FixtureInspection",
    "FixtureSpec",
    "FunctionalDeviation",
    "IndicatorRecord",
    "Registration",
    "Scan",
    "SimulatedScan",
    "acceptance_bands",
    "cam_profile",
    "compare_cmm_fixture",
    "conjugate_factors",
    "conjugate_variation",
    "functional_deviation",
    "inspect_conjugate",
    "inspect_scan",
    "inverse_estimate",
    "parse_error_function",
    "process_record",
    "read_indicator_csv",
    "read_scan",
    "record_estimates",
    "simulate_record",
    "simulate_scan",
    "write_indicator_csv",
]
