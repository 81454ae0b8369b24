"""Motion programs: follower lift S(θ) and its derivatives V, A, J (THEORY §1).

A program is a sequence of segments covering one revolution exactly (rise, dwell, return,
blends) or a lift table through a periodic spline. Derivatives are *reduced* derivatives
per radian of cam angle (THEORY §0): V = dS/dθ, A = d²S/dθ², J = d³S/dθ³. The unit of S
is the follower's: mm for a translating follower, rad for an oscillating one.

Segment programs know their boundaries. At a boundary angle the value is taken from the
segment that *starts* there (right limit) unless the left limit is asked for, so that
jumps of A and J are represented exactly rather than smeared.

Why one module: it is the :class:`MotionProgram` interface and its two implementations,
segments and a lift table, which the engine calls through one contract: ``evaluate`` with
left limits at :attr:`~MotionProgram.boundaries_rad` and an optional (4, N) ``out`` block
checked by one helper. The contract and both implementations of it change together.

References
----------
.. [1] R. L. Norton, *Cam Design and Manufacturing Handbook*, 2nd ed., Industrial Press,
   2009, ch. 3 (modified trapezoid and modified sine laws).
.. [2] H. A. Rothbart (ed.), *Cam Design Handbook*, McGraw-Hill, 2004.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.design.laws import (
    MOTION_LAWS,
    RETIRED_LAWS,
    MotionLawName,
    NormalizedLaw,
    normalized_law,
)
from camtol.exceptions import DesignError
from camtol.grid import ordered_segment_runs, run_bounds

FloatArray = NDArray[np.float64]

SegmentKind = Literal["rise", "return", "dwell"]
TWO_PI = 2.0 * math.pi

#: Programs of up to this many segments find the segment of each angle of a grid of at
#: least _COMPARED_ANGLES angles by comparisons (a binary search costs less on fewer).
_COMPARED_STARTS = 16
_COMPARED_ANGLES = 8192

__all__ = [
    "MOTION_LAWS",
    "RETIRED_LAWS",
    "LiftTable",
    "MotionLawName",
    "NormalizedLaw",
    "MotionProgram",
    "MotionState",
    "Segment",
    "SegmentProgram",
    "normalized_law",
]


@dataclass(frozen=True)
class MotionState:
    """Follower motion over a θ grid (THEORY §0, §1).

    Attributes
    ----------
    lift : ndarray
        S(θ). [mm, or rad for an oscillating follower]
    velocity : ndarray
        V = dS/dθ. [mm/rad, or rad/rad]
    acceleration : ndarray
        A = d²S/dθ². [mm/rad², or rad/rad²]
    jerk : ndarray
        J = d³S/dθ³. [mm/rad³, or rad/rad³]
    """

    lift: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray


# ---------------------------------------------------------------------------------------
# Segments and programs
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Segment:
    """One segment of a motion program (THEORY §1).

    Parameters
    ----------
    kind : {"rise", "return", "dwell"}
        What the follower does.
    start_rad, end_rad : float
        Cam angles bounding the segment, end > start. [rad]
    law : str
        Motion law for a rise or return (ignored for a dwell).
    height : float
        Lift change h > 0 of a rise or return (a return descends by h); 0 for a dwell.
        [mm, or rad for an oscillating follower]
    """

    kind: SegmentKind
    start_rad: float
    end_rad: float
    law: str = "cycloidal"
    height: float = 0.0

    @property
    def duration_rad(self) -> float:
        """Segment length β. [rad]"""
        return self.end_rad - self.start_rad

    @property
    def signed_height(self) -> float:
        """Lift change over the segment: +h rise, −h return, 0 dwell."""
        return {"rise": self.height, "return": -self.height, "dwell": 0.0}[self.kind]


class MotionProgram:
    """Interface of a motion program: S, V, A, J over the θ grid."""

    def evaluate(
        self,
        theta_rad: ArrayLike,
        *,
        left_limit: ArrayLike | None = None,
        out: FloatArray | None = None,
    ) -> MotionState:
        """Return S, V, A, J at the cam angles (left limits where ``left_limit``).

        Parameters
        ----------
        theta_rad : array_like
            Cam angles; any real values (the program is periodic). [rad]
        left_limit : array_like of bool, optional
            Where True, an angle lying on a boundary of :attr:`boundaries_rad` takes the
            limit from below (the segment or interval that ends there) instead of from
            above. Broadcast against ``theta_rad``; None means right limits everywhere.
        out : ndarray, optional
            A (4, N) array for S, V, A, J of a one-dimensional grid of N angles, written
            in place (the engine's result block: no copy); a new one by default.

        Returns
        -------
        MotionState
            S, V, A, J as arrays of the shape of ``theta_rad`` (views of ``out`` when
            given). [mm, or rad for an oscillating follower, per rad^k]
        """
        raise NotImplementedError

    @property
    def boundaries_rad(self) -> FloatArray:
        """Angles where the program's derivatives may jump, in [0, 2π). [rad]"""
        raise NotImplementedError

    @property
    def total_travel(self) -> float:
        """Largest minus smallest lift over a revolution. [mm, or rad]"""
        raise NotImplementedError

    def canonical(self) -> dict[str, object]:
        """Plain data that identifies the program (floats as ``repr``), for hashing."""
        raise NotImplementedError

    def describe(self, *, unit: str = "", scale: float = 1.0) -> str:
        """One-line human summary; heights scaled by ``scale`` and shown in ``unit``.

        Parameters
        ----------
        unit : str
            Unit label appended to each height, including any leading space, e.g.
            ``" mm"`` or ``"°"``.
        scale : float
            Factor from the internal unit of S to ``unit``, e.g. 180/π to show radians in
            degrees. [unit per mm, or unit per rad]

        Returns
        -------
        str
            The summary.
        """
        raise NotImplementedError


@dataclass(frozen=True)
class SegmentProgram(MotionProgram):
    """A program made of contiguous segments covering exactly one revolution.

    Parameters
    ----------
    segments : sequence of Segment
        Contiguous segments; their total span must be exactly 2π and the program must
        return to its starting lift.

    Raises
    ------
    DesignError
        If a law is unknown, a segment is empty, segments are not contiguous, they do not
        cover 360°, or the lift does not return to its start.
    """

    segments: tuple[Segment, ...]
    _starts: FloatArray = field(init=False, repr=False, compare=False)
    _levels: FloatArray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        segs = self.segments
        if not segs:
            raise DesignError("motion.segments is empty; give at least one segment")
        tol = 1e-9
        for i, seg in enumerate(segs):
            where = f"motion.segments[{i}]"
            if seg.kind not in get_args(SegmentKind):
                raise DesignError(
                    f"{where}.kind={seg.kind!r} is unknown; allowed: rise, return, dwell"
                )
            if seg.kind != "dwell":
                normalized_law(seg.law)
                if not seg.height > 0:
                    raise DesignError(f"{where}.height={seg.height:g} must be > 0 for a {seg.kind}")
            if not seg.duration_rad > 0:
                raise DesignError(
                    f"{where} spans {math.degrees(seg.start_rad):g}.."
                    f"{math.degrees(seg.end_rad):g}°; the end must be after the start"
                )
            if i and abs(seg.start_rad - segs[i - 1].end_rad) > tol:
                raise DesignError(
                    f"{where}.start={math.degrees(seg.start_rad):g}° does not continue the"
                    f" previous segment's end {math.degrees(segs[i - 1].end_rad):g}°;"
                    " segments must be contiguous"
                )
        span = segs[-1].end_rad - segs[0].start_rad
        if abs(span - TWO_PI) > tol:
            raise DesignError(
                f"motion.segments cover {math.degrees(span):.6g}°; they must cover exactly 360°"
            )
        levels = np.cumsum([0.0] + [s.signed_height for s in segs])
        if abs(levels[-1]) > 1e-9 * max(1.0, float(np.max(np.abs(levels)))):
            raise DesignError(
                f"motion.segments end at lift {levels[-1]:g} above where they start;"
                " rises and returns must balance over a revolution"
            )
        object.__setattr__(self, "_starts", np.array([s.start_rad for s in segs]))
        object.__setattr__(self, "_levels", levels[:-1] - levels.min())

    def canonical(self) -> dict[str, object]:
        """Plain-data form for :attr:`camtol.design.cam_design.CamDesign.content_hash`."""
        return {
            "segments": [
                [
                    g.kind,
                    repr(float(g.start_rad)),
                    repr(float(g.end_rad)),
                    g.law,
                    repr(float(g.height)),
                ]
                for g in self.segments
            ]
        }

    @property
    def boundaries_rad(self) -> FloatArray:
        """Segment start angles, wrapped to [0, 2π). [rad]"""
        return np.sort(np.mod(self._starts, TWO_PI))

    @property
    def total_travel(self) -> float:
        """Largest minus smallest lift. [mm, or rad]"""
        levels = np.append(self._levels, self._levels[0])
        return float(levels.max() - levels.min())

    def describe(self, *, unit: str = "", scale: float = 1.0) -> str:
        """Summarise, e.g. ``rise 22 mm cycloidal 0-120°, dwell 120-190°``.

        ``scale`` converts heights to ``unit`` (e.g. 180/π and "°" for an oscillating
        follower).
        """
        parts = []
        for s in self.segments:
            span = f"{math.degrees(s.start_rad):g}-{math.degrees(s.end_rad):g}°"
            h = f"{s.height * scale:.6g}{unit}"
            parts.append(
                f"dwell {span}"
                if s.kind == "dwell"
                else f"{s.kind} {h} {s.law.replace('_', ' ')} {span}"
            )
        return ", ".join(parts)

    def segment_index(
        self, theta_rad: ArrayLike, *, left_limit: ArrayLike | None = None, wrapped: bool = False
    ) -> NDArray[np.intp]:
        """Index of the segment each angle belongs to (the one starting there, or ending).

        ``wrapped=True`` says the angles are already mapped into the program's revolution.

        Parameters
        ----------
        theta_rad : array_like
            Cam angles; any real values unless ``wrapped``. [rad]
        left_limit : array_like of bool, optional
            Where True, an angle on a segment boundary belongs to the segment that ends
            there instead of the one that starts there.
        wrapped : bool
            Flag: the angles already lie in the revolution that starts at the first
            segment's start angle, so they are not wrapped again.

        Returns
        -------
        ndarray of intp
            Index into :attr:`segments`, of the shape of ``theta_rad``.
        """
        t = np.asarray(theta_rad, dtype=float) if wrapped else self._wrap(theta_rad)
        if t.ndim == 1 and t.size >= _COMPARED_ANGLES and self._starts.size <= _COMPARED_STARTS:
            # The number of starts at or before each angle, by one comparison per start:
            # searchsorted's binary search costs several times more per angle on a long
            # grid (on a short one, the comparisons' fixed costs are more).
            idx = np.full(t.shape, -1, dtype=np.intp)
            for start in self._starts.tolist():
                idx += t >= start
        else:
            idx = np.searchsorted(self._starts, t, side="right") - 1
        if left_limit is not None:
            left = np.broadcast_to(np.asarray(left_limit, dtype=bool), t.shape)
            if idx.ndim == 0:
                if left:
                    idx = np.searchsorted(self._starts, t, side="left") - 1
            else:  # the few rows that take a left limit (segment boundaries)
                rows = np.flatnonzero(left)
                idx.flat[rows] = np.searchsorted(self._starts, t.flat[rows], side="left") - 1
        if np.ndim(idx) == 0:
            return np.asarray(int(idx) % len(self.segments), dtype=np.intp)
        idx[idx < 0] += len(self.segments)  # a left limit at the first start: the last segment
        return idx

    def _segment_rows(
        self, t: FloatArray, left_limit: ArrayLike | None
    ) -> Iterator[tuple[int, slice | NDArray[np.intp]]]:
        """Yield (segment, its rows) for wrapped angles ``t``.

        A grid in order holds each segment in a run or two (the angle 360° belongs to
        the first segment again): runs are slices, views into the result, found by a
        binary search per start on a long grid without wrapped angles. Angles in no
        order (the extremes' refinement windows) are taken segment by segment.
        """
        left = (
            None if left_limit is None else np.broadcast_to(np.asarray(left_limit, bool), t.shape)
        )
        ordered = (
            ordered_segment_runs(t, self._starts, left) if t.size >= _COMPARED_ANGLES else None
        )
        if ordered is not None:
            for i, lo, hi in ordered:
                yield i, slice(lo, hi)
            return
        idx = np.atleast_1d(self.segment_index(t, left_limit=left, wrapped=True))
        if idx.ndim == 1 and idx.size:
            bounds = run_bounds(idx)
            if len(bounds) - 2 < 2 * len(self.segments):
                for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
                    yield int(idx[lo]), slice(lo, hi)
                return
        for i in range(len(self.segments)):
            rows = np.flatnonzero(idx == i)
            if rows.size:
                lo, hi = int(rows[0]), int(rows[-1]) + 1
                yield i, slice(lo, hi) if hi - lo == rows.size else rows

    def _wrap(self, theta_rad: ArrayLike) -> FloatArray:
        start = self._starts[0]
        theta = np.asarray(theta_rad, dtype=float)
        if start == 0.0 and theta.ndim == 1 and theta.size > 64:
            # A grid of one revolution needs only its few outliers (e.g. 360° itself)
            # wrapped; np.mod leaves 0 <= θ < 2π unchanged, so the values are the same.
            out = theta + 0.0  # a copy; -0.0 + 0.0 is 0.0, as np.mod makes it
            outside = np.flatnonzero((theta < 0.0) | (theta >= TWO_PI))
            if outside.size > theta.size // 8:
                return np.asarray(np.mod(theta, TWO_PI), dtype=float)
            out[outside] = np.mod(theta[outside], TWO_PI)
            return out
        t = np.mod(theta - start, TWO_PI) + start
        return np.asarray(t, dtype=float)

    def evaluate(
        self,
        theta_rad: ArrayLike,
        *,
        left_limit: ArrayLike | None = None,
        out: FloatArray | None = None,
    ) -> MotionState:
        """Return S, V, A, J at ``theta_rad``.

        Parameters
        ----------
        theta_rad : array_like
            Cam angles; any real values (the program is periodic). [rad]
        left_limit : array_like of bool, optional
            Where True, an angle lying on a segment boundary takes the limit from the
            segment that ends there instead of the one that starts there.
        out : ndarray, optional
            (4, N) array written in place, for a grid of N angles
            (:meth:`MotionProgram.evaluate`).

        Returns
        -------
        MotionState
            Arrays of the shape of ``theta_rad``.
        """
        theta = np.asarray(theta_rad, dtype=float)
        t = np.atleast_1d(self._wrap(theta))
        # One block for S, V, A, J: a large allocation gets huge pages (fewer page faults).
        # Every row belongs to a segment, and every segment writes all four of its rows.
        out = _motion_block(out, t.shape)
        for i, m in self._segment_rows(t, left_limit):
            seg = self.segments[i]
            if seg.kind == "dwell":
                out[0][m] = self._levels[i]
                out[1:, m] = 0.0
                continue
            beta = seg.duration_rad
            # A left limit at the segment's start wraps to +2π; map it back into the segment.
            tm = t[m]
            if tm.min() < seg.start_rad - 1e-12 or tm.max() > seg.end_rad + 1e-12:
                tm = np.where(tm < seg.start_rad - 1e-12, tm + TWO_PI, tm)
                tm = np.where(tm > seg.end_rad + 1e-12, tm - TWO_PI, tm)
            x = (tm - seg.start_rad) / beta
            s, v, a, j = normalized_law(seg.law)(x)
            h = seg.signed_height
            if isinstance(m, slice):  # straight into the block, no temporaries
                np.multiply(s, h, out=out[0, m])
                out[0, m] += self._levels[i]
                for row, d, scale in ((1, v, beta), (2, a, beta**2), (3, j, beta**3)):
                    np.multiply(d, h, out=out[row, m])  # h·d/β^k, rounded as below
                    out[row, m] /= scale
            else:
                out[0][m] = self._levels[i] + h * s
                out[1][m] = h * v / beta
                out[2][m] = h * a / beta**2
                out[3][m] = h * j / beta**3
        shape = theta.shape
        return MotionState(*(o.reshape(shape) for o in out))


@dataclass(frozen=True, eq=False)
class LiftTable(MotionProgram):
    """A program given as a table of lifts at equally spaced cam angles (THEORY §1, §6).

    The lifts are interpolated by a periodic cubic spline (scipy); V, A and J are the
    spline's derivatives. Those derivatives depend on the table's precision: rounding the
    table to a quantum Q perturbs A by up to 6Q/Δθ² (THEORY §6.1). J is
    piecewise constant and jumps at every tabulated angle.

    Parameters
    ----------
    theta_rad : ndarray
        Equally spaced angles covering one revolution, without the closing 360°. [rad]
    lift : ndarray
        Lifts at those angles. [mm, or rad for an oscillating follower]
    resolution : float, optional
        Rounding quantum Q of the tabulated values, in the program's unit; ``None`` when
        the values carry full precision. See :func:`camtol.design.table_noise.table_resolution`.

    Raises
    ------
    DesignError
        If the angles are not equally spaced over one revolution or the table is short.
    """

    theta_rad: FloatArray
    lift: FloatArray
    resolution: float | None = None

    def __post_init__(self) -> None:
        t = np.asarray(self.theta_rad, dtype=float)
        s = np.asarray(self.lift, dtype=float)
        if t.ndim != 1 or t.shape != s.shape or t.size < 8:
            raise DesignError(
                f"motion.table needs at least 8 (angle, lift) pairs of equal length; got"
                f" {t.size} angles and {s.size} lifts"
            )
        if not np.all(np.isfinite(s)):
            raise DesignError("motion.table lifts must be finite numbers")
        step = TWO_PI / t.size
        if not np.allclose(np.diff(t), step, rtol=0, atol=1e-9) or abs(t[0]) > 1e-9:
            raise DesignError(
                f"motion.table angles must start at 0° and be equally spaced over 360° "
                f"(expected a step of {math.degrees(step):g}° for {t.size} entries)"
            )
        # The angles are canonical (k·2π/n): a table is its lifts, so that equal tables
        # compare equal and a design written back reads in bit for bit the same.
        object.__setattr__(self, "theta_rad", np.arange(t.size) * step)
        object.__setattr__(self, "lift", s.copy())
        self.lift.setflags(write=False)
        self.theta_rad.setflags(write=False)

    def __eq__(self, other: object) -> bool:
        """Equal lifts (bit for bit) and resolution."""
        if not isinstance(other, LiftTable):
            return NotImplemented
        return bool(np.array_equal(self.lift, other.lift)) and self.resolution == other.resolution

    def __hash__(self) -> int:
        """Hash of the lifts and the resolution."""
        return hash((self.lift.tobytes(), self.resolution))

    def canonical(self) -> dict[str, object]:
        """Plain-data form for :attr:`camtol.design.cam_design.CamDesign.content_hash`."""
        return {
            "table": [repr(float(v)) for v in self.lift],
            "resolution": None if self.resolution is None else repr(float(self.resolution)),
        }

    @property
    def step_rad(self) -> float:
        """Table spacing Δθ. [rad]"""
        return TWO_PI / self.theta_rad.size

    @property
    def _spline(self):  # type: ignore[no-untyped-def]  # cached scipy object
        return _periodic_spline(self.theta_rad.tobytes(), self.lift.tobytes())

    @property
    def boundaries_rad(self) -> FloatArray:
        """The tabulated angles, where J jumps. [rad]"""
        return np.asarray(self.theta_rad, dtype=float)

    @property
    def total_travel(self) -> float:
        """Largest minus smallest tabulated lift. [mm, or rad]"""
        return float(np.ptp(self.lift))

    def describe(self, *, unit: str = "", scale: float = 1.0) -> str:
        """Summarise the table."""
        return f"lift table of {self.theta_rad.size} entries every {math.degrees(self.step_rad):g}°"

    @property
    def acceleration_noise_bound(self) -> float | None:
        """Largest change of the spline's A that rounding to :attr:`resolution` can cause.

        Exact for the interpolant used (THEORY §6.1, :mod:`camtol.design.table_noise`): deviations
        |d_i| ≤ Q/2 change A by at most ‖G‖∞·(Q/2)/Δθ² = 6Q/Δθ² (even N), attained by
        alternating ±Q/2; three times the second-difference bound 2Q/Δθ² ([CDH] eq. 10.4).
        ``None`` without a resolution. [mm/rad², or rad/rad²]
        """
        if self.resolution is None:
            return None
        from camtol.design.table_noise import spline_acceleration_gain

        gain = spline_acceleration_gain(self.theta_rad.size)
        return gain * 0.5 * self.resolution / self.step_rad**2

    def evaluate(
        self,
        theta_rad: ArrayLike,
        *,
        left_limit: ArrayLike | None = None,
        out: FloatArray | None = None,
    ) -> MotionState:
        """Return S, V, A, J from the periodic spline.

        S, V and A are continuous; J is constant between tabulated angles, and a
        ``left_limit`` row at a tabulated angle takes J of the interval that ends there.
        ``out`` as for :meth:`MotionProgram.evaluate`.
        """
        theta = np.asarray(theta_rad, dtype=float)
        t = np.mod(theta, TWO_PI)
        sp = self._spline
        jerk = sp(t, 3)
        if left_limit is not None:
            left = np.broadcast_to(np.asarray(left_limit, dtype=bool), t.shape)
            # J is piecewise constant: its left limit is its value just before the knot.
            before = np.mod(t - 1e-6 * self.step_rad, TWO_PI)
            jerk = np.where(left, sp(before, 3), jerk)
        if out is None:
            return MotionState(sp(t), sp(t, 1), sp(t, 2), jerk)
        block = _motion_block(out, np.shape(t))
        for row, values in zip(block, (sp(t), sp(t, 1), sp(t, 2), jerk), strict=True):
            row[...] = values
        return MotionState(*block)


def _motion_block(out: FloatArray | None, shape: tuple[int, ...]) -> FloatArray:
    """Return a new (4, *shape) block for S, V, A, J, or ``out`` checked to be one."""
    if out is None:
        return np.empty((4, *shape))
    if out.shape != (4, *shape):
        raise ValueError(f"out has shape {out.shape}; S, V, A, J need {(4, *shape)}")
    return out


#: Splines kept for re-use (one per distinct lift table; bounded so that Monte Carlo over
#: perturbed tables cannot grow memory without limit).
SPLINE_CACHE_SIZE = 32


@lru_cache(maxsize=SPLINE_CACHE_SIZE)
def _periodic_spline(t_bytes: bytes, s_bytes: bytes):  # type: ignore[no-untyped-def]
    from scipy.interpolate import CubicSpline  # lazy: keep the core import light

    t = np.frombuffer(t_bytes)
    s = np.frombuffer(s_bytes)
    return CubicSpline(np.append(t, TWO_PI), np.append(s, s[0]), bc_type="periodic")
