"""Names that moved in 0.2 (issue 27), still importable from where they were, with a warning.

The package was reorganised into layers (docs/architecture.md): ``camtol.kinematics`` is
now :mod:`camtol.analysis.kinematics`, the conjugate fixture lives in :mod:`camtol.pair`,
the command line in :mod:`camtol.cli`, and so on. Importing a module by its old name, or
reading a moved name from its old package (``camtol.inspection.FixtureSpec``), still works
and issues a :class:`DeprecationWarning` naming the new place. These aliases are resolved
by name at run time, outside the layers, and will be removed in camtol 0.3.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType
from typing import Any

__all__ = ["MOVED_MODULES", "MOVED_NAMES", "install", "moved_name"]

#: Old module name -> its new name.
MOVED_MODULES: dict[str, str] = {
    "camtol.cli_commands": "camtol.cli.commands",
    "camtol.cli_conjugate": "camtol.cli.conjugate",
    "camtol.cli_inspect": "camtol.cli.inspect",
    "camtol.cli_inspection_options": "camtol.cli.inspection_options",
    "camtol.cli_manufacturing": "camtol.cli.manufacturing",
    "camtol.cli_options": "camtol.cli.options",
    "camtol.cli_records": "camtol.cli.records",
    "camtol.cli_report": "camtol.cli.report",
    "camtol.cli_simulate": "camtol.cli.simulate",
    "camtol.cli_size": "camtol.cli.size",
    "camtol.cli_tolerancing": "camtol.cli.tolerancing",
    "camtol.cli_usage": "camtol.cli.usage",
    "camtol.cli_verify": "camtol.cli.verify",
    "camtol.config_write": "camtol.config.writer",
    "camtol.conjugate": "camtol.pair.kinematics",
    "camtol.contact.fixture": "camtol.pair.contact_fixture",
    "camtol.drawing": "camtol.analysis.drawing",
    "camtol.engine": "camtol.analysis.engine",
    "camtol.errors": "camtol.analysis.errors",
    "camtol.examples": "camtol.config.examples",
    "camtol.extremes": "camtol.analysis.extremes",
    "camtol.inspection._store_sql": "camtol.records.schema",
    "camtol.inspection.acceptance": "camtol.pair.acceptance",
    "camtol.inspection.cmm_fixture": "camtol.pair.cmm_fixture",
    "camtol.inspection.conjugate": "camtol.pair.variation",
    "camtol.inspection.decision": "camtol.pair.decision",
    "camtol.inspection.fixture": "camtol.pair.fixture",
    "camtol.inspection.lots": "camtol.records.lots",
    "camtol.inspection.record": "camtol.pair.indicator",
    "camtol.inspection.simulate": "camtol.pair.twin",
    "camtol.inspection.spec": "camtol.pair.fixture_spec",
    "camtol.inspection.store": "camtol.records.store",
    "camtol.kinematics": "camtol.analysis.kinematics",
    "camtol.motion": "camtol.design.motion",
    "camtol.motion_laws": "camtol.design.laws",
    "camtol.profile": "camtol.analysis.profile",
    "camtol.radius_table": "camtol.analysis.radius_table",
    "camtol.sizing": "camtol.analysis.sizing",
    "camtol.sources": "camtol.design.sources",
    "camtol.summary": "camtol.analysis.summary",
    "camtol.table_noise": "camtol.design.table_noise",
    "camtol.toml_writer": "camtol.config.toml_writer",
    "camtol.validity": "camtol.analysis.validity",
}

#: (old package, name) -> the module that now defines the name.
MOVED_NAMES: dict[tuple[str, str], str] = {
    **{
        ("camtol.inspection", name): "camtol.pair"
        for name in (
            "CmmFixtureComparison",
            "FixtureErrors",
            "FixtureInspection",
            "FixtureSpec",
            "IndicatorRecord",
            "acceptance_bands",
            "compare_cmm_fixture",
            "conjugate_factors",
            "conjugate_variation",
            "inspect_conjugate",
            "inverse_estimate",
            "process_record",
            "read_indicator_csv",
            "record_estimates",
            "simulate_record",
            "write_indicator_csv",
        )
    },
    ("camtol.tolerancing.model", "parse_statistics"): "camtol.config.statistics_table",
    ("camtol.contact", "Fixture"): "camtol.pair",
    ("camtol.contact", "simulate_fixture"): "camtol.pair",
}


def _warn(old: str, new: str) -> None:
    warnings.warn(
        f"{old} moved to {new} in camtol 0.2; the old name goes in 0.3",
        DeprecationWarning,
        stacklevel=3,
    )


def moved_name(package: str, name: str) -> Any:
    """Return a name that moved out of ``package``, with a :class:`DeprecationWarning`.

    Parameters
    ----------
    package : str
        The package the name is read from, e.g. ``"camtol.inspection"``.
    name : str
        The attribute.

    Returns
    -------
    object
        The object under its new home.

    Raises
    ------
    AttributeError
        If the name never lived in ``package``.
    """
    new = MOVED_NAMES.get((package, name))
    if new is None:
        raise AttributeError(f"module {package!r} has no attribute {name!r}")
    _warn(f"{package}.{name}", f"{new}.{name}")
    return getattr(importlib.import_module(new), name)


class _Alias(importlib.abc.Loader):
    """Loads an old module name as the module under its new name."""

    def __init__(self, new: str) -> None:
        self.new = new

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        _warn(spec.name, self.new)
        return importlib.import_module(self.new)

    def exec_module(self, module: ModuleType) -> None:
        """Nothing to run: the new module is already imported."""


class _MovedFinder(importlib.abc.MetaPathFinder):
    """Finds the old names of moved modules (see :data:`MOVED_MODULES`)."""

    def find_spec(
        self, fullname: str, path: Any = None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        new = MOVED_MODULES.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _Alias(new))


def install() -> None:
    """Let the old module names import (once per interpreter)."""
    if not any(isinstance(f, _MovedFinder) for f in sys.meta_path):
        sys.meta_path.append(_MovedFinder())
