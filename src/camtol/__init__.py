"""camtol: precision disk-cam mechanisms: design, tolerance, inspection, manufacturing.

The public API is small; everything else lives in its own module (see the README)::

    from camtol import analyze, load_design, load_example
    result = analyze(load_example("cw06-translating"))
"""

from __future__ import annotations

__version__ = "0.1.0"

from camtol.analysis import Analysis, analyse, analyze
from camtol.config import example_names, load_design, load_example
from camtol.design import CamDesign, ToleranceSpec
from camtol.exceptions import (
    CamtolError,
    ConfigError,
    DesignError,
    GeometryError,
    UndercutError,
)

__all__ = [
    "Analysis",
    "CamDesign",
    "CamtolError",
    "ConfigError",
    "DesignError",
    "GeometryError",
    "ToleranceSpec",
    "UndercutError",
    "__version__",
    "analyse",
    "analyze",
    "example_names",
    "load_design",
    "load_example",
]
