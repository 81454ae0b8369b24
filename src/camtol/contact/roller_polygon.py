"""Exact roller contact on a polygon with straight and circular edges (THEORY §5).

Every feature gives the positions where the roller touches it in closed form (a circle of
radius r_f about a vertex, the two offset lines of a segment, the circles of radius
R ± r_f about an arc's centre, each kept only where the foot of the normal lies on the
feature), and the roller rests at the outermost of them (largest y, or largest γ): the
first contact coming from outside. This is exact for non-convex shapes as well. Windows
of candidate features are found by stabbing sorted extents, evaluated in blocks of at
most :data:`MAX_PAIRS` (θ, feature) pairs.

V and A come from implicit differentiation of the contact with the feature's osculating
circle (a line for a straight edge) frozen: exact one-sided derivatives; they jump where
the feature in contact changes.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from camtol.contact.result import implicit_derivatives
from camtol.contact.roller_path import RollerPath
from camtol.contact.shapes import PolygonShape
from camtol.exceptions import GeometryError
from camtol.jet import FloatArray

__all__ = ["MAX_PAIRS", "derivatives_circle", "derivatives_line", "solve_polygon", "stab"]

TWO_PI = 2.0 * math.pi
#: Largest number of (θ, feature) pairs evaluated at once by the roller solver.
MAX_PAIRS = 2_000_000


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


def derivatives_circle(
    path: RollerPath, theta: FloatArray, x: FloatArray, cx: FloatArray, cy: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Return x', x'' with the contact circle |C − c| = const frozen (implicit derivatives).

    Parameters
    ----------
    path : RollerPath
        The roller centre's path.
    theta : ndarray
        Cam angles. [rad]
    x : ndarray
        Path coordinate at the contact. [mm or rad]
    cx, cy : ndarray
        Centre of the osculating circle (vertex, arc centre) in contact. [mm]

    Returns
    -------
    tuple of ndarray
        dx/dθ and d²x/dθ². [mm or rad, per rad^k]
    """
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


def derivatives_line(
    path: RollerPath, theta: FloatArray, x: FloatArray, nx: FloatArray, ny: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Return x', x'' with the contact line n·C = k frozen (implicit derivatives).

    Parameters
    ----------
    path : RollerPath
        The roller centre's path.
    theta : ndarray
        Cam angles. [rad]
    x : ndarray
        Path coordinate at the contact. [mm or rad]
    nx, ny : ndarray
        Unit normal of the straight edge in contact. [-]

    Returns
    -------
    tuple of ndarray
        dx/dθ and d²x/dθ². [mm or rad, per rad^k]
    """
    parts = path.partials(theta, x)
    g = [nx * p[0] + ny * p[1] for p in parts]
    return implicit_derivatives(g[0], g[1], g[2], g[3], g[4])


def solve_polygon(
    theta: FloatArray,
    poly: PolygonShape,
    path: RollerPath,
    *,
    bruteforce: bool = False,
    pivot: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    """Return x, x', x'', the contact point and the feature id on a polygon.

    Parameters
    ----------
    theta : ndarray
        Cam angles. [rad]
    poly : PolygonShape
        The cam.
    path : RollerPath
        The roller centre's path.
    bruteforce : bool
        Evaluate every (θ, feature) pair instead of the windowed search (for tests).
    pivot : ndarray, optional
        A moving pivot distance per θ (the measuring fixture). [mm]

    Returns
    -------
    tuple
        x, dx/dθ, d²x/dθ² [mm or rad, per rad^k], contact point x and y [mm] and the
        feature index.
    """
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
    x1c, x2c = derivatives_circle(path, theta, x, feat.cx[ic], feat.cy[ic])
    x1l, x2l = (
        derivatives_line(path, theta, x, feat.nx[il], feat.ny[il]) if feat.nx.size else (x1c, x2c)
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
