"""The built-in example designs: names, TOML text and one-line summaries.

Kept free of numpy so that ``camtol examples`` starts fast; loading an
example as a design is :func:`camtol.config.design_file.load_example`.
"""

from __future__ import annotations

import sys
from importlib import resources
from typing import Any

from camtol.exceptions import ConfigError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["example_names", "example_summary", "example_text", "parse_toml"]


def parse_toml(text: str, source: str) -> dict[str, Any]:
    """Parse TOML text; a syntax error becomes a :class:`ConfigError` naming ``source``.

    Parameters
    ----------
    text : str
        TOML document.
    source : str
        What the text is, for the error message (e.g. ``"design file 'cam.toml'"``).

    Returns
    -------
    dict
        The parsed document.

    Raises
    ------
    ConfigError
        The text is not valid TOML.
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{source} is not valid TOML: {exc}") from None


def _examples_dir() -> Any:
    return resources.files("camtol") / "data" / "examples"


def example_names() -> list[str]:
    """Names of the built-in example designs.

    Returns
    -------
    list of str
        Sorted example names (file names without ``.toml``).
    """
    return sorted(
        f.name.removesuffix(".toml") for f in _examples_dir().iterdir() if f.name.endswith(".toml")
    )


def example_text(name: str) -> str:
    """TOML text of a built-in example.

    Parameters
    ----------
    name : str
        Example name, one of :func:`example_names`.

    Returns
    -------
    str
        The example's design file.

    Raises
    ------
    ConfigError
        If there is no such example.
    """
    if name not in example_names():
        raise ConfigError(
            f"example {name!r} does not exist; available: {', '.join(example_names())}"
        )
    return str((_examples_dir() / f"{name}.toml").read_text(encoding="utf-8"))


def example_summary(name: str) -> str:
    """First line of an example's description.

    Parameters
    ----------
    name : str
        Example name, one of :func:`example_names`.

    Returns
    -------
    str
        The first line of its ``description``, or an empty string.
    """
    data = parse_toml(example_text(name), name)
    return (
        str(data.get("description", "")).strip().splitlines()[0] if data.get("description") else ""
    )
