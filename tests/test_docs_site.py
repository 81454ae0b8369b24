"""The documentation site's structure, checked without building it.

- every page in ``docs/`` is in the nav of ``mkdocs.yml`` (no orphan pages), and every nav
  entry is a page that exists, except the declared slots for pages added by later changes;
- every "THEORY §x.y" that camtol cites (docstrings, messages, reports) is a section of
  ``docs/theory.md``, so a user with only the package can follow it.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"

#: Nav entries whose page another change adds; docs/_hooks.py drops them while absent.
SLOTS = {"tolerancing.md", "cmm-inspection.md", "manufacturing.md"}


def _nav_pages() -> list[str]:
    """Pages named in the ``nav:`` section of mkdocs.yml, in order (comments ignored).

    Read as text, so that the test needs no YAML parser: the nav is the last top-level
    key of mkdocs.yml and its entries are ``- page.md`` or ``- Title: page.md``.
    """
    text = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    nav = re.search(r"^nav:\n(.*?)(?=^\S|\Z)", text, flags=re.MULTILINE | re.DOTALL)
    assert nav is not None, "mkdocs.yml has no nav"
    lines = [line.split("#", 1)[0] for line in nav.group(1).splitlines()]
    return re.findall(r"(?:^|[\s:])([\w./-]+\.md)\s*$", "\n".join(lines), flags=re.MULTILINE)


def test_every_page_is_in_the_nav() -> None:
    listed = _nav_pages()
    assert "index.md" in listed and "theory.md" in listed, listed
    assert len(listed) == len(set(listed)), "a page is listed twice in the nav"
    on_disk = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    orphans = sorted(on_disk - set(listed))
    assert not orphans, f"pages in docs/ missing from the nav of mkdocs.yml: {orphans}"
    missing = sorted(set(listed) - on_disk - SLOTS)
    assert not missing, f"nav entries without a page in docs/: {missing}"


def _hooks() -> Any:
    import importlib.util

    spec = importlib.util.spec_from_file_location("docs_hooks", DOCS / "_hooks.py")
    assert spec is not None and spec.loader is not None
    hooks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hooks)
    return hooks


def test_nav_slots_are_dropped_while_absent(tmp_path: Path) -> None:
    """The hook keeps present pages and drops absent slots (no broken links, no stubs)."""
    hooks = _hooks()
    (tmp_path / "index.md").write_text("# x\n", encoding="utf-8")
    (tmp_path / "api").mkdir()
    (tmp_path / "api" / "a.md").write_text("# a\n", encoding="utf-8")
    nav = [
        {"Home": "index.md"},
        {"Manufacturing": "manufacturing.md"},
        {"API": ["api/a.md", {"Gone": "api/gone.md"}]},
        {"Only gone": [{"x": "gone.md"}]},
    ]
    assert hooks._keep(nav, tmp_path) == [{"Home": "index.md"}, {"API": ["api/a.md"]}]


def test_citations_become_links() -> None:
    """On the site, "THEORY §x.y" links to the section; tag attributes are left alone."""
    pytest.importorskip("markdown")  # installed with MkDocs (the docs extra)
    hooks = _hooks()

    class Config:
        docs_dir = str(DOCS)

    hooks.on_files(None, Config())
    html = '<p title="THEORY §2.3">see THEORY §2.3 and THEORY §9.9</p>'
    out = hooks._link_citations(html, "../theory/")
    assert out == (
        '<p title="THEORY §2.3">see <a href="../theory/#23-translating-roller-follower">'
        "THEORY §2.3</a> and THEORY §9.9</p>"
    )


def _theory_sections() -> set[str]:
    text = (DOCS / "theory.md").read_text(encoding="utf-8")
    return set(re.findall(r"^#{2,3} (\d+(?:\.\d+)?)[. ]", text, flags=re.MULTILINE))


def test_theory_keeps_the_section_numbers() -> None:
    sections = _theory_sections()
    for top in range(9):  # §0 .. §8
        assert str(top) in sections, f"docs/theory.md has no section {top}"


def test_every_theory_citation_resolves() -> None:
    sections = _theory_sections()
    cited: dict[str, set[str]] = {}
    pattern = re.compile(
        r"THEORY(?:\.md)?\s*§\s*(\d+(?:\.\d+)?)((?:\s*(?:,|and|-|–)\s*§?\d+(?:\.\d+)?)*)"
    )
    for path in sorted((ROOT / "src" / "camtol").rglob("*.py")):
        for m in pattern.finditer(path.read_text(encoding="utf-8")):
            numbers = [m.group(1), *re.findall(r"\d+(?:\.\d+)?", m.group(2))]
            for n in numbers:
                cited.setdefault(n, set()).add(path.relative_to(ROOT).as_posix())
    assert cited, "no THEORY citation found: the pattern is wrong"
    unresolved = {n: sorted(files) for n, files in cited.items() if n not in sections}
    assert not unresolved, f"THEORY sections cited but absent from docs/theory.md: {unresolved}"
