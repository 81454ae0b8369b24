"""The package's shape, checked on the source of every module (docs/architecture.md).

Every import counts, wherever it stands: at module level, inside a function and under
``if TYPE_CHECKING:``. The layers are read from the import-linter contract in
pyproject.toml (``.ci/run`` also runs ``lint-imports`` on it), so this test and that tool
check one description:

* no import circle between two modules;
* no import from a lower layer to a higher one, and none between the independent
  packages of one layer;
* the core (everything below the report, the store and the design files) imports no
  plotting, terminal, command-line, file-format or database library;
* the report layer formats what it is given and never runs an engine;
* at most a dozen modules directly under ``src/camtol``, the command line a package;
* the conjugate pair's special cases live in its wing (:mod:`camtol.pair`) only;
* a module over about 500 lines says in its docstring why it is one thing;
* every exception camtol raises is defined in :mod:`camtol.exceptions`.
"""

from __future__ import annotations

import ast
import sys
from functools import cache
from pathlib import Path

import pytest

import camtol

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

PACKAGE = Path(camtol.__file__).parent
PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"  # the checkout's


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES: dict[str, Path] = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    out: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                out |= {id(n) for n in ast.walk(sub)}
    return out


@cache
def imports_of(module: str) -> frozenset[str]:
    """Everything ``module`` imports: camtol modules (resolved) and external top names."""
    return imports_in(MODULES[module], module)


def imports_in(path: Path, module: str) -> frozenset[str]:
    """Everything the source at ``path``, read as ``module``, imports (see imports_of)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".") if is_package else module.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            # ``from pkg import sub`` imports the module pkg.sub; ``from mod import name``
            # imports mod (as import-linter reads them).
            targets = [
                f"{stem}.{a.name}" if f"{stem}.{a.name}" in MODULES else stem for a in node.names
            ]
        else:
            continue
        for target in targets:
            if target.split(".")[0] != "camtol":
                found.add(target.split(".")[0])
                continue
            parts = target.split(".")
            while parts and ".".join(parts) not in MODULES:
                parts.pop()
            name = ".".join(parts)
            if name and name != module:
                found.add(name)
    return frozenset(found)


def _internal(module: str) -> set[str]:
    return {m for m in imports_of(module) if m.startswith("camtol")}


def _layers() -> list[list[str]]:
    config = tomllib.loads(PYPROJECT.read_text(encoding="utf-8"))["tool"]["importlinter"]
    (contract,) = [c for c in config["contracts"] if c["type"] == "layers"]
    return [[p.strip() for p in layer.split("|")] for layer in contract["layers"]]


LAYERS = _layers()


def _place(module: str) -> tuple[int, str] | None:
    """(layer index, lowest first; the package of the layer) of a module, or None."""
    for depth, packages in enumerate(reversed(LAYERS)):
        for pkg in packages:
            if module == pkg or module.startswith(pkg + "."):
                return depth, pkg
    return None


#: The package's face and its entry point stand above the layers: they hand names on.
ABOVE_LAYERS = {"camtol", "camtol.__main__"}


@pytest.mark.parametrize("module", sorted(MODULES))
def test_every_module_has_a_layer(module: str) -> None:
    assert module in ABOVE_LAYERS or _place(module) is not None, (
        f"{module}: place its package in the layers of [tool.importlinter] in pyproject.toml"
    )


@pytest.mark.parametrize("module", sorted(set(MODULES) - ABOVE_LAYERS))
def test_no_import_runs_upward_or_sideways(module: str) -> None:
    depth, pkg = _place(module)  # type: ignore[misc]
    bad = []
    for target in sorted(_internal(module)):
        if target in ABOVE_LAYERS:
            bad.append(f"{target} (the package's face: import the module that defines it)")
            continue
        where = _place(target)
        assert where is not None, target
        if where[0] > depth or (where[0] == depth and where[1] != pkg):
            bad.append(target)
    assert bad == [], f"{module} ({pkg}) imports upward or sideways: {bad}"


def test_no_import_circle() -> None:
    """Tarjan's strongly connected components over every import of every module."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(_internal(v) - {"camtol"}):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                circles.append(sorted(group))

    for m in sorted(MODULES):
        if m not in index:
            visit(m)
    assert circles == []


#: Libraries the core never imports: plotting, terminal, command line, file formats,
#: validation of files, databases and the web page belong to the edges (report, records,
#: config, cli, web).
FORBIDDEN_IN_CORE = {
    "matplotlib",
    "ezdxf",
    "click",
    "rich",
    "sqlalchemy",
    "alembic",
    "flask",
    "waitress",
}
EDGES = (
    "camtol.cli",
    "camtol.web",
    "camtol.config",
    "camtol.export",
    "camtol.report",
    "camtol.records",
)


@pytest.mark.parametrize(
    "module",
    sorted(m for m in MODULES if m not in ABOVE_LAYERS and not m.startswith(EDGES)),
)
def test_core_imports_no_io_library(module: str) -> None:
    bad = sorted(imports_of(module) & FORBIDDEN_IN_CORE)
    assert bad == [], f"{module} is core and imports {bad}"


