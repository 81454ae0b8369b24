r"""The follower train: what the cam drives at speed (THEORY §9.1).

A force-closed follower is one degree of freedom: its effective mass M (the follower,
its share of the spring and whatever moves with it), a return spring of rate k_s that
pushes it on the cam with the preload P at zero lift, the train's stiffness k_f between the
contact and the mass (infinite: a rigid train) and a viscous damper c in parallel with
k_f, of damping ratio ζ for the train's first mode with contact kept:

.. math:: M \ddot x = k_f (y - x) + c (\dot y - \dot x) - k_s x - P,
          \qquad ω_n = \sqrt{(k_f + k_s)/M},\quad c = 2 ζ M ω_n,

y = S(θ) the cam's lift, x the mass, both in the unit of S (mm, or rad for an
oscillating follower). The force the train carries at the contact,
Q = k_f (y − x) + c (ẏ − ẋ), is a force [N] for a translating follower and a moment about
the pivot [N·m] for an oscillating one: a *generalised* force. Everything here is in the
units of the design file: lifts in mm or rad, forces in N or N·m, stiffnesses in N/mm or
N·m/rad, and the generalised mass in N·s²/mm (kg × 10⁻³) or N·m·s²/rad (kg·mm² × 10⁻⁶).

A design file's ``[dynamics]`` table (validated by :mod:`camtol.config.dynamics_table`)
is kept on the design as a :class:`DynamicsTable`, which remembers the table as written
(the design's identity is that of its file); :func:`follower_train` turns it, with any
command-line overrides, into the :class:`FollowerTrain` of a design.

References
----------
.. [Nor] R. L. Norton, *Cam Design and Manufacturing Handbook*, 2nd ed., Industrial
   Press, 2009, ch. 10 (lumped-parameter models of a follower train) and ch. 11 (contact
   stress of cams and rollers).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError

__all__ = [
    "GRAVITY_M_PER_S2",
    "STEEL_POISSON_RATIO",
    "STEEL_YOUNGS_MODULUS_GPA",
    "TABLE_FIELDS",
    "ContactMaterials",
    "DynamicsTable",
    "FollowerTrain",
    "follower_train",
    "train_fields",
]

OutputKind = Literal["translating", "oscillating"]

#: Young's modulus of steel, the default of cam and follower (Eurocode 3). [GPa]
STEEL_YOUNGS_MODULUS_GPA = 210.0
#: Poisson's ratio of steel, the default of cam and follower. [-]
STEEL_POISSON_RATIO = 0.3
#: Standard gravity. [m/s²]
GRAVITY_M_PER_S2 = 9.80665

#: The four fields whose name depends on the follower's output: (translating, oscillating).
_KIND_FIELDS: tuple[tuple[str, str], ...] = (
    ("mass_kg", "inertia_kg_mm2"),
    ("spring_rate_n_per_mm", "spring_rate_nm_per_rad"),
    ("preload_n", "preload_nm"),
    ("follower_stiffness_n_per_mm", "follower_stiffness_nm_per_rad"),
)

#: Every field of a ``[dynamics]`` table, in the order the documentation lists them.
TABLE_FIELDS: tuple[str, ...] = (
    *(t for t, _ in _KIND_FIELDS),
    *(o for _, o in _KIND_FIELDS),
    "damping_ratio",
    "face_width_mm",
    "youngs_modulus_cam_gpa",
    "youngs_modulus_follower_gpa",
    "poisson_ratio_cam",
    "poisson_ratio_follower",
    "gravity",
    "gravity_angle_deg",
)

#: Default damping ratio of an elastic train (steel trains measure about 0.05 to 0.15). [-]
DEFAULT_DAMPING_RATIO = 0.05


def train_fields(output: str) -> tuple[str, str, str, str]:
    """Return the names of mass, spring rate, preload and stiffness for a follower output.

    Parameters
    ----------
    output : {"translating", "oscillating"}
        The follower's output (:attr:`camtol.mechanisms.base.Mechanism.output`).

    Returns
    -------
    tuple of str
        E.g. ``("mass_kg", "spring_rate_n_per_mm", "preload_n",
        "follower_stiffness_n_per_mm")`` for a translating follower.
    """
    i = 0 if output == "translating" else 1
    m, k, p, s = (pair[i] for pair in _KIND_FIELDS)
    return m, k, p, s


@dataclass(frozen=True)
class ContactMaterials:
    """Face width and elastic constants of cam and follower, for Hertz stress (THEORY §9.5).

    Attributes
    ----------
    face_width_mm : float or None
        Width L of the line contact (the narrower of cam and follower); None: the contact
        stress is not computed. [mm]
    youngs_modulus_cam_gpa, youngs_modulus_follower_gpa : float
        Young's moduli (steel by default). [GPa]
    poisson_ratio_cam, poisson_ratio_follower : float
        Poisson's ratios (steel by default). [-]
    """

    face_width_mm: float | None = None
    youngs_modulus_cam_gpa: float = STEEL_YOUNGS_MODULUS_GPA
    youngs_modulus_follower_gpa: float = STEEL_YOUNGS_MODULUS_GPA
    poisson_ratio_cam: float = STEEL_POISSON_RATIO
    poisson_ratio_follower: float = STEEL_POISSON_RATIO

    def __post_init__(self) -> None:
        if self.face_width_mm is not None:
            _positive("face_width_mm", self.face_width_mm, "mm")
        _positive("youngs_modulus_cam_gpa", self.youngs_modulus_cam_gpa, "GPa")
        _positive("youngs_modulus_follower_gpa", self.youngs_modulus_follower_gpa, "GPa")
        for name in ("poisson_ratio_cam", "poisson_ratio_follower"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0.0 <= v < 0.5):
                raise DesignError(
                    f"dynamics.{name}={v!r} is not allowed; give a number in [0, 0.5)"
                )

    @property
    def effective_modulus_mpa(self) -> float:
        """Contact modulus E* with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂. [MPa]"""
        inv = (1.0 - self.poisson_ratio_cam**2) / self.youngs_modulus_cam_gpa + (
            1.0 - self.poisson_ratio_follower**2
        ) / self.youngs_modulus_follower_gpa
        return 1e3 / inv


def _positive(name: str, value: float, unit: str) -> None:
    if isinstance(value, bool) or not (math.isfinite(value) and value > 0):
        raise DesignError(f"dynamics.{name}={value!r} is not allowed; give a number > 0 {unit}")


@dataclass(frozen=True)
class FollowerTrain:
    """A follower train of one degree of freedom (THEORY §9.1), in design-file units.

    Build it with :func:`follower_train` (from a design's ``[dynamics]`` table and
    overrides), or directly.

    Attributes
    ----------
    output : {"translating", "oscillating"}
        The follower's output: the lift is in mm, or in rad for an oscillating follower.
    mass : float
        Generalised mass M. [N·s²/mm (kg × 1e-3), or N·m·s²/rad (kg·mm² × 1e-6)]
    spring_rate : float
        Return-spring rate k_s (0 for a form-closed pair). [N/mm, or N·m/rad]
    preload : float
        Spring force at zero lift P, with the weight when gravity is on. [N, or N·m]
    stiffness : float or None
        Train stiffness k_f between the contact and the mass; None: rigid. [N/mm, or N·m/rad]
    damping_ratio : float
        ζ of the first mode with contact kept, in [0, 2); no effect on a rigid train. [-]
    materials : ContactMaterials
        For the Hertz contact stress.
    form_closed : bool
        True for a conjugate pair: its cams hold the follower both ways (no jump).
    gravity_load : float
        The part of ``preload`` that is the follower's weight. [N]
    """

    output: OutputKind
    mass: float
    spring_rate: float
    preload: float
    stiffness: float | None = None
    damping_ratio: float = 0.0
    materials: ContactMaterials = field(default_factory=ContactMaterials)
    form_closed: bool = False
    gravity_load: float = 0.0

    def __post_init__(self) -> None:
        if self.output not in ("translating", "oscillating"):
            raise DesignError(f"output={self.output!r} is not allowed; translating or oscillating")
        for name, value in (("mass", self.mass), ("spring_rate", self.spring_rate)):
            low_ok = value >= 0 if (name == "spring_rate" and self.form_closed) else value > 0
            if isinstance(value, bool) or not (math.isfinite(value) and low_ok):
                raise DesignError(
                    f"FollowerTrain.{name}={value!r} is not allowed; give a number > 0"
                )
        if not math.isfinite(self.preload) or (self.preload < 0 and not self.form_closed):
            raise DesignError(
                f"FollowerTrain.preload={self.preload!r} is not allowed; give a number ≥ 0"
                " (the spring pushes the follower on the cam)"
            )
        if self.stiffness is not None and not (
            math.isfinite(self.stiffness) and self.stiffness > 0
        ):
            raise DesignError(
                f"FollowerTrain.stiffness={self.stiffness!r} is not allowed; give a number > 0"
                " or None (rigid)"
            )
        z = self.damping_ratio
        if isinstance(z, bool) or not (math.isfinite(z) and 0.0 <= z < 2.0):
            raise DesignError(
                f"dynamics.damping_ratio={z!r} is not allowed; give a number in [0, 2)"
            )

    @property
    def rigid(self) -> bool:
        """True when the train has no stiffness of its own (k_f infinite)."""
        return self.stiffness is None

    @property
    def natural_frequency_rad_s(self) -> float | None:
        """ω_n = √((k_f + k_s)/M) with contact kept; None for a rigid train. [rad/s]"""
        if self.stiffness is None:
            return None
        return math.sqrt((self.stiffness + self.spring_rate) / self.mass)

    @property
    def damping(self) -> float:
        """C = 2 ζ M ω_n (0 for a rigid train). [N·s/mm, or N·m·s/rad]"""
        wn = self.natural_frequency_rad_s
        return 0.0 if wn is None else 2.0 * self.damping_ratio * self.mass * wn

    @property
    def force_to_newton(self) -> float:
        """Factor from (generalised force × ∂S/∂n) to the normal contact force in N.

        1 for a translating follower (N × mm/mm); 1000 for an oscillating one
        (N·m × rad/mm = 1000 N). [-]
        """
        return 1.0 if self.output == "translating" else 1e3

    @property
    def torque_factor(self) -> float:
        """Factor from (generalised force × V) to the camshaft torque in N·m. [-]"""
        return 1e-3 if self.output == "translating" else 1.0


@dataclass(frozen=True)
class DynamicsTable:
    """A design file's ``[dynamics]`` table, validated (docs/file-formats.md).

    Attributes
    ----------
    values : tuple of (str, object)
        The table's fields as validated, in file units (see :data:`TABLE_FIELDS`).
    table : tuple of (str, object)
        The table as written, for the design's identity.
    """

    values: tuple[tuple[str, Any], ...] = ()
    table: tuple[tuple[str, Any], ...] = field(default=(), compare=False, repr=False)

    def to_mapping(self) -> dict[str, Any]:
        """Return the ``[dynamics]`` table as written in the design file.

        Returns
        -------
        dict
            Part of the design's identity
            (:attr:`camtol.design.cam_design.CamDesign.content_hash`).
        """
        return dict(self.table)

    def get(self, name: str) -> Any:
        """Return a field's validated value, or None when the table does not give it.

        Parameters
        ----------
        name : str
            A field of :data:`TABLE_FIELDS`.
        """
        return dict(self.values).get(name)


def _table(design: CamDesign) -> DynamicsTable:
    table = design.extras.get("dynamics")
    if table is None:
        return DynamicsTable()
    if isinstance(table, DynamicsTable):
        return table
    raise DesignError(
        f"design {design.name!r}: extras['dynamics'] is a {type(table).__name__}, not a"
        " validated table; read it with camtol.config.dynamics_table.parse_dynamics"
    )


def check_applicable(values: Mapping[str, Any], design: CamDesign, *, form_closed: bool) -> None:
    """Refuse fields that do not apply to the design's follower (one line each).

    Parameters
    ----------
    values : mapping of str to object
        Field name → value (file units), from the table and the overrides.
    design : CamDesign
        The design the fields are for.
    form_closed : bool
        Whether the design is a conjugate pair (no spring, no stiffness).

    Raises
    ------
    DesignError
        Naming the field, the design's follower type and the field to use instead.
    """
    output = design.mechanism.output
    own = train_fields(output)
    other = train_fields("oscillating" if output == "translating" else "translating")
    for name, instead in zip(other, own, strict=True):
        if values.get(name) is not None:
            raise DesignError(
                f"dynamics.{name} does not apply to a {design.mechanism.kind} follower"
                f" ({output}); give {instead}"
            )
    if form_closed:
        for name in own[1:]:
            if values.get(name) not in (None, 0, 0.0) and name != own[2]:
                raise DesignError(
                    f"dynamics.{name}={values[name]!r}: a conjugate pair is form-closed (its"
                    " two cams hold the follower both ways) and is modelled as a rigid train"
                    " with no return spring; leave it out"
                )
    if values.get("gravity") and output != "translating":
        raise DesignError(
            "dynamics.gravity = true applies to a translating follower only: an oscillating"
            " follower's weight acts through its centre of mass, which the table does not"
            " give; add its moment to preload_nm"
        )


def follower_train(
    design: CamDesign, overrides: Mapping[str, Any] | None = None, *, form_closed: bool = False
) -> FollowerTrain:
    """Return the follower train of a design: its ``[dynamics]`` table, overridden.

    Parameters
    ----------
    design : CamDesign
        The design; its ``design.extras["dynamics"]`` (a :class:`DynamicsTable`, absent
        when the file has no ``[dynamics]`` table) gives the fields.
    overrides : mapping of str to object, optional
        Field name (:data:`TABLE_FIELDS`) → value in file units, e.g. from the command
        line; a None value leaves the table's.
    form_closed : bool
        True for a conjugate pair (no return spring; rigid).

    Returns
    -------
    FollowerTrain

    Raises
    ------
    DesignError
        A required field missing (the mass or inertia, the spring rate), a field that does
        not apply to the follower, or a value out of range: one line naming the field.
    """
    values = dict(_table(design).values)
    for k, v in (overrides or {}).items():
        if v is not None:
            values[k] = v
    unknown = sorted(set(values) - set(TABLE_FIELDS))
    if unknown:
        raise DesignError(
            f"dynamics.{unknown[0]} is not a field of the [dynamics] table; allowed:"
            f" {', '.join(TABLE_FIELDS)}"
        )
    check_applicable(values, design, form_closed=form_closed)
    output = design.mechanism.output
    m, k, p, s = train_fields(output)
    flag = {name: "--" + name.replace("_", "-") for name in (m, k, p, s)}
    if values.get(m) is None:
        raise DesignError(
            f"dynamics.{m} is missing: give it in the design's [dynamics] table or as {flag[m]}"
        )
    if not form_closed and values.get(k) is None:
        raise DesignError(
            f"dynamics.{k} is missing: give the return spring's rate in the [dynamics]"
            f" table or as {flag[k]}"
        )
    unit_m, unit_k, unit_p = (
        ("kg", "N/mm", "N") if output == "translating" else ("kg·mm²", "N·m/rad", "N·m")
    )
    _positive(m, float(values[m]), unit_m)
    if not form_closed:
        _positive(k, float(values[k]), unit_k)
    if values.get(s) is not None:
        _positive(s, float(values[s]), unit_k)
    if values.get(p) is not None and not (
        math.isfinite(float(values[p])) and float(values[p]) >= 0
    ):
        raise DesignError(
            f"dynamics.{p}={values[p]!r} is not allowed; give a number ≥ 0 {unit_p} (the"
            " spring force at zero lift, pushing the follower on the cam)"
        )
    scale = 1e-3 if output == "translating" else 1e-6
    mass = float(values[m]) * scale
    gravity = 0.0
    if values.get("gravity"):
        angle = math.radians(float(values.get("gravity_angle_deg") or 0.0))
        gravity = float(values[m]) * GRAVITY_M_PER_S2 * math.cos(angle)
    preload = float(values.get(p) or 0.0)
    materials = ContactMaterials(
        face_width_mm=values.get("face_width_mm"),
        youngs_modulus_cam_gpa=float(
            values.get("youngs_modulus_cam_gpa") or STEEL_YOUNGS_MODULUS_GPA
        ),
        youngs_modulus_follower_gpa=float(
            values.get("youngs_modulus_follower_gpa") or STEEL_YOUNGS_MODULUS_GPA
        ),
        poisson_ratio_cam=float(
            STEEL_POISSON_RATIO
            if values.get("poisson_ratio_cam") is None
            else values["poisson_ratio_cam"]
        ),
        poisson_ratio_follower=float(
            STEEL_POISSON_RATIO
            if values.get("poisson_ratio_follower") is None
            else values["poisson_ratio_follower"]
        ),
    )
    stiffness = None if values.get(s) is None else float(values[s])
    default_zeta = 0.0 if stiffness is None else DEFAULT_DAMPING_RATIO
    zeta = values.get("damping_ratio")
    return FollowerTrain(
        output=output,
        mass=mass,
        spring_rate=0.0 if form_closed else float(values[k]),
        preload=preload + gravity,
        stiffness=stiffness,
        damping_ratio=default_zeta if zeta is None else float(zeta),
        materials=materials,
        form_closed=form_closed,
        gravity_load=gravity,
    )
