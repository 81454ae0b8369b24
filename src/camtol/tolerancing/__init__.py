"""Tolerance design: statistical model, Monte Carlo, contributions and allocation.

Answers "what fraction of mechanisms built to these tolerances meets my motion spec?"
(:func:`monte_carlo`, linear or exact) and "what are the coarsest IT grades that still
meet it?" (:func:`allocate`), as functions of the cam angle (docs/tolerancing.md).
"""

from __future__ import annotations

from camtol.tolerancing.allocation import Allocation, allocate
from camtol.tolerancing.band import ToleranceBand, read_band_csv
from camtol.tolerancing.distributions import SourceDistribution
from camtol.tolerancing.model import StatisticalModel, statistical_model
from camtol.tolerancing.montecarlo import monte_carlo
from camtol.tolerancing.processes import ProfileProcess
from camtol.tolerancing.results import MonteCarloResult

__all__ = [
    "Allocation",
    "MonteCarloResult",
    "ProfileProcess",
    "SourceDistribution",
    "StatisticalModel",
    "ToleranceBand",
    "allocate",
    "monte_carlo",
    "read_band_csv",
    "statistical_model",
]
