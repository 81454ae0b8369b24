"""The revisions of the inspection store's schema, one per version (forward only)."""

from __future__ import annotations
