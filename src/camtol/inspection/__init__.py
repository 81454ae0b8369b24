"""Inspection of machined cams from coordinate-measuring-machine scans (THEORY §2, §3, §5).

The public names below are what a user needs for a CMM scan (issue 12,
docs/cmm-inspection.md): the reader (:func:`read_scan`), the registration datum
(:class:`Datum`), the deviations (:func:`cam_profile`, :func:`inspect_scan`), the
follower-motion error (:func:`functional_deviation`) and the scan twin
(:func:`simulate_scan`), with their result types, and the known errors given as functions
of θ (:class:`ErrorFunction`) that inspection inputs use. Result types and helpers live in
the concept modules: :mod:`~camtol.inspection.formula`, :mod:`~camtol.inspection.units`,
:mod:`~camtol.inspection.error_functions`, :mod:`~camtol.inspection.cmm`,
:mod:`~camtol.inspection.registration`, :mod:`~camtol.inspection.deviations`,
:mod:`~camtol.inspection.functional` and :mod:`~camtol.inspection.twin`.

The conjugate-cam fixture (THEORY §4) is the pair's: :mod:`camtol.pair`. Its names are
still readable here, with a :class:`DeprecationWarning`, until camtol 0.3.
"""

from __future__ import annotations

from typing import Any

from camtol import _compat
from camtol.inspection.cmm import Scan, read_scan
from camtol.inspection.deviations import CamProfile, CmmInspection, cam_profile, inspect_scan
from camtol.inspection.error_functions import ErrorFunction, parse_error_function
from camtol.inspection.functional import FunctionalDeviation, functional_deviation
from camtol.inspection.registration import Datum, Registration
from camtol.inspection.twin import SimulatedScan, simulate_scan

__all__ = [
    "CamProfile",
    "CmmInspection",
    "Datum",
    "ErrorFunction",
    "FunctionalDeviation",
    "Registration",
    "Scan",
    "SimulatedScan",
    "cam_profile",
    "functional_deviation",
    "inspect_scan",
    "parse_error_function",
    "read_scan",
    "simulate_scan",
]


def __getattr__(name: str) -> Any:
    """Return a name moved to :mod:`camtol.pair` (the fixture), with a warning."""
    return _compat.moved_name(__name__, name)
