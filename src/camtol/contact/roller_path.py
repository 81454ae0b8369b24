"""The path of a roller follower's centre, C(θ, x) (THEORY §2.3, §2.4, §5).

- translating (THEORY §2.3): C = e·w + y·t on a line, t = (cos θ, sin θ),
  w = (−sin θ, cos θ); the output is y (S = y − s0 of the reference follower);
- oscillating (THEORY §2.4): C = f·t − l·(cos(θ + σγ), sin(θ + σγ)) on a circle about the
  pivot O3 = f·t, with γ the arm angle from O3O2 (σ = −1, γ = ξ for cam A; σ = +1,
  γ = η − ξ for cam B of a conjugate pair).

The follower states its path itself
(:meth:`~camtol.mechanisms.base.Mechanism.contact_element`, a
:class:`~camtol.mechanisms.elements.RollerGuide`); :func:`roller_path` turns it into the
solver's :class:`RollerPath`. Shared by the single-roller solver
(:mod:`camtol.contact.roller`) and the conjugate measuring fixture
(:mod:`camtol.pair.contact_fixture`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camtol.contact.shapes import AnalyticShape
from camtol.exceptions import DesignError, GeometryError
from camtol.jet import FloatArray
from camtol.mechanisms.base import Mechanism
from camtol.mechanisms.elements import RollerGuide

__all__ = ["RollerPath", "check_clear", "roller_path"]

TWO_PI = 2.0 * math.pi


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

    @classmethod
    def of(cls, guide: RollerGuide) -> RollerPath:
        """Return the path of a follower's roller guide.

        Parameters
        ----------
        guide : RollerGuide
            From :meth:`~camtol.mechanisms.base.Mechanism.contact_element`.

        Returns
        -------
        RollerPath
            The same path for the solvers.
        """
        return cls(
            guide.path,
            guide.roller_radius_mm,
            offset_mm=guide.offset_mm,
            pivot_mm=guide.pivot_mm,
            arm_mm=guide.arm_mm,
            side=guide.side,
        )


def roller_path(follower: Mechanism) -> tuple[RollerPath, float, float, float]:
    """Return the roller path of a follower and how its coordinate x maps to the output.

    Parameters
    ----------
    follower : Mechanism
        A follower whose :meth:`~camtol.mechanisms.base.Mechanism.contact_element` is a
        :class:`~camtol.mechanisms.elements.RollerGuide`.

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
        If the follower is not a roller follower.
    """
    guide = follower.contact_element()
    if not isinstance(guide, RollerGuide):
        raise DesignError(f"follower type {follower.kind!r} is not a roller follower")
    return RollerPath.of(guide), guide.sign, guide.shift, guide.zero


def check_clear(
    shape: AnalyticShape, cx: FloatArray, cy: FloatArray, rf: float, theta: FloatArray
) -> None:
    """Raise unless the roller at C stays clear of every sample of the shape.

    Parameters
    ----------
    shape : AnalyticShape
        The cam; its sampled polygon is checked.
    cx, cy : ndarray
        Roller centres. [mm]
    rf : float
        Roller radius. [mm]
    theta : ndarray
        Cam angles, for the message. [rad]

    Raises
    ------
    GeometryError
        If a sample lies closer than r_f (undercut, or the contact jumped).
    """
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
