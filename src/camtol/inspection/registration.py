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
points kept.

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

    def __post_init__(self) -> None:
        if self.mode not in ("fit", "fit-rotation", "bore", "centre"):
            raise DesignError(
                f"datum {self.mode!r} is not allowed; use fit, fit-rotation, bore or centre:X,Y"
            )
        if self.mode == "centre" and self.centre_mm is None:
            raise DesignError("datum centre needs the cam centre: centre:X,Y in mm")
        if (self.point_mm is None) != (self.point_angle_deg is None):
            raise DesignError("a datum point needs its coordinates and its nominal polar angle")
        stated = self.angle_deg is not None or self.point_mm is not None
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
        Standard uncertainties (0 for a stated value). [deg, mm]
    fitted : tuple of str
        Parameters that were fitted (``rotation``, ``translation``).
    outliers : ndarray of int
        Indices (into the profile points given) of the outliers found.
    warnings : tuple of str
        E.g. that a best fit hides eccentricity.
    points : RegisteredPoints or None
        The points in the cam frame with their closest profile points at the solution
        (saves solving them again).
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
    nodes_x, nodes_y, *_ = table.evaluate(table.nodes_rad[:-1])
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
                new = np.asarray(np.linalg.lstsq(jw.T @ j, -(jw.T @ dn), rcond=None)[0], float)
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
    if names:
        j = jac_rows(phi, xc[keep], yc[keep], nx[keep], ny[keep])
        r = dn[keep]
        dof = max(1, keep.size - len(names))
        s2 = float(np.sum((r - np.mean(r)) ** 2)) / dof
        try:
            cov = s2 * np.linalg.inv(j.T @ j)
        except np.linalg.LinAlgError:
            cov = np.full((len(names), len(names)), np.inf)
        for k, name in enumerate(names):
            u[name] = math.sqrt(max(float(cov[k, k]), 0.0))
    if not fit_translation:
        u["dx"], u["dy"] = u_d
    warnings = (BEST_FIT_WARNING,) if fit_translation else ()
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
    )


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
