"""Design-level error sources: errors of the cam's mounting, not of a follower (THEORY §3).

A follower's own error sources (its dimensions, the profile errors Δr and Δn) are declared
by its mechanism class (:attr:`camtol.mechanisms.base.Mechanism.sources`). Some errors
belong to no follower: the angular phase of the cam on its shaft, the eccentricity of the
cam's bore. They are declared here once, as :class:`DesignSource` objects in a registry,
and every design accepts them in ``[tolerances]`` next to its follower's sources, without
any mechanism knowing of them.

A design-level source gives what the analytic engine needs (the closed-form sensitivity
ΔS/Δp as a jet over θ, so that ΔV and ΔA follow) and what exact re-simulation needs (the
exact output with the deviation applied), so that ``camtol verify`` and Monte Carlo in
exact mode check it like any other source.

Implemented:

* ``phase``: angular phase error Δθ0 of the cam on its shaft [rad; ``phase_deg`` in the
  design file]. The cam sits late by Δθ0 (turned clockwise, against the cam's rotation,
  relative to the shaft's angle reference), so the follower sees the nominal cam at
  θ − Δθ0: S*(θ) = S(θ − Δθ0) exactly, and to first order ΔS = −V·Δθ0 (V = dS/dθ), hence
  ΔV = −A·Δθ0 and ΔA = −J·Δθ0. It has no IT grade (it is not a size).

Registering another source (e.g. the cam-pivot eccentricity) means subclassing
:class:`DesignSource` and calling :func:`register_design_source`; no mechanism changes.
"""

from __future__ import annotations

import dataclasses
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from camtol.design.motion import MotionProgram
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, JetLike
from camtol.mechanisms.base import ErrorSource, Mechanism

__all__ = [
    "DESIGN_SOURCES",
    "AngularPhase",
    "AsMade",
    "DesignSource",
    "apply_source",
    "can_apply",
    "design_source",
    "register_design_source",
]


@dataclass(frozen=True)
class AsMade:
    """A cam and its follower as made: what exact re-simulation applies (THEORY §3, §5).

    Every error source, of the follower or of the design, moves one of these; the
    contact engine then follows the cam as made
    (:func:`camtol.contact.as_made.follow_as_made`). ``camtol verify`` applies one source
    at a time, Monte Carlo in exact mode all of a sample's at once.

    Attributes
    ----------
    mechanism : Mechanism
        The follower as made (its parameter sources applied,
        :meth:`~camtol.mechanisms.base.Mechanism.perturbed`).
    radial_error_mm, normal_error_mm : float or None
        Constant profile errors Δr, Δn of the cam (None: not applied). [mm]
    phase_rad : float
        The cam sits late on its shaft by Δθ0: the follower sees it at θ − Δθ0. [rad]
    """

    mechanism: Mechanism
    radial_error_mm: float | None = None
    normal_error_mm: float | None = None
    phase_rad: float = 0.0


