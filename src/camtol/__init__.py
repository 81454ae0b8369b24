"""camtol: precision disk-cam mechanisms: design, tolerance, inspection, manufacturing.

The public API is small; everything else lives in its own module (see the README)::

    from camtol import analyze, load_design, load_example
    result = analyze(load_example("cw06-translating"))

The names below are imported on first use (PEP 562 module ``__getattr__``), so that
``import camtol`` and ``camtol --help`` do not pay for numpy or scipy.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

from camtol import _compat
from camtol._version import __version__
from camtol.exceptions import (
    CamtolError,
    ConfigError,
    DesignError,
    GeometryError,
    UndercutError,
)

_compat.install()  # modules moved in 0.2 still import by their old names, with a warning

if TYPE_CHECKING:  # pragma: no cover - what the lazy names resolve to, for type checkers
    from camtol.analysis.result import Analysis, analyse, analyze
    from camtol.config.design_file import load_design, load_example
    from camtol.config.examples import example_names
    from camtol.design.cam_design import CamDesign, ToleranceSpec

#: Public name -> module that defines it (imported on first attribute access).
_LAZY = {
    "Analysis": "camtol.analysis.result",
    "analyse": "camtol.analysis.result",
    "analyze": "camtol.analysis.result",
    "CamDesign": "camtol.design.cam_design",
    "ToleranceSpec": "camtol.design.cam_design",
    "example_names": "camtol.config.examples",
    "load_design": "camtol.config.design_file",
    "load_example": "camtol.config.design_file",
}

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


def __getattr__(name: str) -> Any:
    """Import a public name on first use (PEP 562)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'camtol' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    """List the module attributes, including the lazy public names."""
    return sorted(set(globals()) | set(_LAZY))
