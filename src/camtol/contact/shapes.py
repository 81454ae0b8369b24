"""Cam shapes for the contact engine (THEORY §5, §6.3).

Two kinds of shape, both in the cam frame X-Y with origin at the cam pivot O2 (THEORY §0):

- :class:`PolygonShape`: a closed polygon whose edges are straight or circular arcs (DXF
  "bulge" convention). A measured point cloud or an exported polyline is a polygon with
  straight edges; a cam cut by a cylindrical tool is a polygon with arcs (THEORY §6.3).
- :class:`AnalyticShape`: the theoretical profile of a design (THEORY §2) with an optional
  radial error Δr(θ) (along O2A) or normal error Δn(θ) (along the outward normal at A),
  as a parametric curve P(t) whose parameter t is the cam angle at which that point of
  the theoretical profile touches the nominal follower. P, dP/dt and d²P/dt² are exact
  (second-order jets seeded from the motion program's S, V, A, J).

Both give the exact *support function* h(ψ) = max_{X ∈ shape} X·n(ψ), n = (cos ψ, sin ψ),
of the shape's convex hull, with the point where it is attained and the radius of
curvature there (0 at a polygon vertex). That is everything a flat-faced follower sees
(THEORY §5): a flat face only ever touches the convex hull.

Notes
-----
For a polygon the support function is evaluated by a monotone sweep over directions: the
hull's outward edge normals are in angular order (an O(M) pass when the polygon is
already convex and counterclockwise, a Qhull convex hull otherwise), and the query
directions are merged with them (:func:`sweep_rank`), O(N + M) for a sorted θ grid, in
vectorised numpy. Convex circular arcs add the candidate c·n + R on the directions their
normals span; concave arcs never support the hull except at their end vertices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol import jet
from camtol.contact.errors_profile import ProfileError
from camtol.exceptions import GeometryError, InputFileError
from camtol.jet import FloatArray, Jet, JetLike
from camtol.mechanisms.base import Mechanism
from camtol.motion import MotionProgram

__all__ = ["AnalyticShape", "PolygonShape", "Support"]

TWO_PI = 2.0 * math.pi
IntArray = NDArray[np.intp]


@dataclass(frozen=True)
class Support:
    """Support function of a shape and where it is attained, per direction ψ.

    Attributes
    ----------
    h_mm : ndarray
        h(ψ) = max X·n(ψ). [mm]
    contact_x_mm, contact_y_mm : ndarray
        Supporting point X*. [mm]
    centre_x_mm, centre_y_mm : ndarray
        Centre of curvature c of the shape at X* (X* = c + ρ n). [mm]
    radius_mm : ndarray
        Radius of curvature ρ at X* (0 at a polygon vertex). [mm]
    feature : ndarray of int
        Polygon feature in contact (vertex index, or M + edge index for an arc); −1 for an
        analytic shape.
    param_rad : ndarray
        Profile parameter t of X* for an analytic shape; NaN for a polygon. [rad]
    """

    h_mm: FloatArray
    contact_x_mm: FloatArray
    contact_y_mm: FloatArray
    centre_x_mm: FloatArray
    centre_y_mm: FloatArray
    radius_mm: FloatArray
    feature: IntArray
    param_rad: FloatArray


def sweep_rank(sorted_mm: FloatArray, query: FloatArray) -> IntArray:
    """Count the entries of a sorted array ≤ each query, by one merge of sorted runs.

    Equivalent to ``np.searchsorted(sorted_mm, query, side="right")``. The queries are put
    in order with a stable sort and merged with the sorted array by a second stable sort;
    numpy's stable sort of floats is a timsort, linear on already sorted runs, so for a θ
    grid (sorted, or a rotation of a sorted grid: two runs) the whole sweep is O(N + M).

    Parameters
    ----------
    sorted_mm : ndarray
        Non-decreasing values (M). [any unit]
    query : ndarray
        Query values (N), same unit.

    Returns
    -------
    ndarray of int
        Ranks in 0..M.
    """
    order = np.argsort(query, kind="stable")
    merged = np.argsort(np.concatenate([sorted_mm, query[order]]), kind="stable")
    pos = np.flatnonzero(merged >= sorted_mm.size)
    rank = np.empty(query.size, dtype=np.intp)
    rank[order] = pos - np.arange(query.size)
    return rank


def _as_jet(x: JetLike, like: FloatArray) -> Jet:
    if isinstance(x, Jet):
        return x
    return Jet.constant(x, like)


# ---------------------------------------------------------------------------------------
# Polygons with straight and circular edges
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PolygonShape:
    """A closed polygon with straight or circular-arc edges, in the cam frame.

    Parameters
    ----------
    vertices_mm : array_like, shape (M, 2)
        Vertices in order, without repeating the first at the end. [mm]
    bulges : array_like, shape (M,), optional
        DXF bulge of edge i (vertex i to i+1): tan(sweep/4), positive for an arc turning
        counterclockwise from vertex i to vertex i+1; 0 (default) for a straight edge.
        [-]

    Notes
    -----
    The polygon is stored counterclockwise (reversed on input if needed, with the bulges
    negated); on a counterclockwise polygon a positive bulge is a convex arc.
    Consecutive duplicate vertices are dropped.

    Raises
    ------
    InputFileError
        Fewer than 3 distinct vertices, non-finite coordinates, or bulges of the wrong
        length.
    """

    vertices_mm: FloatArray
    bulges: FloatArray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices_mm, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2:
            raise InputFileError(f"shape vertices must be an (M, 2) array, got shape {v.shape}")
        b = np.asarray(self.bulges, dtype=float)
        if b.size == 0:
            b = np.zeros(v.shape[0])
        if b.shape != (v.shape[0],):
            raise InputFileError(
                f"shape bulges: expected {v.shape[0]} values (one per edge), got {b.size}"
            )
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(b))):
            raise InputFileError("shape vertices and bulges must be finite numbers")
        scale = float(np.max(np.abs(v))) if v.size else 0.0
        nxt = np.roll(v, -1, axis=0)
        keep = np.hypot(*(nxt - v).T) > 1e-12 * max(scale, 1.0)
        v, b = v[keep], b[keep]
        if v.shape[0] < 3:
            raise InputFileError("a shape needs at least 3 distinct vertices")
        x, y = v[:, 0], v[:, 1]
        area2 = float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        if area2 < 0:
            v = v[::-1].copy()
            b = -np.roll(b[::-1], -1)
        object.__setattr__(self, "vertices_mm", v)
        object.__setattr__(self, "bulges", b)

    @classmethod
    def from_point_cloud(cls, points_mm: ArrayLike) -> PolygonShape:
        """Build a polygon through points in unknown order, sorted by polar angle about O2.

        Valid for a profile that every ray from the cam pivot crosses once (star-shaped
        about O2, as cam profiles are); a flat-faced follower only sees the convex hull, so
        the order does not matter to it.

        Parameters
        ----------
        points_mm : array_like, shape (M, 2)
            Points in the cam frame. [mm]

        Raises
        ------
        InputFileError
            As for the constructor.
        """
        pts = np.asarray(points_mm, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise InputFileError(f"shape vertices must be an (M, 2) array, got shape {pts.shape}")
        order = np.argsort(np.arctan2(pts[:, 1], pts[:, 0]), kind="stable")
        return cls(pts[order])

    # --- geometry ----------------------------------------------------------------------
    @property
    def size(self) -> int:
        """Number of vertices M."""
        return int(self.vertices_mm.shape[0])

    @cached_property
    def arcs(self) -> tuple[IntArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """Arc edges: (edge index, centre x, centre y, radius, signed sweep). [-, mm, rad]

        The signed sweep is 4 atan(bulge): positive for a convex (counterclockwise) arc.
        """
        idx = np.flatnonzero(self.bulges != 0.0)
        v0 = self.vertices_mm[idx]
        v1 = np.roll(self.vertices_mm, -1, axis=0)[idx]
        sweep = 4.0 * np.arctan(self.bulges[idx])
        chord = v1 - v0
        length = np.hypot(chord[:, 0], chord[:, 1])
        left = np.stack([-chord[:, 1], chord[:, 0]], axis=1) / length[:, None]
        mid = 0.5 * (v0 + v1)
        dist = 0.5 * length / np.tan(0.5 * sweep)
        centre = mid + left * dist[:, None]
        radius = 0.5 * length / np.abs(np.sin(0.5 * sweep))
        return idx, centre[:, 0], centre[:, 1], radius, sweep

    @cached_property
    def _hull(self) -> tuple[IntArray, FloatArray]:
        """Hull vertex indices (counterclockwise) and unwrapped outward edge-normal angles."""
        v = self.vertices_mm
        e = np.roll(v, -1, axis=0) - v
        e_next = np.roll(e, -1, axis=0)
        cross = e[:, 0] * e_next[:, 1] - e[:, 1] * e_next[:, 0]
        ang = np.arctan2(e[:, 1], e[:, 0])
        turn = np.mod(np.diff(np.append(ang, ang[0])) + math.pi, TWO_PI) - math.pi
        scale = float(np.max(np.hypot(e[:, 0], e[:, 1]))) ** 2
        if np.all(cross >= -1e-13 * scale) and abs(float(np.sum(turn)) - TWO_PI) < 1e-6:
            hull = np.arange(v.shape[0])  # already convex and counterclockwise: O(M)
        else:
            from scipy.spatial import ConvexHull

            hull = np.asarray(ConvexHull(v).vertices, dtype=np.intp)  # counterclockwise
        hv = v[hull]
        he = np.roll(hv, -1, axis=0) - hv
        normal = np.unwrap(np.arctan2(he[:, 1], he[:, 0]) - 0.5 * math.pi)
        return hull, normal

    @property
    def is_convex(self) -> bool:
        """True when every vertex is on the hull and no arc is concave."""
        return bool(self._hull[0].size == self.size and np.all(self.bulges >= 0))

    # --- support function ---------------------------------------------------------------
    def support(self, psi_rad: ArrayLike) -> Support:
        """Exact support function of the convex hull in the directions ψ (fast sweep).

        Parameters
        ----------
        psi_rad : array_like
            Directions ψ of the unit normal n = (cos ψ, sin ψ). [rad]

        Returns
        -------
        Support
            h(ψ), the supporting vertex or arc point, and its radius of curvature.
        """
        psi = np.atleast_1d(np.asarray(psi_rad, dtype=float))
        hull, normal = self._hull
        p = normal[0] + np.mod(psi - normal[0], TWO_PI)
        k = sweep_rank(normal, p)
        k[k == normal.size] = 0
        vert = hull[k]
        return self._finish(psi, vert, self._arc_candidates(psi))

    def support_bruteforce(self, psi_rad: ArrayLike, *, chunk: int = 512) -> Support:
        """Support function by brute force over every vertex and arc, O(N·M).

        The reference for :meth:`support` (tests and benchmark).

        Parameters
        ----------
        psi_rad : array_like
            Directions. [rad]
        chunk : int
            Directions per vectorised block (memory control).
        """
        psi = np.atleast_1d(np.asarray(psi_rad, dtype=float))
        v = self.vertices_mm
        vert = np.empty(psi.size, dtype=np.intp)
        for s in range(0, psi.size, chunk):
            ps = psi[s : s + chunk]
            dots = np.cos(ps)[:, None] * v[None, :, 0] + np.sin(ps)[:, None] * v[None, :, 1]
            vert[s : s + chunk] = np.argmax(dots, axis=1)
        idx, cx, cy, radius, sweep = self.arcs
        convex = sweep > 0
        arc_best: tuple[IntArray, FloatArray, IntArray] | None = None
        if np.any(convex):
            start = np.arctan2(self.vertices_mm[idx, 1] - cy, self.vertices_mm[idx, 0] - cx)
            qs, vals, arcs = [], [], []
            for j in np.flatnonzero(convex):
                inside = np.mod(psi - start[j], TWO_PI) <= sweep[j]
                q = np.flatnonzero(inside)
                qs.append(q)
                vals.append(cx[j] * np.cos(psi[q]) + cy[j] * np.sin(psi[q]) + radius[j])
                arcs.append(np.full(q.size, j, dtype=np.intp))
            arc_best = (np.concatenate(qs), np.concatenate(vals), np.concatenate(arcs))
        return self._finish(psi, vert, arc_best)

    def _arc_candidates(self, psi: FloatArray) -> tuple[IntArray, FloatArray, IntArray] | None:
        """(query index, c·n + R, arc number) for each convex arc spanning a direction."""
        idx, cx, cy, radius, sweep = self.arcs
        convex = np.flatnonzero(sweep > 0)
        if convex.size == 0:
            return None
        start = np.arctan2(self.vertices_mm[idx, 1] - cy, self.vertices_mm[idx, 0] - cx)
        p = np.mod(psi, TWO_PI)
        order = np.argsort(p, kind="stable")
        ps = p[order]
        # Pad the spans by 1e-12 rad so that rounding of the end normals leaves no crack
        # (outside its span an arc overestimates h by only about R·1e-24 mm).
        lo = np.mod(start[convex] - 1e-12, TWO_PI)
        hi = lo + sweep[convex] + 2e-12
        s1 = np.searchsorted(ps, lo, side="left")
        e1 = np.searchsorted(ps, np.minimum(hi, TWO_PI), side="right")
        s2 = np.zeros_like(s1)
        e2 = np.where(hi > TWO_PI, np.searchsorted(ps, hi - TWO_PI, side="right"), 0)
        starts = np.concatenate([s1, s2])
        counts = np.maximum(np.concatenate([e1, e2]) - starts, 0)
        arc_no = np.repeat(np.concatenate([convex, convex]), counts)
        first = np.cumsum(counts) - counts
        pos = np.arange(int(counts.sum())) - np.repeat(first, counts) + np.repeat(starts, counts)
        q = order[pos]
        val = cx[arc_no] * np.cos(psi[q]) + cy[arc_no] * np.sin(psi[q]) + radius[arc_no]
        return q, val, arc_no

    def _finish(
        self,
        psi: FloatArray,
        vert: IntArray,
        arc_best: tuple[IntArray, FloatArray, IntArray] | None,
    ) -> Support:
        c, s = np.cos(psi), np.sin(psi)
        v = self.vertices_mm
        cx = v[vert, 0].copy()
        cy = v[vert, 1].copy()
        h = cx * c + cy * s
        rad = np.zeros_like(h)
        feature = vert.copy()
        if arc_best is not None:
            q, val, arc_no = arc_best
            best = np.full(psi.size, -np.inf)
            np.maximum.at(best, q, val)
            # Ties at an arc's end (its own end vertex) go to the arc, whose curvature is
            # the right one-sided value on a tangent-continuous outline.
            tie = 1e-12 * (1.0 + np.abs(h[q]))
            win = (val == best[q]) & (val >= h[q] - tie)
            q, arc_no = q[win], arc_no[win]
            idx, acx, acy, radius, _ = self.arcs
            cx[q], cy[q], rad[q] = acx[arc_no], acy[arc_no], radius[arc_no]
            h[q] = np.maximum(best[q], h[q])
            feature[q] = self.size + idx[arc_no]
        return Support(
            h_mm=h,
            contact_x_mm=cx + rad * c,
            contact_y_mm=cy + rad * s,
            centre_x_mm=cx,
            centre_y_mm=cy,
            radius_mm=rad,
            feature=feature,
            param_rad=np.full(h.shape, np.nan),
        )


# ---------------------------------------------------------------------------------------
# Analytic profiles with an error function
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class AnalyticShape:
    """The theoretical profile of a design, optionally with a profile error (THEORY §2, §5).

    Parameters
    ----------
    mechanism : Mechanism
        The nominal follower mechanism whose profile is synthesised (THEORY §2).
    program : MotionProgram
        The nominal motion program.
    radial_error : ProfileError, optional
        Δr(t) along O2A of the theoretical point A(t) (papers' convention). [mm]
    normal_error : ProfileError, optional
        Δn(t) along the outward normal at A(t). [mm]
    samples : int
        Points of the sampled polygon used to seed the exact solutions (and to check
        that each is the global one).

    Notes
    -----
    P(t) = A(t) + Δr(t) A/|A| or A(t) + Δn(t) N(t), where N = ±(A − Q)/|A − Q| is the
    unit outward normal (the common normal passes through the instant centre Q, THEORY
    §2), oriented by the sense of travel of A (counterclockwise, THEORY §0). Every term is
    a second-order jet, so dP/dt and d²P/dt² are exact.
    """

    mechanism: Mechanism
    program: MotionProgram
    radial_error: ProfileError | None = None
    normal_error: ProfileError | None = None
    samples: int = 7200

    def __post_init__(self) -> None:
        if self.samples < 64:
            from camtol.exceptions import DesignError

            raise DesignError(
                f"AnalyticShape.samples={self.samples} is not allowed; use at least 64 points"
            )

    def with_errors(
        self,
        *,
        radial_error: ProfileError | None = None,
        normal_error: ProfileError | None = None,
    ) -> AnalyticShape:
        """Return the same profile with other error functions.

        Parameters
        ----------
        radial_error : ProfileError, optional
            Δr(t) along O2A, replacing the current one; None for none. [mm]
        normal_error : ProfileError, optional
            Δn(t) along the outward normal, replacing the current one; None for none. [mm]

        Returns
        -------
        AnalyticShape
            Same mechanism, program and samples with the new errors.
        """
        return AnalyticShape(self.mechanism, self.program, radial_error, normal_error, self.samples)

    def jets(self, t_rad: ArrayLike, *, left_limit: ArrayLike | None = None) -> tuple[Jet, Jet]:
        """P(t) with dP/dt and d²P/dt², as jets. [mm, mm/rad, mm/rad²]

        Parameters
        ----------
        t_rad : array_like
            Profile parameters. [rad]
        left_limit : array_like of bool, optional
            Take left limits of the motion program where t lies on a boundary.
        """
        t = np.atleast_1d(np.asarray(t_rad, dtype=float))
        m = self.program.evaluate(t, left_limit=left_limit)
        theta = Jet.variable(t)
        lift = Jet(m.lift, m.velocity, m.acceleration)
        vel = Jet(m.velocity, m.acceleration, m.jerk)
        g = self.mechanism.contact(theta, lift, vel)
        ax, ay = _as_jet(g.contact_x, t), _as_jet(g.contact_y, t)
        px, py = ax, ay
        if self.radial_error is not None:
            d = self.radial_error(t)
            r = _as_jet(jet.hypot(ax, ay), t)
            px, py = px + d * ax / r, py + d * ay / r
        if self.normal_error is not None:
            d = self.normal_error(t)
            qx, qy = _as_jet(g.centre_x, t), _as_jet(g.centre_y, t)
            nx, ny = ax - qx, ay - qy
            nn = _as_jet(jet.hypot(nx, ny), t)
            # Outward for a counterclockwise curve: the tangent turned clockwise.
            sign = np.sign(nx.v * ay.d1 - ny.v * ax.d1)
            sign[sign == 0] = 1.0
            px, py = px + d * nx * sign / nn, py + d * ny * sign / nn
        return px, py

    @cached_property
    def sample_param_rad(self) -> FloatArray:
        """Parameters of the sampled polygon's vertices. [rad]"""
        return np.linspace(0.0, TWO_PI, self.samples, endpoint=False)

    @cached_property
    def polygon(self) -> PolygonShape:
        """The profile sampled at :attr:`sample_param_rad` (vertices on the curve)."""
        px, py = self.jets(self.sample_param_rad)
        pts = np.stack([px.v, py.v], axis=1)
        if not np.all(np.isfinite(pts)):
            i = int(np.argmax(~np.all(np.isfinite(pts), axis=1)))
            raise GeometryError(
                f"the profile is undefined at θ={math.degrees(self.sample_param_rad[i]):.2f}°"
            )
        return PolygonShape(pts)

    def vertex_param(self, feature: IntArray) -> FloatArray:
        """Profile parameter of a vertex of :attr:`polygon`. [rad]

        Parameters
        ----------
        feature : ndarray of int
            Vertex indices into :attr:`polygon`, taken modulo its size.

        Returns
        -------
        ndarray
            Profile parameter t of each vertex. [rad]
        """
        poly = self.polygon
        # The polygon may have been reversed on input; map back through the coordinates.
        return self._vertex_param_map[np.asarray(feature) % poly.size]

    @cached_property
    def _vertex_param_map(self) -> FloatArray:
        poly = self.polygon
        px, py = self.jets(self.sample_param_rad)
        if poly.size == self.samples and np.allclose(poly.vertices_mm[0], [px.v[0], py.v[0]]):
            return self.sample_param_rad
        # Reversed (clockwise input) or de-duplicated: match coordinates.
        from scipy.spatial import cKDTree

        tree = cKDTree(np.stack([px.v, py.v], axis=1))
        _, j = tree.query(poly.vertices_mm)
        return np.asarray(self.sample_param_rad[j], dtype=float)

    @property
    def boundaries_rad(self) -> FloatArray:
        """Parameters where the profile's curvature may jump (program boundaries). [rad]"""
        return np.asarray(self.program.boundaries_rad, dtype=float)

    def snap(self, t_rad: FloatArray) -> FloatArray:
        """Wrap t to [0, 2π) and snap values within 1e-9 rad of a boundary onto it. [rad]

        Parameters
        ----------
        t_rad : ndarray
            Profile parameters, 1-D. [rad]

        Returns
        -------
        ndarray
            The wrapped and snapped parameters. [rad]
        """
        t = np.mod(t_rad, TWO_PI)
        b = np.append(self.boundaries_rad, TWO_PI)
        if b.size:
            j = np.argmin(np.abs(t[:, None] - b[None, :]), axis=1)
            near = np.abs(t - b[j]) < 1e-9
            t = np.where(near, np.mod(b[j], TWO_PI), t)
        return t

    def support(self, psi_rad: ArrayLike, *, left_limit: ArrayLike | None = None) -> Support:
        """Exact support function h(ψ) of the profile's hull (Newton on the parameter).

        The sampled polygon's supporting vertex seeds Newton's method on
        F(t) = P'(t)·n(ψ) = 0; the result is checked to be at least the polygon's h (the
        vertices lie on the curve), so it is the global maximum.

        Parameters
        ----------
        psi_rad : array_like
            Directions. [rad]
        left_limit : array_like of bool, optional
            Per direction: take left limits when the contact lies on a program boundary
            (for one-sided A at boundaries).

        Raises
        ------
        GeometryError
            If Newton's method does not converge or finds less than the polygon's h.
        """
        psi = np.atleast_1d(np.asarray(psi_rad, dtype=float))
        poly_sup = self.polygon.support(psi)
        t = self.vertex_param(poly_sup.feature)
        nx, ny = np.cos(psi), np.sin(psi)
        step = 2.0 * TWO_PI / self.samples
        for _ in range(60):
            px, py = self.jets(t)
            f = px.d1 * nx + py.d1 * ny
            fp = px.d2 * nx + py.d2 * ny
            with np.errstate(divide="ignore", invalid="ignore"):
                dt = np.where(fp < 0, -f / fp, np.sign(f) * step)
            dt = np.clip(dt, -step, step)
            t = t + dt
            if np.max(np.abs(dt)) < 1e-13:
                break
        else:
            raise GeometryError("support point of the analytic profile did not converge")
        return self.point_support(psi, t, left_limit=left_limit, check_h=poly_sup.h_mm)

    def point_support(
        self,
        psi: FloatArray,
        t: FloatArray,
        *,
        left_limit: ArrayLike | None = None,
        check_h: FloatArray | None = None,
    ) -> Support:
        """Support record of the profile point P(t) seen in direction ψ.

        Parameters
        ----------
        psi : ndarray
            Directions ψ of the outward normal n(ψ) = (cos ψ, sin ψ). [rad]
        t : ndarray
            Profile parameter of the supporting point for each direction; wrapped and
            snapped with :meth:`snap`. [rad]
        left_limit : array_like of bool, optional
            Take left limits of the motion program where t lies on a boundary.
        check_h : ndarray, optional
            Lower bound on h (e.g. the sampled polygon's); raise if h falls below it.
            [mm]

        Returns
        -------
        Support
            Support value h, contact point and centre of curvature at P(t). [mm]

        Raises
        ------
        GeometryError
            If h is less than ``check_h`` (the point is not the global support point).
        """
        t = self.snap(t)
        px, py = self.jets(t, left_limit=left_limit)
        nx, ny = np.cos(psi), np.sin(psi)
        h = px.v * nx + py.v * ny
        if check_h is not None:
            bad = h < check_h - 1e-9 * (1.0 + np.abs(check_h))
            if np.any(bad):
                i = int(np.argmax(bad))
                raise GeometryError(
                    f"the exact support point in direction ψ={math.degrees(psi[i]):.3f}° is"
                    " not the global one (non-convex profile?)"
                )
        speed = np.hypot(px.d1, py.d1)
        cross = px.d1 * py.d2 - py.d1 * px.d2
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = speed**3 / cross
        return Support(
            h_mm=h,
            contact_x_mm=px.v,
            contact_y_mm=py.v,
            centre_x_mm=px.v - rho * nx,
            centre_y_mm=py.v - rho * ny,
            radius_mm=rho,
            feature=np.full(h.shape, -1, dtype=np.intp),
            param_rad=t,
        )
