"""Exact motion of roller followers on any cam shape (THEORY §5; §2.3, §2.4).

A roller needs the true distance to the cam, not its hull: the roller centre C sits where
its distance to the cam equals r_f, on the follower's path for the cam angle θ:

- translating (THEORY §2.3): C = e·w + y·t on a line, t = (cos θ, sin θ),
  w = (−sin θ, cos θ); the output is y (S = y − s0 of the reference follower);
- oscillating (THEORY §2.4): C = f·t − l·(cos(θ + σγ), sin(θ + σγ)) on a circle about the
  pivot O3 = f·t, with γ the arm angle from O3O2 (σ = −1, γ = ξ for cam A; σ = +1,
  γ = η − ξ for cam B of a conjugate pair).

On a polygon with straight and circular edges every feature gives the positions where
the roller touches it in closed form (a circle of radius r_f about a vertex, the two
offset lines of a segment, the circles of radius R ± r_f about an arc's centre, each kept
only where the foot of the normal lies on the feature), and the roller rests at the
outermost of them (largest y, or largest γ): the first contact coming from outside. This
is exact for non-convex shapes as well. It is a brute-force O(N·M) evaluation, vectorised
in blocks.

On an analytic profile the contact (t, y) or (t, γ) solves the two conditions
(C − P(t))·P'(t) = 0 and |C − P(t)|² = r_f² by Newton's method from the nominal contact,
and the result is checked against the sampled profile (no sample point may lie closer
than r_f to the roller centre).

V and A come from implicit differentiation of the contact with the feature's osculating
circle (a line for a straight edge) frozen: exact one-sided derivatives; they jump where
the feature in contact changes.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.contact.result import FollowerMotion, implicit_derivatives
from camtol.contact.shapes import AnalyticShape, PolygonShape
from camtol.exceptions import DesignError, GeometryError
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism
from camtol.motion import MotionState

__all__ = ["RollerPath", "follow_roller_oscillating", "follow_roller_translating", "roller_path"]

TWO_PI = 2.0 * math.pi
Shape = AnalyticShape | PolygonShape
#: Largest number of (θ, feature) pairs evaluated at once by the roller solver.
MAX_PAIRS = 2_000_000


# ---------------------------------------------------------------------------------------
# The follower's path of roller centres
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RollerPath:
    """The roller centre's path as a function of (θ, x) for one follower.

    Parameters
    ----------
    kind : {"line", "circle"}
        Translating (x = axial position y [mm]) or oscillating (x = arm angle γ [rad]).
    offset_mm : float
        Translating: offset e. [mm]
    pivot_mm : float or ndarray
        Oscillating: centre distance f (an array broadcasting with θ when the pivot
        moves, as in the measuring fixture). [mm]
    arm_mm : float
        Oscillating: arm length l. [mm]
    side : int
        Oscillating: −1 (cam A, γ = ξ) or +1 (cam B, γ = η − ξ).
    roller_mm : float
        Roller radius r_f. [mm]
    """

    kind: str
    roller_mm: float
    offset_mm: float = 0.0
    pivot_mm: float | FloatArray = 0.0
    arm_mm: float = 0.0
    side: int = -1

    def centre(self, theta: FloatArray, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Roller centre C(θ, x). [mm]

        Parameters
        ----------
        theta : ndarray
            Cam angles θ. [rad]
        x : ndarray
            Path coordinate, broadcasting with ``theta``: axial position y (line) [mm] or
            arm angle γ (circle) [rad].

        Returns
        -------
        cx, cy : ndarray
            Roller centre in the cam frame. [mm]
        """
        ct, st = np.cos(theta), np.sin(theta)
        if self.kind == "line":
            return -self.offset_mm * st + x * ct, self.offset_mm * ct + x * st
        beta = theta + self.side * x
        return (
            self.pivot_mm * ct - self.arm_mm * np.cos(beta),
            self.pivot_mm * st - self.arm_mm * np.sin(beta),
        )

    def partials(
        self, theta: FloatArray, x: FloatArray
    ) -> tuple[tuple[FloatArray, FloatArray], ...]:
        """(C_θ, C_x, C_θθ, C_θx, C_xx), each as an (x, y) pair. [mm per unit^k]

        Parameters
        ----------
        theta : ndarray
            Cam angles θ. [rad]
        x : ndarray
            Path coordinate, broadcasting with ``theta``: axial position y (line) [mm] or
            arm angle γ (circle) [rad].

        Returns
        -------
        tuple of (ndarray, ndarray)
            The five partial derivatives of C, in the order above. [mm per rad or mm per
            unit of x, to the order of the derivative]
        """
        ct, st = np.cos(theta), np.sin(theta)
        z = np.zeros_like(theta)
        if self.kind == "line":
            e = self.offset_mm
            return (
                (-e * ct - x * st, -e * st + x * ct),
                (ct, st),
                (e * st - x * ct, -e * ct - x * st),
                (-st, ct),
                (z, z),
            )
        f, ln, s = self.pivot_mm, self.arm_mm, self.side
        beta = theta + s * x
        cb, sb = np.cos(beta), np.sin(beta)
        return (
            (-f * st + ln * sb, f * ct - ln * cb),
            (s * ln * sb, -s * ln * cb),
            (-f * ct + ln * cb, -f * st + ln * sb),
            (s * ln * cb, s * ln * sb),
            (ln * cb, ln * sb),
        )

    # --- intersections of the path with circles and lines --------------------------------
    def circle_roots(
        self, theta: FloatArray, cx: FloatArray, cy: FloatArray, d: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Both x where |C(θ, x) − c| = d (NaN where none); broadcasting (N,1) × (1,K).

        Parameters
        ----------
        theta : ndarray
            Cam angles θ, e.g. of shape (N, 1). [rad]
        cx, cy : ndarray
            Centre c of the circle in the cam frame, e.g. of shape (1, K). [mm]
        d : ndarray
            Required distance between C and c. [mm]

        Returns
        -------
        x1, x2 : ndarray
            The two roots, broadcast shape of the inputs; NaN where the path misses the
            circle. [mm for a line path, rad for a circle path]
        """
        ct, st = np.cos(theta), np.sin(theta)
        if self.kind == "line":
            p = cx * ct + cy * st
            s = -cx * st + cy * ct
            with np.errstate(invalid="ignore"):
                root = np.sqrt(d * d - (self.offset_mm - s) ** 2)
            return p + root, p - root
        f, ln = self.pivot_mm, self.arm_mm
        ux, uy = cx - f * ct, cy - f * st
        big_d = np.hypot(ux, uy)
        with np.errstate(invalid="ignore", divide="ignore"):
            kappa = np.arccos((ln * ln + big_d * big_d - d * d) / (2.0 * ln * big_d))
        base = np.arctan2(uy, ux)
        return self._angle_to_x(theta, base + kappa), self._angle_to_x(theta, base - kappa)

    def line_roots(
        self, theta: FloatArray, nx: FloatArray, ny: FloatArray, k: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Return x where n·C(θ, x) = k (NaN where none; a line path gives one root twice).

        Parameters
        ----------
        theta : ndarray
            Cam angles θ. [rad]
        nx, ny : ndarray
            Unit normal n of the line in the cam frame. [dimensionless]
        k : ndarray
            Signed distance of the line from O2 along n. [mm]

        Returns
        -------
        x1, x2 : ndarray
            The two roots, broadcast shape of the inputs; NaN where there is none.
            [mm for a line path, rad for a circle path]
        """
        ct, st = np.cos(theta), np.sin(theta)
        if self.kind == "line":
            den = nx * ct + ny * st
            ok = np.abs(den) > 1e-14
            with np.errstate(invalid="ignore", divide="ignore"):
                y = np.where(ok, (k - self.offset_mm * (-nx * st + ny * ct)) / den, np.nan)
            return y, y
        f, ln = self.pivot_mm, self.arm_mm
        m = (k - f * (nx * ct + ny * st)) / ln
        with np.errstate(invalid="ignore"):
            a = np.arccos(m)
        base = np.arctan2(ny, nx)
        return self._angle_to_x(theta, base + a), self._angle_to_x(theta, base - a)

    def _angle_to_x(self, theta: FloatArray, alpha: FloatArray) -> FloatArray:
        """Arm angle γ for the direction α of O3→C, wrapped to (−π, π]. [rad]"""
        g = self.side * (alpha - theta - math.pi)
        return np.asarray(math.pi - np.mod(math.pi - g, TWO_PI))


def roller_path(follower: Mechanism) -> tuple[RollerPath, float, float, float]:
    """Return the roller path of a mechanism and how its coordinate x maps to the output.

    Parameters
    ----------
    follower : Mechanism
        A roller follower: translating, oscillating, conjugate cam B, or a conjugate pair
        (which stands for its cam A).

    Returns
    -------
    path : RollerPath
    sign, shift : float
        The follower's absolute output is sign·x + shift: the axial position y
        (translating, 1, 0), ξ = γ (cam A, 1, 0) or ξ = η − γ (cam B, −1, η). [mm or rad]
    zero : float
        The absolute output at S = 0: s0 (translating) or ξ0 (oscillating). [mm or rad]

    Raises
    ------
    DesignError
        If the mechanism is not a roller follower.
    """
    if follower.kind == "conjugate":
        follower = follower.cam_a  # type: ignore[attr-defined]
    kind = follower.kind
    params = vars(follower)
    if kind == "roller_translating":
        path = RollerPath("line", params["roller_radius_mm"], offset_mm=params["offset_mm"])
        return path, 1.0, 0.0, float(follower.s0_mm)  # type: ignore[attr-defined]
    if kind in ("roller_oscillating", "conjugate_cam_b"):
        side = -1 if kind == "roller_oscillating" else 1
        path = RollerPath(
            "circle",
            params["roller_radius_mm"],
            pivot_mm=params["pivot_distance_mm"],
            arm_mm=params["arm_length_mm"],
            side=side,
        )
        xi0 = float(follower.initial_angle_rad)  # type: ignore[attr-defined]
        if side < 0:
            return path, 1.0, 0.0, xi0
        return path, -1.0, float(params["arm_angle_rad"]), xi0
    raise DesignError(f"follower type {kind!r} is not a roller follower")


# ---------------------------------------------------------------------------------------
# Polygon features
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Features:
    # circles: centre, radius d, feature id, span (start, sweep; sweep 0 = no check),
    # foot sign (+1: foot along C − c; −1: opposite)
    cx: FloatArray
    cy: FloatArray
    d: FloatArray
    cid: NDArray[np.intp]
    start: FloatArray
    sweep: FloatArray
    foot: FloatArray
    rho: FloatArray  # signed radius of curvature of the feature (0 vertex, ±R arc)
    # lines: unit normal n, level k (n·C = k), segment start, unit direction, length, id
    nx: FloatArray
    ny: FloatArray
    k: FloatArray
    sx: FloatArray
    sy: FloatArray
    tx: FloatArray
    ty: FloatArray
    length: FloatArray
    lid: NDArray[np.intp]
    lsign: FloatArray


def _features(poly: PolygonShape, rf: float) -> _Features:
    """Contact features facing outward: the only ones that can hold the roller.

    The roller rests at the outermost point of the set of centres within r_f of the
    boundary; there the centre lies outside the cam, so its nearest boundary point is
    approached from outside: vertex circles (radius r_f), the outward offset of each
    straight edge, the circle R + r_f of a convex arc and R − r_f of a concave arc (when
    r_f < R; a roller wider than a concave arc cannot touch its inside).
    """
    v = poly.vertices_mm
    m = poly.size
    nxt = np.roll(v, -1, axis=0)
    idx, acx, acy, radius, sweep = poly.arcs
    start = np.arctan2(v[idx, 1] - acy, v[idx, 0] - acx)
    convex = sweep > 0
    fits = convex | (radius > rf)
    idx, convex = idx[fits], convex[fits]
    acx, acy, radius, sweep, start = (a[fits] for a in (acx, acy, radius, sweep, start))
    d_arc = np.where(convex, radius + rf, radius - rf)
    cx = np.concatenate([v[:, 0], acx])
    cy = np.concatenate([v[:, 1], acy])
    d = np.concatenate([np.full(m, rf), d_arc])
    cid = np.concatenate([np.arange(m), m + idx]).astype(np.intp)
    st = np.concatenate([np.zeros(m), start])
    sw = np.concatenate([np.zeros(m), sweep])
    foot = np.ones(cx.size)
    rho = np.concatenate([np.zeros(m), np.where(convex, radius, -radius)])
    straight = np.flatnonzero(poly.bulges == 0.0)
    seg = nxt[straight] - v[straight]
    length = np.hypot(seg[:, 0], seg[:, 1])
    tx, ty = seg[:, 0] / length, seg[:, 1] / length
    nx, ny = ty, -tx  # outward normal of a counterclockwise polygon
    level = nx * v[straight, 0] + ny * v[straight, 1]
    return _Features(
        cx, cy, d, cid, st, sw, foot, rho,
        nx, ny, level + rf, v[straight, 0], v[straight, 1], tx, ty, length,
        (m + straight).astype(np.intp), np.ones(straight.size),
    )  # fmt: skip


def _in_span(angle: FloatArray, start: FloatArray, sweep: FloatArray) -> NDArray[np.bool_]:
    fwd = np.mod(angle - start, TWO_PI) <= sweep + 1e-12
    back = np.mod(start - angle, TWO_PI) <= -sweep + 1e-12
    return np.asarray((sweep == 0) | ((sweep > 0) & fwd) | ((sweep < 0) & back))


@dataclass(frozen=True)
class _Contact:
    x: FloatArray
    kind: NDArray[np.intp]  # 0 circle, 1 line
    index: NDArray[np.intp]  # into the circle or line arrays


def stab(
    query_rad: FloatArray, lo_rad: FloatArray, width_rad: FloatArray
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """All (query, interval) pairs with the query angle inside the interval (mod 2π).

    Parameters
    ----------
    query_rad : ndarray
        Query angles. [rad]
    lo_rad, width_rad : ndarray
        Interval starts and widths (0 ≤ width ≤ 2π). [rad]

    Returns
    -------
    query_index, interval_index : ndarray of int
        Pairs, O(N log N + K log N + pairs).
    """
    p = np.mod(query_rad, TWO_PI)
    order = np.argsort(p, kind="stable")
    ps = p[order]
    lo = np.mod(lo_rad, TWO_PI)
    hi = lo + np.minimum(width_rad, TWO_PI)
    s1 = np.searchsorted(ps, lo, side="left")
    e1 = np.searchsorted(ps, np.minimum(hi, TWO_PI), side="right")
    s2 = np.zeros_like(s1)
    wrap = hi - TWO_PI
    e2 = np.where(
        wrap > 0,
        np.where(wrap < lo, np.searchsorted(ps, wrap, side="right"), s1),
        0,
    )
    starts = np.concatenate([s1, s2])
    counts = np.maximum(np.concatenate([e1, e2]) - starts, 0)
    k = np.arange(lo.size)
    interval = np.repeat(np.concatenate([k, k]), counts)
    first = np.cumsum(counts) - counts
    pos = np.arange(int(counts.sum())) - np.repeat(first, counts) + np.repeat(starts, counts)
    return order[pos], interval


def _windows(
    path: RollerPath, bx: FloatArray, by: FloatArray, bd: FloatArray
) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
    """θ intervals (start, width, feature) where the path passes within bd of (bx, by)."""
    r = np.hypot(bx, by)
    beta = np.arctan2(by, bx)
    with np.errstate(invalid="ignore", divide="ignore"):
        if path.kind == "line":
            # |e − b·w| ≤ bd with b·w = r sin(β − θ).
            lo = np.clip((path.offset_mm - bd) / r, -1.0, 1.0)
            hi = np.clip((path.offset_mm + bd) / r, -1.0, 1.0)
            a_lo, a_hi = np.arcsin(lo), np.arcsin(hi)
            starts = [beta - a_hi, beta - math.pi + a_lo]
            widths = [a_hi - a_lo, a_hi - a_lo]
        else:
            # l − bd ≤ |f t − b| ≤ l + bd, |f t − b|² = f² + r² − 2 f r cos(θ − β).
            f, ln = path.pivot_mm, path.arm_mm
            c_hi = (f * f + r * r - np.maximum(ln - bd, 0.0) ** 2) / (2 * f * r)
            c_lo = (f * f + r * r - (ln + bd) ** 2) / (2 * f * r)
            g_lo = np.arccos(np.clip(c_hi, -1.0, 1.0))
            g_hi = np.arccos(np.clip(c_lo, -1.0, 1.0))
            starts = [beta + g_lo, beta - g_hi]
            widths = [g_hi - g_lo, g_hi - g_lo]
    everywhere = ~(r > bd)  # feature near O2 (or the pivot circle): keep for all θ
    feat = np.arange(bx.size)
    s = np.concatenate([np.where(everywhere, 0.0, starts[0]), starts[1][~everywhere]])
    w = np.concatenate([np.where(everywhere, TWO_PI, widths[0]), widths[1][~everywhere]])
    fi = np.concatenate([feat, feat[~everywhere]]).astype(np.intp)
    pad = 1e-9
    return s - pad, np.minimum(w + 2 * pad, TWO_PI), fi


def _polygon_contact(
    theta: FloatArray, path: RollerPath, feat: _Features, pivot: FloatArray | None = None
) -> _Contact:
    """Outermost roller position over the features the path can reach (exact prefilter).

    Each feature has a bounding circle (the contact circle itself, or the offset
    segment's circumcircle); it can only touch the roller for θ where the path passes
    within that circle, an angular window found in closed form. Pairs (θ, feature) are
    built by interval stabbing, so the cost is O((N + M) log N + pairs) instead of
    O(N·M). With ``pivot`` (one centre distance per θ, the measuring fixture) the windows
    are widened by half the spread of the pivot positions.
    """
    mx = feat.sx + 0.5 * feat.length * feat.tx
    my = feat.sy + 0.5 * feat.length * feat.ty
    bx = np.concatenate([feat.cx, mx])
    by = np.concatenate([feat.cy, my])
    bd = np.concatenate([feat.d, 0.5 * feat.length + path.roller_mm]) * (1 + 1e-9) + 1e-9
    wpath, spread = path, 0.0
    if pivot is not None:
        lo, hi = float(np.min(pivot)), float(np.max(pivot))
        wpath, spread = dataclasses.replace(path, pivot_mm=0.5 * (lo + hi)), 0.5 * (hi - lo)
    s, w, fi = _windows(wpath, bx, by, bd + spread)
    # Memory: about 10 arrays per (θ, feature) pair; work in blocks of θ of at most
    # MAX_PAIRS expected pairs.
    expected = float(np.sum(w)) / TWO_PI * theta.size
    blocks = max(1, math.ceil(expected / MAX_PAIRS))
    if blocks > 1:
        parts = [
            _polygon_contact_block(
                theta[b], path, feat, s, w, fi, None if pivot is None else pivot[b]
            )
            for b in np.array_split(np.arange(theta.size), blocks)
        ]
        return _Contact(
            np.concatenate([c.x for c in parts]),
            np.concatenate([c.kind for c in parts]),
            np.concatenate([c.index for c in parts]),
        )
    return _polygon_contact_block(theta, path, feat, s, w, fi, pivot)


def _polygon_contact_block(
    theta: FloatArray,
    path: RollerPath,
    feat: _Features,
    s: FloatArray,
    w: FloatArray,
    fi: NDArray[np.intp],
    pivot: FloatArray | None,
) -> _Contact:
    """:func:`_polygon_contact` for one block of θ, given the features' θ windows."""
    kc = feat.cx.size
    qi, ii = stab(theta, s, w)
    fj = fi[ii]
    th = theta[qi]
    pv = None if pivot is None else np.asarray(pivot)[qi]

    def at(mask: NDArray[np.bool_]) -> RollerPath:
        return path if pv is None else dataclasses.replace(path, pivot_mm=pv[mask])

    val = np.full(qi.size, -np.inf)
    circ = fj < kc
    if np.any(circ):
        j, t = fj[circ], th[circ]
        best = np.full(j.size, -np.inf)
        pc = at(circ)
        arc = feat.sweep[j] != 0.0  # vertex circles need no span check
        for root in pc.circle_roots(t, feat.cx[j], feat.cy[j], feat.d[j]):
            ok = np.isfinite(root)
            if np.any(arc):
                ja, ta, ra = j[arc], t[arc], root[arc]
                pa = pc if pv is None else dataclasses.replace(pc, pivot_mm=pc.pivot_mm[arc])  # type: ignore[index]
                px, py = pa.centre(ta, ra)
                gx, gy = (px - feat.cx[ja]) * feat.foot[ja], (py - feat.cy[ja]) * feat.foot[ja]
                ok[arc] &= _in_span(np.arctan2(gy, gx), feat.start[ja], feat.sweep[ja])
            best = np.maximum(best, np.where(ok, root, -np.inf))
        val[circ] = best
    line = ~circ
    if np.any(line):
        j, t = fj[line] - kc, th[line]
        best = np.full(j.size, -np.inf)
        pl = at(line)
        for root in pl.line_roots(t, feat.nx[j], feat.ny[j], feat.k[j]):
            px, py = pl.centre(t, root)
            fx = px - feat.lsign[j] * path.roller_mm * feat.nx[j]
            fy = py - feat.lsign[j] * path.roller_mm * feat.ny[j]
            u = (fx - feat.sx[j]) * feat.tx[j] + (fy - feat.sy[j]) * feat.ty[j]
            ok = np.isfinite(root) & (u >= 0) & (u <= feat.length[j])
            best = np.maximum(best, np.where(ok, root, -np.inf))
        val[line] = best
    n = theta.size
    top = np.full(n, -np.inf)
    np.maximum.at(top, qi, val)
    if not np.all(np.isfinite(top)):
        i = int(np.argmax(~np.isfinite(top)))
        raise GeometryError(
            f"the roller cannot reach the cam at θ={math.degrees(theta[i]):.2f}°"
            " (check the follower's dimensions against the shape)"
        )
    win = np.flatnonzero(val == top[qi])
    winner = np.zeros(n, dtype=np.intp)
    winner[qi[win]] = fj[win]
    is_line = winner >= kc
    return _Contact(top, is_line.astype(np.intp), np.where(is_line, winner - kc, winner))


def _polygon_contact_bruteforce(
    theta: FloatArray, path: RollerPath, feat: _Features, chunk_elements: int = 2_000_000
) -> _Contact:
    """Outermost roller position over every feature: brute force O(N·M), blocks of θ."""
    n = theta.size
    kc, kl = feat.cx.size, feat.nx.size
    chunk = max(1, chunk_elements // max(kc + kl, 1))
    best = np.full(n, -np.inf)
    kind = np.zeros(n, dtype=np.intp)
    index = np.zeros(n, dtype=np.intp)
    for s0 in range(0, n, chunk):
        th = theta[s0 : s0 + chunk, None]
        cand_c = np.full((th.shape[0], max(kc, 1)), -np.inf)
        if kc:
            for root in path.circle_roots(th, feat.cx, feat.cy, feat.d):
                px, py = path.centre(th, root)
                gx, gy = (px - feat.cx) * feat.foot, (py - feat.cy) * feat.foot
                ok = np.isfinite(root) & _in_span(np.arctan2(gy, gx), feat.start, feat.sweep)
                cand_c = np.maximum(cand_c, np.where(ok, root, -np.inf))
        cand_l = np.full((th.shape[0], max(kl, 1)), -np.inf)
        if kl:
            for root in path.line_roots(th, feat.nx, feat.ny, feat.k):
                px, py = path.centre(th, root)
                fx = px - feat.lsign * path.roller_mm * feat.nx
                fy = py - feat.lsign * path.roller_mm * feat.ny
                u = (fx - feat.sx) * feat.tx + (fy - feat.sy) * feat.ty
                ok = np.isfinite(root) & (u >= 0) & (u <= feat.length)
                cand_l = np.maximum(cand_l, np.where(ok, root, -np.inf))
        ic = np.argmax(cand_c, axis=1)
        il = np.argmax(cand_l, axis=1)
        rows = np.arange(th.shape[0])
        vc, vl = cand_c[rows, ic], cand_l[rows, il]
        use_l = vl > vc
        sl = slice(s0, s0 + th.shape[0])
        best[sl] = np.where(use_l, vl, vc)
        kind[sl] = use_l.astype(np.intp)
        index[sl] = np.where(use_l, il, ic)
    if not np.all(np.isfinite(best)):
        i = int(np.argmax(~np.isfinite(best)))
        raise GeometryError(
            f"the roller cannot reach the cam at θ={math.degrees(theta[i]):.2f}°"
            " (check the follower's dimensions against the shape)"
        )
    return _Contact(best, kind, index)


def _derivatives_circle(
    path: RollerPath, theta: FloatArray, x: FloatArray, cx: FloatArray, cy: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """x', x'' with the contact circle |C − c| = const frozen (implicit derivatives)."""
    px, py = path.centre(theta, x)
    gx, gy = px - cx, py - cy
    (t1, x1, tt, tx, xx) = path.partials(theta, x)

    def dot(a: tuple[FloatArray, FloatArray], b: tuple[FloatArray, FloatArray]) -> FloatArray:
        return np.asarray(a[0] * b[0] + a[1] * b[1])

    g = (gx, gy)
    return implicit_derivatives(
        2 * dot(g, t1),
        2 * dot(g, x1),
        2 * (dot(t1, t1) + dot(g, tt)),
        2 * (dot(t1, x1) + dot(g, tx)),
        2 * (dot(x1, x1) + dot(g, xx)),
    )


def _derivatives_line(
    path: RollerPath, theta: FloatArray, x: FloatArray, nx: FloatArray, ny: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """x', x'' with the contact line n·C = k frozen."""
    parts = path.partials(theta, x)
    g = [nx * p[0] + ny * p[1] for p in parts]
    return implicit_derivatives(g[0], g[1], g[2], g[3], g[4])


# ---------------------------------------------------------------------------------------
# Solvers
# ---------------------------------------------------------------------------------------
def _solve_polygon(
    theta: FloatArray,
    poly: PolygonShape,
    path: RollerPath,
    *,
    bruteforce: bool = False,
    pivot: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    """x, x', x'', contact point and feature id on a polygon."""
    feat = _features(poly, path.roller_mm)
    if pivot is not None:
        path = dataclasses.replace(path, pivot_mm=pivot)
        sol = _polygon_contact(theta, path, feat, pivot)
    else:
        solve = _polygon_contact_bruteforce if bruteforce else _polygon_contact
        sol = solve(theta, path, feat)
    x = sol.x
    px, py = path.centre(theta, x)
    is_line = sol.kind == 1
    ic = np.where(is_line, 0, sol.index)
    il = np.where(is_line, sol.index, 0)
    x1c, x2c = _derivatives_circle(path, theta, x, feat.cx[ic], feat.cy[ic])
    x1l, x2l = (
        _derivatives_line(path, theta, x, feat.nx[il], feat.ny[il]) if feat.nx.size else (x1c, x2c)
    )
    x1 = np.where(is_line, x1l, x1c)
    x2 = np.where(is_line, x2l, x2c)
    # Contact point: r_f from C along the normal, towards the feature (away from the
    # centre of a concave arc, whose inside the roller rolls on).
    gx, gy = px - feat.cx[ic], py - feat.cy[ic]
    gn = np.hypot(gx, gy)
    towards = np.where(feat.rho[ic] < 0, -1.0, 1.0) * path.roller_mm / gn
    ax_c, ay_c = px - towards * gx, py - towards * gy
    if feat.nx.size:
        ax_l = px - feat.lsign[il] * path.roller_mm * feat.nx[il]
        ay_l = py - feat.lsign[il] * path.roller_mm * feat.ny[il]
    else:
        ax_l, ay_l = ax_c, ay_c
    ax = np.where(is_line, ax_l, ax_c)
    ay = np.where(is_line, ay_l, ay_c)
    lid = feat.lid[il] if feat.lid.size else np.zeros_like(il)
    fid = np.where(is_line, lid, feat.cid[ic])
    return x, x1, x2, ax, ay, fid


def _solve_analytic(
    theta: FloatArray,
    shape: AnalyticShape,
    path: RollerPath,
    t0: FloatArray,
    x0: FloatArray,
    left_limit: ArrayLike | None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """x, x', x'', contact point and profile parameter by 2×2 Newton from (t0, x0)."""
    t, x = t0.copy(), x0.copy()
    rf = path.roller_mm
    step_t = 4.0 * TWO_PI / shape.samples
    for _ in range(60):
        px, py = shape.jets(t)
        cx, cy = path.centre(theta, x)
        (_, (cxx, cxy), *_rest) = path.partials(theta, x)
        gx, gy = cx - px.v, cy - py.v
        g1 = gx * px.d1 + gy * py.d1
        g2 = gx * gx + gy * gy - rf * rf
        a11 = -(px.d1**2 + py.d1**2) + gx * px.d2 + gy * py.d2
        a12 = cxx * px.d1 + cxy * py.d1
        a21 = -2.0 * g1
        a22 = 2.0 * (gx * cxx + gy * cxy)
        det = a11 * a22 - a12 * a21
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = -(a22 * g1 - a12 * g2) / det
            dx = -(-a21 * g1 + a11 * g2) / det
        if not (np.all(np.isfinite(dt)) and np.all(np.isfinite(dx))):
            raise GeometryError("the roller contact on the analytic profile is singular")
        dt = np.clip(dt, -step_t, step_t)
        t, x = t + dt, x + dx
        if np.max(np.abs(dt)) < 1e-13 and np.max(np.abs(dx)) < 1e-12:
            break
    else:
        raise GeometryError("the roller contact on the analytic profile did not converge")
    t = shape.snap(t)
    px, py = shape.jets(t, left_limit=left_limit)
    cx, cy = path.centre(theta, x)
    _check_clear(shape, cx, cy, rf, theta)
    speed = np.hypot(px.d1, py.d1)
    cross = px.d1 * py.d2 - py.d1 * px.d2
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = speed**3 / cross
    nx, ny = py.d1 / speed, -px.d1 / speed  # outward normal (counterclockwise profile)
    ccx, ccy = px.v - rho * nx, py.v - rho * ny
    flat = ~np.isfinite(rho) | (np.abs(rho) > 1e9)
    x1, x2 = _derivatives_circle(path, theta, x, ccx, ccy)
    if np.any(flat):
        l1, l2 = _derivatives_line(path, theta, x, nx, ny)
        x1, x2 = np.where(flat, l1, x1), np.where(flat, l2, x2)
    return x, x1, x2, px.v, py.v, t


def _check_clear(
    shape: AnalyticShape, cx: FloatArray, cy: FloatArray, rf: float, theta: FloatArray
) -> None:
    from scipy.spatial import cKDTree

    tree = cKDTree(shape.polygon.vertices_mm)
    dist, _ = tree.query(np.stack([cx, cy], axis=1))
    bad = dist < rf - 1e-7
    if np.any(bad):
        i = int(np.argmax(bad))
        raise GeometryError(
            f"the roller overlaps the cam at θ={math.degrees(theta[i]):.2f}° (distance"
            f" {dist[i]:.6g} mm < r_f = {rf:g} mm): the profile is undercut or the contact"
            " jumped to another part of the cam"
        )


def _follow_roller(
    theta_rad: ArrayLike,
    shape: Shape,
    follower: Mechanism,
    reference: Mechanism | None,
    left_limit: ArrayLike | None,
) -> FollowerMotion:
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    path, sign, shift, _ = roller_path(follower)
    zero = roller_path(follower if reference is None else reference)[3]
    param = np.full(theta.shape, np.nan)
    if isinstance(shape, AnalyticShape):
        seed = _analytic_seed(theta, shape, path)
        solved = None
        if seed is not None:
            try:
                solved = _solve_analytic(theta, shape, path, seed[0], seed[1], left_limit)
            except GeometryError:
                solved = None  # e.g. the error moved the contact: seed from the polygon
        if solved is None:
            # Global seed: the exact contact on the sampled polygon (vertex, or an edge's
            # first vertex), then Newton on the curve.
            xs, *_r, fid = _solve_polygon(theta, shape.polygon, path)
            seed = (shape.vertex_param(fid), xs)
            solved = _solve_analytic(theta, shape, path, seed[0], seed[1], left_limit)
        x, x1, x2, ax, ay, param = solved
        fid = np.full(theta.shape, -1, dtype=np.intp)
    else:
        x, x1, x2, ax, ay, fid = _solve_polygon(theta, shape, path)
    output = sign * x + shift
    lift = output - zero
    rx, ry = path.centre(theta, x)
    extras = {"roller_x_mm": rx, "roller_y_mm": ry}
    if path.kind == "circle":
        extras["follower_angle_rad"] = output
    return FollowerMotion(
        theta_rad=theta,
        motion=MotionState(lift, sign * x1, sign * x2, np.full_like(lift, np.nan)),
        contact_x_mm=ax,
        contact_y_mm=ay,
        feature=fid,
        param_rad=param,
        extras=extras,
    )


def _analytic_seed(
    theta: FloatArray, shape: AnalyticShape, path: RollerPath
) -> tuple[FloatArray, FloatArray] | None:
    """(t0, x0) from the shape's own nominal mechanism when it is a roller of this path."""
    mech = shape.mechanism
    try:
        own_path, sign, shift, zero = roller_path(mech)
    except (DesignError, KeyError):
        return None
    if own_path.kind != path.kind or own_path.side != path.side:
        return None
    lift = shape.program.evaluate(theta).lift
    return np.mod(theta, TWO_PI), sign * (lift + zero - shift)


def follow_roller_translating(
    theta_rad: ArrayLike,
    shape: Shape,
    follower: Mechanism,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
) -> FollowerMotion:
    """Exact lift of a translating (offset) roller follower on a shape.

    Parameters
    ----------
    theta_rad : array_like
        Cam angles. [rad]
    shape : AnalyticShape or PolygonShape
        The cam.
    follower : RollerTranslating
        The actual follower (offset e, roller radius r_f).
    reference : RollerTranslating, optional
        Follower whose s0 = sqrt((r_b + r_f)² − e²) defines S = 0 (default: ``follower``).
    left_limit : array_like of bool, optional
        Rows taking one-sided derivatives at profile boundaries.

    Returns
    -------
    FollowerMotion
        S [mm], V [mm/rad], A [mm/rad²], contact point, ``roller_x_mm``/``roller_y_mm``.
    """
    return _follow_roller(theta_rad, shape, follower, reference, left_limit)


def follow_roller_oscillating(
    theta_rad: ArrayLike,
    shape: Shape,
    follower: Mechanism,
    *,
    reference: Mechanism | None = None,
    left_limit: ArrayLike | None = None,
) -> FollowerMotion:
    """Exact angle of an oscillating roller follower (cam A, or cam B of a pair).

    Parameters
    ----------
    theta_rad : array_like
        Cam angles from the line of centres. [rad]
    shape : AnalyticShape or PolygonShape
        The cam.
    follower : RollerOscillating or ConjugateCamB
        The actual follower (f, l, r_f; η for cam B).
    reference : same type, optional
        Follower whose ξ0 defines S = 0 (default: ``follower``).
    left_limit : array_like of bool, optional
        Rows taking one-sided derivatives at profile boundaries.

    Returns
    -------
    FollowerMotion
        S = ξ − ξ0 [rad], V, A, contact point, ``follower_angle_rad`` ξ, roller centre.
    """
    return _follow_roller(theta_rad, shape, follower, reference, left_limit)
