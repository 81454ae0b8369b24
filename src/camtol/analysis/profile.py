r"""Adaptive sampling of the analytic cam profile within a chordal tolerance (THEORY §2).

The profile (and, for roller followers, the pitch curve; for conjugate designs both cams;
on request the cutter-centre path) is sampled *adaptively*: the vertices lie exactly on
the analytic curve and are spaced by its radius of curvature so that every chord deviates
from the curve by less than a tolerance (0.1 µm by default). The spacing comes from the
sagitta of a circular arc,

.. math:: h = ρ\left(1 - \cos\frac{Δs}{2ρ}\right) \approx \frac{Δs^2}{8ρ},

and is then *verified*: the analytic curve is evaluated at the quarter points of every
chord, and any chord whose deviation exceeds the tolerance is bisected until none does.

Coordinates are in the cam frame X-Y of THEORY §0 (origin at the cam pivot O2, θ measured
counterclockwise from the cam's reference radial; for oscillating followers from the line
of centres), in millimetres.

The sampled curves (:func:`profile_points`) are written by :mod:`camtol.report.export`
(CSV, DXF, SVG) and checked by :mod:`camtol.verify`; this module is part of the core.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.kinematics import analysis_grid, contact_jets
from camtol.design.cam_design import CamDesign
from camtol.exceptions import ExportError, GeometryError, UndercutError
from camtol.jet import FloatArray, Jet, JetLike

__all__ = [
    "DEFAULT_TOLERANCE_MM",
    "MAX_TOOL_RADIUS_MM",
    "CurveSpec",
    "ProfileCurve",
    "ProfilePoints",
    "curve_specs",
    "profile_points",
    "profile_table",
]

#: Default chordal tolerance of exported polylines (0.1 µm). [mm]
DEFAULT_TOLERANCE_MM = 1e-4

#: Largest cutter, grinding-wheel or wire-EDM offset radius accepted for a tool path
#: (100 m: far beyond any real tool, and room for limit studies such as a cylinder tending
#: to a flat tool). The path's length, and the number of its vertices at a given chordal
#: tolerance, grow with the radius: a mistyped 1e30 gave "the curve is undefined" for a
#: CSV, a G-code run that exhausted the memory, and scallops of 1e18 µm. [mm]
MAX_TOOL_RADIUS_MM = 100_000.0

#: Step of the grid on which the curvature is sampled to plan the spacing. [deg]
_PLAN_STEP_DEG = 0.05
#: Largest cam-angle step between two vertices, whatever the curvature. [deg]
_MAX_STEP_DEG = 1.0
#: Planned chords use at most this fraction of the allowed arc length.
_SAFETY = 0.8
#: Bisection passes allowed for the verification.
_MAX_PASSES = 40
#: Most vertices of one exported curve; more means the tolerance is too fine for the cam's
#: size (bounds the work and the file). [vertices]
MAX_VERTICES = 2_000_000


@dataclass(frozen=True)
class _Sample:
    """A planar curve at some cam angles: point, unit tangent, speed and curvature radius."""

    x: FloatArray
    y: FloatArray
    tx: FloatArray
    ty: FloatArray
    speed: FloatArray  # |dP/dθ| [mm/rad]
    rho: FloatArray  # signed radius of curvature, > 0 turning counterclockwise [mm]


CurveFunction = Callable[[FloatArray, NDArray[np.bool_]], _Sample]


@dataclass(frozen=True)
class CurveSpec:
    """A curve to sample: layer name, description and its evaluator over θ."""

    layer: str
    description: str
    evaluate: CurveFunction


@dataclass(frozen=True)
class ProfileCurve:
    """One exported closed curve, sampled adaptively.

    Attributes
    ----------
    layer : str
        Layer (DXF) or group (SVG) name, e.g. ``CAM_PROFILE``, ``PITCH_CURVE``.
    description : str
        What the curve is.
    theta_rad : ndarray
        Cam angle of each vertex, increasing over [0, 2π); the curve is closed (the last
        vertex joins the first). [rad]
    x_mm, y_mm : ndarray
        Vertices in the cam frame, exactly on the analytic curve. [mm]
    max_deviation_mm : float
        Largest deviation of the analytic curve from the polygon found by the
        verification (evaluated at the quarter points of every chord). [mm]
    """

    layer: str
    description: str
    theta_rad: FloatArray
    x_mm: FloatArray
    y_mm: FloatArray
    max_deviation_mm: float


@dataclass(frozen=True)
class ProfilePoints:
    """Every curve exported for a design, each below the chordal tolerance.

    Attributes
    ----------
    design_name : str
        Name of the design.
    tolerance_mm : float
        Requested chordal tolerance. [mm]
    cutter_radius_mm : float or None
        Cutter radius of the cutter-centre path, if one was asked for. [mm]
    curves : tuple of ProfileCurve
        The cam profile first (cam A for a conjugate pair), then the others.
    """

    design_name: str
    tolerance_mm: float
    cutter_radius_mm: float | None
    curves: tuple[ProfileCurve, ...]

    @property
    def profile(self) -> ProfileCurve:
        """The cam profile (cam A's for a conjugate pair)."""
        return self.curves[0]

    def curve(self, layer: str) -> ProfileCurve:
        """Return the curve on ``layer``.

        Parameters
        ----------
        layer : str
            Layer name, e.g. ``"CAM_PROFILE"``.

        Returns
        -------
        ProfileCurve
            The first curve on that layer.

        Raises
        ------
        KeyError
            If no curve has that layer name.
        """
        for c in self.curves:
            if c.layer == layer:
                return c
        raise KeyError(f"no curve on layer {layer!r}; layers: {[c.layer for c in self.curves]}")


# ---------------------------------------------------------------------------------------
# Curves of a design
# ---------------------------------------------------------------------------------------
def _from_jets(x: JetLike, y: JetLike) -> _Sample:
    if not (isinstance(x, Jet) and isinstance(y, Jet)):  # pragma: no cover - defensive
        raise TypeError("expected jets")
    speed = np.hypot(x.d1, y.d1)
    cross = x.d1 * y.d2 - y.d1 * x.d2
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = speed**3 / cross
        tx, ty = x.d1 / speed, y.d1 / speed
    return _Sample(x.v, y.v, tx, ty, speed, rho)


def _offset(base: _Sample, distance_mm: float, what: str) -> _Sample:
    """Offset a counterclockwise curve by ``distance_mm`` along its outward normal."""
    nx, ny = base.ty, -base.tx
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = np.where(np.isfinite(base.rho), (base.rho + distance_mm) / base.rho, 1.0)
        rho = base.rho + distance_mm
    if np.any(ratio <= 0):
        raise UndercutError(
            f"the {what} of radius {distance_mm:g} mm cannot follow the profile: the concave"
            f" profile radius of curvature {float(np.min(np.abs(base.rho[ratio <= 0]))):.4g} mm"
            f" is smaller than it (the path loops; the cutter would gouge)"
        )
    return _Sample(
        base.x + distance_mm * nx,
        base.y + distance_mm * ny,
        base.tx,
        base.ty,
        base.speed * ratio,
        rho,
    )


def _single_curves(
    design: CamDesign, prefix: str, label: str, cutter_radius_mm: float | None
) -> list[CurveSpec]:
    """Profile, pitch curve (rollers) and cutter path of a single-contact design."""

    def geometry(theta: FloatArray, left: NDArray[np.bool_]) -> tuple[_Sample, _Sample | None]:
        motion = design.program.evaluate(theta, left_limit=left)
        g = contact_jets(design, theta, motion)
        prof = _from_jets(g.contact_x, g.contact_y)
        pitch = (
            _from_jets(g.extras["pitch_x"], g.extras["pitch_y"]) if "pitch_x" in g.extras else None
        )
        return prof, pitch

    specs = [
        CurveSpec(f"{prefix}PROFILE", f"{label}profile", lambda t, m: geometry(t, m)[0]),
    ]
    probe = geometry(np.array([0.0]), np.array([False]))[1]
    if probe is not None:

        def pitch(t: FloatArray, m: NDArray[np.bool_]) -> _Sample:
            p = geometry(t, m)[1]
            assert p is not None
            return p

        specs.append(
            CurveSpec(f"{prefix}PITCH_CURVE", f"{label}pitch curve (roller-centre path)", pitch)
        )
    if cutter_radius_mm is not None:
        r = float(cutter_radius_mm)
        specs.append(
            CurveSpec(
                f"{prefix}CUTTER_PATH",
                f"{label}cutter-centre path, cutter radius {r:g} mm",
                lambda t, m: _offset(geometry(t, m)[0], r, "cutter"),
            )
        )
    return specs


def curve_specs(design: CamDesign, cutter_radius_mm: float | None) -> list[CurveSpec]:
    """Return the curves to sample for every cam of the design (:meth:`CamDesign.cams`).

    Parameters
    ----------
    design : CamDesign
        The design; each of its cams gives a profile, a pitch curve (rollers) and, on
        request, a cutter path, on layers ``CAM_...`` (``CAM_A_...``, ``CAM_B_...`` for
        the labelled cams of a conjugate pair).
    cutter_radius_mm : float or None
        Cutter radius of the cutter-centre path, or None. [mm]

    Returns
    -------
    list of CurveSpec
        Layer, description and evaluator of each curve.
    """
    specs: list[CurveSpec] = []
    for cam in design.cams():
        tag = f"{cam.label}_" if cam.label else ""
        label = f"cam {cam.label} " if cam.label else "cam "
        specs += _single_curves(cam.design, f"CAM_{tag}", label, cutter_radius_mm)
    return specs


def _check_design(design: CamDesign) -> None:
    """Raise if a cam cannot be made (undercut, V ≥ 1, ...), naming the cam and angle."""
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)  # every cam, independent of any grid (issue 9)


