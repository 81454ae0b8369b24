"""Errors and warnings raised by camtol.

Every error subclasses a built-in (mostly :class:`ValueError`) and its message names the
field, the value and what is allowed, so the command line can print it as one line.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "CamtolError",
    "ConfigError",
    "DesignError",
    "ExportError",
    "FieldErrors",
    "GeometryError",
    "InputFileError",
    "OutputError",
    "PressureAngleWarning",
    "RecordError",
    "ToleranceGradeError",
    "UndercutError",
]


class CamtolError(Exception):
    """Base class of every error camtol raises on purpose."""


class DesignError(CamtolError, ValueError):
    """A cam design's parameters or motion program are invalid."""


class ConfigError(DesignError):
    """A design file (TOML) is malformed or a field is missing or out of range."""


class FieldErrors(ConfigError):
    """Every problem found in the fields of one table (:mod:`camtol.config.fields`).

    ``problems`` holds each problem (its field path, kind, value and what is allowed), so
    that a caller can word them for its own table; the message lists them all.
    """

    def __init__(self, message: str, problems: tuple[Any, ...] = ()) -> None:
        super().__init__(message)
        self.problems = problems


class InputFileError(CamtolError, ValueError):
    """A data file (CSV table, measurement) cannot be read or is malformed."""


class OutputError(CamtolError, ValueError):
    """An output cannot be written: a bad destination, an OS error, or a non-finite value."""


class ToleranceGradeError(CamtolError, ValueError):
    """An unknown tolerance grade, or a grade/size ISO 286 does not define (THEORY §3.6)."""


class ExportError(CamtolError, ValueError):
    """An export was asked for in a form camtol cannot write (suffix, path, tolerance)."""


class GeometryError(DesignError):
    """The design cannot produce its motion (cusp, V ≥ 1, pressure angle ≥ 90°...)."""


class UndercutError(GeometryError):
    """The cam profile would be undercut or cusped (radius of curvature ≤ 0)."""


class PressureAngleWarning(UserWarning):
    """The pressure angle exceeds the design's limit but the cam still works."""


class RecordError(CamtolError, ValueError):
    """An inspection record or the store holding it is invalid, unreachable or too new."""
