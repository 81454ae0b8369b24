"""Oscillating roller follower (THEORY §2.4, §3.3; [CW11] §2, [Wu03], [WC05]).

The same closed forms serve cam A of a conjugate pair (a single oscillating roller cam is
cam A alone) and, mirrored, cam B (:mod:`camtol.mechanisms.conjugate`).

Why one module: it is the oscillating roller's closed forms (pitch point, pitch curvature,
contact, general and lean sensitivities, reach check) and the follower class that applies
them to cam A. The functions take ``side`` so that cam B of a conjugate pair reuses them
mirrored, and the lean form is held equal to the general one, so they change together.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
.. [Wu03] L.-I. Wu, Proc. IMechE C 217(10):1117-1123, 2003. doi:10.1243/095440603322517126
.. [WC05] L.-I. Wu, W.-T. Chang, Proc. IMechE C 219(2):209-224, 2005.
   doi:10.1243/095440605X8478
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from camtol import jet
from camtol.exceptions import DesignError
from camtol.jet import FloatArray, Jet, JetLike
from camtol.mechanisms.base import (
    ContactGeometry,
    ErrorSource,
    OutputKind,
    Parameter,
    RollerGuide,
    length,
    register_follower,
    require_positive,
    shift_angle,
)
from camtol.mechanisms.roller_common import RollerMechanism

__all__ = [
    "RollerOscillating",
    "check_arm_reaches_prime_circle",
    "oscillating_roller_contact",
    "oscillating_roller_lean_sensitivities",
    "oscillating_roller_pitch",
    "oscillating_roller_pitch_curvature_radius",
    "oscillating_roller_sensitivities",
]


def oscillating_roller_pitch(
    theta: JetLike, gamma: JetLike, pivot_mm: float, arm_mm: float, side: int
) -> tuple[JetLike, JetLike]:
    """Roller centre of an oscillating arm in the cam frame (THEORY §2.4). [mm]

    Parameters
    ----------
    theta : JetLike
        Cam angle θ from the line of centres O2O3. [rad]
    gamma : JetLike
        Arm angle at O3 from O3O2: ξ for cam A, η − ξ for cam B. [rad]
    pivot_mm, arm_mm : float
        Centre distance f and arm length l. [mm]
    side : {-1, +1}
        −1 for cam A (arm at θ + 180° − ξ), +1 for cam B (arm at θ + 180° + η − ξ).

    Returns
    -------
    tuple of JetLike
        C = f·(cos θ, sin θ) − l·(cos(θ + side·γ), sin(θ + side·γ)). [mm]
    """
    beta = theta + side * gamma
    return (
        pivot_mm * jet.cos(theta) - arm_mm * jet.cos(beta),
        pivot_mm * jet.sin(theta) - arm_mm * jet.sin(beta),
    )


def oscillating_roller_pitch_curvature_radius(
    gamma: Jet, pivot_mm: float, arm_mm: float, side: int
) -> FloatArray:
    r"""Signed radius of curvature of an oscillating roller's pitch curve (THEORY §2.4). [mm]

    Parameters
    ----------
    gamma : Jet
        Arm angle at O3 from O3O2 with its θ-derivatives: ξ (cam A) or η − ξ (cam B).
        [rad, rad/rad, rad/rad²]
    pivot_mm, arm_mm : float
        Centre distance f and arm length l. [mm]
    side : {-1, +1}
        −1 cam A, +1 cam B (see :func:`oscillating_roller_pitch`).

    Returns
    -------
    ndarray
        ρ_pitch, > 0 convex. [mm]

    Notes
    -----
    In the frame of the line of centres the roller centre is
    c = (f − l cos γ, −side·l sin γ) (:func:`oscillating_roller_pitch` turned back by θ).
    :func:`~camtol.mechanisms.roller_common.pitch_curvature_radius`'s
    ρ = |c' + Jc|³ / ((c' + Jc) × (c'' + 2Jc' − c)) then reduces, with m = γ' + side
    (side² = 1), to

    .. math::

        |c' + Jc|^2 = l^2 m^2 + f^2 - 2\,\mathrm{side}\, f l m \cos γ

        (c' + Jc) × (c'' + 2Jc' − c) = \mathrm{side}\, l^2 m^3 + f^2
            - f l \left(m (m + \mathrm{side}) \cos γ + γ'' \sin γ\right)

    which needs one sine and one cosine of γ and no jet arithmetic (the tests hold it to
    the general form and to the cam frame's |P'|³/(P' × P'')).
    """
    f, l_ = pivot_mm, arm_mm
    sin_g, cos_g = jet.sincos(gamma.v)
    m = gamma.d1 + side
    m2 = m * m
    fl_cos = (f * l_) * cos_g
    speed2 = (l_ * l_) * m2 + f * f - (2.0 * side) * m * fl_cos
    cross = (side * l_ * l_) * m2 * m + f * f - (m2 + side * m) * fl_cos
    cross -= (f * l_) * gamma.d2 * sin_g
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(speed2 * np.sqrt(speed2) / cross)


def oscillating_roller_contact(
    theta: JetLike,
    gamma: JetLike,
    velocity: JetLike,
    pivot_mm: float,
    arm_mm: float,
    roller_mm: float,
    side: int,
) -> ContactGeometry:
    r"""Contact geometry of an oscillating roller on its cam (THEORY §2.4, [CW11] eqs. 1-11).

    Parameters
    ----------
    theta : JetLike
        Cam angle θ from the line of centres. [rad]
    gamma : JetLike
        Arm angle at O3 from O3O2: ξ (cam A) or η − ξ (cam B). [rad]
    velocity : JetLike
        V = dξ/dθ of the follower. [rad/rad]
    pivot_mm, arm_mm, roller_mm : float
        f, l and r_f. [mm]
    side : {-1, +1}
        −1 cam A, +1 cam B (see :func:`oscillating_roller_pitch`).

    Returns
    -------
    ContactGeometry
        Extras: ``pitch_x``, ``pitch_y`` roller centre [mm]; ``normal_x``, ``normal_y``
        outward unit normal A → C [-]; ``follower_angle`` is *not* set here;
        ``centre_line_angle`` α [rad]; ``arm_angle`` γ [rad].

    Notes
    -----
    With O2Q = −q (cos θ, sin θ), q = fV/(1 − V) (THEORY §0), the normal through Q and the
    roller centre C gives A = C − r_f n, n = (C − Q)/|C − Q|. α is the angle at Q from the
    line of centres to the normal QC, counterclockwise for cam A and clockwise for cam B
    (THEORY's asin forms; atan2 here keeps the branch), and φ = 90° − α − γ
    (φ_A = 90° − α_A − ξ, φ_B = 90° − α_B − (η − ξ)), signed as THEORY writes it.
    """
    cx: JetLike
    cy: JetLike
    qx: JetLike
    qy: JetLike
    dx: JetLike
    dy: JetLike
    q = pivot_mm * velocity / (1.0 - velocity)
    frame = isinstance(theta, float) and theta == 0.0 and not isinstance(gamma, Jet)
    if frame:
        # The frame of the line of centres, where the engine evaluates a motion-only
        # follower: the same formulas with cos θ = 1 and sin θ = 0 written out, the
        # same numbers bit for bit and some ten array operations fewer.
        sin_g, cos_g = jet.sincos(jet.value(gamma))  # arrays here
        cx, cy = pivot_mm - arm_mm * cos_g, -(arm_mm * (side * sin_g))
        qx, qy = -q, 0.0
        dx, dy = cx - qx, cy
    else:
        cx, cy = oscillating_roller_pitch(theta, gamma, pivot_mm, arm_mm, side)
        c, s = jet.cos(theta), jet.sin(theta)
        qx, qy = -q * c, -q * s
        dx, dy = cx - qx, cy - qy
    dist = jet.hypot(dx, dy)
    nx, ny = dx / dist, dy / dist
    ax, ay = cx - roller_mm * nx, cy - roller_mm * ny
    # The normal in the frame of the line of centres (along it, across it).
    along, across = (nx, ny) if frame else (c * nx + s * ny, c * ny - s * nx)
    alpha = jet.arctan2(-side * across, along)
    pressure = math.pi / 2 - alpha - gamma
    return ContactGeometry(
        ax,
        ay,
        qx,
        qy,
        q,
        pressure,
        shift_angle(ax, ay, qx, qy),
        {
            "pitch_x": cx,
            "pitch_y": cy,
            "normal_x": nx,
            "normal_y": ny,
            "centre_line_angle": alpha,
            "arm_angle": gamma,
        },
    )


def oscillating_roller_sensitivities(
    geometry: ContactGeometry, arm_mm: float, side: int
) -> dict[str, JetLike]:
    r"""Δξ per unit error of an oscillating roller, rad per mm (THEORY §3.3, [WC05]).

    Parameters
    ----------
    geometry : ContactGeometry
        From :func:`oscillating_roller_contact`.
    arm_mm : float
        Arm length l. [mm]
    side : {-1, +1}
        −1 cam A, +1 cam B.

    Returns
    -------
    dict
        ``r``, ``n``, ``rf``, ``l``, ``f`` [rad/mm].

    Notes
    -----
    Implicit differentiation of the contact constraint "C stays at distance r_f from the
    profile along the outward normal n": n·ΔC = Δn + Δr_f. With the arm direction û (O3 → C),
    v̂ = dC/dξ / l (û turned −90°) and the line of centres ê = (cos θ, sin θ):
    n·v̂ = k cos φ, n·û = −sin φ, n·ê = cos α, where k = +1 for cam A (ξ up pushes the
    roller out of the cam) and k = −1 for cam B. ΔC = l v̂ Δξ + û Δl + ê Δf, hence

    .. math::

        Δξ = \frac{Δn + Δr_f + Δl \sin φ - Δf \cos α}{k\, l \cos φ}

    i.e. (cam A, k = 1) ΔS_r = Δr cos λ/(l cos φ), ΔS_n = Δn/(l cos φ),
    ΔS_rf = Δr_f/(l cos φ), **ΔS_l = +Δl tan φ / l**, ΔS_f = −Δf cos α/(l cos φ).

    THEORY §3.3 expects ΔS_l = −Δl tan φ/l; with §2.4's signed φ the sign is + (on the base
    circle l² + f² − 2lf cos ξ = r_p² gives dξ/dl = (f cos ξ − l)/(l f sin ξ) = tan φ/l),
    which also agrees with the + sign of Δl_A in THEORY §4.1's Δf_l. Exact re-solution in
    the tests confirms it.
    """
    k = -float(side)
    phi = geometry.pressure_angle
    inv = k / (arm_mm * jet.cos(phi))
    return {
        "r": jet.cos(geometry.shift_angle) * inv,
        "n": inv,
        "rf": inv,
        "l": k * jet.tan(phi) / arm_mm,
        "f": -jet.cos(geometry.extras["centre_line_angle"]) * inv,
    }


def oscillating_roller_lean_sensitivities(
    gamma: JetLike,
    velocity: JetLike,
    pivot_mm: float,
    arm_mm: float,
    roller_mm: float,
    side: int,
) -> dict[str, JetLike]:
    r"""Lean form of :func:`oscillating_roller_sensitivities`, straight from the motion.

    Parameters
    ----------
    gamma : JetLike
        Arm angle at O3 from O3O2: ξ (cam A) or η − ξ (cam B). [rad]
    velocity : JetLike
        V = dξ/dθ of the follower. [rad/rad]
    pivot_mm, arm_mm, roller_mm : float
        f, l and r_f. [mm]
    side : {-1, +1}
        −1 cam A, +1 cam B.

    Returns
    -------
    dict
        ``r``, ``n``, ``rf``, ``l``, ``f`` [rad/mm], equal to the general form.

    Notes
    -----
    In the frame turning with the line of centres, C = (f − l cos γ, −side·l sin γ) and
    Q = (−q, 0), so C − Q = (d, −side·l sin γ) with d = f + q − l cos γ and ρ = |C − Q|:
    cos α = d/ρ, cos φ = sin(α + γ) = (f + q) sin γ/ρ and
    tan φ = ((f + q) cos γ − l)/((f + q) sin γ) (THEORY §2.4). With n = (C − Q)/ρ and
    A = C − r_f n, |A|² = |C|² − 2 r_f n·C + r_f² and λ is the angle between n and O2A
    (THEORY §2.5): cos λ = n·A/|A| = (n·C − r_f)/|A|, taken ≥ 0 as the arcsin of §2.5
    gives it (|cos λ| = √(1 − sin²λ), fewer operations than through sin λ).
    """
    f, l_, rf = pivot_mm, arm_mm, roller_mm
    k = -float(side)
    fq = f / (1.0 - velocity)  # f + q, q = fV/(1 − V)
    sin_g, cos_g = jet.sincos(gamma)
    lc = l_ * cos_g
    d = fq - lc
    ls = l_ * sin_g
    ls2 = ls * ls
    rho = jet.sqrt(d * d + ls2)
    inv_rho = 1.0 / rho
    fq_sin = fq * sin_g
    inv = (k / l_) * rho / fq_sin  # k / (l cos φ)
    n_dot_c = (d * (f - lc) + ls2) * inv_rho
    radius = jet.sqrt((f * f + l_ * l_ + rf * rf) - (2.0 * f) * lc - (2.0 * rf) * n_dot_c)
    cos_shift = (n_dot_c - rf) / radius
    facing_in = jet.value(cos_shift) < 0.0  # n·A < 0: |cos λ| as the arcsin gives it
    if np.any(facing_in):
        cos_shift = cos_shift * np.where(facing_in, -1.0, 1.0)
    return {
        "r": cos_shift * inv,
        "n": inv,
        "rf": inv,
        "l": k * (fq * cos_g - l_) / (fq_sin * l_),
        "f": -(d * inv_rho) * inv,
    }


def check_arm_reaches_prime_circle(
    pivot_mm: float, arm_mm: float, prime_radius_mm: float, arm_field: str
) -> None:
    """Raise unless an arm of length l about O3 can reach the prime circle (THEORY §2.4).

    Parameters
    ----------
    pivot_mm, arm_mm : float
        Centre distance f and arm length l. [mm]
    prime_radius_mm : float
        r_b + r_f. [mm]
    arm_field : str
        The arm's field name as the design file writes it (for the message).

    Raises
    ------
    DesignError
        Unless |f − l| < r_b + r_f < f + l.
    """
    f, l_, rp = pivot_mm, arm_mm, prime_radius_mm
    if not abs(f - l_) < rp < f + l_:
        raise DesignError(
            f"follower.{arm_field}={l_:g} with pivot_distance_mm={f:g} cannot put the"
            f" roller on the prime circle r_b + r_f = {rp:g} mm; need |f − l| < r_b + r_f"
            " < f + l"
        )


@register_follower
@dataclass(frozen=True)
class RollerOscillating(RollerMechanism):
    r"""Oscillating roller follower (cam A of THEORY §2.4 alone); output ξ in radians.

    Parameters
    ----------
    base_radius_mm : float
        Base-circle radius r_b of the cam profile. [mm]
    roller_radius_mm : float
        Roller radius r_f. [mm]
    pivot_distance_mm : float
        Centre distance f = |O2O3|. [mm]
    arm_length_mm : float
        Arm length l = |O3C|. [mm]

    Notes
    -----
    THEORY §2.4 ([CW11] §2): ξ = acos((l² + f² − (r_b + r_f)²)/(2lf)) + S, θ measured from the
    line of centres, O3 = f·(cos θ, sin θ), C = O3 + l·(cos(θ+180°−ξ), sin(θ+180°−ξ)),
    q = fV/(1 − V) (follower turning with the cam, THEORY §0; V < 1 required),
    φ = 90° − α − ξ. Profile radius of curvature ρ = ρ_pitch − r_f (signed, > 0 convex);
    undercut where 0 < ρ_pitch ≤ r_f.
    """

    base_radius_mm: float
    roller_radius_mm: float
    pivot_distance_mm: float
    arm_length_mm: float

    kind: ClassVar[str] = "roller_oscillating"
    motion_only: ClassVar[bool] = True
    listing_order: ClassVar[int] = 4
    output: ClassVar[OutputKind] = "oscillating"
    title: ClassVar[str] = "oscillating roller"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / (l cos φ)"
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("base_radius_mm", "base-circle radius r_b of the cam profile"),
        length("roller_radius_mm", "roller radius r_f"),
        length("pivot_distance_mm", "centre distance f = |O2O3|"),
        length("arm_length_mm", "arm length l = |O3C|"),
    )
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr", "mm", profile="radial"),
        ErrorSource("n", "normal profile error Δn", "mm", profile="normal"),
        ErrorSource("rf", "roller-radius error Δr_f", "mm", "roller_radius_mm"),
        ErrorSource("l", "arm-length error Δl", "mm", "arm_length_mm"),
        ErrorSource("f", "pivot-distance error Δf", "mm", "pivot_distance_mm"),
    )
    #: −1: the arm of cam A (THEORY §2.4).
    side: ClassVar[int] = -1

    def __post_init__(self) -> None:
        require_positive("follower.base_radius_mm", self.base_radius_mm)
        require_positive("follower.roller_radius_mm", self.roller_radius_mm)
        require_positive("follower.pivot_distance_mm", self.pivot_distance_mm)
        require_positive("follower.arm_length_mm", self.arm_length_mm)
        check_arm_reaches_prime_circle(
            self.pivot_distance_mm, self.arm_length_mm, self.prime_radius_mm, "arm_length_mm"
        )

    @property
    def prime_radius_mm(self) -> float:
        """Prime-circle radius r_p = r_b + r_f. [mm]"""
        return self.base_radius_mm + self.roller_radius_mm

    @property
    def initial_angle_rad(self) -> float:
        """ξ0 = acos((l² + f² − r_p²)/(2lf)), the follower angle on the base circle. [rad]"""
        f, l_ = self.pivot_distance_mm, self.arm_length_mm
        return math.acos((l_**2 + f**2 - self.prime_radius_mm**2) / (2.0 * l_ * f))

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2.4); extras as :func:`oscillating_roller_contact`.

        Also ``follower_angle`` ξ [rad].
        """
        xi = self.initial_angle_rad + lift
        g = oscillating_roller_contact(
            theta,
            xi,
            velocity,
            self.pivot_distance_mm,
            self.arm_length_mm,
            self.roller_radius_mm,
            self.side,
        )
        g.extras["follower_angle"] = xi
        return g

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """Δξ per unit error, rad per mm (THEORY §3.3).

        The derivation is in :func:`oscillating_roller_sensitivities`.
        """
        return oscillating_roller_sensitivities(geometry, self.arm_length_mm, self.side)

    def error_sensitivities(
        self, theta: JetLike, lift: JetLike, velocity: JetLike
    ) -> dict[str, JetLike]:
        """Lean form of :meth:`sensitivities` (:func:`oscillating_roller_lean_sensitivities`)."""
        return oscillating_roller_lean_sensitivities(
            self.initial_angle_rad + lift,
            velocity,
            self.pivot_distance_mm,
            self.arm_length_mm,
            self.roller_radius_mm,
            self.side,
        )

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Signed profile radius of curvature ρ = ρ_pitch − r_f (> 0 convex). [mm]"""
        xi = self.initial_angle_rad + Jet(
            np.asarray(lift, float), np.asarray(velocity, float), np.asarray(acceleration, float)
        )
        rho_pitch = oscillating_roller_pitch_curvature_radius(
            xi, self.pivot_distance_mm, self.arm_length_mm, self.side
        )
        return rho_pitch - self.roller_radius_mm

    def contact_element(self) -> RollerGuide:
        """Return the roller on its arm (cam A side); S = 0 at ξ0."""
        return RollerGuide(
            "circle",
            self.roller_radius_mm,
            pivot_mm=self.pivot_distance_mm,
            arm_mm=self.arm_length_mm,
            side=-1,
            zero=self.initial_angle_rad,
        )

    @property
    def pivot_clearance_mm(self) -> float:
        """The pivot distance f, which the cam must not reach. [mm]"""
        return self.pivot_distance_mm

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT-grade nominal sizes: max radial dimension for r and n, r_f, l, f."""
        return {
            "r": max_radius_mm,
            "n": max_radius_mm,
            "rf": self.roller_radius_mm,
            "l": self.arm_length_mm,
            "f": self.pivot_distance_mm,
        }[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [
            ("follower", self.title),
            ("base radius r_b", f"{self.base_radius_mm:g} mm"),
            ("roller radius r_f", f"{self.roller_radius_mm:g} mm"),
            ("pivot distance f", f"{self.pivot_distance_mm:g} mm"),
            ("arm length l", f"{self.arm_length_mm:g} mm"),
            ("initial follower angle ξ0", f"{math.degrees(self.initial_angle_rad):.4f}°"),
        ]
