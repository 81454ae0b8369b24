"""The ``camtol`` command line: one module per command or command group.

Each command parses its options, builds one inputs object, calls one library function
and renders the result (docs/architecture.md). :func:`main` runs it in-process and
returns the exit status (0 ok, 1 out of tolerance, 2 usage error or invalid input).
"""

from __future__ import annotations

from camtol.cli.app import cli, console_main, main

__all__ = ["cli", "console_main", "main"]
