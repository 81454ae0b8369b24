"""One reader for every table of numbers camtol reads (lift tables, error tables, records, scans).

Shop-floor files come from spreadsheets, CMM software and data loggers, so the reader is
tolerant about form and strict about content:

- text in UTF-8 (a byte-order mark is accepted) or UTF-16 with its byte-order mark;
  anything else is an :class:`~camtol.exceptions.InputFileError` naming the file and line;
- ``#`` starts a comment (whole line or the rest of a line); blank lines are skipped;
  CRLF and LF line ends;
- cells separated by ``;``, ``,``, tabs or runs of blanks, detected from the first line
  and then required of every line;
- a header line naming the columns, with units in the names (``theta_deg``, ``lift_mm``,
  ``df_um``); a column may be renamed through ``aliases`` (``{"X": "x_mm"}``);
- every cell a finite number: a text, a missing cell, ``nan`` or ``inf`` is an error
  naming the file, the line and the column.

Parsing is vectorised (:func:`numpy.loadtxt` over the file, in bounded memory); the
slow line-by-line scan runs only to locate an error for its message.
"""

from __future__ import annotations

import codecs
import io
import math
import re
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from camtol.exceptions import InputFileError
from camtol.jet import FloatArray

__all__ = ["Table", "parse_table", "read_table"]

#: Bytes read to detect the encoding, the header and the separator.
_HEAD_BYTES = 1 << 16
#: Largest file read (a 10-million-row record is about 200 MB). [bytes]
MAX_TABLE_BYTES = 1 << 30

#: Texts up to this size are kept with the table for :meth:`Table.line_of`. [characters]
_KEEP_TEXT_CHARS = 1 << 23

_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


@dataclass(frozen=True)
class Table:
    """Columns of numbers read from a file.

    Attributes
    ----------
    source : str
        File name (or a label) used in messages.
    names : tuple of str
        Column names in file order, after ``aliases``.
    data : ndarray
        Values, shape (rows, columns). [units as the column names say]
    """

    source: str
    names: tuple[str, ...]
    data: FloatArray
    _text: str | None = field(default=None, repr=False, compare=False)

    @property
    def rows(self) -> int:
        """Number of data rows."""
        return int(self.data.shape[0])

    def __contains__(self, name: object) -> bool:
        return name in self.names

    def column(self, name: str) -> FloatArray:
        """Return one column by name.

        Parameters
        ----------
        name : str
            Column name as in :attr:`names`.

        Returns
        -------
        ndarray
            The column's values (a view). [unit of the column]

        Raises
        ------
        InputFileError
            If the table has no such column (the message lists the columns found).
        """
        try:
            return self.data[:, self.names.index(name)]
        except ValueError:
            raise InputFileError(
                f"{self.source}: no column {name!r}; found: {', '.join(self.names)}"
            ) from None

    def line_of(self, row: int) -> int:
        """File line (1-based) of data row ``row``, for error messages.

        Parameters
        ----------
        row : int
            Row index into :attr:`data`.

        Returns
        -------
        int
            Line number in the file, or 0 when it cannot be told.
        """
        text = self._text if self._text is not None else _read_text(Path(self.source))
        for i, (lineno, _) in enumerate(_data_lines(text)):
            if i == row:
                return lineno
        return 0


