"""One evaluation of the analytic engine on a grid, in cache-sized chunks (THEORY §2, §3).

:func:`evaluate_engine` returns what :func:`camtol.analysis.analyse` needs from a mechanism
at every angle: the kinematics (THEORY §2) and the sensitivity of the output to every
error source with its first and second θ-derivatives (THEORY §3.1-3.5), from a single
evaluation of the mechanism's closed forms:

- a mechanism with a lean closed form for its sensitivities (flat faces) gets its contact
  geometry as plain arrays and its sensitivities as jets;
- otherwise one evaluation of the contact geometry as jets serves both (the kinematics
  are its values).

Long grids are evaluated in chunks of :data:`CHUNK` angles written into the result
arrays, so the many intermediate arrays of the formulas stay in cache and never exist at
full length: time and peak memory grow with what the result holds, not with the number
of intermediate steps.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol import jet
from camtol.design import CamDesign
from camtol.jet import FloatArray, Jet, JetLike
from camtol.kinematics import Kinematics, check_geometry, check_velocity_ratio
from camtol.mechanisms.base import Mechanism
from camtol.sources import DESIGN_SOURCES

__all__ = ["CHUNK", "evaluate_engine"]

#: Angles per chunk: a few dozen intermediate arrays of this length fit in a core's cache.
CHUNK = 16_384

_GEOMETRY = (
    "contact_x",
    "contact_y",
    "centre_x",
    "centre_y",
    "q",
    "pressure_angle",
    "shift_angle",
)
_EXTRAS = ("face_contact", "follower_angle")


class _Columns:
    """Full-length result arrays filled chunk by chunk.

    A quantity that is the same constant in every chunk (e.g. the pressure angle of a
    translating flat face) is kept as a read-only broadcast view instead of an array.
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self._full: dict[str, FloatArray] = {}
        self._const: dict[str, float] = {}

    def put(self, key: str, value: JetLike, where: slice) -> None:
        v = jet.value(value)
        out = self._full.get(key)
        if out is None:
            first = where.start == 0
            if v.size and (first or key in self._const):
                c = float(v.flat[0])
                if (first or self._const[key] == c) and bool(np.all(v == c)):
                    self._const[key] = c
                    return
            if first and where.stop >= self.n and v.shape == (self.n,):
                self._full[key] = v  # a single chunk: keep the array itself
                return
            out = self._full[key] = np.empty(self.n)
            if key in self._const:
                out[: where.start] = self._const.pop(key)
        out[where] = v

    def get(self, key: str) -> FloatArray | None:
        """Return the full-length array (or broadcast constant) of a quantity, if it was put."""
        if key in self._const:
            return np.broadcast_to(self._const[key], (self.n,))
        return self._full.get(key)

    def __getitem__(self, key: str) -> FloatArray:
        out = self.get(key)
        if out is None:
            raise KeyError(key)
        return out

    def keys(self) -> list[str]:
        """Keys put so far."""
        return [*self._full, *self._const]


def evaluate_engine(
    design: CamDesign,
    theta_rad: ArrayLike,
    left_limit: ArrayLike | None = None,
    *,
    check: bool = True,
    chunk: int = CHUNK,
) -> tuple[Kinematics, dict[str, Jet]]:
    """Kinematics and per-unit-deviation sensitivities (jets) on a grid, in one pass.

    Parameters
    ----------
    design : CamDesign
        The design.
    theta_rad : array_like
        Cam angles. [rad]
    left_limit : array_like of bool, optional
        Rows that take the left limit at a segment boundary.
    check : bool
        Raise if the geometry cannot work, as :func:`camtol.kinematics.kinematics`.
    chunk : int
        Angles evaluated at once. [-]

    Returns
    -------
    kinematics : Kinematics
        As :func:`camtol.kinematics.kinematics` returns it.
    sensitivities : dict of str to Jet
        ∂S/∂p of every source of the mechanism, and of every design-level source
        (:mod:`camtol.sources`) the design tolerances, with its θ-derivatives; a constant
        sensitivity has broadcast (read-only) zero derivatives. [output unit per mm or
        per rad, per rad^k]

    Raises
    ------
    GeometryError, UndercutError
        With ``check``, as :func:`camtol.kinematics.kinematics`.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    left = np.zeros(theta.shape, bool) if left_limit is None else np.asarray(left_limit, bool)
    mech = design.mechanism
    motion = design.program.evaluate(theta, left_limit=left)
    if check:
        check_velocity_ratio(design, theta, motion)
    shared = type(mech).error_sensitivities is Mechanism.error_sensitivities
    own = {src.key for src in mech.sources}
    design_keys = [t.key for t in design.tolerances if t.key not in own and t.key in DESIGN_SOURCES]
    n = theta.size
    geo, sens = _Columns(n), _Columns(n)
    plain: set[str] = set()
    q_is_velocity = False
    for a in range(0, n, max(int(chunk), 1)):
        at = slice(a, min(n, a + chunk))
        t, s, v = theta[at], motion.lift[at], motion.velocity[at]
        acc, jerk = motion.acceleration[at], motion.jerk[at]
        th, lift, vel = Jet.variable(t), Jet(s, v, acc), Jet(v, acc, jerk)
        if shared:
            g = mech.contact(th, lift, vel)
            sources = dict(mech.sensitivities(g, th))
        else:
            g = mech.contact(t, s, v)
            sources = dict(mech.error_sensitivities(th, lift, vel))
        for key in design_keys:  # design-level sources the design tolerances
            sources[key] = DESIGN_SOURCES[key].sensitivity(mech, th, lift, vel)
        q_is_velocity = g.q is v
        for key in _GEOMETRY:
            if not (key == "q" and q_is_velocity):
                geo.put(key, getattr(g, key), at)
        for key in _EXTRAS:
            if key in g.extras:
                geo.put(key, g.extras[key], at)
        geo.put("curvature_radius", mech.curvature_radius(t, s, v, acc), at)
        geo.put("radius", np.hypot(jet.value(g.contact_x), jet.value(g.contact_y)), at)
        for key, x in sources.items():
            if isinstance(x, Jet):
                sens.put(key, x.v, at)
                sens.put(f"{key}'", x.d1, at)
                sens.put(f"{key}''", x.d2, at)
            else:
                plain.add(key)
                sens.put(key, np.broadcast_to(np.asarray(x, dtype=float), t.shape), at)
        del g, sources, th, lift, vel
    c = geo
    kin = Kinematics(
        theta_rad=theta,
        left_limit=left,
        lift=motion.lift,
        velocity=motion.velocity,
        acceleration=motion.acceleration,
        jerk=motion.jerk,
        contact_x_mm=c["contact_x"],
        contact_y_mm=c["contact_y"],
        radius_mm=c["radius"],
        centre_x_mm=c["centre_x"],
        centre_y_mm=c["centre_y"],
        q_mm=motion.velocity if q_is_velocity else c["q"],
        pressure_angle_rad=c["pressure_angle"],
        shift_angle_rad=c["shift_angle"],
        curvature_radius_mm=c["curvature_radius"],
        face_contact_mm=c.get("face_contact"),
        follower_angle_rad=c.get("follower_angle"),
    )
    if check:
        check_geometry(design, kin)
    zero: NDArray[np.float64] = np.broadcast_to(0.0, theta.shape)
    out: dict[str, Jet] = {}
    for key in (k for k in sens.keys() if not k.endswith("'")):
        if key in plain:
            out[key] = Jet(sens[key], zero, zero)
        else:
            out[key] = Jet(sens[key], sens[f"{key}'"], sens[f"{key}''"])
    return kin, out
