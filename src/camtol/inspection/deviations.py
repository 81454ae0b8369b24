"""Profile deviations of a registered CMM scan and the verdict (THEORY §0, §2).

For every point, after registration (:mod:`camtol.inspection.registration`), in the cam
frame:

- Δn: the signed distance to the exact closest point of the *analytic* profile
  (> 0 outside: material added, THEORY §0), along the profile's outward normal;
- Δr: the radial deviation |p| − |P| with P the profile point on the ray O2p;
- the profile form: the zone width max Δn − min Δn, and the minimum-zone value, the
  smallest width over the transforms the datum leaves free (a linear programme on the
  linearised deviations Δn + J δ, solved by :func:`scipy.optimize.linprog`);
- the verdict against the profile zone (:mod:`camtol.inspection.zone`) and the
  polar-angle intervals where points fall outside it. Outliers (reported by index) do
  not enter the verdict.

The zone is the ISO 1101 profile of a line stated in the design's ``[inspection]`` table
(``profile_tolerance_um`` = t: ±t/2 along the normal, optional UZ offset, or
``limits_um``), or one given explicitly (``--tolerance-um``). It is never derived from the
error-analysis tolerances (``tolerances.r`` is a deviation of a dimension, THEORY §3.6,
not a zone; issue 31). A zone on Δr (``--tolerance-on dr``) is a radial band, not ISO
1101, and is labelled so. Without a datum the zone **floats**: the verdict asks whether
some placement of the fitted rigid modes puts every point in it
(:func:`~camtol.inspection.zone.zone_placement`); a located datum fixes it.

Why one module: every part turns one registered scan into its deviations and verdict:
the cam's tabulated profile and its zone, the stylus check, the deviations Δn and Δr, the
form and the minimum zone, the zone's placement and the failing angles of one
:class:`CmmInspection`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError, InputFileError
from camtol.inspection.cmm import CamLabel, Scan, check_coverage
from camtol.inspection.profile_table import ProfileTable, profile_table
from camtol.inspection.registration import Datum, Registration, register
from camtol.inspection.zone import ProfileZone, ZoneSpec, zone_from_limits, zone_placement
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism

__all__ = [
    "CamProfile",
    "CmmInspection",
    "cam_profile",
    "check_stylus",
    "inspect_scan",
    "minimum_zone",
    "ToleranceKind",
    "design_zone",
    "profile_tolerance",
]

ToleranceKind = Literal["normal", "radial"]

#: A scan whose points lie further than this from the nominal (90th percentile of |Δn|,
#: after registration) is refused as a scan of another part, unless the tolerance is
#: wider. [mm]
IMPLAUSIBLE_MM = 1.0


@dataclass(frozen=True)
class CamProfile:
    """One cam of a design, ready for inspection.

    Attributes
    ----------
    label : {"A", "B"}
        Which cam (a single cam is ``"A"``).
    design : CamDesign
        The single-contact design of that cam (its mechanism drives only this cam).
    table : ProfileTable
        Its nominal profile, tabulated for fast exact queries.
    """

    label: str
    design: CamDesign
    table: ProfileTable

    @property
    def mechanism(self) -> Mechanism:
        """The cam's follower mechanism."""
        return self.design.mechanism


def cam_profile(design: CamDesign, cam: CamLabel = "A") -> CamProfile:
    """Return cam ``cam`` of a design with its tabulated nominal profile.

    Parameters
    ----------
    design : CamDesign
        Any design; for a conjugate pair cam "A" or "B".
    cam : {"A", "B"}
        Which cam; "B" only for a conjugate pair.

    Raises
    ------
    DesignError
        Cam "B" of a single cam, or an unknown label.
    """
    one = design.cam(cam)
    single = one.design
    return CamProfile(one.letter, single, profile_table(single.mechanism, single.program))


