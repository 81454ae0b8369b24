"""MkDocs hooks of the camtol documentation site (``hooks:`` in mkdocs.yml).

The nav holds slots for pages that other changes add (``tolerancing.md``,
``cmm-inspection.md``, ``manufacturing.md``). A slot whose file does not exist yet is
dropped from the nav before MkDocs validates it, so the site never shows a broken link and
the slot needs no placeholder page; once the file exists it appears where the nav puts it.
"""

from __future__ import annotations

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
