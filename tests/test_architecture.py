"""Layering of the package, checked on the source of every module (STYLE point 1).

Every module of ``src/camtol`` belongs to exactly one layer (a new module fails this test
until it is classified here):

* **core**: the numerics (motion, mechanisms, kinematics, errors, contact, inspection
  computations, manufacturing, Monte Carlo, verification, ...). It never imports the
  report layer, the command line, the design-file layer or plotting/terminal/file-format
  libraries.
* **report**: formats results it is given. It never calls the engines (analysis,
  kinematics, contact, inspection, drawing) to produce them.
* **edge**: the design-file layer (config, TOML writer, examples), the command line, and
  the package entry points; may import anything.

The check reads the import statements (module level and inside functions, outside
``if TYPE_CHECKING:`` blocks), so a lazy import counts too. Known exceptions are listed in
:data:`PENDING` with the reason; the list may only shrink.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import camtol

PACKAGE = Path(camtol.__file__).parent

EDGE = [
    "__init__.py",
    "__main__.py",
    "config.py",
    "config_write.py",
    "toml_writer.py",
    "examples.py",
    "export.py",
    "cli.py",
    "cli_*.py",
]
REPORT = ["report"]
#: Everything else is core (listed so that a new module must be placed deliberately).
CORE = [
    "jet.py",
    "exceptions.py",
    "motion.py",
    "motion_laws.py",
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
    "files.py",
    "textfile.py",
    "grid.py",
    "validity.py",
    "textfile.py",
    "contact",
    "manufacturing",
    "table_noise.py",
    "profile.py",
    "conjugate.py",
    "drawing.py",
    "radius_table.py",
    "study.py",
    "verify.py",
    "inspection",
    "tolerancing",
    "montecarlo.py",
]
FORBIDDEN_IN_CORE = (
    "camtol.report",
    "camtol.cli",
    "camtol.config",
    "camtol.config_write",
    "camtol.examples",
    "matplotlib",
    "ezdxf",
    "click",
    "rich",
)
#: What the report layer may not call: the engines that produce results.
FORBIDDEN_IN_REPORT = (
    "camtol.analysis.analyze",
    "camtol.analysis.analyse",
    "camtol.kinematics.kinematics",
    "camtol.errors.error_analysis",
    "camtol.contact",
    "camtol.conjugate",
    "camtol.drawing",
    "camtol.study",
    "camtol.verify",
    "camtol.inspection.fixture.inspect_conjugate",
    "camtol.inspection.fixture.conjugate_kinematics",
    "camtol.profile.profile_points",
    "camtol.profile.profile_table",
)
#: Known exceptions, (module, imported name): reason. To be removed, never extended.
PENDING: dict[tuple[str, str], str] = {}


def _matches(rel: str, patterns: list[str]) -> bool:
    parts = Path(rel).parts
    for pat in patterns:
        if Path(rel).match(pat) and len(parts) == 1:
            return True
        if len(parts) > 1 and parts[0] == pat:
            return True
    return False


def _layer(rel: str) -> str | None:
    found = [
        name
        for name, patterns in (("edge", EDGE), ("report", REPORT), ("core", CORE))
        if _matches(rel, patterns)
    ]
    return found[0] if len(found) == 1 else None


ALL = sorted(p.relative_to(PACKAGE).as_posix() for p in PACKAGE.rglob("*.py"))


def _imports(path: Path) -> set[str]:
    """Imported modules and ``module.name`` pairs, outside ``if TYPE_CHECKING:``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                skip |= {id(n) for n in ast.walk(sub)}
    names: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names |= {f"{node.module}.{a.name}" for a in node.names}
    return names


def _hits(name: str, forbidden: tuple[str, ...]) -> bool:
    return any(name == f or name.startswith(f + ".") for f in forbidden)


def _excused(rel: str, name: str) -> bool:
    return any(r == rel and (_hits(name, (p,)) or _hits(p, (name,))) for r, p in PENDING)


@pytest.mark.parametrize("rel", ALL)
def test_every_module_has_a_layer(rel: str) -> None:
    assert _layer(rel) is not None, f"{rel}: classify it in tests/test_architecture.py"


@pytest.mark.parametrize("rel", [r for r in ALL if _layer(r) == "core"])
def test_core_does_not_import_edges(rel: str) -> None:
    bad = sorted(
        n for n in _imports(PACKAGE / rel) if _hits(n, FORBIDDEN_IN_CORE) and not _excused(rel, n)
    )
    assert bad == [], f"{rel} imports {bad}"


@pytest.mark.parametrize("rel", [r for r in ALL if _layer(r) == "report"])
def test_report_only_formats(rel: str) -> None:
    bad = sorted(
        n for n in _imports(PACKAGE / rel) if _hits(n, FORBIDDEN_IN_REPORT) and not _excused(rel, n)
    )
    assert bad == [], f"{rel} runs an engine: {bad} (pass the result in instead)"


def test_pending_exceptions_are_still_real() -> None:
    """An exception that no longer occurs must be removed from PENDING."""
    for rel, name in PENDING:
        assert name in _imports(PACKAGE / rel), f"remove ({rel}, {name}) from PENDING"


@pytest.mark.parametrize("rel", ALL)
def test_no_module_above_600_lines(rel: str) -> None:
    n = len((PACKAGE / rel).read_text(encoding="utf-8").splitlines())
    assert n <= 600, f"{rel} has {n} lines; split it by concept"


@pytest.mark.parametrize("rel", ALL)
def test_exceptions_live_in_one_module(rel: str) -> None:
    """Every exception class camtol defines is in camtol.exceptions (a CamtolError)."""
    if rel == "exceptions.py":
        return
    tree = ast.parse((PACKAGE / rel).read_text(encoding="utf-8"))
    defined = [
        node.name
        for node in ast.walk(tree)
        if isinstance(node, ast.ClassDef)
        and not node.name.startswith("_")  # private control flow (e.g. the CLI's exit)
        and any(
            isinstance(b, ast.Name) and (b.id.endswith("Error") or b.id == "Exception")
            for b in node.bases
        )
    ]
    assert defined == [], f"{rel} defines {defined}; define errors in camtol/exceptions.py"


def test_every_error_is_a_camtol_error() -> None:
    from camtol import exceptions

    for name in exceptions.__all__:
        obj = getattr(exceptions, name)
        if isinstance(obj, type) and issubclass(obj, Exception) and name.endswith("Error"):
            assert issubclass(obj, exceptions.CamtolError), name