def _decode(raw: bytes, source: str) -> str:
    """Decode UTF-8 (with or without BOM) or UTF-16 with BOM; else a clear error."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            raise InputFileError(f"{source}: is not valid UTF-16 text") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        raise InputFileError(
            f"{source}, line {line}: is not UTF-8 text (byte 0x{raw[exc.start]:02x});"
            " save the file as UTF-8 (or UTF-16 with a byte-order mark)"
        ) from None


def _file_size(path: Path) -> int:
    """Size of a table file; refuse a missing file, a directory or one beyond the limit."""
    try:
        if path.is_dir():
            raise InputFileError(f"{path}: is a directory, not a table file")
        size = path.stat().st_size
    except OSError as exc:
        raise InputFileError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if size > MAX_TABLE_BYTES:
        raise InputFileError(
            f"{path}: the file has {size / 2**20:.0f} MiB; camtol reads tables up to"
            f" {MAX_TABLE_BYTES / 2**20:.0f} MiB"
        )
    return size


def _read_head(path: Path) -> bytes:
    try:
        with path.open("rb") as fh:
            return fh.read(_HEAD_BYTES)
    except OSError as exc:
        raise InputFileError(f"{path}: cannot be read ({exc.strerror or exc})") from None


def _read_text(path: Path) -> str:
    try:
        _file_size(path)
        raw = path.read_bytes()
        from camtol.textfile import note_input

        note_input(path)  # an output may not replace it (camtol.files)
    except IsADirectoryError:
        raise InputFileError(f"{path}: is a directory, not a table file") from None
    except OSError as exc:
        raise InputFileError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    return _decode(raw, str(path))


def _strip_comment(line: str) -> str:
    cut = line.find("#")
    return (line if cut < 0 else line[:cut]).strip()


def _data_lines(text: str) -> Iterator[tuple[int, str]]:
    """(line number, content) of the lines after the header that hold data."""
    seen_header = False
    for lineno, line in enumerate(text.splitlines(), start=1):
        content = _strip_comment(line)
        if not content:
            continue
        if not seen_header and not _is_numeric_row(_split(content, _separator(content))):
            seen_header = True
            continue
        seen_header = True
        yield lineno, content


def _separator(line: str) -> str | None:
    """Return the cell separator of a line: ``;``, ``,``, a tab, or None for blanks."""
    for sep in (";", ",", "\t"):
        if sep in line:
            return sep
    return None


def _split(line: str, sep: str | None) -> list[str]:
    cells = line.split(sep) if sep is not None else line.split()
    return [c.strip().strip('"').strip("'").strip() for c in cells]


def _is_numeric_row(cells: Sequence[str]) -> bool:
    return all(_NUMBER.match(c) or c.lower() in ("nan", "inf", "-inf", "+inf") for c in cells)


def _locate_error(
    text: str,
    source: str,
    names: Sequence[str],
    sep: str | None,
    first_line: int,
    use: Sequence[int] | None = None,
) -> InputFileError:
    """Scan line by line (error path only) for the first bad row; return its error."""
    width = len(names)
    checked = range(width) if use is None else use
    for lineno, line in enumerate(text.splitlines(), start=1):
        if lineno <= first_line:
            continue
        content = _strip_comment(line)
        if not content:
            continue
        cells = _split(content, sep)
        if len(cells) != width:
            return InputFileError(
                f"{source}, line {lineno}: expected {width} cells ({', '.join(names)}),"
                f" got {len(cells)}"
            )
        for i in checked:
            name, cell = names[i], cells[i]
            try:
                value = float(cell)
            except ValueError:
                shown = cell if len(cell) <= 40 else cell[:37] + "..."
                return InputFileError(
                    f"{source}, line {lineno}, column {name}: {shown!r} is not a number"
                )
            if not math.isfinite(value):
                return InputFileError(
                    f"{source}, line {lineno}, column {name}: {cell!r} is not allowed;"
                    " every value must be a finite number"
                )
    return InputFileError(f"{source}: the table cannot be read as numbers")


@dataclass(frozen=True)
class _Layout:
    """Header, separator and columns of a table, found from its first lines."""

    names: list[str]
    sep: str | None
    skip: int
    use: list[int] | None


def _layout(
    text: str,
    source: str,
    required: Sequence[str],
    optional: Sequence[str],
    aliases: Mapping[str, str] | None,
    default_names: Sequence[str] | None,
    what: str,
    ignore_other_columns: bool,
) -> _Layout:
    """Find the header line, the separator and the columns to read (from the head)."""
    header_at = 0
    first: list[str] | None = None
    sep: str | None = None
    for lineno, line in enumerate(text.splitlines(), start=1):
        content = _strip_comment(line)
        if content:
            sep = _separator(content)
            first, header_at = _split(content, sep), lineno
            break
    if first is None:
        raise InputFileError(f"{source}: the {what} is empty (no header and no data line)")
    if _is_numeric_row(first):
        if default_names is None:
            raise InputFileError(
                f"{source}, line {header_at}: the {what} needs a header line naming its columns"
                f" ({', '.join(required) or 'with units, e.g. theta_deg'})"
            )
        names = list(default_names)[: len(first)]
        if len(names) < len(first):
            names += [f"column_{i + 1}" for i in range(len(names), len(first))]
        skip = header_at - 1
    else:
        alias = {k.lower(): v for k, v in (aliases or {}).items()}
        names = [alias.get(n.lower(), n) for n in first]
        skip = header_at
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise InputFileError(
            f"{source}, line {header_at}: column {dupes[0]!r} is given twice; each column once"
        )
    missing = [c for c in required if c not in names]
    if missing:
        allowed = ", ".join([*required, *(f"{o} (optional)" for o in optional)])
        raise InputFileError(
            f"{source}: the {what} needs the columns {allowed}; missing {', '.join(missing)};"
            f" found: {', '.join(names)}"
        )
    use = None
    if ignore_other_columns:
        use = [names.index(c) for c in (*required, *optional) if c in names]
    return _Layout(names, sep, skip, use)


def _load(
    source_io: Any, layout: _Layout, text: Callable[[], str], source: str, what: str
) -> Table:
    """Parse the numbers with :func:`numpy.loadtxt` (vectorised, chunked over the file)."""
    names, sep, skip, use = layout.names, layout.sep, layout.skip, layout.use
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "no data": reported below
            data = np.loadtxt(
                source_io,
                delimiter=sep,
                comments="#",
                skiprows=skip,
                ndmin=2,
                dtype=float,
                quotechar='"',
                usecols=use,
            )
    except (ValueError, UnicodeDecodeError):
        raise _locate_error(text(), source, names, sep, skip, use) from None
    width = len(names) if use is None else len(use)
    if data.shape[0] == 0:
        raise InputFileError(f"{source}: the {what} has no data rows")
    if data.shape[1] != width or not np.all(np.isfinite(data)):
        raise _locate_error(text(), source, names, sep, skip, use)
    kept = tuple(names) if use is None else tuple(names[i] for i in use)
    return Table(source, kept, data)


def parse_table(
    text: str,
    *,
    source: str = "<table>",
    required: Sequence[str] = (),
    optional: Sequence[str] = (),
    aliases: Mapping[str, str] | None = None,
    default_names: Sequence[str] | None = None,
    what: str = "table",
    ignore_other_columns: bool = False,
) -> Table:
    """Parse the text of a table (see the module docstring for the accepted form).

    Parameters
    ----------
    text : str
        The whole file as text.
    source : str
        Name used in messages (the file name).
    required : sequence of str
        Columns that must be present (after ``aliases``).
    optional : sequence of str
        Columns that may be present; listed in the message when a required one is missing.
    aliases : mapping of str to str, optional
        Header names to rename, e.g. ``{"X": "x_mm"}``; matched case-insensitively.
    default_names : sequence of str, optional
        Names of the leading columns when the file has no header line (its first data
        line is all numbers). Without it a header line is required.
    what : str
        What the table is, for messages (``"lift table"``, ``"indicator record"``).
    ignore_other_columns : bool
        Read only the ``required`` and ``optional`` columns; the others may hold anything
        (an operator's name, a status text) and are not in the result.

    Returns
    -------
    Table
        The parsed columns.

    Raises
    ------
    InputFileError
        Naming the file, the line and the column of the first problem.
    """
    text = text.removeprefix("\ufeff")
    layout = _layout(
        text, source, required, optional, aliases, default_names, what, ignore_other_columns
    )
    table = _load(io.StringIO(text), layout, lambda: text, source, what)
    # Keep small texts for line look-ups in later messages; large ones are read again.
    kept = text if len(text) < _KEEP_TEXT_CHARS else None
    return Table(table.source, table.names, table.data, kept)


def read_table(
    path: str | Path,
    *,
    required: Sequence[str] = (),
    optional: Sequence[str] = (),
    aliases: Mapping[str, str] | None = None,
    default_names: Sequence[str] | None = None,
    what: str = "table",
    ignore_other_columns: bool = False,
) -> Table:
    r"""Read a table file (CSV, TXT); see the module docstring for the accepted form.

    Files up to 8 MiB are decoded whole; larger ones (up to 1 GiB) are parsed straight
    from the file by :func:`numpy.loadtxt` in chunks, so that memory stays about the size
    of the numbers read (a 10-million-row, 3-column record: about 0.3 GB and 3 s).

    Parameters
    ----------
    path : str or Path
        The file.
    required : sequence of str
        Columns that must be present (after ``aliases``).
    optional : sequence of str
        Columns that may be present (listed in messages).
    aliases : mapping of str to str, optional
        Header names to rename, matched case-insensitively.
    default_names : sequence of str, optional
        Names of the leading columns of a file without a header line.
    what : str
        What the table is, for messages.
    ignore_other_columns : bool
        Read only the ``required`` and ``optional`` columns (others may hold text).

    Returns
    -------
    Table
        The columns, with ``source`` the file name.

    Raises
    ------
    InputFileError
        The file is missing, unreadable, not text, or malformed (names file, line, column).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "lift.csv"
    >>> _ = p.write_text("# lift table\ntheta_deg, lift_mm\n0, 0\n180, 5\n")
    >>> t = read_table(p, required=["theta_deg", "lift_mm"])
    >>> t.column("lift_mm").tolist()
    [0.0, 5.0]
    """
    p = Path(path)
    size = _file_size(p)
    if size <= _KEEP_TEXT_CHARS:
        return parse_table(
            _read_text(p),
            source=str(p),
            required=required,
            optional=optional,
            aliases=aliases,
            default_names=default_names,
            what=what,
            ignore_other_columns=ignore_other_columns,
        )
    head = _read_head(p)
    utf16 = head.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE))
    encoding = "utf-16" if utf16 else "utf-8-sig"
    # The head may end inside a line or a character: only its complete lines are used.
    head_text = head.decode(encoding, errors="replace").removeprefix("\ufeff")
    head_text = head_text[: head_text.rfind("\n") + 1] or head_text
    try:
        layout = _layout(
            head_text,
            str(p),
            required,
            optional,
            aliases,
            default_names,
            what,
            ignore_other_columns,
        )
    except InputFileError:  # e.g. more comment lines than the head holds: read it whole
        return parse_table(
            _read_text(p),
            source=str(p),
            required=required,
            optional=optional,
            aliases=aliases,
            default_names=default_names,
            what=what,
            ignore_other_columns=ignore_other_columns,
        )
    try:
        with p.open(encoding=encoding, newline=None) as fh:
            return _load(fh, layout, lambda: _read_text(p), str(p), what)
    except OSError as exc:
        raise InputFileError(f"{p}: cannot be read ({exc.strerror or exc})") from None
