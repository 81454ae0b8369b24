"""The conjugate cam pair as a first-class object (THEORY §2.4, §4; [CW11]).

Everything that needs both cams of a pair at once lives here, and nowhere else: the
pair's joint kinematics, the measuring fixture (its spec and constant errors, the
forward conjugate variation Δf and the inverse analysis, acceptance and decision rules),
the dial-indicator record and its twin, the exact fixture simulation, the CMM-vs-fixture
comparison and the pair's verification. Outside this package a design is a set of cams
(:meth:`camtol.design.CamDesign.cams`), each knowing its own label and tolerances.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover - what the lazy names resolve to, for type checkers
    from camtol.pair.acceptance import AcceptanceBands, CamVerdict, acceptance_bands
    from camtol.pair.cmm_fixture import CmmFixtureComparison, compare_cmm_fixture
    from camtol.pair.contact_fixture import Fixture, simulate_fixture
    from camtol.pair.fixture import FixtureInspection, inspect_conjugate
    from camtol.pair.fixture_spec import FixtureErrors, FixtureSpec
    from camtol.pair.indicator import (
        IndicatorRecord,
        process_record,
        read_indicator_csv,
        record_estimates,
        write_indicator_csv,
    )
    from camtol.pair.kinematics import ConjugateKinematics, conjugate_kinematics
    from camtol.pair.twin import simulate_record
    from camtol.pair.variation import (
        ConjugateFactors,
        ConjugateVariation,
        InverseEstimate,
        conjugate_factors,
        conjugate_variation,
        inverse_estimate,
    )

#: Public name -> module that defines it, imported on first use (PEP 562): a design's
#: fixture spec needs one module, not the whole pair (issue 32: start-up of analyze).
_LAZY = {
    "AcceptanceBands": "camtol.pair.acceptance",
    "CamVerdict": "camtol.pair.acceptance",
    "acceptance_bands": "camtol.pair.acceptance",
    "CmmFixtureComparison": "camtol.pair.cmm_fixture",
    "compare_cmm_fixture": "camtol.pair.cmm_fixture",
    "Fixture": "camtol.pair.contact_fixture",
    "simulate_fixture": "camtol.pair.contact_fixture",
    "FixtureInspection": "camtol.pair.fixture",
    "inspect_conjugate": "camtol.pair.fixture",
    "FixtureErrors": "camtol.pair.fixture_spec",
    "FixtureSpec": "camtol.pair.fixture_spec",
    "IndicatorRecord": "camtol.pair.indicator",
    "process_record": "camtol.pair.indicator",
    "read_indicator_csv": "camtol.pair.indicator",
    "record_estimates": "camtol.pair.indicator",
    "write_indicator_csv": "camtol.pair.indicator",
    "ConjugateKinematics": "camtol.pair.kinematics",
    "conjugate_kinematics": "camtol.pair.kinematics",
    "simulate_record": "camtol.pair.twin",
    "ConjugateFactors": "camtol.pair.variation",
    "ConjugateVariation": "camtol.pair.variation",
    "InverseEstimate": "camtol.pair.variation",
    "conjugate_factors": "camtol.pair.variation",
    "conjugate_variation": "camtol.pair.variation",
    "inverse_estimate": "camtol.pair.variation",
}

__all__ = [
    "AcceptanceBands",
    "CamVerdict",
    "CmmFixtureComparison",
    "ConjugateFactors",
    "ConjugateKinematics",
    "ConjugateVariation",
    "Fixture",
    "FixtureErrors",
    "FixtureInspection",
    "FixtureSpec",
    "IndicatorRecord",
    "InverseEstimate",
    "acceptance_bands",
    "compare_cmm_fixture",
    "conjugate_factors",
    "conjugate_kinematics",
    "conjugate_variation",
    "inspect_conjugate",
    "inverse_estimate",
    "process_record",
    "read_indicator_csv",
    "record_estimates",
    "simulate_fixture",
    "simulate_record",
    "write_indicator_csv",
]


def __getattr__(name: str) -> Any:
    """Import a public name on first use (PEP 562)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    """List the module attributes, including the lazy public names."""
    return sorted(set(globals()) | set(_LAZY))
