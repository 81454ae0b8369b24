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


def on_page_content(html: str, **kwargs: Any) -> str:
    """Render the reStructuredText roles and math markers left in docstrings."""
    return _MATH.sub("", _ROLE.sub(_role, html))
