"""Every public function documents every parameter (STYLE point 13).

The check walks every module of ``camtol`` (except ``camtol.__main__``) and collects the
functions named in the module's ``__all__`` and defined there, plus the public methods
(class and static methods included) defined in classes named in ``__all__`` and defined
there. Each one that takes parameters (``self``/``cls``, ``*args`` and ``**kwargs`` aside)
must have a numpydoc ``Parameters`` section listing every parameter as an entry
(``name : type``; ``a, b : float`` documents both).

Policy: a method that overrides a method of a base class (the nearest one in the MRO that
defines it) is exempt when the base's docstring documents all of the base's parameters and
every parameter of the override among them: the override inherits the base's
documentation, as numpydoc tools do. An override that adds or renames a parameter must
document its own.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from collections.abc import Callable, Iterator
from typing import Any

import pytest

import camtol

_SECTION = "Parameters\n----------"
_NEXT_SECTION = re.compile(r"\n\n[A-Z][a-z]+\n-+")
_ENTRY = re.compile(r"^(\w[\w, ]*?)\s*:")


def _parameters(fn: Callable[..., Any]) -> list[str]:
    """Names of the parameters that must be documented."""
    return [
        p.name
        for p in inspect.signature(fn).parameters.values()
        if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)
    ]


def _documented(fn: Callable[..., Any]) -> set[str] | None:
    """Names listed in the Parameters section, or None when there is no section."""
    doc = inspect.cleandoc(fn.__doc__ or "")
    parts = doc.split(_SECTION, 1)
    if len(parts) < 2:
        return None
    body = _NEXT_SECTION.split(parts[1])[0]
    names: set[str] = set()
    for line in body.splitlines():
        match = _ENTRY.match(line)
        if match:
            names |= {x.strip() for x in match.group(1).split(",")}
    return names


def _undocumented(fn: Callable[..., Any]) -> list[str]:
    """Parameters of ``fn`` missing from its own Parameters section."""
    params = _parameters(fn)
    if not params:
        return []
    names = _documented(fn) or set()
    return [p for p in params if p not in names]


def _function(attr: object) -> Callable[..., Any] | None:
    """The plain function of a method, classmethod or staticmethod; None otherwise."""
    if isinstance(attr, classmethod | staticmethod):
        attr = attr.__func__
    return attr if inspect.isfunction(attr) else None


def _inherits_docs(cls: type, name: str) -> bool:
    """True when the nearest base class defining ``name`` documents all its parameters.

    The override's own parameters must also be among those the base documents, so an
    override that adds or renames a parameter still has to document it.
    """
    own = _function(vars(cls)[name])
    for base in cls.__mro__[1:]:
        meth = _function(vars(base).get(name))
        if meth is not None and own is not None:
            if _undocumented(meth):
                return False
            documented = _documented(meth) or set()
            return set(_parameters(own)) <= documented
    return False


def _targets() -> Iterator[tuple[str, Callable[..., Any]]]:
    """(qualified name, function) of every public function and method to check."""
    for info in pkgutil.walk_packages(camtol.__path__, "camtol."):
        if info.name == "camtol.__main__":
            continue
        mod = importlib.import_module(info.name)
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name, None)
            if getattr(obj, "__module__", None) != mod.__name__:
                continue
            if inspect.isfunction(obj):
                yield f"{mod.__name__}.{name}", obj
            elif inspect.isclass(obj):
                for mname, attr in vars(obj).items():
                    meth = _function(attr)
                    if mname.startswith("_") or meth is None:
                        continue
                    if _inherits_docs(obj, mname):
                        continue
                    yield f"{mod.__name__}.{name}.{mname}", meth


_TARGETS = sorted(_targets(), key=lambda t: t[0])


def test_targets_found() -> None:
    """The walk finds a plausible number of public functions."""
    assert len(_TARGETS) > 50


@pytest.mark.parametrize("fn", [fn for _, fn in _TARGETS], ids=[qn for qn, _ in _TARGETS])
def test_parameters_documented(fn: Callable[..., Any]) -> None:
    """Every parameter appears in the numpydoc Parameters section."""
    missing = _undocumented(fn)
    assert not missing, f"{fn.__qualname__} does not document: {', '.join(missing)}"


def _example(a: float, b: float, *args: float, c: int = 0, **kwargs: float) -> None:
    """Example for the checker.

    Parameters
    ----------
    a, b : float
        Two lengths. [mm]

    Returns
    -------
    None
    """


def test_checker_reads_numpydoc() -> None:
    """Combined entries count for both names; ``*args``/``**kwargs`` are not required."""
    assert _documented(_example) == {"a", "b"}
    assert _undocumented(_example) == ["c"]