# ---------------------------------------------------------------------------------------
# Adaptive sampling
# ---------------------------------------------------------------------------------------
def _allowed_arc_mm(rho: FloatArray, tol: float) -> FloatArray:
    """Arc length whose chord sags by ``tol`` on a circle of radius |ρ|. [mm]"""
    r = np.abs(rho)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.clip(1.0 - tol / r, -1.0, 1.0)
        arc = 2.0 * r * np.arccos(c)
    return np.where(np.isfinite(r), arc, np.inf)


def _plan(fn: CurveFunction, boundaries_rad: FloatArray, tol: float) -> FloatArray:
    """Vertex angles in [0, 2π) so that each chord is within ``_SAFETY`` of the allowed arc."""
    theta, left = analysis_grid(_PLAN_STEP_DEG, boundaries_rad)
    s = fn(theta, left)
    with np.errstate(divide="ignore", invalid="ignore"):
        dtheta = _allowed_arc_mm(s.rho, tol) / s.speed
    dtheta = np.where(np.isfinite(dtheta) & (dtheta > 0), dtheta, np.nan)
    if np.any(np.isnan(dtheta) & (s.speed > 0) & np.isfinite(s.speed)):
        bad = int(np.argmax(np.isnan(dtheta) & (s.speed > 0)))
        raise GeometryError(
            f"the curve is undefined at θ={math.degrees(theta[bad]):.2f}°; cannot export it"
        )
    dtheta = np.minimum(
        np.nan_to_num(dtheta, nan=math.radians(_MAX_STEP_DEG)), math.radians(_MAX_STEP_DEG)
    )
    density = 1.0 / (_SAFETY * dtheta)
    # Split at the duplicated boundary rows: plan each smooth piece on its own.
    cut = np.flatnonzero(np.diff(theta) == 0.0) + 1
    pieces = np.split(np.arange(theta.size), cut)
    out: list[FloatArray] = []
    for idx in pieces:
        t, d = theta[idx], density[idx]
        if t.size < 2:
            continue
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (d[1:] + d[:-1]) * np.diff(t))])
        n = max(1, math.ceil(cum[-1]))
        out.append(np.interp(np.linspace(0.0, cum[-1], n + 1)[:-1], cum, t))
    total = sum(v.size for v in out)
    if total > MAX_VERTICES:
        raise ExportError(
            f"the chordal tolerance {tol * 1e3:g} µm needs about {total:,} vertices per curve"
            f" for a cam of this size; at most {MAX_VERTICES:,} are written: give a larger"
            " --tolerance"
        )
    verts = np.unique(np.concatenate(out))
    return np.asarray(verts[verts < 2.0 * math.pi - 1e-12])


