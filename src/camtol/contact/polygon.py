"""Polygon cam shapes with straight and circular-arc edges, and support functions (THEORY §5).

A measured point cloud or an exported polyline is a polygon with straight edges; a cam
cut by a cylindrical tool is a polygon with arcs (DXF "bulge" convention, THEORY §6.3).
:class:`Support` is the support function h(ψ) of a shape's convex hull, with the point
where it is attained and the radius of curvature there: everything a flat face sees.

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

from camtol.exceptions import InputFileError
from camtol.jet import FloatArray

__all__ = ["PolygonShape", "Support", "sweep_rank"]

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
    normal_x, normal_y : ndarray
        The direction n(ψ) = (cos ψ, sin ψ) itself, for the callers' formulas (so that
        they need not evaluate the sine and cosine again). [1]
    """

    h_mm: FloatArray
    contact_x_mm: FloatArray
    contact_y_mm: FloatArray
    centre_x_mm: FloatArray
    centre_y_mm: FloatArray
    radius_mm: FloatArray
    feature: IntArray
    param_rad: FloatArray
    normal_x: FloatArray
    normal_y: FloatArray


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


def _edges(a: FloatArray) -> FloatArray:
    """Return a[i+1] − a[i] along the first axis, closing the loop (a[0] − a[M−1])."""
    d = np.empty_like(a)
    np.subtract(a[1:], a[:-1], out=d[:-1])
    np.subtract(a[:1], a[-1:], out=d[-1:])
    return d


def _unwrap(ang: FloatArray, turn: FloatArray) -> FloatArray:
    """``np.unwrap(ang)`` from the wrapped differences ``turn`` already at hand.

    ``turn[i]`` is ``ang[i+1] − ang[i]`` wrapped into [−π, π). numpy corrects every
    difference of π or more by a multiple of 2π; on a convex outline that happens once or
    twice (where the edge angle crosses ±π), so the corrections are added run by run, not
    as a cumulative sum over every vertex: the same numbers as numpy's.
    """
    dd = np.diff(ang)
    jumps = np.flatnonzero(np.abs(dd) >= math.pi)
    out = ang.copy()
    if jumps.size == 0:
        return out
    wrapped = turn[jumps]
    wrapped[(wrapped == -math.pi) & (dd[jumps] > 0)] = math.pi  # numpy's choice at ±π
    correction = np.cumsum(wrapped - dd[jumps])
    for start, stop, c in zip(jumps + 1, [*(jumps[1:] + 1), ang.size], correction, strict=True):
        out[start:stop] += c
    return out


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
        if v.shape[0] < 3:
            raise InputFileError("a shape needs at least 3 distinct vertices")
        scale = float(np.max(np.abs(v)))
        if not (math.isfinite(scale) and np.all(np.isfinite(b))):  # max|v| is NaN or inf
            raise InputFileError("shape vertices and bulges must be finite numbers")
        # Edges by slices, not np.roll: the 36,000-vertex polygons of the contact
        # benchmark spend more in copies than in arithmetic.
        d = _edges(v)
        length2 = np.einsum("ij,ij->i", d, d)
        keep = length2 > (1e-12 * max(scale, 1.0)) ** 2
        v, b = (v[keep], b[keep]) if not keep.all() else (v.copy(), b.copy())
        if v.shape[0] < 3:
            raise InputFileError("a shape needs at least 3 distinct vertices")
        x, y = v[:, 0], v[:, 1]
        area2 = float(x[:-1] @ y[1:] - y[:-1] @ x[1:]) + float(x[-1] * y[0] - y[-1] * x[0])
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
        e = _edges(v)
        ang = np.arctan2(e[:, 1], e[:, 0])
        turn = _edges(ang)  # turn of the edge direction at each vertex, in [−π, π)
        np.add(turn, math.pi, out=turn)
        np.mod(turn, TWO_PI, out=turn)
        np.subtract(turn, math.pi, out=turn)
        cross = e[:, 0] * np.roll(e[:, 1], -1)
        cross -= e[:, 1] * np.roll(e[:, 0], -1)
        scale = float(np.max(np.einsum("ij,ij->i", e, e)))
        if np.all(cross >= -1e-13 * scale) and abs(float(np.sum(turn)) - TWO_PI) < 1e-6:
            # Already convex and counterclockwise: O(M), and the edge angles are known.
            hull = np.arange(v.shape[0])
            normal = _unwrap(ang, turn)
        else:
            from scipy.spatial import ConvexHull

            hull = np.asarray(ConvexHull(v).vertices, dtype=np.intp)  # counterclockwise
            he = _edges(v[hull])
            hang = np.arctan2(he[:, 1], he[:, 0])
            normal = np.unwrap(hang)
        normal -= 0.5 * math.pi
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
        cx = v[vert, 0]
        cy = v[vert, 1]
        h = cx * c
        h += cy * s
        feature = vert  # a fresh array, the caller's to keep
        if arc_best is None:  # straight edges only: the contact is a vertex, ρ = 0
            # Contact and centre are the same point: one read-only array for both, and
            # read-only broadcasts for the constants (a full array each is a page-fault
            # cost on long grids, for nothing).
            cx.flags.writeable = cy.flags.writeable = False
            return Support(
                h_mm=h,
                contact_x_mm=cx,
                contact_y_mm=cy,
                centre_x_mm=cx,
                centre_y_mm=cy,
                radius_mm=np.broadcast_to(0.0, h.shape),
                feature=feature,
                param_rad=np.broadcast_to(math.nan, h.shape),
                normal_x=c,
                normal_y=s,
            )
        rad = np.zeros_like(h)
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
            normal_x=c,
            normal_y=s,
        )
