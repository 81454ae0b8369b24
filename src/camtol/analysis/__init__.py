"""The analytic engine over θ (THEORY §2-3).

Kinematics, error sensitivities and ΔS/ΔV/ΔA,
extremes, geometry validity, summaries, sizing, the sampled profile and drawing data.

:func:`analyze` gathers everything the engine says about a design in one
:class:`Analysis` (internal units: mm, rad, per radian of cam angle).
"""

from __future__ import annotations

from camtol.analysis.errors import (
    ErrorAnalysis,
    SourceError,
    error_analysis,
)
from camtol.analysis.kinematics import (
    Kinematics,
    kinematics,
)
from camtol.analysis.result import (
    Analysis,
    Curves,
    Quantity,
    analyse,
    analyze,
    max_radius_mm,
)

__all__ = [
    "Analysis",
    "Curves",
    "ErrorAnalysis",
    "Kinematics",
    "Quantity",
    "SourceError",
    "analyse",
    "analyze",
    "error_analysis",
    "kinematics",
    "max_radius_mm",
]