class DesignSource(ABC):
    """An error source of a design that is not a parameter of its follower.

    Attributes
    ----------
    source : ErrorSource
        Key, description and internal unit (``parameter`` is None).
    """

    source: ErrorSource

    @property
    def key(self) -> str:
        """Tolerance key, e.g. ``"phase"``."""
        return self.source.key

    @abstractmethod
    def sensitivity(
        self, mechanism: Mechanism, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> JetLike:
        """Closed-form ΔS per unit deviation, as a jet over θ (THEORY §3).

        Parameters
        ----------
        mechanism : Mechanism
            The follower (for sources whose effect depends on it).
        theta : JetLike
            ``Jet.variable(θ)``, or θ itself for values without derivatives. [rad]
        lift, velocity : JetLike
            Jets (S, V, A) and (V, A, J) of the motion, or S and V. [output unit per rad^k]

        Returns
        -------
        JetLike
            ΔS/Δp with its first two θ-derivatives (given jets), else its values.
            [output unit per mm or per rad]
        """

    @abstractmethod
    def exact_lift(
        self,
        mechanism: Mechanism,
        program: MotionProgram,
        theta_rad: FloatArray,
        delta: float,
        *,
        left_limit: ArrayLike | None = None,
    ) -> FloatArray:
        """Exact follower output S*(θ) with deviation ``delta`` applied (S = 0 nominal).

        Parameters
        ----------
        mechanism : Mechanism
            The nominal follower.
        program : MotionProgram
            The nominal motion program.
        theta_rad : ndarray
            Cam angles. [rad]
        delta : float
            Deviation Δp. [mm or rad]
        left_limit : array_like of bool, optional
            Rows taking left limits at segment boundaries.

        Returns
        -------
        ndarray
            S*(θ). [mm, or rad for an oscillating follower]
        """

    @abstractmethod
    def perturb(self, as_made: AsMade, delta: float) -> AsMade:
        """Apply deviation ``delta`` of this source to a cam as made (exact re-simulation).

        Parameters
        ----------
        as_made : AsMade
            The cam and follower with the other sources already applied.
        delta : float
            Deviation Δp. [mm or rad]

        Returns
        -------
        AsMade
        """

    def nominal_size(self, mechanism: Mechanism, max_radius_mm: float) -> float:
        """Nominal size for an IT grade (THEORY §3.6); by default there is none.

        Parameters
        ----------
        mechanism : Mechanism
            The follower.
        max_radius_mm : float
            Maximum radial dimension of the cam. [mm]

        Returns
        -------
        float
            Nominal size. [mm, or deg for an angle]

        Raises
        ------
        ValueError
            If the source takes no IT grade (then give an explicit deviation).
        """
        raise ValueError(f"source {self.key!r} takes no IT grade")


class AngularPhase(DesignSource):
    """Angular phase error Δθ0 of the cam on its shaft: S*(θ) = S(θ − Δθ0) (module doc)."""

    source = ErrorSource("phase", "angular phase error Δθ0 of the cam on its shaft", "rad")

    def sensitivity(
        self, mechanism: Mechanism, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> JetLike:
        """ΔS/Δθ0 = −V, with derivatives −A and −J. [output unit per rad]"""
        return -velocity

    def exact_lift(
        self,
        mechanism: Mechanism,
        program: MotionProgram,
        theta_rad: FloatArray,
        delta: float,
        *,
        left_limit: ArrayLike | None = None,
    ) -> FloatArray:
        """S(θ − Δθ0): the nominal program evaluated at the shifted angle."""
        theta = np.asarray(theta_rad, dtype=float)
        return np.asarray(program.evaluate(theta - delta, left_limit=left_limit).lift)

    def perturb(self, as_made: AsMade, delta: float) -> AsMade:
        """Turn the cam late by Δθ0 on its shaft, whatever the other errors."""
        return dataclasses.replace(as_made, phase_rad=as_made.phase_rad + delta)


#: Design-level error sources by tolerance key (see :func:`register_design_source`).
DESIGN_SOURCES: dict[str, DesignSource] = {}


def register_design_source(source: DesignSource) -> DesignSource:
    """Add a design-level source to :data:`DESIGN_SOURCES` (its key must be new).

    Parameters
    ----------
    source : DesignSource
        The source.

    Returns
    -------
    DesignSource
        ``source``, so that this can be used on an instance at module level.

    Raises
    ------
    ValueError
        If a source with the same key is already registered.
    """
    if source.key in DESIGN_SOURCES:
        raise ValueError(f"design-level source {source.key!r} is already registered")
    DESIGN_SOURCES[source.key] = source
    return source


def design_source(key: str) -> DesignSource | None:
    """Return the design-level source with this key, or None.

    Parameters
    ----------
    key : str
        Tolerance key.

    Returns
    -------
    DesignSource or None
        The registered source.
    """
    return DESIGN_SOURCES.get(key)


register_design_source(AngularPhase())


def can_apply(mechanism: Mechanism, key: str) -> bool:
    """Tell whether error source ``key`` can be re-simulated exactly on this follower.

    Parameters
    ----------
    mechanism : Mechanism
        The nominal follower.
    key : str
        Tolerance key.

    Returns
    -------
    bool
        True for a design-level source, a profile error and a follower parameter.
    """
    if key in DESIGN_SOURCES:
        return True
    src = next((s for s in mechanism.sources if s.key == key), None)
    return src is not None and (src.profile is not None or src.parameter is not None)


def apply_source(as_made: AsMade, key: str, delta: float) -> AsMade:
    """Apply error source ``key`` at deviation ``delta`` to a cam as made.

    The source says how: a design-level source by :meth:`DesignSource.perturb`, a profile
    error (:attr:`~camtol.mechanisms.base.ErrorSource.profile`) by adding to the cam's
    radial or normal error, a follower dimension
    (:attr:`~camtol.mechanisms.base.ErrorSource.parameter`) by
    :meth:`~camtol.mechanisms.base.Mechanism.perturbed`.

    Parameters
    ----------
    as_made : AsMade
        The cam and follower so far (start from ``AsMade(design.mechanism)``).
    key : str
        Tolerance key of the source.
    delta : float
        Deviation. [mm or rad]

    Returns
    -------
    AsMade

    Raises
    ------
    DesignError
        A source the follower does not have or that cannot be re-simulated exactly.
    """
    design_level = DESIGN_SOURCES.get(key)
    if design_level is not None:
        return design_level.perturb(as_made, delta)
    src = next((s for s in as_made.mechanism.sources if s.key == key), None)
    if src is not None and src.profile == "radial":
        return dataclasses.replace(
            as_made, radial_error_mm=(as_made.radial_error_mm or 0.0) + delta
        )
    if src is not None and src.profile == "normal":
        return dataclasses.replace(
            as_made, normal_error_mm=(as_made.normal_error_mm or 0.0) + delta
        )
    if src is not None and src.parameter is not None:
        return dataclasses.replace(as_made, mechanism=as_made.mechanism.perturbed(key, delta))
    raise DesignError(f"source {key!r} cannot be re-simulated exactly")
