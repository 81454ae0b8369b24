"""The statistical tolerance model of a design: one distribution per source + processes.

A design file may carry an optional ``[statistics]`` table (docs/tolerancing.md)::

    [statistics]
    default = { distribution = "normal", cp = 1.0 }      # every source not listed
    e = { distribution = "uniform" }
    r = { distribution = "normal", cp = 1.33, bias_um = 2.0 }
    [statistics.profile_process]
    target = "r"            # or "n"
    sigma_um = 2.0
    correlation_deg = 10.0  # or: harmonics = [{ order = 2, amplitude_um = 1.5 }]

A conjugate pair may give each cam its own process (``[statistics.profile_process_a]``,
``[statistics.profile_process_b]``, same fields); ``profile_process`` on a pair means the
same process on both cams, sampled independently.

The table is validated when the design file is loaded
(:mod:`camtol.config.statistics_table`, the file-format edge) and kept on the design as a
:class:`StatisticalModel` (``CamDesign.extras["statistics"]``) that also remembers the
table as written, so the design's identity is that of its file. A design without the
table gets the defaults.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from camtol import _compat
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.tolerancing.distributions import SourceDistribution
from camtol.tolerancing.processes import ProfileProcess

__all__ = ["StatisticalModel", "statistical_model"]


@dataclass(frozen=True)
class StatisticalModel:
    """Distributions of a design's error sources and an optional profile process.

    Parameters
    ----------
    sources : mapping of str to SourceDistribution
        Per-source distributions (keys: tolerance keys of the design).
    default : SourceDistribution
        Distribution of every source not in ``sources`` (normal, Cp = 1, truncated).
    process : ProfileProcess, optional
        Random periodic profile error added to the sampled sources. On a conjugate
        pair: the same process on both cams, sampled independently for each.
    cam_processes : mapping of str to ProfileProcess
        A conjugate pair's process per cam, by cam letter (``profile_process_a``,
        ``profile_process_b``); a cam listed here does not take ``process``.
    table : tuple of (str, object)
        The design file's ``[statistics]`` table it was read from, for the design's
        identity; empty when built in Python.
    """

    sources: Mapping[str, SourceDistribution] = field(default_factory=dict)
    default: SourceDistribution = SourceDistribution()
    process: ProfileProcess | None = None
    cam_processes: Mapping[str, ProfileProcess] = field(default_factory=dict)
    table: tuple[tuple[str, Any], ...] = field(default=(), compare=False, repr=False)

    def to_mapping(self) -> dict[str, Any]:
        """Return the ``[statistics]`` table this model was read from (empty if none).

        Returns
        -------
        dict
            As written in the design file: part of the design's identity
            (:attr:`camtol.design.cam_design.CamDesign.content_hash`).
        """
        return dict(self.table)

    def process_of(self, letter: str) -> ProfileProcess | None:
        """Return the profile process of one cam of a pair (its own, else the common one).

        Parameters
        ----------
        letter : str
            The cam's letter.
        """
        return self.cam_processes.get(letter, self.process)

    def distribution(self, key: str) -> SourceDistribution:
        """Return the distribution of a source.

        Parameters
        ----------
        key : str
            Tolerance key, e.g. ``"e"``.
        """
        return self.sources.get(key, self.default)


def statistical_model(design: CamDesign) -> StatisticalModel:
    """Return the statistical model of a design: its ``[statistics]`` table or defaults.

    Parameters
    ----------
    design : CamDesign
        A design; a design file's ``[statistics]`` table is validated when the file is
        loaded (:mod:`camtol.config.statistics_table`) and kept as a
        :class:`StatisticalModel` in ``design.extras["statistics"]``.

    Returns
    -------
    StatisticalModel
        Normal, Cp = 1, truncated at ±Δ for every source not described.

    Raises
    ------
    DesignError
        If ``design.extras["statistics"]`` holds something else (a raw table put there
        in Python: build it with :func:`camtol.config.statistics_table.parse_statistics`).
    """
    model = design.extras.get("statistics")
    if model is None:
        return StatisticalModel()
    if isinstance(model, StatisticalModel):
        return model
    raise DesignError(
        f"design {design.name!r}: extras['statistics'] is a {type(model).__name__}, not a"
        " validated model; read it with camtol.config.statistics_table.parse_statistics"
    )


def __getattr__(name: str) -> Any:
    """Return ``parse_statistics``, moved to :mod:`camtol.config.statistics_table`."""
    return _compat.moved_name(__name__, name)