def check_stylus(profile: CamProfile, stylus_radius_mm: float) -> None:
    """Raise if a probe ball of this radius cannot touch the cam's profile everywhere.

    On a concave stretch whose radius of curvature is smaller than the ball's, the ball
    bridges the hollow: its centres there are not the profile offset by the radius, so a
    simulated scan would be impossible and a measured one wrongly compensated.

    Parameters
    ----------
    profile : CamProfile
        The cam.
    stylus_radius_mm : float
        Probe-ball radius (0: surface points, nothing to check). [mm]

    Raises
    ------
    GeometryError
        Naming the cam, the angle, the concave radius there and the largest ball that fits.
    """
    if not stylus_radius_mm > 0:
        return
    from camtol.analysis.offset import smallest_concave_radius

    tight = smallest_concave_radius(profile.design)
    if tight is not None and tight[0] < stylus_radius_mm:
        rho, at = tight
        raise GeometryError(
            f"a stylus ball of radius {stylus_radius_mm:g} mm cannot touch cam"
            f" {profile.label}'s profile at θ={at:.2f}°, where it is concave with a radius of"
            f" curvature of {rho:.4g} mm (the ball bridges the hollow); use a ball of"
            f" radius at most {rho:.4g} mm"
        )


def design_zone(design: CamDesign, cam: CamLabel = "A") -> ProfileZone | None:
    """Return the CMM profile zone the design's ``[inspection]`` table states, or None.

    A grade is resolved at the cam's largest radius. The error-analysis tolerances
    (``tolerances.r``, ``tolerances.n``) are deviations, not zones, and are not used
    (issue 31); a pair's fixture bands (``tolerance_a_um``) are not a CMM zone either.

    Parameters
    ----------
    design : CamDesign
        The design (for a conjugate pair, the pair's design).
    cam : {"A", "B"}
        Which cam.

    Returns
    -------
    ProfileZone or None
        The zone on Δn, or None when the table states none.
    """
    table = design.inspection
    if table is None:
        return None
    spec = table.profile_zone(design.cam(cam).letter)
    if not isinstance(spec, ZoneSpec):
        return None
    one = design.cam(cam)
    r_max = 0.0
    if spec.grade is not None:
        from camtol.analysis.kinematics import kinematics

        theta = np.linspace(0.0, 2 * math.pi, 3601)
        r_max = float(kinematics(one.design, theta, check=False).radius_mm.max())
    return spec.resolve(r_max)


def profile_tolerance(
    design: CamDesign, cam: CamLabel = "A"
) -> tuple[float, float, ToleranceKind] | None:
    """Return the design's CMM zone as (lower, upper, ``"normal"``), or None.

    Kept for callers of the earlier API; see :func:`design_zone`.

    Parameters
    ----------
    design : CamDesign
        The design.
    cam : {"A", "B"}
        Which cam.
    """
    zone = design_zone(design, cam)
    return None if zone is None else (zone.lower_um, zone.upper_um, "normal")


