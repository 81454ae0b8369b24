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

from importlib import import_module
from typing import TYPE_CHECKING, Any

from camtol import _compat

if TYPE_CHECKING:  # pragma: no cover - what the lazy names resolve to, for type checkers
    from camtol.inspection.cmm import Scan, read_scan
    from camtol.inspection.deviations import CamProfile, CmmInspection, cam_profile, inspect_scan
    from camtol.inspection.error_functions import ErrorFunction, parse_error_function
    from camtol.inspection.functional import FunctionalDeviation, functional_deviation
    from camtol.inspection.registration import Datum, Registration
    from camtol.inspection.twin import SimulatedScan, simulate_scan

#: Public name -> module that defines it, imported on first use (PEP 562): a design file's
#: ``[inspection]`` table needs two of these modules, not the registration and contact
#: machinery behind the others (issue 32: start-up of ``camtol analyze``).
_LAZY = {
    "Scan": "camtol.inspection.cmm",
    "read_scan": "camtol.inspection.cmm",
    "CamProfile": "camtol.inspection.deviations",
    "CmmInspection": "camtol.inspection.deviations",
    "cam_profile": "camtol.inspection.deviations",
    "inspect_scan": "camtol.inspection.deviations",
    "ErrorFunction": "camtol.inspection.error_functions",
    "parse_error_function": "camtol.inspection.error_functions",
    "FunctionalDeviation": "camtol.inspection.functional",
    "functional_deviation": "camtol.inspection.functional",
    "Datum": "camtol.inspection.registration",
    "Registration": "camtol.inspection.registration",
    "SimulatedScan": "camtol.inspection.twin",
    "simulate_scan": "camtol.inspection.twin",
}

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
    """Import a public name on first use; a name moved to :mod:`camtol.pair`, with a warning."""
    module = _LAZY.get(name)
    if module is None:
        return _compat.moved_name(__name__, name)
    value = getattr(import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    """List the module attributes, including the lazy public names."""
    return sorted(set(globals()) | set(_LAZY))
