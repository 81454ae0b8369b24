"""What every follower mechanism provides to the analytic engine (THEORY §2, §3).

A mechanism is a frozen dataclass of its nominal dimensions. Given the cam angle θ and the
motion S(θ), V(θ) (plain arrays, or :class:`~camtol.jet.Jet` for exact derivatives) it
returns the contact geometry (THEORY §2) and the closed-form sensitivities of the output
to each error source (THEORY §3): ΔS_p = sensitivity_p · Δp.

Why one module: it is the contract between a follower and the rest of camtol: the
:class:`Mechanism` interface with the types its methods exchange (:class:`ErrorSource`,
:class:`ContactGeometry`, :func:`shift_angle`), the checks every follower's
``__post_init__`` calls, and the registry of follower types. Every follower module imports
its base from here, and nothing here is about one follower.
"""

from __future__ import annotations

import dataclasses
import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar, Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from camtol import jet
from camtol.jet import FloatArray, JetLike
from camtol.mechanisms.elements import (
    ContactElement,
    OscillatingFace,
    Outline,
    RollerGuide,
    TranslatingFace,
    face_segment,
    point,
)
from camtol.mechanisms.spec import (
    Parameter,
    length,
    offset,
)

OutputKind = Literal["translating", "oscillating"]
SourceUnit = Literal["mm", "rad"]
M = TypeVar("M", bound="Mechanism")
_MechanismType = TypeVar("_MechanismType", bound="type[Mechanism]")

