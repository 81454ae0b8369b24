"""A raw input of an inspection, as the store keeps it: the bytes read, by SHA-256.

A CMM scan, a dial-indicator record, a measured Δf or a master's error (a CSV file, or a
value given as text), the scans of a pair's CMM masters, and the files a design file
names: kept whole, compressed with zlib, once per SHA-256, so that a record can be judged
again from exactly what it was judged on (``camtol records rerun``) and a corrupt blob is
found by its checksum.
"""

from __future__ import annotations

import hashlib
import zlib
from dataclasses import dataclass, field
from functools import cached_property

from camtol.exceptions import RecordError

__all__ = ["MAX_RAW_BYTES", "ZLIB_LEVEL", "RawInput", "sha256_of"]

#: zlib level of the raw blobs: level 1 compresses a CMM scan's text to 47 % in 1.3 ms,
#: level 6 to 45 % in 5.4 ms (3,600 points, 74 kB).
ZLIB_LEVEL = 1
#: Largest raw input kept (a dial-indicator record of many revolutions stays far below). [bytes]
MAX_RAW_BYTES = 256 * 2**20


def sha256_of(data: bytes) -> str:
    """Return ``sha256:<64 hex digits>`` of some bytes.

    Parameters
    ----------
    data : bytes
        The bytes.

    Returns
    -------
    str
    """
    return "sha256:" + hashlib.sha256(data).hexdigest()


@dataclass(frozen=True)
class RawInput:
    """One raw input of an inspection, kept in the store as it was read.

    Attributes
    ----------
    role : str
        What it was to the inspection: ``scan`` (CMM points), ``record`` (dial-indicator
        record), ``df_mea``, ``master_a``, ``master_b`` (a measured Δf or a master's
        error, a CSV file or the text given), ``cmm_a``, ``cmm_b`` (the scans of a
        pair's CMM masters), or ``design:<path>`` (a file the design file names, by the
        path written in it).
    name : str
        The file's name as given ("" for a value given as text).
    data : bytes
        Its contents, uncompressed.
    """

    role: str
    name: str
    data: bytes = field(repr=False)

    @cached_property
    def sha256(self) -> str:
        """``sha256:<hex>`` of the contents (computed once)."""
        return sha256_of(self.data)

    @property
    def is_file(self) -> bool:
        """Whether it was a file (else a value given as text)."""
        return bool(self.name)

    @classmethod
    def from_file(cls, role: str, path: str) -> RawInput:
        """Read a file whole.

        Parameters
        ----------
        role : str
            Its role (see the class).
        path : str
            The file as given.

        Returns
        -------
        RawInput
            ``name`` is the path as given.
        """
        from pathlib import Path

        p = Path(path)
        size = p.stat().st_size
        if size > MAX_RAW_BYTES:
            raise RecordError(
                f"{path}: {size} bytes; the store keeps raw inputs of at most"
                f" {MAX_RAW_BYTES // 2**20} MiB"
            )
        return cls(role, str(path), p.read_bytes())

    @classmethod
    def from_text(cls, role: str, text: str) -> RawInput:
        """Keep a value given as text (``--df-mea 20``): its UTF-8 bytes.

        Parameters
        ----------
        role : str
            Its role (see the class).
        text : str
            The value as given.

        Returns
        -------
        RawInput
        """
        return cls(role, "", text.encode("utf-8"))

    def compressed(self) -> bytes:
        """Return the contents as stored: zlib-compressed."""
        return zlib.compress(self.data, ZLIB_LEVEL)
