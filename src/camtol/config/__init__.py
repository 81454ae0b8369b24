"""Design files: schema, writer and built-in examples (an I/O edge).

The TOML schema (strict tables of fields, :mod:`~camtol.config.fields`, declared by
:mod:`~camtol.config.design_file` and the modules of the other tables), the writer that
reads back as an equal design (:mod:`~camtol.config.writer`,
:mod:`~camtol.config.toml_writer`) and the built-in examples
(:mod:`~camtol.config.examples`). An I/O edge: the core never imports it.

The names below are imported on first use (PEP 562), so that listing the examples does
not load numpy.
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover - what the lazy names resolve to, for type checkers
    from camtol.config.design_file import (
        design_from_mapping,
        follower_types,
        load_design,
        load_example,
    )
    from camtol.config.examples import example_names, example_summary, example_text
    from camtol.config.writer import dump_design

#: Public name -> module that defines it (imported on first attribute access).
_LAZY = {
    "design_from_mapping": "camtol.config.design_file",
    "follower_types": "camtol.config.design_file",
    "load_design": "camtol.config.design_file",
    "load_example": "camtol.config.design_file",
    "dump_design": "camtol.config.writer",
    "example_names": "camtol.config.examples",
    "example_summary": "camtol.config.examples",
    "example_text": "camtol.config.examples",
}

__all__ = [
    "design_from_mapping",
    "dump_design",
    "example_names",
    "example_summary",
    "example_text",
    "follower_types",
    "load_design",
    "load_example",
]


def __getattr__(name: str) -> Any:
    """Import a public name on first use (PEP 562)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'camtol.config' has no attribute {name!r}")
    value = getattr(import_module(module), name)
    globals()[name] = value
    return value
