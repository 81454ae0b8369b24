"""The documentation's worked examples run, and say what camtol really prints.

Every worked example (``docs/examples/*.md``), the home page and ``docs/getting-started.md``
are executed top to bottom
in a fresh temporary directory, the way a reader would follow it:

- a fenced block with a ``title="NAME"`` (e.g. ```` ```toml title="my-cam.toml" ````) is
  written to the file NAME;
- a ``console`` block runs each ``$ camtol ...`` line in-process
  (:func:`camtol.cli.app.main`), with ``> FILE`` redirecting standard output to a file and a
  trailing ``|| echo "exit status $?"`` meaning the command is expected to fail (the shown
  output then ends with that line). The exit status must be 0 otherwise. Every output
  line shown under a command must appear in what the command printed (whitespace
  collapsed); a line ``...`` stands for omitted output;
- a ``python`` block is executed in one namespace per page; its ``assert`` statements check
  the numbers against the published values (each page states the tolerance and why).

Other blocks (``text``, ``toml`` without a title) are illustrations and are not run.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"
PAGES = [
    DOCS / "index.md",
    DOCS / "getting-started.md",
    *sorted(p for p in (DOCS / "examples").glob("*.md") if p.name != "index.md"),
]

_FENCE = re.compile(
    r"^(?P<indent>[ ]*)```(?P<info>[^\n]*)\n(?P<body>.*?)^(?P=indent)```[ ]*$",
    re.MULTILINE | re.DOTALL,
)
_TITLE = re.compile(r'title="([^"]+)"')
_FAIL_SUFFIX = '|| echo "exit status $?"'


def blocks(page: Path) -> list[tuple[str, str | None, str]]:
    """(language, title, body) of every fenced block of a page, in order."""
    out = []
    for m in _FENCE.finditer(page.read_text(encoding="utf-8")):
        info = m.group("info").strip()
        lang = info.split()[0].lstrip(".{") if info else ""
        title = _TITLE.search(info)
        body = "\n".join(line[len(m.group("indent")) :] for line in m.group("body").splitlines())
        out.append((lang, title.group(1) if title else None, body))
    return out


def _squash(text: str) -> str:
    return " ".join(text.split())


def run_console(body: str, where: str) -> None:
    """Run the ``$ camtol`` lines of a console block and check the shown output."""
    from camtol.cli.app import main

    commands: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if line.startswith("$ "):
            commands.append((line[2:].strip(), []))
        elif commands:
            commands[-1][1].append(line)
    assert commands, f"{where}: a console block without a '$ ' command"
    for command, shown in commands:
        expect_failure = command.endswith(_FAIL_SUFFIX)
        words = shlex.split(command.removesuffix(_FAIL_SUFFIX))
        assert words[0] == "camtol", f"{where}: only camtol commands are run: {command!r}"
        target = None
        if ">" in words:
            i = words.index(">")
            target, words = words[i + 1], words[:i]
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(words[1:])
        if target is not None:
            Path(target).write_text(out.getvalue(), encoding="utf-8")
        printed = out.getvalue() + err.getvalue()
        if expect_failure:
            assert code != 0, f"{where}: {command!r} was expected to fail; it exited 0"
            printed += f"\nexit status {code}\n"
        else:
            assert code == 0, f"{where}: {command!r} exited {code}:\n{err.getvalue()}"
        have = _squash(printed)
        for line in shown:
            if line.strip() in ("", "..."):
                continue
            assert _squash(line) in have, (
                f"{where}: {command!r} did not print the documented line\n  {line.strip()}\n"
                f"it printed:\n{printed}"
            )


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(DOCS).as_posix())
def test_page_runs(page: Path, tmp_path: Path) -> None:
    found = blocks(page)
    runnable = [b for b in found if b[0] in ("console", "python") or b[1] is not None]
    assert runnable, f"{page.name}: a worked example with nothing to run"
    namespace: dict[str, object] = {"__name__": f"docs_{page.stem}"}
    old = Path.cwd()
    os.chdir(tmp_path)
    try:
        for n, (lang, title, body) in enumerate(found, start=1):
            where = f"{page.relative_to(DOCS)} block {n}"
            if title is not None:
                Path(title).write_text(body + "\n", encoding="utf-8")
            elif lang == "console":
                run_console(body, where)
            elif lang == "python":
                exec(compile(body, where, "exec"), namespace)  # noqa: S102 - our own docs
    finally:
        os.chdir(old)


def test_runner_checks_shown_output(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The runner itself: a wrong documented line or exit status is caught."""
    monkeypatch.chdir(tmp_path)
    run_console("$ camtol examples\ncw06-translating", "self-test")
    with pytest.raises(AssertionError, match="documented line"):
        run_console("$ camtol examples\nno-such-example", "self-test")
    with pytest.raises(AssertionError, match="exited 2"):
        run_console("$ camtol analyze --example no-such-example", "self-test")
    run_console(
        f"$ camtol analyze --example no-such-example {_FAIL_SUFFIX}\nexit status 2", "self-test"
    )
    run_console("$ camtol examples show cw06-translating > my.toml", "self-test")
    assert 'name = "cw06-translating"' in (tmp_path / "my.toml").read_text(encoding="utf-8")
