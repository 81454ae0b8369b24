"""MkDocs hooks of the camtol documentation site (``hooks:`` in mkdocs.yml).

The nav holds slots for pages that other changes add (``tolerancing.md``,
``cmm-inspection.md``, ``manufacturing.md``). A slot whose file does not exist yet is
dropped from the nav before MkDocs validates it, so the site never shows a broken link and
the slot needs no placeholder page; once the file exists it appears where the nav puts it.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any


def _keep(entry: Any, docs_dir: Path) -> Any:
    """Return the nav entry without its missing pages, or None when nothing is left."""
    if isinstance(entry, str):
        if entry.startswith(("http://", "https://")) or (docs_dir / entry).is_file():
            return entry
        return None
    if isinstance(entry, dict):
        out = {}
        for title, value in entry.items():
            kept = _keep(value, docs_dir)
            if kept is not None:
                out[title] = kept
        return out or None
    if isinstance(entry, list):
        items = [k for k in (_keep(e, docs_dir) for e in entry) if k is not None]
        return items or None
    return entry


def on_config(config: Any) -> Any:
    """Drop nav entries whose page is absent (the slots for pages added later)."""
    if config.nav is not None:
        config.nav = _keep(config.nav, Path(config.docs_dir)) or []
    return config


# Docstrings are numpydoc with a few reStructuredText constructs (roles such as
# :func:`x`, ``.. math::``) that Markdown shows literally. Render them for the site: a
# role becomes an optional cross-reference (a link when camtol documents the object, plain
# code otherwise), and the ``.. math::`` marker is dropped (the formula stays as code).
_ROLE = re.compile(r":(?:func|class|meth|mod|data|attr|exc|obj):<code>~?([\w.]+)</code>")
_MATH = re.compile(r"<p>\.\. math::</p>\s*")


def _role(match: re.Match[str]) -> str:
    target = match.group(1)
    return f'<autoref identifier="{target}" optional><code>{target}</code></autoref>'


# "THEORY §x.y" in docstrings and pages cites section x.y of docs/theory.md: link it.
_CITE = re.compile(r"(THEORY(?:\.md)?\s*)§\s*(\d+(?:\.\d+)?)")
_TAG = re.compile(r"(<[^>]+>)")
_sections: dict[str, str] = {}


def on_files(files: Any, config: Any) -> Any:
    """Read the section numbers of theory.md and their anchors (as the toc makes them)."""
    from markdown.extensions.toc import slugify

    _sections.clear()
    theory = Path(config.docs_dir) / "theory.md"
    if theory.is_file():
        for line in theory.read_text(encoding="utf-8").splitlines():
            m = re.match(r"#{2,3} ((\d+(?:\.\d+)?)[. ].*)$", line)
            if m:
                _sections[m.group(2)] = slugify(m.group(1), "-")
    return files


def _link_citations(text: str, theory_url: str) -> str:
    def link(m: re.Match[str]) -> str:
        anchor = _sections.get(m.group(2))
        if anchor is None:
            return m.group(0)
        return f'<a href="{theory_url}#{anchor}">{m.group(0)}</a>'

    # only in text between tags, never inside a tag's attributes
    return "".join(
        part if part.startswith("<") else _CITE.sub(link, part) for part in _TAG.split(text)
    )


def on_page_markdown(markdown: str, page: Any, **kwargs: Any) -> str:
    """Put the reference of every command (built from the command tree) into commands.md."""
    if page.file.src_uri != "commands.md":
        return markdown
    from camtol.cli.reference import MARKER, commands_markdown

    if MARKER not in markdown:
        raise ValueError(f"docs/commands.md lacks the marker {MARKER}")
    return markdown.replace(MARKER, commands_markdown())


def on_page_content(html: str, page: Any, **kwargs: Any) -> str:
    """Render docstrings' reST roles and math markers; link "THEORY §x" citations."""
    html = _MATH.sub("", _ROLE.sub(_role, html))
    if page.file.src_uri == "theory.md" or not _sections:
        return html
    depth = page.url.count("/") if page.url else 0
    return _link_citations(html, "../" * depth + "theory/")
