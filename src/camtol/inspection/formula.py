"""A small, bounded, safe evaluator of formulas in the cam angle (error functions of §4).

A design file or a command-line option may give an error as a formula such as
``"18.5 + 3.5*sin(theta)"``. It is parsed with :func:`ast.parse` and checked against a
whitelist (numbers, ``theta`` [rad], ``theta_deg`` [deg], ``pi``, ``+ - * / **``, unary
``±`` and the functions ``sin cos tan exp sqrt abs`` of one argument); nothing is ever
``eval``-ed. Its size is bounded before anything else is done, so that a hostile or
accidental input (a 100,000-character chain of minus signs, 20,000 ``+`` terms) gives one
clear :class:`~camtol.exceptions.DesignError` instead of a ``RecursionError`` or
``MemoryError``:

* at most :data:`MAX_FORMULA_CHARS` characters;
* at most :data:`MAX_FORMULA_NODES` syntax-tree nodes;
* at most :data:`MAX_FORMULA_DEPTH` levels of nesting.

Evaluation is vectorised over the angle array (one numpy call per node).
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = ["MAX_FORMULA_CHARS", "MAX_FORMULA_DEPTH", "MAX_FORMULA_NODES", "Formula"]

#: Longest formula accepted. [characters]
MAX_FORMULA_CHARS = 2000
#: Most syntax-tree nodes of a formula (a 40-term Fourier series needs about 400).
MAX_FORMULA_NODES = 1000
#: Deepest nesting of a formula's syntax tree.
MAX_FORMULA_DEPTH = 60

_FUNCTIONS: dict[str, Callable[[FloatArray], FloatArray]] = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "exp": np.exp,
    "sqrt": np.sqrt,
    "abs": np.abs,
}
_CONSTANTS: dict[str, float] = {"pi": math.pi}
_VARIABLES = ("theta", "theta_deg")
_BINOPS: dict[type[ast.operator], Callable[[FloatArray, FloatArray], FloatArray]] = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
    ast.Pow: np.power,
}
_ALLOWED = (
    f"numbers, the variables {', '.join(_VARIABLES)}, pi, + - * / ** and the functions"
    f" {', '.join(sorted(_FUNCTIONS))}"
)


def _shown(text: str) -> str:
    """Quote the formula for a message, shortened to keep the message one short line."""
    return repr(text) if len(text) <= 60 else repr(text[:50]) + f"... ({len(text)} characters)"


def _check_size(tree: ast.AST, text: str) -> None:
    """Refuse a tree with too many nodes or too deep a nesting (iteratively: no recursion)."""
    nodes = 0
    stack: list[tuple[ast.AST, int]] = [(tree, 1)]
    while stack:
        node, depth = stack.pop()
        nodes += 1
        if nodes > MAX_FORMULA_NODES:
            raise DesignError(
                f"error function {_shown(text)} is too large: more than {MAX_FORMULA_NODES}"
                " terms and operators; allowed: a formula of up to that size (use a CSV table"
                " of theta_deg and µm for anything longer)"
            )
        if depth > MAX_FORMULA_DEPTH:
            raise DesignError(
                f"error function {_shown(text)} is nested more than {MAX_FORMULA_DEPTH} levels"
                " deep; allowed: a flatter formula (or a CSV table of theta_deg and µm)"
            )
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))


def _as_float(value: float) -> float:
    try:
        return float(value)
    except OverflowError:  # an integer literal beyond the float range
        return math.inf


def _check_whitelist(tree: ast.AST, text: str) -> None:
    """Reject anything but numbers, θ, pi, + − * / **, unary ±, and the allowed functions."""
    for sub in ast.walk(tree):
        ok = isinstance(
            sub,
            ast.Expression | ast.BinOp | ast.UnaryOp | ast.Load | ast.UAdd | ast.USub,
        ) or (isinstance(sub, ast.operator) and type(sub) in _BINOPS)
        if isinstance(sub, ast.Constant):
            value = sub.value
            ok = isinstance(value, int | float) and not isinstance(value, bool)
            if isinstance(value, int | float) and ok and not math.isfinite(_as_float(value)):
                raise DesignError(
                    f"error function {_shown(text)}: the number {_shown(str(sub.value))} is"
                    " not finite; allowed: finite numbers"
                )
        elif isinstance(sub, ast.Name):
            ok = sub.id in _VARIABLES or sub.id in _CONSTANTS or sub.id in _FUNCTIONS
        elif isinstance(sub, ast.Call):
            ok = (
                isinstance(sub.func, ast.Name)
                and sub.func.id in _FUNCTIONS
                and len(sub.args) == 1
                and not sub.keywords
            )
        if not ok:
            raise DesignError(
                f"error function {_shown(text)}: {type(sub).__name__} is not allowed;"
                f" allowed: {_ALLOWED}"
            )


def _evaluate(node: ast.AST, env: dict[str, FloatArray]) -> FloatArray:
    """Evaluate a checked tree (its depth is bounded, so the recursion is too)."""
    if isinstance(node, ast.Expression):
        return _evaluate(node.body, env)
    if isinstance(node, ast.Constant):
        value = node.value
        assert isinstance(value, int | float)  # checked by _check_whitelist
        return np.asarray(float(value))
    if isinstance(node, ast.Name):
        if node.id in env:
            return env[node.id]
        return np.asarray(_CONSTANTS[node.id])
    if isinstance(node, ast.UnaryOp):
        val = _evaluate(node.operand, env)
        return np.asarray(-val if isinstance(node.op, ast.USub) else val)
    if isinstance(node, ast.BinOp):
        return np.asarray(
            _BINOPS[type(node.op)](_evaluate(node.left, env), _evaluate(node.right, env))
        )
    if isinstance(node, ast.Call):
        assert isinstance(node.func, ast.Name)
        return np.asarray(_FUNCTIONS[node.func.id](_evaluate(node.args[0], env)))
    raise AssertionError("unreachable: formula was checked")  # pragma: no cover


@dataclass(frozen=True)
class Formula:
    """A checked formula in ``theta`` [rad] or ``theta_deg`` [deg].

    Build with :meth:`parse`; call with cam angles θ [rad] to evaluate it (the result may
    hold inf or NaN where the formula is not defined: the caller checks).

    Attributes
    ----------
    text : str
        The formula as given (stripped).
    """

    text: str
    _tree: ast.Expression = field(repr=False, compare=False)

    @classmethod
    def parse(cls, text: str) -> Formula:
        """Parse and check a formula.

        Parameters
        ----------
        text : str
            E.g. ``"18.5 + 3.5*sin(theta)"``; at most :data:`MAX_FORMULA_CHARS`
            characters, :data:`MAX_FORMULA_NODES` nodes and :data:`MAX_FORMULA_DEPTH`
            levels.

        Returns
        -------
        Formula
            The checked formula.

        Raises
        ------
        DesignError
            On a syntax error, anything not allowed, or a formula beyond the size bounds.
        """
        s = text.strip()
        if len(s) > MAX_FORMULA_CHARS:
            raise DesignError(
                f"error function {_shown(s)} is too long; allowed: up to {MAX_FORMULA_CHARS}"
                " characters (use a CSV table of theta_deg and µm for anything longer)"
            )
        try:
            tree = ast.parse(s, mode="eval")
        except SyntaxError as exc:
            raise DesignError(
                f"error function {_shown(s)} is not a valid formula: {exc.msg}"
            ) from None
        except (RecursionError, MemoryError):  # pragma: no cover - bounded by the length
            raise DesignError(
                f"error function {_shown(s)} is nested too deeply to be read"
            ) from None
        _check_size(tree, s)
        _check_whitelist(tree, s)
        return cls(s, tree)

    def __call__(self, theta_rad: FloatArray) -> FloatArray:
        """Evaluate at cam angles θ [rad]; inf/NaN are returned, not raised."""
        env = {"theta": theta_rad, "theta_deg": np.degrees(theta_rad)}
        with np.errstate(all="ignore"):
            return np.broadcast_to(_evaluate(self._tree, env), theta_rad.shape).astype(float)