__all__ = [
    "FOLLOWER_TYPES",
    "ContactElement",
    "ContactGeometry",
    "ErrorSource",
    "Mechanism",
    "OscillatingFace",
    "Outline",
    "OutputKind",
    "Parameter",
    "RollerGuide",
    "TranslatingFace",
    "length",
    "offset",
    "register_follower",
    "shift_angle",
    "face_segment",
    "point",
]


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
    parameter : str or None
        Name of the mechanism's dataclass field that this source perturbs (a follower
        dimension, e.g. ``"roller_radius_mm"``), or None for sources that are not a
        parameter of the mechanism (profile errors ``r``, ``n``; design-level sources of
        :mod:`camtol.design.sources`). :meth:`Mechanism.perturbed` uses it.
    profile : {"radial", "normal"} or None
        For a profile error of the cam: the direction in which it moves the profile, how
        exact re-simulation applies it (:func:`camtol.design.sources.apply_source`). By
        the design files' convention the keys ``r`` and ``n`` are the radial and normal
        profile errors of every follower type, so a source so named that perturbs no
        parameter is one unless stated otherwise.
    """

    key: str
    description: str
    unit: SourceUnit
    parameter: str | None = None
    profile: Literal["radial", "normal"] | None = None

    def __post_init__(self) -> None:
        if self.profile is None and self.parameter is None:
            conventional = {"r": "radial", "n": "normal"}.get(self.key)
            if conventional is not None:
                object.__setattr__(self, "profile", conventional)


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
        ``pitch_x``/``pitch_y`` for rollers). Units in the mechanism's docstring. A
        ``radius`` |O2A| in closed form [mm] is what the analytic engine reports instead
        of the norm of the contact point.
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
    #: Dimensions as written in the ``[follower]`` table (empty: not a file type).
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    #: One-line name of the follower for summaries, e.g. "translating roller".
    title: ClassVar[str] = ""
    #: Closed form of the radial-error factor ΔS_r/Δr shown by ``analyze`` (THEORY §3).
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr"
    #: The contact point moves along a flat face (``analyze`` reports u).
    has_face: ClassVar[bool] = False
    #: Position in lists of follower types (messages, documentation).
    listing_order: ClassVar[int] = 100
    #: :meth:`error_sensitivities` and :meth:`curvature_radius` depend on the motion
    #: state (S, V, A, J) alone, not on θ, and :meth:`contact` at θ is its geometry at
    #: θ = 0 turned by θ. True of every follower whose frame turns uniformly against the
    #: cam (kinematic inversion, THEORY §0): what the follower sees does not depend on
    #: where the cam is. The engine then evaluates them once per dwell and turns the
    #: points (tested for every follower type that sets it).
    motion_only: ClassVar[bool] = False
    #: Angles the analytic engine (:mod:`camtol.analysis.engine`) evaluates at once: the
    #: intermediate arrays of :meth:`contact` and :meth:`error_sensitivities` at this
    #: length should fit in a core's cache. A follower with lean formulas takes longer
    #: chunks, so fewer numpy calls (measured by ``bench/bench_analyze.py``).
    chunk_angles: ClassVar[int] = 16_384

    @classmethod
    def from_parameters(cls: type[M], values: Mapping[str, float | None]) -> M:
        """Build the mechanism from file values (keys: :attr:`Parameter.name`).

        Omitted optional fields take their defaults; degrees become radians.

        Parameters
        ----------
        values : mapping of str to float or None
            Values in file units, keyed by file field name. [mm or deg]

        Returns
        -------
        Mechanism
            The validated mechanism.

        Raises
        ------
        DesignError
            If the dimensions are inconsistent (message naming the file fields).
        """
        kwargs = {p.attribute: p.to_internal(values.get(p.name, p.default)) for p in cls.parameters}
        return cls(**kwargs)

    def parameter_values(self) -> dict[str, float]:
        """File values of :attr:`parameters` (radians back to degrees; None left out).

        Returns
        -------
        dict of str to float
            Values keyed by file field name. [mm or deg]
        """
        out: dict[str, float] = {}
        for p in self.parameters:
            v = getattr(self, p.attribute)
            if v is not None:
                out[p.name] = math.degrees(v) if p.unit == "deg" else float(v)
        return out

    def field_name(self, attribute: str) -> str:
        """Return the file field name of a dataclass field, ``follower.<name>``.

        Parameters
        ----------
        attribute : str
            Dataclass field, e.g. ``"arm_length_mm"``.

        Returns
        -------
        str
            ``"follower." + name`` as the file writes it.
        """
        for p in self.parameters:
            if p.attribute == attribute:
                return f"follower.{p.name}"
        return f"follower.{attribute}"

    def contact_element(self) -> ContactElement:
        """Return what the contact engine solves for this follower (THEORY §5).

        Returns
        -------
        RollerGuide or TranslatingFace or OscillatingFace
            The follower's contact element with its output datum.

        Raises
        ------
        DesignError
            If the follower type has no exact-contact solver.
        """
        from camtol.exceptions import DesignError

        raise DesignError(f"follower type {self.kind!r} has no exact-contact solver")

    def undercut_message(self, curvature_radius_mm: float, theta_deg: float) -> str:
        """Say why the profile cannot be generated at one angle (flat faces: ρ ≤ 0).

        Parameters
        ----------
        curvature_radius_mm : float
            Signed profile radius of curvature there. [mm]
        theta_deg : float
            Cam angle. [deg]

        Returns
        -------
        str
            The reason, without the remedy.
        """
        return (
            f"the profile is not convex: radius of curvature {curvature_radius_mm:.4g} mm at"
            f" θ={theta_deg:.2f}° (cusp/undercut); a {self.kind} follower needs ρ > 0"
            " everywhere"
        )

    @property
    def pivot_clearance_mm(self) -> float | None:
        """Distance from the cam centre to the follower pivot, which the cam must not reach.

        None for a translating follower. [mm]
        """
        return None

    def outline(self, theta_rad: float, lift: float, velocity: float, scale_mm: float) -> Outline:
        """Return the follower at one cam angle, in the cam frame, for drawing.

        Parameters
        ----------
        theta_rad : float
            Cam angle θ. [rad]
        lift : float
            Follower output S(θ). [mm, or rad for an oscillating follower]
        velocity : float
            V = dS/dθ. [mm/rad or rad/rad]
        scale_mm : float
            Size of the drawing (the base radius): lengths of stems and faces. [mm]

        Returns
        -------
        Outline
            Circles, segments and pivots (empty by default). [mm]
        """
        return Outline()

    @abstractmethod
    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2) for cam angle, lift S and V = dS/dθ.

        Parameters
        ----------
        theta : JetLike
            Cam angle θ, as an array or as the jet ``Jet.variable(θ)``
            (:meth:`camtol.jet.Jet.variable`) for exact θ-derivatives. [rad]
        lift : JetLike
            Follower output S(θ), broadcastable with ``theta``; a jet (S, V, A) for exact
            derivatives. [mm, or rad for an oscillating follower]
        velocity : JetLike
            Kinematic velocity V = dS/dθ; a jet (V, A, J) for exact derivatives.
            [mm/rad, or rad/rad for an oscillating follower]

        Returns
        -------
        ContactGeometry
            Contact point, instant centre, pressure and shift angles, plus the
            mechanism's ``extras``; jets where the inputs are jets. [mm, rad]
        """

    @abstractmethod
    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """ΔS per unit deviation of each source (THEORY §3), keyed by source key.

        Parameters
        ----------
        geometry : ContactGeometry
            Contact geometry from :meth:`contact` at the same angles. [mm, rad]
        theta : JetLike
            Cam angle θ, the same array or jet that was given to :meth:`contact`. [rad]

        Returns
        -------
        dict of str to JetLike
            ∂S/∂p for every key of :attr:`sources`, jets where ``geometry`` holds jets.
            [unit of S per unit of the source: mm/mm, mm/rad, rad/mm or rad/rad]
        """

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """ΔS per unit deviation straight from the motion (the error engine's hot path).

        The default goes through :meth:`contact`; a mechanism may override it with a
        leaner closed form that must agree with the default (tested).

        Parameters
        ----------
        theta : JetLike
            Cam angle θ, as an array or a jet. [rad]
        lift : JetLike
            Follower output S(θ), as an array or a jet. [mm, or rad for an oscillating
            follower]
        velocity : JetLike
            Kinematic velocity V = dS/dθ, as an array or a jet. [mm/rad, or rad/rad for an
            oscillating follower]

        Returns
        -------
        dict of str to JetLike
            Same as :meth:`sensitivities` of :meth:`contact`: ∂S/∂p for every key of
            :attr:`sources`. [unit of S per unit of the source]
        """
        return self.sensitivities(self.contact(theta, lift, velocity), theta)

    @abstractmethod
    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Radius of curvature ρ of the cam profile at the contact point (> 0 convex). [mm]

        Parameters
        ----------
        theta_rad : ndarray
            Cam angles θ. [rad]
        lift : ndarray
            Follower output S(θ). [mm, or rad for an oscillating follower]
        velocity : ndarray
            Kinematic velocity V = dS/dθ. [mm/rad, or rad/rad for an oscillating follower]
        acceleration : ndarray
            Kinematic acceleration A = d²S/dθ². [mm/rad², or rad/rad² for an oscillating
            follower]

        Returns
        -------
        ndarray
            Signed radius of curvature ρ of the profile at the contact point, > 0 where the
            profile is convex, < 0 where concave. [mm]
        """

    def cam_source_keys(self, label: str) -> dict[str, str]:
        """How the design's tolerance keys name the error sources of its cam ``label``.

        A single cam's keys are its own. A mechanism of several cams (a conjugate pair)
        maps its per-cam keys (``r_a``, ``rf_d``) to the sources of each cam (``r``, ``rf``)
        and a key shared by the cams (the centre distance ``f``) to both.

        Parameters
        ----------
        label : str
            The cam's label, as :meth:`cams` gives it.

        Returns
        -------
        dict of str to str
            Design tolerance key -> the cam's own source key.
        """
        return {s.key: s.key for s in self.sources}

    @abstractmethod
    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """Nominal size used to look up an IT grade for a source (THEORY §3.6).

        Lengths in mm; angles in degrees (the papers' angle convention).

        Parameters
        ----------
        key : str
            Error-source key, one of the keys of :attr:`sources`.
        max_radius_mm : float
            Maximum radial dimension of the cam profile, the nominal size of profile
            tolerances. [mm]

        Returns
        -------
        float
            Nominal size for the ISO 286 look-up. [mm for lengths, deg for angles]

        Raises
        ------
        KeyError
            If the mechanism has no source ``key``.
        """

    @abstractmethod
    def summary(self) -> list[tuple[str, str]]:
        """(parameter, value with unit) pairs for the design summary."""

    def undercut_mask(self, curvature_radius_mm: FloatArray) -> NDArray[np.bool_]:
        """Where the profile cannot be generated by the follower (cusp or undercut).

        The default, for flat faces, is ρ ≤ 0 (a flat face needs a convex profile, THEORY
        §2.1). Roller followers override it: undercut only where the convex pitch curve is
        sharper than the roller (THEORY §2.3).

        Parameters
        ----------
        curvature_radius_mm : ndarray
            Signed profile radius of curvature from :meth:`curvature_radius`. [mm]

        Returns
        -------
        ndarray of bool
            True where the follower cannot generate the profile; same shape as
            ``curvature_radius_mm``.
        """
        return np.asarray(np.asarray(curvature_radius_mm) <= 0.0)

    @property
    def output_unit(self) -> str:
        """Internal unit of the follower output S: ``"mm"`` or ``"rad"``."""
        return "mm" if self.output == "translating" else "rad"

    def perturbed(self, source: str, delta: float) -> Mechanism:
        """Return a copy with the follower parameter behind error source ``source`` moved.

        This is how an error source is applied exactly (``camtol verify``, Monte Carlo in
        exact mode): the copy is re-simulated by the contact engine on the nominal cam,
        with the nominal mechanism as reference for S = 0 (THEORY §5).

        Parameters
        ----------
        source : str
            Error-source key whose :attr:`ErrorSource.parameter` names a field.
        delta : float
            Deviation Δp added to that field. [mm, or rad for an angle]

        Returns
        -------
        Mechanism
            A validated copy of the same type.

        Raises
        ------
        DesignError
            If ``source`` is not an error source of this follower or is not a follower
            parameter (profile errors ``r``, ``n``), naming the sources that are.
        """
        from camtol.exceptions import DesignError

        allowed = ", ".join(s.key for s in self.sources if s.parameter is not None)
        src = next((s for s in self.sources if s.key == source), None)
        if src is None or src.parameter is None:
            what = "is not an error source" if src is None else "is not a follower parameter"
            raise DesignError(
                f"source {source!r} {what} of a {self.kind} follower; perturbed() takes one"
                f" of: {allowed or '(none)'}"
            )
        return dataclasses.replace(  # type: ignore[type-var]
            self, **{src.parameter: getattr(self, src.parameter) + delta}
        )

    def cams(self) -> tuple[tuple[str, Mechanism], ...]:
        """Return the single-contact cams this mechanism stands for: (label, mechanism).

        One unlabelled cam (``("", self)``) for an ordinary follower; a conjugate pair
        returns its cams ``"A"`` and ``"B"``. :meth:`camtol.design.cam_design.CamDesign.cams` builds
        on it.

        Returns
        -------
        tuple of (str, Mechanism)
            Label (``""``, or ``"A"``/``"B"``) and the single-contact mechanism.
        """
        return (("", self),)

    def source(self, key: str) -> ErrorSource:
        """Return the error source with this key.

        Parameters
        ----------
        key : str
            Error-source key as in the design file's tolerances, e.g. ``"r"``.

        Returns
        -------
        ErrorSource
            The source with that key.

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


#: Follower types by the name used in design files (``follower.type``), built from the
#: classes by :func:`register_follower`. Every other table of types derives from it.
FOLLOWER_TYPES: dict[str, type[Mechanism]] = {}


def register_follower(cls: _MechanismType) -> _MechanismType:
    """Class decorator: make a mechanism a follower type of design files.

    The class must define ``kind`` (the ``follower.type`` name) and ``parameters``. The
    design-file schema, the contact engine and the reports take everything else from the
    class itself, so adding a follower type touches one module (plus its tests).

    Parameters
    ----------
    cls : type of Mechanism
        The follower class.

    Returns
    -------
    type
        ``cls`` unchanged.

    Raises
    ------
    ValueError
        If another class already uses that ``kind``.
    """
    other = FOLLOWER_TYPES.get(cls.kind)
    if other is not None and other is not cls:
        raise ValueError(f"follower type {cls.kind!r} is already registered by {other!r}")
    FOLLOWER_TYPES[cls.kind] = cls
    return cls