#: What the report layer may not call: the engines that produce results.
FORBIDDEN_IN_REPORT = (
    "camtol.analysis.result.analyze",
    "camtol.analysis.result.analyse",
    "camtol.analysis.kinematics.kinematics",
    "camtol.analysis.errors.error_analysis",
    "camtol.analysis.drawing",
    "camtol.analysis.profile.profile_points",
    "camtol.analysis.profile.profile_table",
    "camtol.contact",
    "camtol.pair.kinematics",
    "camtol.pair.fixture.inspect_conjugate",
    "camtol.study",
    "camtol.verify",
)


def _imported_names(path: Path) -> set[str]:
    """``module.name`` of every ``from module import name`` and every ``import module``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _type_checking_nodes(tree)
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


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("camtol.report")))
def test_report_only_formats(module: str) -> None:
    bad = sorted(
        n
        for n in _imported_names(MODULES[module])
        if any(n == f or n.startswith(f + ".") for f in FORBIDDEN_IN_REPORT)
    )
    assert bad == [], f"{module} runs an engine: {bad} (pass the result in instead)"


def test_a_dozen_modules_at_the_top_and_the_command_line_a_package() -> None:
    top = sorted(
        p.name for p in PACKAGE.glob("*.py") if p.name not in {"__init__.py", "__main__.py"}
    )
    assert len(top) <= 12, top
    assert not [n for n in top if n.startswith("cli")], top
    assert (PACKAGE / "cli" / "__init__.py").is_file()


PAIR_WING = "camtol.pair"


def _pair_special_cases(path: Path) -> list[str]:
    """``isinstance(..., ConjugatePair)`` and comparisons of a value with "A" or "B"."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id == "isinstance"
            and len(node.args) == 2
            and "ConjugatePair" in ast.unparse(node.args[1])
        ):
            found.append(f"line {node.lineno}: {ast.unparse(node)}")
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            for op in operands:
                literal = isinstance(op, ast.Constant) and op.value in ("A", "B")
                members = isinstance(op, ast.Tuple | ast.Set | ast.List) and any(
                    isinstance(e, ast.Constant) and e.value in ("A", "B") for e in op.elts
                )
                if literal or members:
                    found.append(f"line {node.lineno}: {ast.unparse(node)}")
                    break
    return found


@pytest.mark.parametrize(
    "module",
    sorted(
        m for m in MODULES if not m.startswith(PAIR_WING) and m != "camtol.mechanisms.conjugate"
    ),
)
def test_the_pair_is_special_only_in_its_wing(module: str) -> None:
    """Outside camtol.pair a design is a set of cams: no isinstance, no "A"/"B" branch."""
    assert _pair_special_cases(MODULES[module]) == []


def test_the_pair_check_finds_what_it_looks_for(tmp_path: Path) -> None:
    probe = tmp_path / "probe.py"
    probe.write_text(
        "if isinstance(m, ConjugatePair):\n    pass\nx = 1 if cam == 'A' else 2\n"
        "y = cam in ('A', 'B')\n"
    )
    assert len(_pair_special_cases(probe)) == 3


#: Lines past which a module must say, in its docstring, why it is one thing.
LONG_MODULE_LINES = 500
WHY_ONE_MODULE = "Why one module:"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_a_long_module_says_why_it_is_one_thing(module: str) -> None:
    path = MODULES[module]
    text = path.read_text(encoding="utf-8")
    if len(text.splitlines()) <= LONG_MODULE_LINES:
        return
    doc = ast.get_docstring(ast.parse(text)) or ""
    assert WHY_ONE_MODULE in doc, (
        f"{module} has {len(text.splitlines())} lines: split it by concept, or say in its"
        f" docstring, after {WHY_ONE_MODULE!r}, why it is one thing"
    )


@pytest.mark.parametrize("module", sorted(MODULES))
def test_exceptions_live_in_one_module(module: str) -> None:
    """Every exception class camtol defines is in camtol.exceptions (a CamtolError)."""
    if module == "camtol.exceptions":
        return
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
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
    assert defined == [], f"{module} defines {defined}; define errors in camtol/exceptions.py"


def test_every_error_is_a_camtol_error() -> None:
    from camtol import exceptions

    for name in exceptions.__all__:
        obj = getattr(exceptions, name)
        if isinstance(obj, type) and issubclass(obj, Exception) and name.endswith("Error"):
            assert issubclass(obj, exceptions.CamtolError), name


def test_the_import_reader_sees_lazy_and_type_checking_imports(tmp_path: Path) -> None:
    """An upward import hidden in a function or under TYPE_CHECKING still counts."""
    probe = tmp_path / "probe.py"
    probe.write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import camtol.pair.fixture\n"
        "def f() -> None:\n    from camtol.report import tables\n    from . import motion\n"
    )
    found = imports_in(probe, "camtol.design.probe")
    assert {"camtol.pair.fixture", "camtol.report.tables", "camtol.design.motion"} <= found
    depth = _place("camtol.design.probe")
    assert depth is not None and _place("camtol.pair.fixture")[0] > depth[0]  # type: ignore[index]
