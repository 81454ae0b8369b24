"""The CMM profile zone as a drawing states it (ISO 1101 profile of a line; issue 31).

A drawing's profile tolerance of a line, t, is a zone **t wide**, bounded by two lines
enveloping circles of diameter t centred on the true profile: ±t/2 along the normal
about the nominal, unless an offset UZ is stated (ISO 1101:2017, "UZ"; > 0 moves the
zone outwards, towards added material, THEORY §0). An explicit zone [lower, upper] µm
may be given instead. A grade (``"IT7"``) means t = the ISO 286 value at the cam's
largest radius: **the zone ±IT/2**, not ±IT.

This is a different convention from the error analysis (``camtol analyze``), where a
tolerance is a *deviation* equal to the whole IT value ([CW06] §2), and from Monte Carlo,
where it is a *distribution* of ±IT (docs/cmm-inspection.md has the table).

The zone **floats** when the registration fits the placement (a best fit, no datum):
the part conforms when some placement of the free rigid modes puts every point in the
zone (a Chebyshev placement, :func:`zone_placement`); it is **located** when the datum
fixes the placement (bore or centre with a stated angle or a keyway point).

``[inspection]`` keys (validated by :mod:`camtol.config.inspection_table`)::

    profile_tolerance_um = 30     # t: a zone 30 µm wide, ±15 µm about the nominal
    profile_offset_um = 5         # optional UZ: the zone [−10, +20] µm
    # or profile_tolerance = "IT7"  (t = IT7 at the largest radius)
    # or limits_um = [-10, 20]      (explicit zone; not with profile_tolerance_um)

and, for a conjugate pair, the same keys per cam with ``_a``/``_b``
(``profile_tolerance_a_um``, ``profile_offset_b_um``, ``limits_a_um``, ...).

References
----------
.. [ISO1101] ISO 1101:2017, Geometrical product specifications (GPS) — Geometrical
   tolerancing — Tolerances of form, orientation, location and run-out, §18.4 (line
   profile), "UZ" (unequally disposed zone).
.. [CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from camtol.exceptions import DesignError
from camtol.inspection.units import MAX_ERROR_UM
from camtol.jet import FloatArray

__all__ = [
    "ISO_LABEL",
    "RADIAL_LABEL",
    "ProfileZone",
    "ZoneSpec",
    "ZoneTable",
    "zone_from_limits",
    "zone_from_width",
    "zone_placement",
]

ZoneOn = Literal["normal", "radial"]

#: How outputs name the two conventions.
ISO_LABEL = "ISO 1101 profile of a line (zone along the normal)"
RADIAL_LABEL = "radial band on Δr (not ISO 1101; --tolerance-on dr)"


@dataclass(frozen=True)
class ProfileZone:
    """A resolved profile zone: limits on a deviation, and where they came from.

    Attributes
    ----------
    lower_um, upper_um : float
        The zone's limits (lower < upper). [µm]
    on : {"normal", "radial"}
        Δn (ISO 1101) or Δr (a radial band, not ISO 1101).
    source : str
        Where the zone came from, e.g. ``"inspection.profile_tolerance = 'IT7' (IT7 at
        62.9 mm: 30 µm)"`` or ``"--tolerance-um 30"``.
    """

    lower_um: float
    upper_um: float
    on: ZoneOn = "normal"
    source: str = ""

    def __post_init__(self) -> None:
        lo, hi = self.lower_um, self.upper_um
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise DesignError(
                f"profile zone [{lo:g}, {hi:g}] µm is not allowed; give lower < upper"
            )
        if max(abs(lo), abs(hi)) > MAX_ERROR_UM:
            raise DesignError(
                f"profile zone [{lo:g}, {hi:g}] µm is not allowed; give limits within"
                f" ±{MAX_ERROR_UM:g} µm (check the unit)"
            )
        if self.on not in ("normal", "radial"):
            raise DesignError(f"zone on {self.on!r} is not allowed; use normal or radial")

    @property
    def width_um(self) -> float:
        """Zone width t = upper − lower. [µm]"""
        return self.upper_um - self.lower_um

    @property
    def offset_um(self) -> float:
        """Offset of the zone's centre from the nominal (UZ; > 0 outwards). [µm]"""
        return 0.5 * (self.upper_um + self.lower_um)

    @property
    def limits_um(self) -> tuple[float, float]:
        """(lower, upper). [µm]"""
        return self.lower_um, self.upper_um

    @property
    def convention(self) -> str:
        """The zone's convention in words (ISO 1101 or the radial band)."""
        return ISO_LABEL if self.on == "normal" else RADIAL_LABEL

    def describe(self) -> str:
        """Limits and width in one phrase, e.g. ``"[-15, +15] µm (t = 30 µm) on Δn"``."""
        dev = "Δn" if self.on == "normal" else "Δr"
        uz = f", UZ {self.offset_um:+g} µm" if self.offset_um != 0 else ""
        return (
            f"[{self.lower_um:+g}, {self.upper_um:+g}] µm (t = {self.width_um:g} µm{uz}) on {dev}"
        )

    def with_guard_band(self, u_um: float) -> ProfileZone:
        """Return the acceptance zone shrunk by ``u_um`` on both sides (ISO 14253-1).

        Parameters
        ----------
        u_um : float
            Expanded uncertainty U ≥ 0. [µm]

        Raises
        ------
        DesignError
            When the guard bands leave no zone (2U ≥ t).
        """
        if not (math.isfinite(u_um) and u_um >= 0):
            raise DesignError(f"uncertainty {u_um!r} µm is not allowed; give a number ≥ 0")
        if 2 * u_um >= self.width_um:
            raise DesignError(
                f"the guard band 2U = {2 * u_um:.3g} µm leaves nothing of the zone"
                f" {self.describe()}: no part can be proved conforming; use a more"
                " accurate measurement or --decision simple"
            )
        return ProfileZone(self.lower_um + u_um, self.upper_um - u_um, self.on, self.source)


