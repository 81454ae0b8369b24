"""Every result a design report shows, computed once by the core (issue 8 layering).

:func:`study` analyses a design, draws it and, for a conjugate design with an
``[inspection]`` table, runs the fixture analysis (THEORY §4). The report layer
(:mod:`camtol.report.html`) only formats the :class:`Study` it is given.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from camtol.analysis.drawing import CamDrawing, analysis_drawing
from camtol.analysis.result import Analysis, analyze
from camtol.design.cam_design import CamDesign
from camtol.pair.fixture_spec import fixture_spec
from camtol.pair.kinematics import is_pair

if TYPE_CHECKING:  # pragma: no cover
    from camtol.pair.fixture import FixtureInspection
    from camtol.pair.fixture_spec import FixtureSpec

__all__ = ["Study", "study"]


@dataclass(frozen=True)
class Study:
    """The results of one design for a report.

    Attributes
    ----------
    analysis : Analysis
        From :func:`camtol.analysis.result.analyze`.
    drawing : CamDrawing
        The cams and follower where the worst-case error is largest.
    fixture : FixtureInspection or None
        The fixture analysis of a conjugate design with an ``[inspection]`` table.
    fixture_spec : FixtureSpec or None
        The ``[inspection]`` table it used.
    """

    analysis: Analysis
    drawing: CamDrawing
    fixture: FixtureInspection | None = None
    fixture_spec: FixtureSpec | None = None


def study(design_or_analysis: CamDesign | Analysis) -> Study:
    """Compute everything a report of the design shows.

    Parameters
    ----------
    design_or_analysis : CamDesign or Analysis
        A design (analysed with the default 0.1° step) or a finished analysis.

    Returns
    -------
    Study
        Analysis, drawing and (conjugate designs with ``[inspection]``) fixture results.

    Raises
    ------
    GeometryError, UndercutError, DesignError
        The design cannot be analysed.
    """
    a = (
        design_or_analysis
        if isinstance(design_or_analysis, Analysis)
        else analyze(design_or_analysis)
    )
    design = a.design
    spec = fixture_spec(design)
    if spec is None or not is_pair(design):
        return Study(a, analysis_drawing(a))

    # Imported here: a single cam's report does not load the fixture machinery.
    from camtol.pair.fixture import inspect_conjugate

    return Study(a, analysis_drawing(a), inspect_conjugate(design, spec), spec)
