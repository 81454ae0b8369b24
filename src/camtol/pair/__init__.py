"""The conjugate cam pair as a first-class object (THEORY §2.4, §4; [CW11]).

Everything that needs both cams of a pair at once lives here, and nowhere else: the
pair's joint kinematics, the measuring fixture (its spec and constant errors, the
forward conjugate variation Δf and the inverse analysis, acceptance and decision rules),
the dial-indicator record and its twin, the exact fixture simulation, the CMM-vs-fixture
comparison and the pair's verification. Outside this package a design is a set of cams
(:meth:`camtol.design.CamDesign.cams`), each knowing its own label and tolerances.
"""

from __future__ import annotations

from camtol.pair.acceptance import (
    AcceptanceBands,
    CamVerdict,
    acceptance_bands,
)
from camtol.pair.cmm_fixture import (
    CmmFixtureComparison,
    compare_cmm_fixture,
)
from camtol.pair.contact_fixture import (
    Fixture,
    simulate_fixture,
)
from camtol.pair.fixture import (
    FixtureInspection,
    inspect_conjugate,
)
from camtol.pair.fixture_spec import (
    FixtureErrors,
    FixtureSpec,
)
from camtol.pair.indicator import (
    IndicatorRecord,
    process_record,
    read_indicator_csv,
    record_estimates,
    write_indicator_csv,
)
from camtol.pair.kinematics import (
    ConjugateKinematics,
    conjugate_kinematics,
)
from camtol.pair.twin import (
    simulate_record,
)
from camtol.pair.variation import (
    ConjugateFactors,
    ConjugateVariation,
    InverseEstimate,
    conjugate_factors,
    conjugate_variation,
    inverse_estimate,
)

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