def _chord_deviation(
    fn: CurveFunction, theta: FloatArray, x: FloatArray, y: FloatArray
) -> FloatArray:
    """Largest distance of the curve from each chord (closed polygon), at quarter points."""
    t1 = np.append(theta[1:], theta[0] + 2.0 * math.pi)
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    dx, dy = x1 - x, y1 - y
    length = np.hypot(dx, dy)
    fractions = np.array([0.25, 0.5, 0.75])
    tm = (theta[:, None] + fractions[None, :] * (t1 - theta)[:, None]).ravel()
    s = fn(np.mod(tm, 2.0 * math.pi), np.zeros(tm.size, bool))
    px = s.x.reshape(-1, fractions.size) - x[:, None]
    py = s.y.reshape(-1, fractions.size) - y[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        dist = np.abs(dx[:, None] * py - dy[:, None] * px) / length[:, None]
    dist = np.where(length[:, None] > 0, dist, np.hypot(px, py))
    return np.asarray(np.max(dist, axis=1))


def _sample_curve(spec: CurveSpec, boundaries_rad: FloatArray, tol: float) -> ProfileCurve:
    theta = _plan(spec.evaluate, boundaries_rad, tol)
    for _ in range(_MAX_PASSES):
        s = spec.evaluate(theta, np.zeros(theta.size, bool))
        dev = _chord_deviation(spec.evaluate, theta, s.x, s.y)
        bad = np.flatnonzero(dev > tol)
        if bad.size == 0:
            area = 0.5 * float(np.sum(s.x * np.roll(s.y, -1) - np.roll(s.x, -1) * s.y))
            if area <= 0:
                raise GeometryError(
                    f"the {spec.description} does not run counterclockwise around the cam"
                    " centre as θ grows (THEORY §0); cannot orient it for export"
                )
            return ProfileCurve(spec.layer, spec.description, theta, s.x, s.y, float(np.max(dev)))
        t1 = np.append(theta[1:], 2.0 * math.pi)
        theta = np.sort(np.concatenate([theta, 0.5 * (theta[bad] + t1[bad])]))
        if theta.size > MAX_VERTICES:
            raise ExportError(
                f"the {spec.description} needs more than {MAX_VERTICES:,} vertices at the"
                f" chordal tolerance {tol * 1e3:g} µm; give a larger --tolerance"
            )
    raise GeometryError(  # pragma: no cover - would need a non-smooth curve
        f"the {spec.description} could not be sampled within {tol * 1e3:g} µm"
        f" (worst chord at θ={math.degrees(theta[int(np.argmax(dev))]):.3f}°)"
    )


def _check_tolerance(tolerance_mm: float) -> None:
    if not (math.isfinite(tolerance_mm) and 1e-7 <= tolerance_mm <= 1.0):
        raise ExportError(
            f"tolerance_mm={tolerance_mm:g} is not allowed; the chordal tolerance must lie"
            " between 1e-7 mm (0.1 nm) and 1 mm"
        )


def _check_cutter(cutter_radius_mm: float | None) -> None:
    if cutter_radius_mm is not None and not (0 < cutter_radius_mm <= MAX_TOOL_RADIUS_MM):
        raise ExportError(
            f"cutter_radius_mm={cutter_radius_mm:g} is not allowed; it must be a positive"
            f" length of at most {MAX_TOOL_RADIUS_MM:g} mm"
        )


def profile_points(
    design: CamDesign,
    *,
    tolerance_mm: float = DEFAULT_TOLERANCE_MM,
    cutter_radius_mm: float | None = None,
) -> ProfilePoints:
    """Sample the design's profile curves so every chord is within a tolerance.

    Parameters
    ----------
    design : CamDesign
        The design; it is checked first (undercut, V ≥ 1, pressure angle ≥ 90°).
    tolerance_mm : float
        Largest allowed deviation between a chord and the analytic curve, 1e-7..1. [mm]
    cutter_radius_mm : float, optional
        Also sample the cutter-centre path for a cutter of this radius: the profile
        offset outward along its normal by this distance (for a roller follower, a cutter
        of the roller's radius follows the pitch curve). [mm]

    Returns
    -------
    ProfilePoints
        The cam profile (``CAM_PROFILE``; ``CAM_A_PROFILE`` and ``CAM_B_PROFILE`` for a
        conjugate pair), the pitch curve of roller followers (``..._PITCH_CURVE``), and
        the cutter path if asked (``..._CUTTER_PATH``).

    Raises
    ------
    ExportError
        Tolerance or cutter radius out of range.
    GeometryError, UndercutError
        The design cannot be made, or the cutter is larger than a concave radius of
        curvature of the profile (it would gouge).

    Notes
    -----
    Vertices are evaluated exactly on the analytic profile (THEORY §2, [Wu03]). Their
    spacing Δs follows from the signed radius of curvature ρ of each curve (from exact
    θ-jets; the offset curves have ρ + d) through the arc sagitta
    h = ρ(1 − cos(Δs/2ρ)) ≈ Δs²/(8ρ), with Δs taken at 80 % of the arc that gives
    h = tolerance, and segment boundaries of the motion program are always vertices. The
    result is then verified on the analytic curve at the quarter points of every chord,
    bisecting any chord beyond the tolerance. The cam-angle step never exceeds 1°.

    References
    ----------
    .. [Wu03] L.-I. Wu, "Calculating conjugate cam profiles by vector equations",
       Proc. IMechE C 217(10):1117-1123, 2003.

    Examples
    --------
    >>> from camtol.config.design_file import load_example
    >>> pts = profile_points(load_example("cw06-translating"))
    >>> pts.profile.layer, bool(pts.profile.max_deviation_mm < 1e-4)
    ('CAM_PROFILE', True)
    """
    _check_tolerance(tolerance_mm)
    _check_cutter(cutter_radius_mm)
    _check_design(design)
    bounds = np.asarray(design.program.boundaries_rad, dtype=float)
    curves = tuple(
        _sample_curve(spec, bounds, tolerance_mm) for spec in curve_specs(design, cutter_radius_mm)
    )
    return ProfilePoints(design.name, tolerance_mm, cutter_radius_mm, curves)


def profile_table(design: CamDesign, points: ProfilePoints) -> dict[str, FloatArray]:
    """Every sampled curve at the union of their vertex angles, as CSV-ready columns.

    Parameters
    ----------
    design : CamDesign
        The design whose curves were sampled.
    points : ProfilePoints
        From :func:`profile_points`.

    Returns
    -------
    dict of str to ndarray
        ``theta_deg`` [deg], then ``<layer>_x_mm`` and ``<layer>_y_mm`` [mm] of every
        curve (layer in lower case), evaluated exactly on the analytic curves.
    """
    theta = np.unique(np.concatenate([c.theta_rad for c in points.curves]))
    # Curves planned separately share boundary angles to within rounding: one row each.
    theta = theta[np.concatenate([[True], np.diff(theta) > 1e-12])]
    specs = {s.layer: s for s in curve_specs(design, points.cutter_radius_mm)}
    cols: dict[str, FloatArray] = {"theta_deg": np.degrees(theta)}
    for c in points.curves:
        s = specs[c.layer].evaluate(theta, np.zeros(theta.size, bool))
        name = c.layer.lower()
        cols[f"{name}_x_mm"] = s.x
        cols[f"{name}_y_mm"] = s.y
    return cols