@dataclass(frozen=True)
class CmmInspection:
    """Deviations and verdict of one scanned cam.

    Attributes
    ----------
    cam : str
        ``"A"`` or ``"B"``.
    source : str
        The scan's file name.
    registration : Registration
        Placement of the cam frame in the CMM frame, with uncertainties and outliers.
    index : ndarray of int
        Data row (0-based, in the file) of each profile point (bore points and the other
        cam's points excluded).
    x_mm, y_mm : ndarray
        Points in the cam frame. [mm]
    theta_deg : ndarray
        Polar angle of each point in the cam frame, in [0, 360). [deg]
    param_rad : ndarray
        Profile parameter (cam angle of contact) of each point's closest point. [rad]
    dn_um, dr_um : ndarray
        Normal and radial deviations. [µm]
    outlier : ndarray of bool
        Points reported as outliers (not in the verdict).
    zone : ProfileZone
        The profile zone judged against (limits, width, Δn or Δr, where from).
    floating : bool
        Whether the zone floats (the datum leaves rigid modes to fit) or is located.
    excess_um : float
        Largest excursion beyond the zone at the zone's best placement (≤ 0: inside).
        [µm]
    form_um : float
        Zone width max Δn − min Δn of the points kept. [µm]
    min_zone_um : float
        Minimum-zone width over the transforms the datum leaves free. [µm]
    failing_intervals_deg : list of (float, float)
        Polar-angle intervals with points outside the acceptance zone (end < start:
        wraps). [deg]
    decision : {"simple", "guard-band"}
        The decision rule (ISO 14253-1).
    u_um : float
        Expanded uncertainty U of the deviations judged: the CMM's and the located
        registration's, combined (0 under ``simple`` without one given). [µm]
    acceptance : ProfileZone
        The zone the verdict uses: the zone itself (``simple``) or shrunk by U on both
        sides (``guard-band``).
    """

    cam: str
    source: str
    registration: Registration
    index: NDArray[np.intp]
    x_mm: FloatArray
    y_mm: FloatArray
    theta_deg: FloatArray
    param_rad: FloatArray
    dn_um: FloatArray
    dr_um: FloatArray
    outlier: NDArray[np.bool_]
    zone: ProfileZone
    floating: bool
    excess_um: float
    form_um: float
    min_zone_um: float
    failing_intervals_deg: list[tuple[float, float]]
    decision: str = "simple"
    u_um: float = 0.0
    acceptance: ProfileZone | None = None

    @property
    def tolerance_um(self) -> tuple[float, float]:
        """The zone's limits [lower, upper]. [µm]"""
        return self.zone.limits_um

    @property
    def tolerance_kind(self) -> str:
        """``"normal"`` (Δn, ISO 1101) or ``"radial"`` (Δr band)."""
        return self.zone.on

    @property
    def passed(self) -> bool:
        """True when every point kept lies inside the tolerance."""
        return not self.failing_intervals_deg

    @property
    def kept(self) -> NDArray[np.bool_]:
        """Points that are not outliers."""
        return ~self.outlier

    @property
    def max_dn_um(self) -> float:
        """Largest Δn of the points kept. [µm]"""
        return float(np.max(self.dn_um[self.kept]))

    @property
    def min_dn_um(self) -> float:
        """Smallest Δn of the points kept. [µm]"""
        return float(np.min(self.dn_um[self.kept]))


