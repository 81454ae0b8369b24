"""Registration of a CMM scan to the nominal cam profile (datum frame or best fit).

The scan is in the CMM's frame; the cam's frame (THEORY §0: origin at the pivot O2, θ
counterclockwise from the reference radial) is placed in it by a rotation φ and a
translation d: x_CMM = R(φ) x_cam + d. Registration finds (φ, d) as an inspector would:

- ``bore``: d is the centre of a circle fitted to the points flagged as bore points;
- ``centre``: d is given;
- ``fit``: d and φ minimise the normal deviations (best fit over rotation and
  translation). **A best fit hides eccentricity**: a cam machined off its bore centre
  is moved back onto the nominal and passes; the result carries that warning;
- ``fit-rotation``: φ only, with d = 0 (the CMM frame's origin on the cam axis).

The angular datum is a stated angle φ, or a datum point (e.g. a keyway) at a stated
nominal polar angle, or (without either) a best fit of φ alone. Fits minimise a robust
loss (``soft_l1`` by default, or ``huber``, as in :func:`scipy.optimize.least_squares`) of
the exact normal deviations to the analytic profile (:mod:`camtol.inspection.profile_table`)
with their exact Jacobian (the closest point moves along the profile, so ∂Δn/∂x = N), by
Gauss-Newton with the loss's weights (iteratively reweighted least squares: a few
closest-point solves), or by :func:`scipy.optimize.least_squares` itself (``solver="scipy"``,
the slower reference; both reach the same minimum). The rotation starts from a coarse
search (1°, then 0.1°) of the median radial misfit, the centre of a best fit from the
scan's area centroid (so the CMM frame's origin may be anywhere). Standard uncertainties follow from
the Jacobian at the solution, cov = s² (JᵀJ)⁻¹ with s² the residual variance of the
points kept: the **random** part, which assumes independent residuals.

A profile error is not independent from point to point: on a non-circular cam the rigid
fit absorbs part of it (a 10 µm·sin 4θ error turns the fitted rotation by several times
its random u). The **form** part of the uncertainty is what the profile error can
absorb: the covariance of the rigid modes with the low harmonics of the deviation. The
residuals are resolved into harmonics k = 1..:data:`FORM_HARMONICS` of the profile
parameter; each harmonic's variance σ_k² = (a_k² + b_k²)/2 is corrected for the part of
it the fit itself removed (its leverage h_k on the rigid modes: σ_k²/(1 − h_k), as HC2
corrects a sandwich estimator, [MW85]); then cov_form = G diag(σ²) Gᵀ with
G = (JᵀJ)⁻¹ Jᵀ [cos kt, sin kt], the sandwich ([White80]) of a random-phase profile
error. The combined standard uncertainty is √(u_random² + u_form²); its 95 % expanded
uncertainty uses, per parameter, the Student factor of the Welch-Satterthwaite degrees of
freedom (GUM G.4), each σ_k² counting 2. Tested: over 200 seeded scans of cw06 designs
with random profile errors (harmonics 2-20, 2-10 µm rms), the 95 % interval covers the
true placement in ≥ 92 % of them. A warning says when the form part dominates.

References: [White80] H. White, Econometrica 48(4):817-838, 1980. [MW85] J. G. MacKinnon,
H. White, J. Econometrics 29(3):305-325, 1985. [GUM] JCGM 100:2008, Annex G.

Outliers are points far from their neighbours' trend (a running median of Δn along the
profile): more than ``k`` robust standard deviations (1.4826 × MAD) and more than a floor.
They are excluded from the fit and reported by index, never silently dropped.

Why one module: every part serves :func:`register`, the placement (φ, d) of the cam frame
in the CMM frame. The datum says what is stated and what is fitted, the coarse search
starts the fit, the IRLS and scipy solvers minimise the same normal deviations with the same
Jacobian (``jac_rows``), and the outliers and uncertainties are those of that one fit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.exceptions import DesignError, InputFileError
from camtol.inspection.cmm import fit_circle
from camtol.inspection.profile_table import ProfileTable
from camtol.jet import FloatArray

__all__ = [
    "Datum",
    "DatumMode",
    "Loss",
    "RegisteredPoints",
    "Registration",
    "find_outliers",
    "register",
]

DatumMode = Literal["fit", "fit-rotation", "bore", "centre"]
Loss = Literal["linear", "soft_l1", "huber"]

#: Points used by the iterative fit (an even subsample of larger scans; the deviations,
#: outliers and uncertainties always use every point).
FIT_POINTS = 20_000

#: Harmonics of the deviation the form part of the uncertainty is resolved into.
FORM_HARMONICS = 30

BEST_FIT_WARNING = (
    "best-fit registration moves the scan onto the nominal and so hides eccentricity (a cam"
    " machined off its bore centre passes); register on the bore (--datum bore or"
    " --datum centre:X,Y) to judge the profile against its bore"
)


@dataclass(frozen=True)
class Datum:
    """How the cam frame is placed in the CMM frame (see the module notes).

    Parameters
    ----------
    mode : {"fit", "fit-rotation", "bore", "centre"}
        Datum frame or best fit.
    centre_mm : (float, float), optional
        Cam centre in CMM coordinates, for ``mode="centre"``. [mm]
    angle_deg : float, optional
        Stated rotation φ of the cam frame (its reference radial) in the CMM frame. [deg]
    point_mm : (float, float), optional
        A datum point (keyway, mark) in CMM coordinates ... [mm]
    point_angle_deg : float, optional
        ... lying at this nominal polar angle of the cam frame. [deg]
    loss : {"soft_l1", "huber", "linear"}
        Loss of the robust fit.
    f_scale_mm : float
        Smallest soft margin of the robust loss (residuals beyond the margin count less
        than squared); the margin used is 3 robust standard deviations (1.4826 × MAD) of
        the starting residuals when larger: the loss then guards against gross errors
        while the form deviations of the cam keep their full weight. [mm]
    outlier_sigma : float
        Outlier threshold in robust standard deviations of the local residual.
    outlier_floor_mm : float
        Outliers must also depart from the local trend by more than this. [mm]
    keyway_deg : float, optional
        Nominal polar angle of the keyway whose points the scan flags (column
        ``keyway``): their centroid becomes the datum point (a feature datum). [deg]
    """

    mode: DatumMode = "fit"
    centre_mm: tuple[float, float] | None = None
    angle_deg: float | None = None
    point_mm: tuple[float, float] | None = None
    point_angle_deg: float | None = None
    loss: Loss = "soft_l1"
    f_scale_mm: float = 0.005
    outlier_sigma: float = 6.0
    outlier_floor_mm: float = 0.002
    keyway_deg: float | None = None

    def __post_init__(self) -> None:
        if self.mode not in ("fit", "fit-rotation", "bore", "centre"):
            raise DesignError(
                f"datum {self.mode!r} is not allowed; use fit, fit-rotation, bore or centre:X,Y"
            )
        if self.mode == "centre" and self.centre_mm is None:
            raise DesignError("datum centre needs the cam centre: centre:X,Y in mm")
        if (self.point_mm is None) != (self.point_angle_deg is None):
            raise DesignError("a datum point needs its coordinates and its nominal polar angle")
        stated = (
            self.angle_deg is not None or self.point_mm is not None or self.keyway_deg is not None
        )
        if (
            self.keyway_deg is not None
            and (self.point_mm is not None or self.angle_deg is not None)
            and not (self.point_mm is not None and self.point_angle_deg == self.keyway_deg)
        ):
            raise DesignError("give the angular datum once: a keyway, a stated angle or a point")
        if self.keyway_deg is not None and not math.isfinite(self.keyway_deg):
            raise DesignError(f"keyway angle {self.keyway_deg!r} is not allowed; give degrees")
        if self.mode.startswith("fit") and stated:
            raise DesignError(
                f"datum {self.mode!r} fits the rotation; an angular datum (stated angle or"
                " datum point) goes with --datum bore or centre:X,Y"
            )
        if self.angle_deg is not None and self.point_mm is not None:
            raise DesignError("give the angular datum once: a stated angle or a datum point")
        if self.loss not in ("linear", "soft_l1", "huber"):
            raise DesignError(f"loss {self.loss!r} is not allowed; use linear, soft_l1 or huber")
        for name, v in (("f_scale_mm", self.f_scale_mm), ("outlier_sigma", self.outlier_sigma)):
            if not (math.isfinite(v) and v > 0):
                raise DesignError(f"{name}={v!r} is not allowed; give a number > 0")


@dataclass(frozen=True)
class RegisteredPoints:
    """Points in the cam frame and their closest nominal points at a registration.

    Attributes
    ----------
    x_mm, y_mm : ndarray
        Points in the cam frame. [mm]
    param_rad : ndarray
        Profile parameter of the closest point. [rad]
    dn_mm : ndarray
        Normal deviation. [mm]
    nx, ny : ndarray
        Outward unit normal at the closest point.
    """

    x_mm: FloatArray
    y_mm: FloatArray
    param_rad: FloatArray
    dn_mm: FloatArray
    nx: FloatArray
    ny: FloatArray


@dataclass(frozen=True)
class Registration:
    """Placement of the cam frame in the CMM frame: x_CMM = R(φ) x_cam + d.

    Attributes
    ----------
    mode : str
        The datum mode used.
    rotation_deg, dx_mm, dy_mm : float
        φ in (−180, 180] [deg] and d [mm].
    u_rotation_deg, u_dx_mm, u_dy_mm : float
        Random standard uncertainties (0 for a stated value): residuals taken as
        independent. [deg, mm]
    fitted : tuple of str
        Parameters that were fitted (``rotation``, ``translation``).
    outliers : ndarray of int
        Indices (into the profile points given) of the outliers found.
    warnings : tuple of str
        E.g. that a best fit hides eccentricity.
    points : RegisteredPoints or None
        The points in the cam frame with their closest profile points at the solution
        (saves solving them again).
    u_form_rotation_deg, u_form_dx_mm, u_form_dy_mm : float
        Form part of the standard uncertainties: what the profile error can shift the
        fitted parameters by (see the module notes; 0 for a stated value). [deg, mm]
    coverage_factors : (float, float, float)
        95 % coverage factors of φ, dx, dy (Welch-Satterthwaite Student factors, ≥ 2).
    """

    mode: str
    rotation_deg: float
    dx_mm: float
    dy_mm: float
    u_rotation_deg: float
    u_dx_mm: float
    u_dy_mm: float
    fitted: tuple[str, ...]
    outliers: NDArray[np.intp]
    warnings: tuple[str, ...] = ()
    points: RegisteredPoints | None = field(default=None, repr=False, compare=False)
    u_form_rotation_deg: float = 0.0
    u_form_dx_mm: float = 0.0
    u_form_dy_mm: float = 0.0
    coverage_factors: tuple[float, float, float] = (2.0, 2.0, 2.0)

    @property
    def u_total(self) -> tuple[float, float, float]:
        """Combined standard uncertainties √(u_random² + u_form²) of φ, dx, dy. [deg, mm]"""
        return (
            math.hypot(self.u_rotation_deg, self.u_form_rotation_deg),
            math.hypot(self.u_dx_mm, self.u_form_dx_mm),
            math.hypot(self.u_dy_mm, self.u_form_dy_mm),
        )

    @property
    def expanded_95(self) -> tuple[float, float, float]:
        """95 % expanded uncertainties k·u of φ, dx, dy (k: :attr:`coverage_factors`). [deg, mm]"""
        (a, b, c), (ka, kb, kc) = self.u_total, self.coverage_factors
        return ka * a, kb * b, kc * c

    def to_cam(self, x_mm: FloatArray, y_mm: FloatArray) -> tuple[FloatArray, FloatArray]:
        """CMM coordinates into the cam frame: x_cam = R(−φ)(x − d). [mm]

        Parameters
        ----------
        x_mm, y_mm : ndarray
            Points in the CMM frame. [mm]
        """
        return _to_cam(math.radians(self.rotation_deg), self.dx_mm, self.dy_mm, x_mm, y_mm)


def _to_cam(
    phi: float, dx: float, dy: float, x: FloatArray, y: FloatArray
) -> tuple[FloatArray, FloatArray]:
    c, s = math.cos(phi), math.sin(phi)
    u, v = x - dx, y - dy
    return c * u + s * v, -s * u + c * v


def area_centroid(x_mm: FloatArray, y_mm: FloatArray) -> tuple[float, float]:
    """Return the centroid of the area a closed scan encloses (ordered about its mean). [mm]

    Unlike the mean of the points, it does not depend on how densely each part of the
    profile was probed.

    Parameters
    ----------
    x_mm, y_mm : ndarray
        Points round the cam. [mm]
    """
    mx, my = float(np.mean(x_mm)), float(np.mean(y_mm))
    order = np.argsort(np.arctan2(y_mm - my, x_mm - mx), kind="stable")
    u, v = x_mm[order] - mx, y_mm[order] - my
    un, vn = np.roll(u, -1), np.roll(v, -1)
    cross = u * vn - un * v
    area = 0.5 * float(np.sum(cross))
    if abs(area) < 1e-12:
        return mx, my
    return (
        mx + float(np.sum((u + un) * cross)) / (6.0 * area),
        my + float(np.sum((v + vn) * cross)) / (6.0 * area),
    )


def _coarse_rotation(
    table: ProfileTable,
    x: FloatArray,
    y: FloatArray,
    dx: float,
    dy: float,
    free_centre: bool = False,
) -> tuple[float, float, float]:
    """Rotation (and centre) minimising the median radial misfit, every 1° then 0.1°.

    With ``free_centre`` the centre for each trial rotation φ puts the scan's area
    centroid on the nominal profile's: d(φ) = C_scan − R(φ) C_nominal.

    Returns
    -------
    (float, float, float)
        φ [rad] and the centre (dx, dy). [mm]
    """
    nodes_x, nodes_y = table.node_points
    if free_centre:
        csx, csy = area_centroid(x, y)
        cnx, cny = area_centroid(nodes_x, nodes_y)
    step = max(1, x.size // 120)
    xs, ys = x[::step], y[::step]
    r_nom = np.hypot(nodes_x, nodes_y)
    p0 = table.polar_rad
    ext_p, ext_r = np.append(p0, p0[0] + 2 * math.pi), np.append(r_nom, r_nom[0])

    def centre(phis: FloatArray) -> tuple[FloatArray, FloatArray]:
        if not free_centre:
            return np.full(phis.shape, dx), np.full(phis.shape, dy)
        c, s = np.cos(phis), np.sin(phis)
        return csx - (c * cnx - s * cny), csy - (s * cnx + c * cny)

    def cost(phis: FloatArray) -> FloatArray:
        cx, cy = centre(phis)
        u, v = xs[None, :] - cx[:, None], ys[None, :] - cy[:, None]
        r, pol = np.hypot(u, v), np.arctan2(v, u)
        ang = p0[0] + np.mod(pol - phis[:, None] - p0[0], 2 * math.pi)
        return np.asarray(np.median(np.abs(r - np.interp(ang, ext_p, ext_r)), axis=1))

    coarse = np.radians(np.arange(0.0, 360.0, 1.0))
    best = float(coarse[int(np.argmin(cost(coarse)))])
    fine = best + np.radians(np.arange(-1.0, 1.0001, 0.1))
    phi = float(fine[int(np.argmin(cost(fine)))])
    cx, cy = centre(np.array([phi]))
    return phi, float(cx[0]), float(cy[0])


def find_outliers(
    t_rad: FloatArray, dn_mm: FloatArray, *, sigma: float = 6.0, floor_mm: float = 0.002
) -> NDArray[np.intp]:
    """Points far from the running median of Δn along the profile (see the module notes).

    Parameters
    ----------
    t_rad : ndarray
        Profile parameter of each point's closest point (orders the points). [rad]
    dn_mm : ndarray
        Normal deviations. [mm]
    sigma : float
        Threshold in robust standard deviations of the local residual.
    floor_mm : float
        Smallest departure counted as an outlier. [mm]

    Returns
    -------
    ndarray of int
        Indices of the outliers, ascending.
    """
    from scipy.ndimage import median_filter

    order = np.argsort(t_rad, kind="stable")
    d = dn_mm[order]
    trend = median_filter(d, size=min(9, d.size - (1 - d.size % 2)), mode="wrap")
    res = d - trend
    scale = 1.4826 * float(np.median(np.abs(res - np.median(res))))
    bad = np.abs(res) > max(sigma * scale, floor_mm)
    return np.sort(order[bad]).astype(np.intp)


def register(
    table: ProfileTable,
    x_mm: FloatArray,
    y_mm: FloatArray,
    datum: Datum,
    *,
    bore_x_mm: FloatArray | None = None,
    bore_y_mm: FloatArray | None = None,
    source: str = "scan",
    solver: Literal["irls", "scipy"] = "irls",
) -> Registration:
    """Place the nominal profile in the CMM frame (see the module notes).

    Parameters
    ----------
    table : ProfileTable
        The nominal profile of the inspected cam.
    x_mm, y_mm : ndarray
        Profile points in the CMM frame (surface points). [mm]
    datum : Datum
        Datum mode, angular datum and robust-fit settings.
    bore_x_mm, bore_y_mm : ndarray, optional
        Bore points, for ``datum.mode == "bore"``. [mm]
    source : str
        File name for messages.
    solver : {"irls", "scipy"}
        ``irls``: Gauss-Newton on the exact Jacobian with the robust loss's weights
        (iteratively reweighted, a few closest-point solves); ``scipy``:
        :func:`scipy.optimize.least_squares` with the same loss (slower; the reference).

    Returns
    -------
    Registration

    Raises
    ------
    InputFileError
        A bore datum without at least 3 bore points.
    """
    dx = dy = 0.0
    u_d = (0.0, 0.0)
    if datum.mode == "bore":
        if bore_x_mm is None or bore_y_mm is None or bore_x_mm.size < 3:
            raise InputFileError(
                f"{source}: --datum bore needs at least 3 points flagged bore=1 in the scan"
            )
        dx, dy, radius = fit_circle(bore_x_mm, bore_y_mm)
        u_d = _circle_uncertainty(bore_x_mm, bore_y_mm, dx, dy, radius)
    elif datum.mode == "centre":
        assert datum.centre_mm is not None
        dx, dy = datum.centre_mm
    fit_translation = datum.mode == "fit"
    if datum.angle_deg is not None:
        phi0, fit_rotation = math.radians(datum.angle_deg), False
    elif datum.point_mm is not None and datum.point_angle_deg is not None:
        px, py = datum.point_mm
        phi0 = math.atan2(py - dy, px - dx) - math.radians(datum.point_angle_deg)
        fit_rotation = False
    else:
        phi0, cx0, cy0 = _coarse_rotation(table, x_mm, y_mm, dx, dy, fit_translation)
        fit_rotation = True
        if fit_translation:  # start from the centre that matches the area centroids
            dx, dy = cx0, cy0
    names = (["rotation"] if fit_rotation else []) + (["dx", "dy"] if fit_translation else [])
    params0 = np.array(([phi0] if fit_rotation else []) + ([dx, dy] if fit_translation else []))

    def unpack(p: FloatArray) -> tuple[float, float, float]:
        i = 0
        phi, ddx, ddy = phi0, dx, dy
        if fit_rotation:
            phi, i = float(p[0]), 1
        if fit_translation:
            ddx, ddy = float(p[i]), float(p[i + 1])
        return phi, ddx, ddy

    def jac_rows(
        phi: float, xc: FloatArray, yc: FloatArray, nx: FloatArray, ny: FloatArray
    ) -> FloatArray:
        cols = []
        if fit_rotation:  # ∂x_cam/∂φ = (y_cam, −x_cam)
            cols.append(nx * yc - ny * xc)
        if fit_translation:  # ∂x_cam/∂d = −R(−φ)
            c, s = math.cos(phi), math.sin(phi)
            cols += [-(nx * c - ny * s), -(nx * s + ny * c)]
        return np.stack(cols, axis=1) if cols else np.zeros((xc.size, 0))

    def solve(params: FloatArray, idx: NDArray[np.intp], tol: float = 1e-10) -> FloatArray:
        """Robust fit on ``idx`` (an even subsample of at most FIT_POINTS of them)."""
        if not names:
            return params
        idx = idx[:: max(1, idx.size // FIT_POINTS)]
        sx, sy = x_mm[idx], y_mm[idx]
        if solver == "scipy":
            return _solve_scipy(table, sx, sy, params, unpack, jac_rows, datum)
        t_prev: FloatArray | None = None
        f_scale = 0.0
        for _ in range(30):
            # Gauss-Newton: the deviations are linear in the transform near the current
            # closest points (exact to first order), so the robust loss's weights are
            # iterated on that linear model (IRLS, cheap), then the closest points solved
            # again at the new transform.
            phi, ddx, ddy = unpack(params)
            xc, yc = _to_cam(phi, ddx, ddy, sx, sy)
            t_prev, dn, nx, ny = table.closest(xc, yc, t_prev)
            j = jac_rows(phi, xc, yc, nx, ny)
            if f_scale == 0.0:
                f_scale = _auto_scale(dn, datum.f_scale_mm)
            step = np.zeros(len(names))
            for _ in range(100):
                w = _weights(dn + j @ step, datum.loss, f_scale)
                jw = j * w[:, None]
                new = _solve_small(jw.T @ j, -(jw.T @ dn))
                done = np.max(np.abs(new - step)) < 0.1 * tol
                step = new
                if done:
                    break
            params = params + step
            if np.max(np.abs(step)) < tol:
                break
        return params

    # Fit, find the outliers on every point, and fit again without them when any of them
    # was among the points fitted (an even subsample of a large scan).
    fitted_idx = np.arange(0, x_mm.size, max(1, x_mm.size // FIT_POINTS))
    params = solve(params0, np.arange(x_mm.size))
    phi, ddx, ddy = unpack(params)
    xc, yc = _to_cam(phi, ddx, ddy, x_mm, y_mm)
    t, dn, nx, ny = table.closest(xc, yc)
    outliers = find_outliers(t, dn, sigma=datum.outlier_sigma, floor_mm=datum.outlier_floor_mm)
    is_out = np.zeros(x_mm.size, dtype=bool)
    is_out[outliers] = True
    keep = np.flatnonzero(~is_out)
    if names and np.any(is_out[fitted_idx]):
        params = solve(params, keep)
        phi, ddx, ddy = unpack(params)
        xc, yc = _to_cam(phi, ddx, ddy, x_mm, y_mm)
        t, dn, nx, ny = table.closest(xc, yc, t)
    # Uncertainties from the Jacobian of every kept point at the solution.
    u = dict.fromkeys(("rotation", "dx", "dy"), 0.0)
    u_form = dict.fromkeys(("rotation", "dx", "dy"), 0.0)
    k_cover = dict.fromkeys(("rotation", "dx", "dy"), 2.0)
    if names:
        j = jac_rows(phi, xc[keep], yc[keep], nx[keep], ny[keep])
        r = dn[keep]
        dof = max(1, keep.size - len(names))
        s2 = float(np.sum((r - np.mean(r)) ** 2)) / dof
        try:
            cov = s2 * np.linalg.inv(j.T @ j)
        except np.linalg.LinAlgError:
            cov = np.full((len(names), len(names)), np.inf)
        sub = np.arange(0, keep.size, max(1, keep.size // FIT_POINTS))
        var_form, dof_form = _form_variance(j[sub], (r - np.mean(r))[sub], t[keep][sub])
        # (no 1/N: what the profile error shifts the fit by does not average out)
        for k, name in enumerate(names):
            u[name] = math.sqrt(max(float(cov[k, k]), 0.0))
            u_form[name] = math.sqrt(max(float(var_form[k]), 0.0))
            k_cover[name] = _coverage_factor(u[name], u_form[name], dof, float(dof_form[k]))
    if not fit_translation:
        u["dx"], u["dy"] = u_d
    warnings: tuple[str, ...] = (BEST_FIT_WARNING,) if fit_translation else ()
    dominated = [
        n for n in names if u_form[n] > 2.0 * u[n] and u_form[n] > 0.0 and math.isfinite(u[n])
    ]
    if dominated:
        warnings += (
            "the profile error, not probe noise, limits the registration: the form part of"
            f" the uncertainty of {', '.join(dominated)} is over twice its random part; the"
            " fit absorbs some of the profile error (the combined uncertainty says how much;"
            " a bore and keyway datum does not depend on it)",
        )
    return Registration(
        mode=datum.mode,
        rotation_deg=math.degrees(math.remainder(phi, 2 * math.pi)),
        dx_mm=ddx,
        dy_mm=ddy,
        u_rotation_deg=math.degrees(u["rotation"]),
        u_dx_mm=u["dx"],
        u_dy_mm=u["dy"],
        fitted=tuple(dict.fromkeys("translation" if n in ("dx", "dy") else n for n in names)),
        outliers=outliers,
        warnings=warnings,
        points=RegisteredPoints(xc, yc, t, dn, nx, ny),
        u_form_rotation_deg=math.degrees(u_form["rotation"]),
        u_form_dx_mm=u_form["dx"],
        u_form_dy_mm=u_form["dy"],
        coverage_factors=(k_cover["rotation"], k_cover["dx"], k_cover["dy"]),
    )


def _form_variance(
    j: FloatArray, r: FloatArray, t_rad: FloatArray, harmonics: int = FORM_HARMONICS
) -> tuple[FloatArray, FloatArray]:
    """Return what a random-phase profile error can shift the fitted parameters by.

    Parameters
    ----------
    j : ndarray, shape (N, p)
        ∂Δn/∂(fitted parameters) of the kept points.
    r : ndarray
        Their residuals at the solution (mean removed). [mm]
    t_rad : ndarray
        Their profile parameters. [rad]
    harmonics : int
        Harmonics H resolved (fewer when the points are few: at most (N − p)/4).

    Returns
    -------
    (ndarray, ndarray)
        The form variance of each parameter and its Welch-Satterthwaite degrees of
        freedom (inf when the variance is 0).
    """
    n, p = j.shape
    h = max(1, min(harmonics, (n - p) // 4))
    k = np.arange(1, h + 1)
    phase = np.outer(t_rad, k)
    basis = np.concatenate([np.cos(phase), np.sin(phase)], axis=1)  # (N, 2H)
    coef = _solve_small(basis.T @ basis, basis.T @ r)  # well conditioned: near-orthogonal
    q, _ = np.linalg.qr(j)
    # Leverage of each harmonic on the rigid modes: the fraction of it the fit removed.
    lev = np.minimum(np.sum((q.T @ basis) ** 2, axis=0) / np.sum(basis**2, axis=0), 0.9)
    adjusted = coef**2 / (1.0 - lev)
    sigma2 = 0.5 * (adjusted[:h] + adjusted[h:])  # per harmonic, its two phases pooled
    try:
        g = np.linalg.solve(j.T @ j, j.T @ basis)  # (p, 2H)
    except np.linalg.LinAlgError:
        return np.full(p, np.inf), np.full(p, np.inf)
    terms = (g[:, :h] ** 2 + g[:, h:] ** 2) * sigma2  # (p, H)
    var = terms.sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        dof = np.where(var > 0, var**2 / np.sum(terms**2 / 2.0, axis=1), np.inf)
    return np.asarray(var, dtype=float), np.asarray(dof, dtype=float)


def _coverage_factor(u_random: float, u_form: float, dof_random: int, dof_form: float) -> float:
    """95 % Student factor at the Welch-Satterthwaite degrees of freedom (GUM G.4)."""
    from scipy.special import stdtrit  # Student quantile (scipy.stats imports slowly)

    if not (math.isfinite(u_random) and math.isfinite(u_form)) or u_form <= 0.0:
        return 2.0
    uc4 = (u_random**2 + u_form**2) ** 2
    nu = uc4 / (u_random**4 / dof_random + u_form**4 / dof_form)
    return 2.0 if not math.isfinite(nu) else max(2.0, float(stdtrit(max(nu, 1.0), 0.975)))


def _solve_small(a: FloatArray, b: FloatArray) -> FloatArray:
    """Solve a small normal-equation system; least squares when it is singular."""
    try:
        return np.asarray(np.linalg.solve(a, b), dtype=float)
    except np.linalg.LinAlgError:
        return np.asarray(np.linalg.lstsq(a, b, rcond=None)[0], dtype=float)


def _auto_scale(r: FloatArray, floor_mm: float) -> float:
    """Soft margin of the robust loss: 3 robust standard deviations of r, at least the floor."""
    mad = float(np.median(np.abs(r - np.median(r))))
    return max(floor_mm, 3.0 * 1.4826 * mad)


def _weights(r: FloatArray, loss: Loss, f_scale: float) -> FloatArray:
    """IRLS weights ρ'(z), z = (r/f)², of the losses of scipy.optimize.least_squares."""
    z = (r / f_scale) ** 2
    if loss == "soft_l1":
        return np.asarray(1.0 / np.sqrt(1.0 + z))
    if loss == "huber":
        return np.asarray(np.where(z <= 1.0, 1.0, 1.0 / np.sqrt(np.maximum(z, 1.0))))
    return np.ones_like(r)


