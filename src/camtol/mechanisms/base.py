"""What every follower mechanism provides to the analytic engine (THEORY §2, §3).

A mechanism is a frozen dataclass of its nominal dimensions. Given the cam angle θ and the
motion S(θ), V(θ) (plain arrays, or :class:`~camtol.jet.Jet` for exact derivatives) it
returns the contact geometry (THEORY §2) and the closed-form sensitivities of the output
to each error source (THEORY §3): ΔS_p = sensitivity_p · Δp.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np

from camtol import jet
from camtol.jet import FloatArray, JetLike

OutputKind = Literal["translating", "oscillating"]
SourceUnit = Literal["mm", "rad"]

__all__ = ["ContactGeometry", "ErrorSource", "Mechanism", "OutputKind", "shift_angle"]


@dataclass(frozen=True)
class ErrorSource:
    """An error source of a mechanism (a tolerance key in the design file).

    Attributes
    ----------
    key : str
        Tolerance key, e.g. ``"r"``, ``"phi"``.
    description : str
        What the deviation is, e.g. "radial profile error Δr".
    unit : {"mm", "rad"}
        Internal unit of the deviation Δp.
    """

    key: str
    description: str
    unit: SourceUnit


@dataclass(frozen=True)
class ContactGeometry:
    """Contact geometry at each θ, as arrays or jets (THEORY §2).

    Attributes
    ----------
    contact_x, contact_y : JetLike
        Contact point A on the cam profile, cam frame. [mm]
    centre_x, centre_y : JetLike
        Instant centre Q = I23, cam frame. [mm]
    q : JetLike
        Signed distance q of Q from O2 as defined per mechanism in THEORY §2. [mm]
    pressure_angle : JetLike
        Pressure angle φ, signed as THEORY writes it. [rad]
    shift_angle : JetLike
        Shift angle λ between O2A and the common normal AQ (THEORY §2.5). [rad]
    extras : dict
        Mechanism-specific arrays (e.g. ``face_contact`` u, ``follower_angle`` ξ,
        ``pitch_x``/``pitch_y`` for rollers). Units in the mechanism's docstring.
    """

    contact_x: JetLike
    contact_y: JetLike
    centre_x: JetLike
    centre_y: JetLike
    q: JetLike
    pressure_angle: JetLike
    shift_angle: JetLike
    extras: dict[str, JetLike]


def shift_angle(ax: JetLike, ay: JetLike, qx: JetLike, qy: JetLike) -> JetLike:
    """Shift angle λ = asin((QA × O2A) / (|QA| |O2A|)) (THEORY §2.5, CW06 eqs. 38-42).

    Parameters
    ----------
    ax, ay : JetLike
        Contact point A in the cam frame. [mm]
    qx, qy : JetLike
        Instant centre Q in the cam frame. [mm]

    Returns
    -------
    JetLike
        λ, positive when the normal AQ is turned counterclockwise from O2A. [rad]
    """
    qax = ax - qx
    qay = ay - qy
    cross = qax * ay - qay * ax
    return jet.arcsin(cross / (jet.hypot(qax, qay) * jet.hypot(ax, ay)))


class Mechanism(ABC):
    """A cam-follower mechanism of fixed nominal dimensions."""

    #: Follower type name as used in design files.
    kind: ClassVar[str]
    #: Translating (output S in mm) or oscillating (output S in rad).
    output: ClassVar[OutputKind]
    #: Error sources understood by :meth:`sensitivities`, in report order.
    sources: ClassVar[tuple[ErrorSource, ...]]

    @abstractmethod
    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2) for cam angle, lift S and V = dS/dθ."""

    @abstractmethod
    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """ΔS per unit deviation of each source (THEORY §3), keyed by source key."""

    @abstractmethod
    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Radius of curvature ρ of the cam profile at the contact point (> 0 convex). [mm]"""

    @abstractmethod
    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """Nominal size used to look up an IT grade for a source (THEORY §3.6).

        Lengths in mm; angles in degrees (the papers' angle convention).
        """

    @abstractmethod
    def summary(self) -> list[tuple[str, str]]:
        """(parameter, value with unit) pairs for the design summary."""

    @property
    def output_unit(self) -> str:
        """Internal unit of the follower output S: ``"mm"`` or ``"rad"``."""
        return "mm" if self.output == "translating" else "rad"

    def source(self, key: str) -> ErrorSource:
        """Return the error source with this key.

        Raises
        ------
        KeyError
            If the mechanism has no such source.
        """
        for s in self.sources:
            if s.key == key:
                return s
        raise KeyError(key)


def require_positive(field: str, value: float) -> None:
    """Raise a DesignError unless ``value`` is a finite number > 0."""
    from camtol.exceptions import DesignError

    if not (math.isfinite(value) and value > 0):
        raise DesignError(f"{field}={value:g} is not allowed; it must be a positive length")


def require_finite(field: str, value: float) -> None:
    """Raise a DesignError unless ``value`` is finite."""
    from camtol.exceptions import DesignError

    if not math.isfinite(value):
        raise DesignError(f"{field}={value!r} is not allowed; it must be a finite number")


def as_array(x: JetLike) -> FloatArray:
    """Plain value array of a jet or array."""
    return np.asarray(jet.value(x), dtype=float)
