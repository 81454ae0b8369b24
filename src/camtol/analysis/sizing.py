"""Sizing: the smallest base radius (and best offset) that makes a design work.

A designer who meets an undercut or a pressure angle past the limit asks one question:
*how large must the cam be?* :func:`minimum_base_radius` answers it by search over the
base radius r_b, every other dimension and the motion program kept, with the analytic
engine (THEORY §2) evaluated on a fixed grid plus every segment boundary (one-sided), for
every cam of the design (both cams of a conjugate pair). A base radius is acceptable when,
on every cam:

- the pressure angle stays within the limit, |φ| ≤ φ_max (THEORY §2: 90° when no limit);
- the profile is not undercut or cusped (the follower's own rule: ρ > 0 for a flat face,
  a convex pitch curve flatter than the roller for a roller; THEORY §2.1, §2.3);
- the smallest *convex* radius of curvature of the profile is at least ``min_radius_mm``
  (a grinding or inspection requirement), and the smallest *concave* radius at least the
  cutter radius (a cutter larger than a concave radius gouges);
- the geometry is defined (an oscillating cam does not reach the follower pivot).

The search climbs a geometric ladder of radii (factors of √2 from 1/2¹⁰ to 2¹⁰ times the
given radius) to the first that works, then bisects between it and the rung below to
``tolerance_mm``: the answer works and the radius one tolerance below it does not. The
ladder matters for oscillating followers, whose pressure angle is not monotone in r_b (the
pivot is fixed) and whose cam must not reach the pivot: a feasible band is found wherever
it lies on the ladder. A band narrower than a rung could be missed; the message then
lists every requirement that failed on the way. With ``optimise_offset`` the offset of a
translating roller follower is chosen at each radius to minimise the largest |φ| (the
classic rise/return balance), by bounded scalar minimisation.

An oscillating follower is sized by its linkage too (``linkage``): its pressure angle is
set by the ratios of the prime radius, the pivot distance f and the arm length l, so the
base radius alone often cannot help (the cam soon reaches the fixed pivot).

- ``"pivot"``: the arm length is kept (the output it drives needs it) and the pivot
  distance f is chosen at each r_b to minimise the largest |φ|: the oscillating
  counterpart of the offset balance, since f places the follower as e does. f is scanned
  over the whole band in which the arm reaches the prime circle (|l − r_p| < f < l + r_p;
  for a flat face |r_b − e| < f < 8 max(|r_b − e|, r_b)) on a 1° grid plus the segment
  boundaries, refined by bounded minimisation, then checked on the full grid.
- ``"scale"``: the linkage lengths (f, l; a flat face's offset; a conjugate pair's two
  arms) grow in proportion to r_b, keeping the design's proportions: the whole mechanism
  is sized. |φ| hardly changes then (it depends on the ratios; only the roller, a bought
  part never changed, breaks the proportion), so this answers the curvature limits.

Left free, the arm would shrink to nothing (a shorter arm always lowers |φ|, the roller
travelling less for the same swing), so it is never optimised; an arm no longer than its
roller's radius (the roller would enclose the pivot) is refused as a requirement.

Why one module: it is one search. The requirements, the radius ladder with its bisection
and the two balances (a translating roller's offset, an oscillating follower's pivot) are
one loop over candidate designs: each balance is evaluated at every radius the search
tries, and the answer's limiting requirement is read from the same assessment.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.kinematics import (
    Kinematics,
    analysis_grid,
    beyond_pressure_angle_limit,
    kinematics,
)
from camtol.analysis.summary import CamGeometry, cam_geometry
from camtol.design.cam_design import CamDesign
from camtol.exceptions import CamtolError, DesignError
from camtol.grid import check_step
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism

__all__ = ["LINKAGE_MODES", "LINKAGE_FIELDS", "sizing_hint", "SizingResult", "minimum_base_radius"]

#: Largest base radius tried before giving up. [mm]
MAX_BASE_RADIUS_MM = 1e5
#: How an oscillating follower's linkage follows the base radius (see the module notes).
LINKAGE_MODES: tuple[str, ...] = ("fixed", "pivot", "scale")
#: The linkage lengths of each oscillating follower kind (file field names).
LINKAGE_FIELDS: dict[str, tuple[str, ...]] = {
    "roller_oscillating": ("pivot_distance_mm", "arm_length_mm"),
    "flat_oscillating": ("pivot_distance_mm", "face_offset_mm"),
    "conjugate": ("pivot_distance_mm", "arm_a_mm", "arm_b_mm"),
}
#: The arms of each kind with a roller, and the field of that roller's radius.
_ARMS: dict[str, tuple[tuple[str, str], ...]] = {
    "roller_oscillating": (("arm_length_mm", "roller_radius_mm"),),
    "conjugate": (("arm_a_mm", "roller_radius_mm"), ("arm_b_mm", "roller_b_radius_mm")),
}


@dataclass(frozen=True)
class SizingResult:
    """Result of :func:`minimum_base_radius`.

    Attributes
    ----------
    base_radius_mm : float
        Smallest base radius that meets every requirement (within ``tolerance_mm``). [mm]
    offset_mm : float or None
        Offset chosen with it (translating roller with ``optimise_offset``), else None. [mm]
    given_base_radius_mm : float
        Base radius of the design as given. [mm]
    limiting : str
        Requirement that sets the size at ``base_radius_mm − tolerance_mm``, e.g.
        ``"pressure angle"``.
    cams : tuple of CamGeometry
        Geometry of each cam at the chosen size.
    pressure_angle_limit_deg, min_radius_mm, cutter_radius_mm : float or None
        The requirements. [deg, mm, mm]
    tolerance_mm : float
        Resolution of the search. [mm]
    linkage : {"fixed", "pivot", "scale"}
        How an oscillating follower's linkage followed the base radius.
    dimensions_mm : dict of str to float
        The linkage lengths chosen with the base radius, by follower field name (e.g.
        ``pivot_distance_mm``, ``arm_length_mm``); empty with ``linkage="fixed"``. [mm]
    given_dimensions_mm : dict of str to float
        The same lengths as given. [mm]
    """

    base_radius_mm: float
    offset_mm: float | None
    given_base_radius_mm: float
    limiting: str
    cams: tuple[CamGeometry, ...]
    pressure_angle_limit_deg: float | None
    min_radius_mm: float | None
    cutter_radius_mm: float | None
    tolerance_mm: float
    linkage: str = "fixed"
    dimensions_mm: dict[str, float] = dataclasses.field(default_factory=dict)
    given_dimensions_mm: dict[str, float] = dataclasses.field(default_factory=dict)


def _cam_kinematics(
    design: CamDesign, theta: FloatArray, left: NDArray[np.bool_]
) -> list[tuple[str, Mechanism, Kinematics]]:
    """(label, mechanism, kinematics) of every cam of the design, unchecked."""
    return [
        (c.label, c.mechanism, kinematics(c.design, theta, left_limit=left, check=False))
        for c in design.cams()
    ]


def _problems(geometry: CamGeometry, kin: Kinematics) -> list[str]:
    """Names of the always-checked requirements one cam violates."""
    problems = []
    if not (np.all(np.isfinite(kin.radius_mm)) and np.all(np.isfinite(kin.pressure_angle_rad))):
        problems.append("undefined geometry")
    if geometry.undercut:
        problems.append("undercut")
    return problems


def _pressure_angle_problem(max_abs_deg: float, limit_deg: float | None) -> bool:
    """Whether a largest |φ| fails the sizing's pressure-angle requirement.

    Parameters
    ----------
    max_abs_deg : float
        Largest |φ| of a cam. [deg]
    limit_deg : float or None
        The limit; None: none beyond the 90° at which no cam works. [deg]

    Returns
    -------
    bool
        True at or beyond 90°, or beyond the limit by more than rounding noise
        (:func:`~camtol.analysis.kinematics.beyond_pressure_angle_limit`: a pressure angle equal to
        the limit meets it, as the reports say).
    """
    return max_abs_deg >= 90.0 or beyond_pressure_angle_limit(max_abs_deg, limit_deg)


def minimum_base_radius(
    design: CamDesign,
    *,
    pressure_angle_limit_deg: float | None = None,
    min_radius_mm: float | None = None,
    cutter_radius_mm: float | None = None,
    optimise_offset: bool = False,
    step_deg: float = 0.1,
    tolerance_mm: float = 1e-3,
    linkage: str = "fixed",
) -> SizingResult:
    """Smallest base radius (and best offset) meeting the pressure-angle and curvature limits.

    Parameters
    ----------
    design : CamDesign
        The design; only its base radius (and with ``optimise_offset`` its offset) changes.
    pressure_angle_limit_deg : float, optional
        Largest allowed |φ|; default the design's ``pressure_angle_limit_deg``, else 90°
        (the follower would jam). [deg]
    min_radius_mm : float, optional
        Smallest allowed convex radius of curvature of the profile. [mm]
    cutter_radius_mm : float, optional
        Radius of the cutter or grinding wheel; concave stretches must be at least this
        flat. [mm]
    optimise_offset : bool
        Choose the offset of a translating roller follower to minimise the largest |φ|.
    step_deg : float
        Grid step of the evaluation (segment boundaries are always included). [deg]
    tolerance_mm : float
        Resolution of the answer. [mm]
    linkage : {"fixed", "pivot", "scale"}
        Oscillating followers: keep the pivot distance and arm length (``"fixed"``),
        choose the pivot distance at each base radius for the smallest largest |φ| with
        the arm kept (``"pivot"``), or scale both with the base radius (``"scale"``).

    Returns
    -------
    SizingResult

    Raises
    ------
    DesignError
        If no base radius up to 1e5 mm meets the requirements (naming the requirement
        that fails, e.g. V ≥ 1 of an oscillating follower, which no size cures), if the
        design has no base radius, or if a requirement is not a positive number.
    """
    check_step(step_deg, name="step_deg", max_points=360_000)
    mech = design.mechanism
    if not hasattr(mech, "base_radius_mm"):
        raise DesignError(f"a {mech.kind} follower has no base radius to size")
    fields = LINKAGE_FIELDS.get(mech.kind)
    if optimise_offset and mech.kind != "roller_translating":
        if fields is not None:
            names = " and ".join(f"follower.{f}" for f in fields)
            raise DesignError(
                f"--optimise-offset is for the offset e of a translating roller follower; a"
                f" {mech.kind} follower is sized with its {names}: use --linkage pivot or"
                " --linkage scale"
            )
        raise DesignError(
            f"--optimise-offset is for a translating roller follower, not a {mech.kind}"
            " follower (a flat face's offset does not change its pressure angle)"
        )
    if linkage not in LINKAGE_MODES:
        raise DesignError(
            f"linkage={linkage!r} is not allowed; allowed: {', '.join(LINKAGE_MODES)}"
        )
    optimisable = mech.kind == "roller_translating"
    if linkage != "fixed" and fields is None:
        raise DesignError(
            f"--linkage {linkage} is for an oscillating follower's pivot distance and arm"
            f" length; a {mech.kind} follower has none"
            + (": use --optimise-offset for its offset e" if optimisable else "")
        )
    limit = pressure_angle_limit_deg
    if limit is None:
        limit = design.pressure_angle_limit_deg
    for name, value, upper in (
        ("pressure_angle_limit_deg", limit, 90.0),
        ("min_radius_mm", min_radius_mm, math.inf),
        ("cutter_radius_mm", cutter_radius_mm, math.inf),
    ):
        if value is not None and not (math.isfinite(value) and 0 < value <= upper):
            raise DesignError(
                f"{name}={value!r} is not allowed; give a positive number"
                + (f" up to {upper:g}" if math.isfinite(upper) else "")
            )
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    if mech.output == "oscillating":
        v = design.program.evaluate(theta, left_limit=left).velocity
        if np.any(v >= 1.0):
            i = int(np.argmax(v))
            raise DesignError(
                f"no base radius helps: the oscillating follower's velocity ratio V reaches"
                f" {v[i]:.4g} at θ={math.degrees(theta[i]):.2f}° (it must stay below 1);"
                " slow the motion (longer segments or a smaller swing)"
            )

    given = float(mech.base_radius_mm)
    given_dims = {f: float(getattr(mech, f)) for f in (fields or ())}
    coarse, coarse_left = analysis_grid(1.0, design.program.boundaries_rad)

    def build(
        rb: float, offset: float | None, dims: dict[str, float] | None = None
    ) -> CamDesign | None:
        changes: dict[str, float] = {"base_radius_mm": rb, **(dims or {})}
        if offset is not None:
            changes["offset_mm"] = offset
        try:
            new = dataclasses.replace(mech, **changes)  # type: ignore[type-var]
        except DesignError:
            return None
        return dataclasses.replace(design, mechanism=new, tolerances=())

    def assess(d: CamDesign) -> tuple[list[CamGeometry], list[str]]:
        sizes, problems = [], []
        for label, m, kin in _cam_kinematics(d, theta, left):
            s = cam_geometry(label, m, kin, pressure_angle_limit_deg=limit)
            sizes.append(s)
            problems += _problems(s, kin)
            if _pressure_angle_problem(s.max_abs_pressure_angle_deg, limit):
                problems.append("pressure angle")
            if min_radius_mm is not None and s.min_convex_radius_mm < min_radius_mm:
                problems.append("convex radius of curvature")
            if cutter_radius_mm is not None and s.min_concave_radius_mm < cutter_radius_mm:
                problems.append("concave radius of curvature (cutter)")
            pivot = getattr(m, "pivot_distance_mm", None)
            if pivot is not None and np.nanmax(kin.radius_mm) >= pivot:
                problems.append("cam reaches the follower pivot")
        mm = d.mechanism
        for arm, roller in _ARMS.get(mm.kind, ()):
            r_f = getattr(mm, roller, None) or float(mm.roller_radius_mm)  # type: ignore[attr-defined]
            if float(getattr(mm, arm)) <= r_f:
                problems.append("roller encloses the follower pivot (arm ≤ roller radius)")
        return sizes, sorted(set(problems))

    def best_offset(rb: float) -> float | None:
        if not optimise_offset:
            return None
        from scipy.optimize import minimize_scalar

        rp = rb + float(mech.roller_radius_mm)  # type: ignore[attr-defined]

        def worst(e: float) -> float:
            d = build(rb, e)
            if d is None:
                return math.inf
            kin = _cam_kinematics(d, theta, left)[0][2]
            pa = np.abs(kin.pressure_angle_rad)
            return float(np.max(pa)) if np.all(np.isfinite(pa)) else math.inf

        res = minimize_scalar(worst, bounds=(-0.9 * rp, 0.9 * rp), method="bounded")
        return float(res.x)

    def scaled(rb: float) -> dict[str, float]:
        if linkage == "scale":
            return {f: v * rb / given for f, v in given_dims.items()}
        return dict(given_dims) if linkage == "pivot" else {}

    def linkage_worst(rb: float, dims: dict[str, float]) -> float:
        """Largest |φ| of every cam on the coarse grid; inf where the linkage fails."""
        d = build(rb, None, dims)
        if d is None:
            return math.inf
        worst = 0.0
        with np.errstate(all="ignore"):  # a failing linkage gives inf/NaN: judged below
            cams = _cam_kinematics(d, coarse, coarse_left)
        for label, m, kin in cams:
            pa = np.abs(kin.pressure_angle_rad)
            pivot = getattr(m, "pivot_distance_mm", None)
            reach = pivot is not None and float(np.nanmax(kin.radius_mm)) >= pivot
            if reach or not (np.all(np.isfinite(pa)) and np.all(np.isfinite(kin.radius_mm))):
                return math.inf
            if cam_geometry(label, m, kin, pressure_angle_limit_deg=limit).undercut:
                return math.inf  # a pivot that undercuts is no answer, whatever its |φ|
            worst = max(worst, float(np.max(pa)))
        return worst

    def pivot_range(rb: float, dims: dict[str, float]) -> tuple[float, float]:
        """Pivot distances at which the follower can touch the base circle. [mm]"""
        if mech.kind == "flat_oscillating":
            low = abs(rb - dims["face_offset_mm"])
            return low, 8.0 * max(low, rb)
        arm = dims["arm_length_mm" if mech.kind == "roller_oscillating" else "arm_a_mm"]
        rp = rb + float(mech.roller_radius_mm)  # type: ignore[attr-defined]
        return abs(arm - rp), arm + rp

    def best_linkage(rb: float) -> dict[str, float]:
        start = scaled(rb)
        if linkage != "pivot":
            return start
        from scipy.optimize import minimize_scalar

        lo, hi = pivot_range(rb, start)

        def at(u: float) -> dict[str, float]:
            return {**start, "pivot_distance_mm": lo + u * (hi - lo)}

        # Scan the whole band, then refine the best bracket (the largest |φ| is unimodal
        # near its minimum, not over the band).
        us = np.linspace(0.01, 0.99, 33)
        own = (start["pivot_distance_mm"] - lo) / (hi - lo)  # the given f, when in the band
        if 0.0 < own < 1.0:
            us = np.sort(np.append(us, own))
        vals = np.array([linkage_worst(rb, at(float(u))) for u in us])
        if not np.any(np.isfinite(vals)):
            return start
        k = int(np.argmin(vals))
        a, b = float(us[max(k - 1, 0)]), float(us[min(k + 1, us.size - 1)])
        res = minimize_scalar(  # a large finite value for a failing f keeps Brent's steps finite
            lambda u: min(linkage_worst(rb, at(float(u))), 1e3),
            bounds=(a, b),
            method="bounded",
            options={"xatol": 1e-6},
        )
        return at(float(res.x) if res.fun <= vals[k] else float(us[k]))

    def ok(rb: float) -> tuple[bool, list[str], list[CamGeometry], float | None]:
        e = best_offset(rb)
        dims = best_linkage(rb)
        d = build(rb, e, dims)
        chosen[rb] = dims
        if d is None:
            return False, ["dimensions impossible"], [], e
        sizes, problems = assess(d)
        if problems and linkage == "pivot":  # the coarse grid misled: the given f may do
            own = build(rb, e, scaled(rb))
            if own is not None:
                own_sizes, own_problems = assess(own)
                if not own_problems:
                    chosen[rb] = scaled(rb)
                    return True, [], own_sizes, e
        return not problems, problems, sizes, e

    chosen: dict[float, dict[str, float]] = {}
    res = _search(design, given, ok, tolerance_mm, limit, min_radius_mm, cutter_radius_mm)
    if linkage == "fixed":
        return res
    return dataclasses.replace(
        res,
        linkage=linkage,
        dimensions_mm=chosen[res.base_radius_mm],
        given_dimensions_mm=given_dims,
    )


def _search(
    design: CamDesign,
    given: float,
    ok: Callable[[float], tuple[bool, list[str], list[CamGeometry], float | None]],
    tolerance_mm: float,
    limit: float | None,
    min_radius_mm: float | None,
    cutter_radius_mm: float | None,
) -> SizingResult:
    """Scan radii on a geometric ladder, bisect above the first that works, check it."""
    ladder = given * 2.0 ** (np.arange(-40, 41) / 2.0)
    ladder = ladder[(ladder >= tolerance_mm) & (ladder <= MAX_BASE_RADIUS_MM)]
    lo, hi = 0.0, None
    limiting: list[str] = []
    seen: list[str] = []
    for r in ladder:
        good, problems, _, _ = ok(float(r))
        if good:
            hi = float(r)
            break
        lo, limiting = float(r), problems
        seen += problems
    if hi is None:
        reasons = ", ".join(sorted(set(seen))) or "no radius tried"
        stated = [
            f"{what} {value:g}{unit}"
            for what, value, unit in (
                ("|φ| ≤", limit, "°"),
                ("convex ρ ≥", min_radius_mm, " mm"),
                ("cutter radius", cutter_radius_mm, " mm"),
            )
            if value is not None
        ]
        raise DesignError(
            f"no base radius from {ladder[0]:.3g} to {ladder[-1]:.3g} mm works for design"
            f" {design.name!r} ({reasons}); change the motion (longer segments, smaller"
            " lift), the follower or the limits" + (f" ({', '.join(stated)})" if stated else "")
        )
    while hi - lo > tolerance_mm:
        mid = 0.5 * (lo + hi)
        good, problems, _, _ = ok(mid)
        if good:
            hi = mid
        else:
            lo, limiting = mid, problems
    _, _, sizes, offset = ok(hi)
    return SizingResult(
        base_radius_mm=hi,
        offset_mm=offset,
        given_base_radius_mm=given,
        limiting=", ".join(limiting) if limiting else "none (any positive radius works)",
        cams=tuple(sizes),
        pressure_angle_limit_deg=limit,
        min_radius_mm=min_radius_mm,
        cutter_radius_mm=cutter_radius_mm,
        tolerance_mm=tolerance_mm,
    )


def sizing_hint(design: CamDesign) -> str | None:
    """One sentence saying which base radius would make a failing design work, or None.

    Parameters
    ----------
    design : CamDesign
        A design that failed for undercut or pressure angle.

    Returns
    -------
    str or None
        E.g. "a base radius of at least 24.66 mm would work (camtol size)", or None when
        no base radius helps or the follower has none.
    """
    try:
        r = minimum_base_radius(design, tolerance_mm=0.01)
    except CamtolError:
        return None
    return (
        f"a base radius of at least {math.ceil(r.base_radius_mm * 100) / 100:g} mm would work"
        f" (given {r.given_base_radius_mm:g} mm; limited by {r.limiting}; see `camtol size`)"
    )
