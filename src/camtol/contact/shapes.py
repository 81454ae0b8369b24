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
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol import jet
from camtol.contact.errors_profile import ProfileError
from camtol.contact.polygon import PolygonShape, Support, sweep_rank
from camtol.design.motion import MotionProgram
from camtol.exceptions import GeometryError
from camtol.jet import FloatArray, Jet, JetLike
from camtol.mechanisms.base import Mechanism

__all__ = ["AnalyticShape", "PolygonShape", "Support", "sweep_rank"]

TWO_PI = 2.0 * math.pi
IntArray = NDArray[np.intp]


def _as_jet(x: JetLike, like: FloatArray) -> Jet:
    if isinstance(x, Jet):
        return x
    return Jet.constant(x, like)


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
            Same mechanism, program and samples with the new errors; it shares this
            shape's nominal geometry at the sampled polygon's parameters (the errors do
            not change it), so a series of shapes with other errors computes it once.
        """
        new = AnalyticShape(self.mechanism, self.program, radial_error, normal_error, self.samples)
        new.__dict__["_grid_contact"] = self._grid_contact  # a cached_property's slot
        return new

    def _contact(self, t: FloatArray, left_limit: ArrayLike | None) -> Any:
        """Return the nominal follower's contact geometry at parameters t (jets)."""
        m = self.program.evaluate(t, left_limit=left_limit)
        theta = Jet.variable(t)
        lift = Jet(m.lift, m.velocity, m.acceleration)
        vel = Jet(m.velocity, m.acceleration, m.jerk)
        return self.mechanism.contact(theta, lift, vel)

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
        return self._with_profile_errors(t, self._contact(t, left_limit))

    def _with_profile_errors(self, t: FloatArray, g: Any) -> tuple[Jet, Jet]:
        """P(t) from the nominal contact geometry g at t and the profile errors."""
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
    def _grid_contact(self) -> Any:
        """The nominal geometry at :attr:`sample_param_rad` (shared by :meth:`with_errors`)."""
        return self._contact(self.sample_param_rad, None)

    @cached_property
    def _grid_jets(self) -> tuple[Jet, Jet]:
        """P(t) at :attr:`sample_param_rad` (the polygon's vertices and their parameters)."""
        return self._with_profile_errors(self.sample_param_rad, self._grid_contact)

    @cached_property
    def polygon(self) -> PolygonShape:
        """The profile sampled at :attr:`sample_param_rad` (vertices on the curve)."""
        px, py = self._grid_jets
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
        return self.sample_param_rad[self._vertex_grid_index(feature)]

    def _vertex_grid_index(self, feature: IntArray) -> IntArray:
        """Index into :attr:`sample_param_rad` of a vertex of :attr:`polygon`."""
        return self._vertex_grid_map[np.asarray(feature) % self.polygon.size]

    @cached_property
    def _vertex_grid_map(self) -> IntArray:
        poly = self.polygon
        px, py = self._grid_jets
        if poly.size == self.samples and np.allclose(poly.vertices_mm[0], [px.v[0], py.v[0]]):
            return np.arange(self.samples, dtype=np.intp)
        # The polygon may have been reversed on input (clockwise) or de-duplicated: map
        # back through the coordinates.
        from scipy.spatial import cKDTree

        tree = cKDTree(np.stack([px.v, py.v], axis=1))
        _, j = tree.query(poly.vertices_mm)
        return np.asarray(j, dtype=np.intp)

    def _grid_jets_at(self, index: IntArray) -> tuple[Jet, Jet]:
        """:attr:`_grid_jets` at grid indices: P(t) at those vertices, computed once."""
        out = []
        for g in self._grid_jets:
            parts = [
                np.broadcast_to(a, self.sample_param_rad.shape)[index] for a in (g.v, g.d1, g.d2)
            ]
            out.append(Jet(parts[0], parts[1], parts[2]))
        return out[0], out[1]

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
        b = np.unique(np.append(self.boundaries_rad, TWO_PI))  # sorted
        # the nearest boundary is one of the two around t (a search, not all pairs)
        hi = np.clip(np.searchsorted(b, t), 0, b.size - 1)
        lo = np.maximum(hi - 1, 0)
        j = np.where(np.abs(t - b[lo]) <= np.abs(b[hi] - t), lo, hi)
        near = np.abs(t - b[j]) < 1e-9
        return np.where(near, np.mod(b[j], TWO_PI), t)

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
        seed = self._vertex_grid_index(poly_sup.feature)
        t = self.sample_param_rad[seed]
        nx, ny = np.cos(psi), np.sin(psi)
        step = 2.0 * TWO_PI / self.samples
        for k in range(60):
            # The seeds are polygon vertices, where P is known already (the polygon).
            px, py = self._grid_jets_at(seed) if k == 0 else self.jets(t)
            f = px.d1 * nx + py.d1 * ny
            fp = px.d2 * nx + py.d2 * ny
            with np.errstate(divide="ignore", invalid="ignore"):
                dt = np.where(fp < 0, -f / fp, np.sign(f) * step)
            dt = np.clip(dt, -step, step)
            if np.max(np.abs(dt)) < 1e-13:
                # Converged at t itself (the next step is below 1e-13 rad): its jets are
                # the support point's, so point_support need not evaluate them again.
                break
            t = t + dt
        else:
            raise GeometryError("support point of the analytic profile did not converge")
        return self.point_support(
            psi, t, left_limit=left_limit, check_h=poly_sup.h_mm, jets_at_t=(px, py)
        )

    def _jets_reusing(
        self,
        t_given: FloatArray,
        t_snapped: FloatArray,
        jets_given: tuple[Jet, Jet],
        left_limit: ArrayLike | None,
    ) -> tuple[Jet, Jet]:
        """P at ``t_snapped`` from jets at ``t_given``, re-evaluating only where they differ.

        Rows that snapping moved onto a boundary, or that lie on a program boundary
        (where the left or right limit is chosen), are evaluated afresh; the others are
        the given jets (P is 2π-periodic, so a row that was only wrapped keeps them).
        """
        b = np.append(self.boundaries_rad, 0.0)
        redo = (t_snapped != np.mod(t_given, TWO_PI)) | np.isin(t_snapped, b)
        if not np.any(redo):
            return jets_given
        ll = None if left_limit is None else np.broadcast_to(left_limit, t_given.shape)[redo]
        fx, fy = self.jets(t_snapped[redo], left_limit=ll)
        out = []
        for given, fresh in ((jets_given[0], fx), (jets_given[1], fy)):
            parts = []
            for a, c in ((given.v, fresh.v), (given.d1, fresh.d1), (given.d2, fresh.d2)):
                m = np.array(np.broadcast_to(a, t_given.shape), dtype=float)
                m[redo] = c
                parts.append(m)
            out.append(Jet(parts[0], parts[1], parts[2]))
        return out[0], out[1]

    def point_support(
        self,
        psi: FloatArray,
        t: FloatArray,
        *,
        left_limit: ArrayLike | None = None,
        check_h: FloatArray | None = None,
        jets_at_t: tuple[Jet, Jet] | None = None,
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
        jets_at_t : (Jet, Jet), optional
            P(t) already evaluated at the given ``t`` (before snapping), e.g. by Newton's
            last iterate: reused wherever snapping leaves t unchanged and t is not a
            program boundary (where ``left_limit`` matters). [mm, mm/rad, mm/rad²]

        Returns
        -------
        Support
            Support value h, contact point and centre of curvature at P(t). [mm]

        Raises
        ------
        GeometryError
            If h is less than ``check_h`` (the point is not the global support point).
        """
        t_in = np.asarray(t, dtype=float)
        t = self.snap(t_in)
        if jets_at_t is None:
            px, py = self.jets(t, left_limit=left_limit)
        else:
            px, py = self._jets_reusing(t_in, t, jets_at_t, left_limit)
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
            normal_x=nx,
            normal_y=ny,
        )
