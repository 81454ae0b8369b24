"""Plain-text terminal output: wrapped paragraphs, key/value blocks and column tables.

What ``camtol analyze`` and ``camtol conjugate`` print. Every line fits the width (the
terminal's, or 80 columns in a file or a pipe), ends without trailing blanks, and carries
colour (ANSI styles) only on a terminal, never when ``NO_COLOR`` is set.

Why not rich: importing rich and laying out two tables with it took about a fifth of
``camtol analyze``'s start-up budget (issue 32: at most 2.5 times ``import numpy``). These
tables need only fixed columns beside one word-wrapped column, so they are laid out here;
rich keeps the Monte Carlo progress bar (:mod:`camtol.cli.tolerancing`).
"""

from __future__ import annotations

import os
import shutil
import sys
import textwrap
from collections.abc import Sequence
from typing import IO, Literal, NamedTuple

__all__ = ["EXTREMES_COLUMNS", "NO_BREAK", "Column", "Terminal"]

#: Width of output that is not a terminal (a file, a pipe). [characters]
PIPE_WIDTH = 80
#: Spaces between two columns of a table. [characters]
GAP = 2
#: Joins words that wrapping must keep on one line (written as a plain space).
NO_BREAK = "\u00a0"

Style = Literal["bold", "dim", "red", "bold red", "green", "yellow"]
_ANSI: dict[str, str] = {
    "bold": "\x1b[1m",
    "dim": "\x1b[2m",
    "red": "\x1b[31m",
    "bold red": "\x1b[1;31m",
    "green": "\x1b[32m",
    "yellow": "\x1b[33m",
}
_RESET = "\x1b[0m"


class Column(NamedTuple):
    """A table column: its heading, alignment, and whether long cells wrap at words."""

    heading: str
    align: Literal["left", "right"] = "left"
    wrap: bool = False


#: The columns of an extremes table (``analyze``, ``conjugate``): the quantity's name
#: wraps; each extreme's angles are whole lines of their cell.
EXTREMES_COLUMNS = (
    Column("quantity", wrap=True),
    Column("unit"),
    Column("max", "right"),
    Column("at θ"),
    Column("min", "right"),
    Column("at θ"),
)


class Terminal:
    """Where terminal output goes: its width and whether it takes colour.

    Parameters
    ----------
    file : text stream, optional
        Standard output by default.
    width : int, optional
        Characters per line; by default the terminal's width, or :data:`PIPE_WIDTH` when
        ``file`` is not a terminal.
    colour : bool, optional
        Write ANSI styles; by default only on a terminal and without ``NO_COLOR``.
    """

    def __init__(
        self, file: IO[str] | None = None, *, width: int | None = None, colour: bool | None = None
    ) -> None:
        self.file = file if file is not None else sys.stdout
        tty = bool(getattr(self.file, "isatty", lambda: False)())
        if width is None:
            width = shutil.get_terminal_size((PIPE_WIDTH, 24)).columns if tty else PIPE_WIDTH
        self.width = max(20, width)
        self.colour = (tty and "NO_COLOR" not in os.environ) if colour is None else colour

    def _styled(self, text: str, style: Style | None) -> str:
        if style is None or not self.colour or not text:
            return text
        return f"{_ANSI[style]}{text}{_RESET}"

    def write_lines(self, lines: Sequence[str], style: Style | None = None) -> None:
        """Write lines as they are (without trailing blanks), in one style.

        Parameters
        ----------
        lines : sequence of str
            Lines already fitted to :attr:`width`.
        style : str, optional
            ``"bold"``, ``"dim"``, ``"red"``, ``"bold red"``, ``"green"`` or ``"yellow"``.
        """
        self.file.write("".join(self._styled(ln.rstrip(), style) + "\n" for ln in lines))

    def paragraph(self, text: str, style: Style | None = None, *, indent: str = "") -> None:
        """Write text wrapped at words to the width, each line of ``text`` on its own.

        Parameters
        ----------
        text : str
            The text; its own line breaks are kept.
        style : str, optional
            As for :meth:`write_lines`.
        indent : str
            Prefix of every line after the first (e.g. two spaces under a note).
        """
        out: list[str] = []
        for line in text.split("\n"):
            out += wrap(line, self.width, subsequent_indent=indent) or [""]
        self.write_lines(out, style)

    def key_values(self, rows: Sequence[tuple[str, str]]) -> None:
        """Write a block of ``key  value`` rows; long values wrap under their column.

        Parameters
        ----------
        rows : sequence of (str, str)
            Name and value of each row.
        """
        self.write_lines(table_lines([Column(""), Column("", wrap=True)], rows, self.width))

    def table(
        self,
        columns: Sequence[Column],
        rows: Sequence[Sequence[str]],
        *,
        title: str | None = None,
    ) -> None:
        r"""Write a table with a heading row and a rule under it, then a blank line.

        Parameters
        ----------
        columns : sequence of Column
            Headings and layout; the wrapping columns share what the others leave.
        rows : sequence of sequence of str
            Cells; a cell may hold several lines (``"\n"``), never split further.
        title : str, optional
            Centred above the table.
        """
        lines = table_lines(columns, rows, self.width, heading=True)
        table_width = max(len(ln) for ln in lines)
        if title is not None:
            for ln in wrap(title, self.width):
                self.write_lines([ln.center(table_width).rstrip()])
        self.write_lines(lines[:1], "bold")
        self.write_lines(lines[1:] + [""])


