"""The numeric core stays pure (STYLE point 1, ARCHITECTURE principles).

An import-linter-style contract checked on the source: the core modules may not import
the report layer, the command line, plotting, file formats or terminal libraries. The
check reads the import statements (module level and inside functions), so a lazy import
counts too.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import camtol

PACKAGE = Path(camtol.__file__).parent
CORE = [
    "jet.py",
    "motion.py",
    "mechanisms",
    "design.py",
    "sources.py",
    "kinematics.py",
    "engine.py",
    "errors.py",
    "extremes.py",
    "iso286.py",
    "analysis.py",
    "sizing.py",
    "summary.py",
    "tables.py",
    "grid.py",
    "contact",
    "manufacturing",
    "table_noise.py",
    "tolerancing",
]
FORBIDDEN = ("camtol.report", "camtol.cli", "camtol.config", "matplotlib", "ezdxf", "click", "rich")


def _core_files() -> list[Path]:
    files: list[Path] = []
    for name in CORE:
        p = PACKAGE / name
        files += sorted(p.rglob("*.py")) if p.is_dir() else [p]
    return files


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names |= {f"{node.module}.{a.name}" for a in node.names}
    return names


@pytest.mark.parametrize("path", _core_files(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_core_does_not_import_edges(path: Path) -> None:
    bad = sorted(
        n for n in _imports(path) if any(n == f or n.startswith(f + ".") for f in FORBIDDEN)
    )
    assert bad == [], f"{path.name} imports {bad}"