def zone_from_width(
    width_um: float, offset_um: float = 0.0, *, source: str = "", on: ZoneOn = "normal"
) -> ProfileZone:
    """Return the zone of a tolerance t with an offset UZ: [UZ − t/2, UZ + t/2].

    Parameters
    ----------
    width_um : float
        t > 0. [µm]
    offset_um : float
        UZ, > 0 outwards (towards added material). [µm]
    source : str
        Where the value came from, for outputs and messages.
    on : {"normal", "radial"}
        The deviation the zone bounds.

    Raises
    ------
    DesignError
        t ≤ 0, not finite, or an offset that puts the nominal outside the zone (|UZ| ≥
        t/2 is allowed by ISO 1101 but almost always a unit mistake; refused here).

    Examples
    --------
    >>> zone_from_width(30.0).limits_um
    (-15.0, 15.0)
    """
    if not (math.isfinite(width_um) and 0 < width_um <= 2 * MAX_ERROR_UM):
        raise DesignError(
            f"{source or 'profile tolerance'}={width_um!r} µm is not allowed; give a zone"
            f" width t > 0 µm (at most {2 * MAX_ERROR_UM:g})"
        )
    if not math.isfinite(offset_um) or abs(offset_um) >= 0.5 * width_um:
        raise DesignError(
            f"profile offset UZ={offset_um!r} µm is not allowed with t = {width_um:g} µm;"
            f" give |UZ| < t/2 = {0.5 * width_um:g} µm (the nominal must lie in the zone)"
        )
    return ProfileZone(offset_um - 0.5 * width_um, offset_um + 0.5 * width_um, on, source)


def zone_from_limits(
    lower_um: float, upper_um: float, *, source: str = "", on: ZoneOn = "normal"
) -> ProfileZone:
    """Return the zone [lower, upper] given explicitly.

    Parameters
    ----------
    lower_um, upper_um : float
        The limits, lower < upper. [µm]
    source : str
        Where they came from.
    on : {"normal", "radial"}
        The deviation the zone bounds.

    Raises
    ------
    DesignError
        lower ≥ upper, or not finite, or beyond ±10 mm.
    """
    if not (math.isfinite(lower_um) and math.isfinite(upper_um) and lower_um < upper_um):
        raise DesignError(
            f"{source or 'zone'}=[{lower_um:g}, {upper_um:g}] µm is not allowed; give"
            " [lower, upper] with lower < upper"
        )
    return ProfileZone(float(lower_um), float(upper_um), on, source)