def wrap(text: str, width: int, *, subsequent_indent: str = "") -> list[str]:
    """Wrap text at spaces to ``width``; a word longer than that is split.

    A no-break space (U+00A0) joins words that must stay on one line (``> 10° LIMIT``);
    it is written as a plain space.

    Parameters
    ----------
    text : str
        One line of text.
    width : int
        Characters per line.
    subsequent_indent : str
        Prefix of every line after the first.

    Returns
    -------
    list of str
        The lines (none for empty text).
    """
    lines = textwrap.wrap(  # breaks at ASCII whitespace only, never at U+00A0
        text,
        width,
        subsequent_indent=subsequent_indent,
        break_on_hyphens=False,
        drop_whitespace=True,
    )
    return [line.replace(NO_BREAK, " ") for line in lines]


def table_lines(
    columns: Sequence[Column],
    rows: Sequence[Sequence[str]],
    width: int,
    *,
    heading: bool = False,
) -> list[str]:
    r"""Lay out a table within ``width`` characters (see :meth:`Terminal.table`).

    The columns that do not wrap take their widest cell; the wrapping columns share the
    rest in proportion to their widest cells, each at least as wide as its longest word.

    Parameters
    ----------
    columns : sequence of Column
        Headings and layout.
    rows : sequence of sequence of str
        Cells (``"\\n"`` separates a cell's own lines).
    width : int
        Characters per line.
    heading : bool
        Start with the headings and a rule (``─``) under them.

    Returns
    -------
    list of str
        The lines, without trailing blanks.
    """
    body = [[cell.split("\n") for cell in row] for row in rows]
    heads = [[c.heading] for c in columns] if heading else None
    every = ([heads] if heads else []) + body

    def widest(i: int) -> int:
        return max((len(part) for row in every for part in row[i]), default=0)

    natural = [widest(i) for i in range(len(columns))]
    fixed = sum(n for c, n in zip(columns, natural, strict=True) if not c.wrap)
    free = width - fixed - GAP * (len(columns) - 1)
    wrapping = [i for i, c in enumerate(columns) if c.wrap]
    widths = list(natural)
    wanted = sum(natural[i] for i in wrapping)
    if wrapping and wanted > free:
        for i in wrapping:
            longest = max(
                (len(w) for row in every for part in row[i] for w in part.split(" ")), default=1
            )
            share = max(1, free * natural[i] // max(wanted, 1))
            widths[i] = min(natural[i], max(share, min(longest, free)))
    lines: list[str] = []
    for n, row in enumerate(every):
        cells = []
        for i, (col, parts) in enumerate(zip(columns, row, strict=True)):
            if col.wrap:
                parts = [w for part in parts for w in (wrap(part, widths[i]) or [""])]
            cells.append(parts)
        for k in range(max(len(parts) for parts in cells)):
            out = []
            for col, parts, w in zip(columns, cells, widths, strict=True):
                text = parts[k] if k < len(parts) else ""
                out.append(text.rjust(w) if col.align == "right" else text.ljust(w))
            lines.append((" " * GAP).join(out).rstrip())
        if heading and n == 0:
            lines.append("─" * min(width, sum(widths) + GAP * (len(columns) - 1)))
    return lines
