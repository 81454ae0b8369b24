"""Reading camtol's text inputs (design TOML, CSV tables, records): one clear line on bad bytes.

Every input file is UTF-8 text. A UTF-8 byte-order mark (written by some spreadsheet
programs) is accepted and dropped, and UTF-16 with a byte-order mark is decoded (as
:mod:`camtol.tables` does for tables); UTF-32 files and bytes that are not UTF-8 give
one :class:`~camtol.exceptions.InputFileError` (or the error class the caller chooses)
naming the file, the problem, and where it is.

While the command line runs, the files read are remembered (:func:`tracking_inputs`), so
the output layer can refuse to replace an input file (:func:`is_input_file`).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from camtol.exceptions import CamtolError, InputFileError

__all__ = ["MAX_INPUT_BYTES", "is_input_file", "read_text", "tracking_inputs"]

#: Largest input file read into memory. [bytes]
MAX_INPUT_BYTES = 512 * 1024 * 1024

_BOMS = (
    (b"\xff\xfe\x00\x00", "UTF-32 (little-endian)"),
    (b"\x00\x00\xfe\xff", "UTF-32 (big-endian)"),
)
_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
_tracked: list[set[tuple[int, int]]] = []


def _identity(path: str | Path) -> tuple[int, int] | None:
    try:
        st = os.stat(path)
    except OSError:
        return None
    return (st.st_dev, st.st_ino)


@contextmanager
def tracking_inputs() -> Iterator[None]:
    """Remember every file read by :func:`read_text` (or :func:`note_input`) inside."""
    _tracked.append(set())
    try:
        yield
    finally:
        _tracked.pop()


def note_input(path: str | Path) -> None:
    """Record ``path`` as an input of the running command (when tracking).

    Parameters
    ----------
    path : str or Path
        A file the command reads.
    """
    ident = _identity(path)
    if _tracked and ident is not None:
        _tracked[-1].add(ident)


def is_input_file(path: str | Path) -> bool:
    """Tell whether ``path`` is (the same file as) an input read by the running command.

    Parameters
    ----------
    path : str or Path
        A prospective output file; symbolic links and hard links count as the same file.

    Returns
    -------
    bool
        Whether writing it would replace an input.
    """
    ident = _identity(path)
    return bool(_tracked) and ident is not None and ident in _tracked[-1]


def read_text(
    path: str | Path,
    *,
    what: str,
    error: type[CamtolError] = InputFileError,
    max_bytes: int = MAX_INPUT_BYTES,
    label: str | None = None,
) -> str:
    """Read a UTF-8 text file (BOM allowed) or raise one clear error line.

    Parameters
    ----------
    path : str or Path
        The file.
    what : str
        What the file is, for the message, e.g. ``"design file"``,
        ``"motion.table_file"``.
    error : type
        Error class to raise (a :class:`~camtol.exceptions.CamtolError`).
    max_bytes : int
        Larger files are refused. [bytes]
    label : str, optional
        Subject of the messages instead of ``<what> '<path>'``, e.g.
        ``motion.table_file='lift.csv'`` (the field as the user wrote it).

    Returns
    -------
    str
        The text, without a leading byte-order mark.

    Raises
    ------
    CamtolError
        (``error``) The file cannot be read, is too large, is UTF-16/32, or is not UTF-8.
    """
    p = Path(path)
    subject = label if label is not None else f"{what} {str(p)!r}"
    try:
        size = p.stat().st_size
        if p.is_dir():
            raise error(f"{subject} is a directory; give a file")
        if size > max_bytes:
            raise error(
                f"{subject} is {size / 2**20:.0f} MiB; camtol reads input files of up"
                f" to {max_bytes / 2**20:.0f} MiB"
            )
        data = p.read_bytes()
    except OSError as exc:
        raise error(f"{subject} cannot be read: {exc.strerror or exc}") from None
    note_input(p)
    for bom, name in _BOMS:
        if data.startswith(bom):
            raise error(f"{subject} is {name} text; camtol reads UTF-8: save it as UTF-8")
    if data.startswith(_UTF16_BOMS):  # as the table reader (camtol.tables): BOM required
        try:
            return data.decode("utf-16")
        except UnicodeDecodeError:
            raise error(f"{subject} is not valid UTF-16 text; save it as UTF-8") from None
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise error(
            f"{subject} is not UTF-8 text: byte 0x{data[exc.start]:02x} at line {line},"
            f" column {col}; save it as UTF-8"
        ) from None
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise error(f"{subject} contains a NUL byte (line {line}): it is not a text file")
    return text
