"""Start-up: what ``import camtol``, ``camtol analyze`` and ``camtol report`` import (issue 32).

The time is measured by ``bench/bench_startup.py`` (benchmarks measure, tests assert);
this checks the module lists, which do not depend on the machine's load: the optional
libraries of other commands (a database, a web framework, sensitivity analysis) are never
imported by these commands, and ``analyze`` imports no plotting, no rich and none of the
inspection, pair or contact machinery a single cam does not use.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import camtol

SRC = str(Path(camtol.__file__).resolve().parent.parent)

#: Optional libraries of other commands (records, the web service, sensitivity studies).
OPTIONAL = ("sqlalchemy", "alembic", "flask", "fastapi", "starlette", "uvicorn", "SALib")
#: What `camtol analyze` on a single cam needs none of.
NOT_FOR_ANALYZE = (
    *OPTIONAL,
    "matplotlib",
    "ezdxf",
    "scipy",
    "rich",  # the terminal tables are plain text (camtol.report.terminal)
    "asyncio",  # what pydantic's import brought on Python 3.11 (no longer a dependency)
    "numpy.polynomial",  # the polynomial laws take their derivatives directly
    "numpy.ma",  # np.unique imports it only to ask about masks (camtol.grid.sorted_unique)
    "camtol.contact",
    "camtol.inspection.deviations",
    "camtol.inspection.registration",
    "camtol.pair.acceptance",
    "camtol.pair.fixture_run",
)


def _modules_after(code: str, tmp_path: Path) -> set[str]:
    """Names in sys.modules after running ``code`` in a fresh interpreter."""
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            "import contextlib, io, json, sys\n"
            f"with contextlib.redirect_stdout(io.StringIO()):\n    {code}\n"
            "print(json.dumps(sorted(sys.modules)))",
        ],
        capture_output=True,
        text=True,
        check=True,
        env=env,
        cwd=tmp_path,
    ).stdout
    return set(json.loads(out.splitlines()[-1]))


def _loaded(modules: set[str], names: tuple[str, ...]) -> list[str]:
    return sorted(n for n in names if any(m == n or m.startswith(n + ".") for m in modules))


def test_import_camtol_imports_no_optional_library(tmp_path: Path) -> None:
    loaded = _modules_after("import camtol", tmp_path)
    assert "camtol" in loaded
    assert _loaded(loaded, (*OPTIONAL, "matplotlib", "numpy", "rich")) == []


@pytest.mark.parametrize("example", ["cw06-translating", "roller-oscillating"])
def test_analyze_imports_only_what_it_uses(tmp_path: Path, example: str) -> None:
    code = f"from camtol.cli.app import main; main(['analyze', '--example', '{example}'])"
    loaded = _modules_after(code, tmp_path)
    assert "camtol.analysis.result" in loaded  # the command ran
    # what `import numpy` itself loads is numpy's (numpy < 2 imports numpy.ma eagerly)
    numpy_own = _modules_after("import numpy", tmp_path)
    assert _loaded(loaded - numpy_own, NOT_FOR_ANALYZE) == []


def test_report_imports_no_optional_library(tmp_path: Path) -> None:
    code = (
        "from camtol.cli.app import main;"
        " main(['report', '--example', 'cw06-translating', '-o', 'r.html'])"
    )
    loaded = _modules_after(code, tmp_path)
    assert "matplotlib" in loaded and (tmp_path / "r.html").exists()
    assert _loaded(loaded, (*OPTIONAL, "camtol.pair.fixture_run", "camtol.pair.fixture")) == []