@dataclass(frozen=True)
class ZoneSpec:
    """One cam's profile zone as the ``[inspection]`` table writes it.

    A grade is resolved at the cam's size by :meth:`resolve`.

    Attributes
    ----------
    key : str
        The key it was given by, for messages (``inspection.profile_tolerance_a_um``).
    width_um : float or None
        t. [µm]
    grade : str or None
        An IT grade (``"IT7"``): t = that grade at the cam's largest radius.
    offset_um : float
        UZ. [µm]
    limits_um : (float, float) or None
        An explicit zone. [µm]
    """

    key: str
    width_um: float | None = None
    grade: str | None = None
    offset_um: float = 0.0
    limits_um: tuple[float, float] | None = None

    def resolve(self, max_radius_mm: float) -> ProfileZone:
        """Return the zone, a grade taken at the cam's largest radius.

        Parameters
        ----------
        max_radius_mm : float
            The cam's largest radius, the nominal size of a graded profile. [mm]
        """
        if self.limits_um is not None:
            lo, hi = self.limits_um
            return zone_from_limits(lo, hi, source=f"{self.key} = [{lo:g}, {hi:g}]")
        if self.grade is not None:
            from camtol import iso286

            try:
                t = float(iso286.tolerance_um(self.grade, max_radius_mm))
            except ValueError as exc:
                raise DesignError(f"{self.key}={self.grade!r} cannot be applied: {exc}") from None
            src = f"{self.key} = {self.grade!r} ({self.grade} at {max_radius_mm:.4g} mm: {t:g} µm)"
            return zone_from_width(t, self.offset_um, source=src)
        assert self.width_um is not None
        return zone_from_width(
            self.width_um, self.offset_um, source=f"{self.key} = {self.width_um:g}"
        )


@dataclass(frozen=True)
class ZoneTable:
    """An ``[inspection]`` table that states only CMM profile zones (no fixture inputs).

    Attributes
    ----------
    zones : mapping of str to ZoneSpec
        Cam letter (``"A"``, ``"B"``) → its zone.
    table : tuple of (str, object)
        The table as validated, for writing the design back and its hash.
    """

    zones: Mapping[str, ZoneSpec]
    table: tuple[tuple[str, Any], ...] = field(default=(), compare=False, repr=False)

    def to_mapping(self) -> dict[str, Any]:
        """Return the table as validated (field name → value)."""
        return dict(self.table)

    def band_um(self, cam: str) -> tuple[float, float] | None:
        """No fixture tolerance band: a zone-only table (None).

        Parameters
        ----------
        cam : str
            The cam's letter.
        """
        return None

    def profile_zone(self, cam: str) -> ZoneSpec | None:
        """Return cam ``cam``'s profile zone, or None.

        Parameters
        ----------
        cam : str
            The cam's letter.
        """
        return self.zones.get(cam)


def zone_placement(
    dev_mm: FloatArray,
    jac: FloatArray,
    lower_mm: float,
    upper_mm: float,
    *,
    max_rounds: int = 8,
) -> tuple[float, FloatArray]:
    """Best placement of a floating zone: the smallest largest excursion beyond it.

    Solves min s over (δ, s) subject to lower − s ≤ d_i + J_i δ ≤ upper + s (a linear
    programme, HiGHS, on the points nearest the edges, adding violated points until all
    hold); the part lies in the zone for some placement of the free rigid modes iff
    s ≤ 0. With no free mode (a located zone) s is the largest excursion itself.

    Parameters
    ----------
    dev_mm : ndarray
        Deviations at the registration. [mm]
    jac : ndarray, shape (N, p)
        ∂d/∂(free transform parameters); p = 0 for a located zone.
    lower_mm, upper_mm : float
        The zone. [mm]
    max_rounds : int
        Rounds of adding violated points.

    Returns
    -------
    (float, ndarray)
        s [mm] (≤ 0: conforms) and δ (the placement's change, length p).
    """
    p = jac.shape[1]
    excess = float(np.max(np.maximum(dev_mm - upper_mm, lower_mm - dev_mm)))
    if p == 0 or dev_mm.size == 0:
        return excess, np.zeros(p)
    from scipy.optimize import linprog

    n = dev_mm.size
    m = min(n, 400)
    order = np.argsort(dev_mm)
    active = np.unique(np.concatenate([order[:m], order[-m:], np.arange(0, n, max(1, n // m))]))
    cost = np.concatenate([np.zeros(p), [1.0]])  # variables δ, s
    delta = np.zeros(p)
    for _ in range(max_rounds):
        ja = jac[active]
        ones = np.ones((active.size, 1))
        a_ub = np.block([[ja, -ones], [-ja, -ones]])
        b_ub = np.concatenate([upper_mm - dev_mm[active], dev_mm[active] - lower_mm])
        res = linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=[(None, None)] * (p + 1), method="highs")
        if res.status != 0:
            return excess, np.zeros(p)
        delta, s = res.x[:p], float(res.x[p])
        moved = dev_mm + jac @ delta
        viol = np.flatnonzero((moved > upper_mm + s + 1e-12) | (moved < lower_mm - s - 1e-12))
        if viol.size == 0:
            return s, np.asarray(delta, dtype=float)
        active = np.union1d(active, viol)
    moved = dev_mm + jac @ delta
    return float(np.max(np.maximum(moved - upper_mm, lower_mm - moved))), np.asarray(delta)