def _solve_scipy(
    table: ProfileTable,
    sx: FloatArray,
    sy: FloatArray,
    params: FloatArray,
    unpack: Callable[[FloatArray], tuple[float, float, float]],
    jac_rows: Callable[..., FloatArray],
    datum: Datum,
) -> FloatArray:
    """Fit by scipy.optimize.least_squares (exact Jacobian)."""
    from scipy.optimize import least_squares

    state: dict[str, FloatArray] = {}

    def residual(p: FloatArray) -> FloatArray:
        phi, ddx, ddy = unpack(p)
        xc, yc = _to_cam(phi, ddx, ddy, sx, sy)
        t, dn, nx, ny = table.closest(xc, yc, state.get("t"))
        state.update(t=t, xc=xc, yc=yc, nx=nx, ny=ny)
        return dn

    def jac(p: FloatArray) -> FloatArray:
        phi, _, _ = unpack(p)
        residual(p)
        return jac_rows(phi, state["xc"], state["yc"], state["nx"], state["ny"])

    sol = least_squares(
        residual,
        params,
        jac=jac,
        loss=datum.loss,
        f_scale=_auto_scale(residual(params), datum.f_scale_mm),
        x_scale="jac",
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=200,
    )
    return np.asarray(sol.x, dtype=float)


def _circle_uncertainty(
    x: FloatArray, y: FloatArray, cx: float, cy: float, radius: float
) -> tuple[float, float]:
    """Return the standard uncertainties of a fitted circle's centre (its Jacobian). [mm]"""
    dx, dy = x - cx, y - cy
    r = np.hypot(dx, dy)
    res = r - radius
    j = np.stack([-dx / r, -dy / r, -np.ones_like(r)], axis=1)
    dof = max(1, x.size - 3)
    s2 = float(np.sum(res**2)) / dof
    try:
        cov = s2 * np.linalg.inv(j.T @ j)
    except np.linalg.LinAlgError:
        return math.inf, math.inf
    return math.sqrt(max(float(cov[0, 0]), 0.0)), math.sqrt(max(float(cov[1, 1]), 0.0))
