"""Inspection of machined cams (THEORY §4): the conjugate-cam measuring fixture."""

from __future__ import annotations

from camtol.inspection.fixture import (
    AcceptanceBands,
    CamVerdict,
    ConjugateFactors,
    ConjugateVariation,
    ErrorFunction,
    FixtureErrors,
    FixtureInspection,
    FixtureSpec,
    InverseEstimate,
    acceptance_bands,
    conjugate_factors,
    conjugate_variation,
    failing_intervals,
    inspect_conjugate,
    inverse_estimate,
    parse_error_function,
    parse_length_um,
)

__all__ = [
    "AcceptanceBands",
    "CamVerdict",
    "ConjugateFactors",
    "ConjugateVariation",
    "ErrorFunction",
    "FixtureErrors",
    "FixtureInspection",
    "FixtureSpec",
    "InverseEstimate",
    "acceptance_bands",
    "conjugate_factors",
    "conjugate_variation",
    "failing_intervals",
    "inspect_conjugate",
    "inverse_estimate",
    "parse_error_function",
    "parse_length_um",
]
