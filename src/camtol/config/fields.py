"""What each field of a design file's tables allows, checked in one pass.

A table is declared as a :class:`Table` of named :class:`Field` objects, each of one
kind: :class:`Number` (bounds and unit), :class:`Text`, :class:`Flag`, :class:`Choice`,
:class:`ListOf`, :class:`AnyOf`, :class:`AnyTable` or a nested :class:`Table`.
:meth:`Table.validate` returns the table as a plain ``dict`` with defaults filled in, or
raises :class:`FieldErrors` listing every problem found: a missing field, an unknown
field, or a value that is not allowed, each with the field's path and what it allows.

The rules are strict, as a design file's numbers deserve: a string is not a number, a
boolean is not a length, an integer is a number (TOML writes ``40`` for ``40.0``), and a
number is finite unless a field says otherwise. TOML has no null; a ``None`` given from
Python counts as an omitted field.

The declarations are named tuples, not dataclasses: a frozen dataclass costs about
0.7 ms to create at import, a named tuple a tenth of that, and these are immutable
values either way.

Why not pydantic: the tables are flat records of bounded numbers and short strings, and
importing pydantic and building its models cost more than importing numpy, more than a
whole ``camtol analyze`` may spend on start-up (issue 32, docs/performance.md). Declaring
the fields here keeps one place that states each bound, and the messages say what is
allowed in the field's own unit instead of a generic "Input should be ...".
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any, Literal, NamedTuple, Protocol

from camtol.exceptions import FieldErrors

__all__ = [
    "AnyOf",
    "AnyTable",
    "Choice",
    "Field",
    "FieldErrors",
    "FieldProblem",
    "Flag",
    "Integer",
    "ListOf",
    "Number",
    "Table",
    "Text",
    "describe_problem",
    "describe_problems",
    "location",
    "short_repr",
]

#: Longest value shown in a message (longer ones are shortened with "…"). [characters]
VALUE_CHARS = 80
#: Longest message of several problems (further ones are counted, not listed). [characters]
MESSAGE_CHARS = 400

Location = tuple[str | int, ...]


class FieldProblem(NamedTuple):
    """One problem with one field: where, what kind, the value given and what is allowed.

    ``allowed`` lists the known fields for an ``"unknown"`` field, and is the whole
    reason for an ``"explained"`` value (one a :class:`Choice` refuses in its own words).
    """

    loc: Location
    kind: Literal["missing", "unknown", "value", "explained"]
    value: object
    allowed: str


class _Invalid:
    """Marks a value that failed (its problem is already recorded)."""


_INVALID = _Invalid()


class Kind(Protocol):
    """A kind of value: says what it allows, and converts a value or records a problem.

    ``_convert(value, loc, problems)`` returns the value as the table holds it, or records
    a :class:`FieldProblem` at ``loc`` and returns a marker of the failure.
    """

    def describe(self) -> str: ...

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any: ...


def _refuse(problems: list[FieldProblem], loc: Location, value: object, allowed: str) -> _Invalid:
    problems.append(FieldProblem(loc, "value", value, allowed))
    return _INVALID


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


class Number(NamedTuple):
    """A real number (an integer is accepted and returned as a float) within bounds."""

    minimum: float = -math.inf
    maximum: float = math.inf
    exclusive_minimum: bool = False
    exclusive_maximum: bool = False
    unit: str = ""
    #: False lets ±inf and NaN through (the caller checks them with its own message).
    finite: bool = True

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        lo = "" if self.minimum == -math.inf else f"{'>' if self.exclusive_minimum else '≥'} "
        hi = "" if self.maximum == math.inf else f"{'<' if self.exclusive_maximum else '≤'} "
        bounds = []
        if lo:
            bounds.append(f"{lo}{self.minimum:g}")
        if hi:
            bounds.append(f"{hi}{self.maximum:g}")
        text = "a finite number" if self.finite else "a number"
        if bounds:
            text += " " + " and ".join(bounds)
        return f"{text} {self.unit}" if self.unit else text

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if not _is_number(value):
            return _refuse(problems, loc, value, self.describe())
        x = float(value)  # type: ignore[arg-type]
        if math.isnan(x):
            return x if not self.finite else _refuse(problems, loc, value, self.describe())
        if self.finite and math.isinf(x):
            return _refuse(problems, loc, value, self.describe())
        below = x <= self.minimum if self.exclusive_minimum else x < self.minimum
        above = x >= self.maximum if self.exclusive_maximum else x > self.maximum
        if below or above:
            return _refuse(problems, loc, value, self.describe())
        return x


class Integer(NamedTuple):
    """A whole number (not a boolean, not a float) of at least ``minimum``."""

    minimum: int | None = None

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return "a whole number" + ("" if self.minimum is None else f" ≥ {self.minimum}")

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if not isinstance(value, int) or isinstance(value, bool):
            return _refuse(problems, loc, value, self.describe())
        if self.minimum is not None and value < self.minimum:
            return _refuse(problems, loc, value, self.describe())
        return value


class Text(NamedTuple):
    """A string of ``min_chars`` to ``max_chars`` characters."""

    min_chars: int = 0
    max_chars: int | None = None

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        if self.max_chars is not None:
            return f"a string of {self.min_chars} to {self.max_chars} characters"
        return "a non-empty string" if self.min_chars else "a string"

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if not isinstance(value, str) or len(value) < self.min_chars:
            return _refuse(problems, loc, value, self.describe())
        if self.max_chars is not None and len(value) > self.max_chars:
            return _refuse(problems, loc, value, self.describe())
        return value


class Flag(NamedTuple):
    """``true`` or ``false`` (not 0 or 1)."""

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return "true or false"

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        return value if isinstance(value, bool) else _refuse(problems, loc, value, "true or false")


class Choice(NamedTuple):
    """One of the listed strings; ``explain`` gives a value its own message (a retired one)."""

    values: tuple[str, ...]
    explain: Mapping[str, str] = MappingProxyType({})
    #: What a value is, for messages (``"motion law"``: "a known motion law: ...").
    noun: str = ""

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        listed = ", ".join(self.values)
        return f"a known {self.noun}: {listed}" if self.noun else f"one of {listed}"

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if isinstance(value, str) and value in self.values:
            return value
        if isinstance(value, str) and value in self.explain:
            problems.append(FieldProblem(loc, "explained", value, self.explain[value]))
            return _INVALID
        return _refuse(problems, loc, value, self.describe())


class ListOf(NamedTuple):
    """An array whose every item is of one kind."""

    item: Kind

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return f"an array of items, each {self.item.describe()}"

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if isinstance(value, str | bytes | Mapping) or not isinstance(value, Sequence):
            return _refuse(problems, loc, value, self.describe())
        before = len(problems)
        out = [self.item._convert(v, (*loc, i), problems) for i, v in enumerate(value)]
        return _INVALID if len(problems) > before else out


class AnyOf(NamedTuple):
    """The first of several kinds the value is (e.g. a number of µm, or a formula string)."""

    kinds: tuple[Kind, ...]

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return " or ".join(k.describe() for k in self.kinds)

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        for kind in self.kinds:
            trial: list[FieldProblem] = []
            out = kind._convert(value, loc, trial)
            if not trial:
                return out
        return _refuse(problems, loc, value, self.describe())


class AnyTable(NamedTuple):
    """A table whose fields another module checks (returned as a ``dict``)."""

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return "a table"

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        return (
            dict(value) if isinstance(value, Mapping) else _refuse(problems, loc, value, "a table")
        )


_REQUIRED: Any = object()


class Field(NamedTuple):
    """A named field: its kind, and its default (none: the field is required)."""

    kind: Kind
    default: Any = _REQUIRED

    @property
    def required(self) -> bool:
        """Whether the field has no default (the file must give it)."""
        return self.default is _REQUIRED


class Table(NamedTuple):
    """A TOML table of named fields; unknown fields are refused."""

    fields: Mapping[str, Field]

    def describe(self) -> str:
        """Say what the kind allows, in words (for messages)."""
        return "a table"

    def validate(self, raw: object, prefix: str = "") -> dict[str, Any]:
        """Return the table with defaults filled in.

        Parameters
        ----------
        raw : object
            The table as read from TOML (a mapping; anything else is a problem).
        prefix : str
            Where the table sits in the file (``"follower"``), written before every
            field's path in the message.

        Returns
        -------
        dict
            Every declared field: the value given, or the field's default.

        Raises
        ------
        FieldErrors
            Every problem found, each naming its field path (a :class:`ConfigError`:
            one line, ``prefix`` before each path; ``problems`` relative to the table).
        """
        problems: list[FieldProblem] = []
        out = self._convert(raw, (), problems)
        if problems:
            raise FieldErrors(describe_problems(problems, prefix), tuple(problems))
        assert isinstance(out, dict)
        return out

    def _convert(self, value: object, loc: Location, problems: list[FieldProblem]) -> Any:
        if not isinstance(value, Mapping):
            return _refuse(problems, loc, value, "a table")
        before = len(problems)
        out: dict[str, Any] = {}
        for name, spec in self.fields.items():
            given = value.get(name)
            if given is None:
                if spec.required:
                    allowed = spec.kind.describe()
                    problems.append(FieldProblem((*loc, name), "missing", None, allowed))
                else:  # a fresh copy: a default table or list is never shared
                    default = spec.default
                    out[name] = (
                        type(default)(default) if isinstance(default, dict | list) else default
                    )
                continue
            out[name] = spec.kind._convert(given, (*loc, name), problems)
        for name in value:
            if name not in self.fields:
                allowed = ", ".join(self.fields)
                problems.append(FieldProblem((*loc, str(name)), "unknown", value[name], allowed))
        return _INVALID if len(problems) > before else out


def short_repr(value: object) -> str:
    """Repr of a value, at most :data:`VALUE_CHARS` characters.

    Parameters
    ----------
    value : object
        What the file gave.

    Returns
    -------
    str
        ``repr(value)``, shortened with "…" when longer.
    """
    text = repr(value)
    return text if len(text) <= VALUE_CHARS else text[: VALUE_CHARS - 1] + "…"


def location(loc: Location, prefix: str = "") -> str:
    """Write a field's path as the file writes it.

    Parameters
    ----------
    loc : tuple of str and int
        Table and field names, and array indices: ``("segments", 2, "lift_mm")``.
    prefix : str
        The enclosing table (``"motion"``; a trailing dot is ignored).

    Returns
    -------
    str
        ``motion.segments[2].lift_mm``.
    """
    text = prefix.rstrip(".")
    for part in loc:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text = f"{text}.{part}" if text else part
    return text


def describe_problem(problem: FieldProblem, prefix: str = "") -> str:
    """One problem in words: the field, the value and what is allowed.

    Parameters
    ----------
    problem : FieldProblem
        The problem.
    prefix : str
        The enclosing table, prefixed to the field's path.

    Returns
    -------
    str
        E.g. ``operation.speed_rpm=-3 is not allowed; give a finite number > 0 ...``.
    """
    where = location(problem.loc, prefix)
    if not where:  # the table itself (given from Python as something else)
        return f"{short_repr(problem.value)} is not allowed; give {problem.allowed}"
    if problem.kind == "missing":
        return f"{where} is missing; give {problem.allowed}"
    if problem.kind == "unknown":
        return f"{where} is not a known field; allowed: {problem.allowed}"
    if problem.kind == "explained":
        return f"{where}={short_repr(problem.value)}: {problem.allowed}"
    return f"{where}={short_repr(problem.value)} is not allowed; give {problem.allowed}"


def describe_problems(problems: Sequence[FieldProblem], prefix: str = "") -> str:
    """Every problem on one line of at most :data:`MESSAGE_CHARS` (the rest counted).

    Parameters
    ----------
    problems : sequence of FieldProblem
        The problems, in the order found.
    prefix : str
        The enclosing table, prefixed to each field's path.

    Returns
    -------
    str
        The problems joined by "; ", then "and N more problem(s)" when too long.
    """
    parts = [describe_problem(p, prefix) for p in problems]
    if not parts:
        return "no problem"
    out = parts[0]
    for n, part in enumerate(parts[1:], start=1):
        last = n == len(parts) - 1
        room = MESSAGE_CHARS - (0 if last else len("; and 999 more problem(s)"))
        if len(out) + len(part) + 2 > room:
            return f"{out}; and {len(parts) - n} more problem(s)"
        out += "; " + part
    return out
