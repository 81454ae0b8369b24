"""The rich console commands print their tables to (standard output)."""

from __future__ import annotations

import sys
from typing import Any

__all__ = ["terminal_console"]


class _TrimmedLines:
    """A text stream that writes whole lines without their trailing blanks.

    rich pads every line of a table to the table's width; on a terminal that is invisible,
    in a file or a pipe it leaves trailing blanks that show in every diff of two runs.
    """

    def __init__(self, out: Any) -> None:
        self._out = out
        self._pending = ""

    def write(self, text: str) -> int:
        *lines, self._pending = (self._pending + text).split("\n")
        for line in lines:
            self._out.write(line.rstrip(" ") + "\n")
        return len(text)

    def flush(self) -> None:
        if self._pending:
            self._out.write(self._pending.rstrip(" "))
            self._pending = ""
        self._out.flush()

    def isatty(self) -> bool:
        return False


def terminal_console() -> Any:
    """Return a rich console for standard output.

    On a terminal it takes the terminal's width; in a file or a pipe 80 columns, without
    colour, each line written without trailing blanks.
    """
    from rich.console import Console

    if sys.stdout.isatty():
        return Console()
    return Console(width=80, file=_TrimmedLines(sys.stdout))  # type: ignore[arg-type]