def minimum_zone(dn_mm: FloatArray, jac: FloatArray, *, max_rounds: int = 8) -> float:
    """Smallest width max − min of Δn + J δ over δ (linearised transforms). [mm]

    Solves min (u − l) s.t. l ≤ Δn_i + J_i δ ≤ u by :func:`scipy.optimize.linprog`
    (HiGHS) on the points nearest the zone's edges, adding violated points until all hold.

    Parameters
    ----------
    dn_mm : ndarray
        Deviations at the registration. [mm]
    jac : ndarray, shape (N, p)
        ∂Δn/∂(transform parameters); p = 0 gives the zone width itself.
    max_rounds : int
        Rounds of adding violated points.
    """
    if jac.shape[1] == 0:
        return float(np.max(dn_mm) - np.min(dn_mm))
    from scipy.optimize import linprog

    n, p = jac.shape
    m = min(n, 400)
    order = np.argsort(dn_mm)
    active = np.unique(np.concatenate([order[:m], order[-m:], np.arange(0, n, max(1, n // m))]))
    cost = np.concatenate([np.zeros(p), [-1.0, 1.0]])  # variables δ, l, u
    width = float(np.max(dn_mm) - np.min(dn_mm))
    for _ in range(max_rounds):
        ja = jac[active]
        ones = np.ones((active.size, 1))
        a_ub = np.block([[ja, np.zeros_like(ones), -ones], [-ja, ones, np.zeros_like(ones)]])
        b_ub = np.concatenate([-dn_mm[active], dn_mm[active]])
        res = linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=[(None, None)] * (p + 2), method="highs")
        if res.status != 0:
            return width
        delta, lo, hi = res.x[:p], res.x[p], res.x[p + 1]
        moved = dn_mm + jac @ delta
        viol = np.flatnonzero((moved > hi + 1e-12) | (moved < lo - 1e-12))
        if viol.size == 0:
            return float(hi - lo)
        active = np.union1d(active, viol)
    moved = dn_mm + jac @ delta
    return float(np.max(moved) - np.min(moved))


def _intervals(theta_deg: FloatArray, fail: NDArray[np.bool_]) -> list[tuple[float, float]]:
    """Polar-angle intervals of consecutive failing points (sorted by angle; wraps)."""
    if not np.any(fail):
        return []
    order = np.argsort(theta_deg, kind="stable")
    th, f = theta_deg[order], fail[order]
    if np.all(f):
        return [(0.0, 360.0)]
    starts = np.flatnonzero(f & ~np.roll(f, 1))
    ends = np.flatnonzero(f & ~np.roll(f, -1))
    out = [(float(th[s]), float(th[e])) for s, e in zip(starts, ends, strict=True)]
    if ends[0] < starts[0]:  # the run through 0° is split: join its two halves
        out = [(float(th[starts[-1]]), float(th[ends[0]]))] + [
            (float(th[s]), float(th[e])) for s, e in zip(starts[:-1], ends[1:], strict=True)
        ]
    return sorted(out)


def inspect_scan(
    design: CamDesign,
    scan: Scan,
    *,
    cam: CamLabel = "A",
    datum: Datum | None = None,
    tolerance_um: tuple[float, float] | None = None,
    tolerance_kind: ToleranceKind | None = None,
    profile: CamProfile | None = None,
    zone: ProfileZone | None = None,
    decision: str = "simple",
    u_cmm_um: float | None = None,
) -> CmmInspection:
    """Register a scan to the nominal cam and compute its deviations and verdict.

    Parameters
    ----------
    design : CamDesign
        The design (for a conjugate pair, the pair).
    scan : Scan
        The measured points (surface points; see :func:`~camtol.inspection.cmm.read_scan`).
    cam : {"A", "B"}
        Which cam of a conjugate pair the scan is.
    datum : Datum, optional
        Registration (default: best fit over rotation and translation).
    tolerance_um : (float, float), optional
        An explicit zone [lower, upper] (default: the design's zone). [µm]
    tolerance_kind : {"normal", "radial"}, optional
        Whether ``tolerance_um`` bounds Δn (default) or Δr (a radial band, not ISO 1101).
    profile : CamProfile, optional
        The cam's tabulated profile, when already built (:func:`cam_profile`).
    zone : ProfileZone, optional
        The zone (instead of ``tolerance_um``; default: the design's,
        :func:`design_zone`).
    decision : {"simple", "guard-band"}
        ISO 14253-1 decision rule: ``guard-band`` shrinks the zone by U on both sides.
    u_cmm_um : float, optional
        The CMM's expanded uncertainty U (k = 2), combined with the located
        registration's (a fitted bore centre); required by ``guard-band``. [µm]

    Returns
    -------
    CmmInspection

    Raises
    ------
    InputFileError
        Points that do not go round the cam, or that lie implausibly far from the
        nominal after registration (a scan of another cam).
    DesignError
        No profile zone in the design and none given; ``guard-band`` without
        ``u_cmm_um``, or a guard band that leaves no zone.
    GeometryError
        The scan's stylus ball is larger than a concave radius of the cam
        (:func:`check_stylus`).
    """
    if zone is None and tolerance_um is not None:
        kind = tolerance_kind or "normal"
        if kind not in ("normal", "radial"):
            raise DesignError(f"tolerance kind {kind!r} is not allowed; use normal or radial")
        zone = zone_from_limits(tolerance_um[0], tolerance_um[1], source="--tolerance-um", on=kind)
    elif zone is not None and tolerance_kind is not None and tolerance_kind != zone.on:
        zone = ProfileZone(zone.lower_um, zone.upper_um, tolerance_kind, zone.source)
    if decision not in ("simple", "guard-band"):
        raise DesignError(f"decision={decision!r} is not allowed; use simple or guard-band")
    if decision == "guard-band" and u_cmm_um is None:
        raise DesignError(
            "--decision guard-band needs the measurement uncertainty: give --u-cmm-um U"
            " (the CMM's expanded uncertainty, µm), or use --decision simple"
        )
    if u_cmm_um is not None and not (math.isfinite(u_cmm_um) and u_cmm_um >= 0):
        raise DesignError(f"--u-cmm-um={u_cmm_um!r} is not allowed; give a number ≥ 0 µm")
    return _inspect_scan(design, scan, cam, datum, zone, profile, True, decision, u_cmm_um or 0.0)


def _inspect_scan(
    design: CamDesign,
    scan: Scan,
    cam: CamLabel,
    datum: Datum | None,
    zone: ProfileZone | None,
    profile: CamProfile | None,
    hint_other_cam: bool,
    decision: str = "simple",
    u_cmm_um: float = 0.0,
) -> CmmInspection:
    """Do :func:`inspect_scan`, trying the other cam of a pair only with ``hint_other_cam``.

    A refused scan of a pair's cam is tried on the other cam for the hint; that try must
    not try back, or a scan of neither cam recurses between the two without end.
    """
    datum = Datum() if datum is None else datum
    if datum.keyway_deg is not None and datum.point_mm is None:  # the scan's keyway feature
        kp = scan.keyway_point()
        if kp is None:
            raise InputFileError(
                f"{scan.source}: --keyway-deg needs points flagged keyway=1 in the scan"
            )
        import dataclasses

        datum = dataclasses.replace(datum, point_mm=kp, point_angle_deg=datum.keyway_deg)
    prof = cam_profile(design, cam) if profile is None else profile
    check_stylus(prof, scan.stylus_radius_mm)  # compensated points assume the ball fits
    if zone is None:
        zone = design_zone(design, cam)
    if zone is None:
        raise DesignError(
            f"the design {design.name!r} states no profile zone for cam {prof.label}"
            " ([inspection] profile_tolerance_um, ISO 1101); give --tolerance-um T (zone"
            " width, ±T/2) or LOWER,UPPER"
        )
    tol = zone.limits_um
    kind: str = zone.on
    px, py, index = scan.profile_points()
    bx, by = scan.x_mm[scan.bore], scan.y_mm[scan.bore]
    centre = (0.0, 0.0)
    if datum.mode == "fit":
        from camtol.inspection.registration import area_centroid

        centre = area_centroid(px, py)
    elif datum.mode == "centre" and datum.centre_mm is not None:
        centre = datum.centre_mm
    elif datum.mode == "bore" and bx.size >= 3:
        from camtol.inspection.cmm import fit_circle

        cx, cy, _ = fit_circle(bx, by)
        centre = (cx, cy)
    check_coverage(scan.source, px - centre[0], py - centre[1])

    def wrong() -> str:
        hint = _other_cam_hint(design, scan, prof.label, datum, zone) if hint_other_cam else ""
        return (
            f"{scan.source}: the points do not match the nominal profile of cam {prof.label}"
            f" of {design.name!r}{hint}"
        )

    try:
        reg = register(prof.table, px, py, datum, bore_x_mm=bx, bore_y_mm=by, source=scan.source)
        pts = reg.points
        if pts is None:
            xc, yc = reg.to_cam(px, py)
            t, dn, nx, ny = prof.table.closest(xc, yc)
        else:
            xc, yc, t, dn, nx, ny = pts.x_mm, pts.y_mm, pts.param_rad, pts.dn_mm, pts.nx, pts.ny
    except GeometryError:
        raise InputFileError(
            f"{wrong()} (no closest profile point found for some): is this a scan of that cam?"
        ) from None
    outlier = np.zeros(px.size, dtype=bool)
    outlier[reg.outliers] = True
    kept = ~outlier
    limit = max(IMPLAUSIBLE_MM, 5e-3 * max(abs(tol[0]), abs(tol[1])))
    p90 = float(np.quantile(np.abs(dn[kept]), 0.9))
    if p90 > limit:
        raise InputFileError(
            f"{wrong()}: after registration 10% of them lie more than {p90:.3g} mm from it,"
            f" beyond any plausible tolerance ({limit:g} mm): is this a scan of that cam?"
        )
    dr = prof.table.radial(xc, yc, t)
    jac = _free_jacobian(reg, xc, yc, nx, ny)
    dn_um, dr_um = dn * 1e3, dr * 1e3
    theta_deg = np.mod(np.degrees(np.arctan2(yc, xc)), 360.0)
    dev_um = dn_um if kind == "normal" else dr_um
    # The located registration's uncertainty (a fitted bore centre moves every Δn by up
    # to |δd|) adds to the CMM's; fitted modes float with the zone and add nothing.
    reg_u_um = 0.0
    if reg.mode == "bore" and "translation" not in reg.fitted:
        reg_u_um = 2.0 * 1e3 * math.hypot(reg.u_dx_mm, reg.u_dy_mm)
    u_um = math.hypot(u_cmm_um, reg_u_um)
    accept = zone.with_guard_band(u_um) if decision == "guard-band" else zone
    floating = kind == "normal" and jac.shape[1] > 0
    if floating:  # ISO 1101 floating zone: best placement of the free rigid modes
        excess_mm, delta = zone_placement(
            dn[kept], jac[kept], accept.lower_um * 1e-3, accept.upper_um * 1e-3
        )
        placed_um = dev_um + 1e3 * (jac @ delta)
    else:
        placed_um = dev_um
        excess_mm = 1e-3 * float(
            np.max(np.maximum(dev_um[kept] - accept.upper_um, accept.lower_um - dev_um[kept]))
        )
    fail = kept & ((placed_um < accept.lower_um - 1e-9) | (placed_um > accept.upper_um + 1e-9))
    if excess_mm <= 0.0:
        fail[:] = False
    return CmmInspection(
        cam=prof.label,
        source=scan.source,
        registration=reg,
        index=scan.rows[index],
        x_mm=xc,
        y_mm=yc,
        theta_deg=theta_deg,
        param_rad=t,
        dn_um=dn_um,
        dr_um=dr_um,
        outlier=outlier,
        zone=zone,
        floating=floating,
        excess_um=1e3 * excess_mm,
        form_um=float(np.ptp(dn_um[kept])),
        min_zone_um=1e3 * minimum_zone(dn[kept], jac[kept]),
        failing_intervals_deg=_intervals(theta_deg, fail),
        decision=decision,
        u_um=u_um,
        acceptance=accept,
    )


def _other_cam_hint(
    design: CamDesign, scan: Scan, label: str, datum: Datum, tol: ProfileZone
) -> str:
    """For a conjugate pair: ' (it matches cam X)' when the scan fits the other cam."""
    for other in design.cams():
        if other.letter == label:
            continue
        try:
            _inspect_scan(design, scan, other.letter, datum, tol, None, False)  # type: ignore[arg-type]
        except (InputFileError, GeometryError):
            continue
        return f" (it matches cam {other.letter}: use --cam {other.letter})"
    return ""


def _free_jacobian(
    reg: Registration, xc: FloatArray, yc: FloatArray, nx: FloatArray, ny: FloatArray
) -> FloatArray:
    """∂Δn/∂(rotation, translation) for the parameters the datum leaves free."""
    cols = []
    if "rotation" in reg.fitted:
        cols.append(nx * yc - ny * xc)
    if "translation" in reg.fitted:
        cols += [-nx, -ny]  # in the cam frame the translation's directions are free
    return np.stack(cols, axis=1) if cols else np.zeros((xc.size, 0))
