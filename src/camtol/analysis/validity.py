"""Can the design produce its motion? One check for every command, independent of the grid.

:func:`check_design_geometry` is the single geometry gate that ``analyze``, ``profile``,
``report``, ``verify`` and ``conjugate`` (and the library functions behind them) pass
through before computing anything. It does not depend on the analysis grid (``--step``):

* at every segment boundary it compares the one-sided limits (THEORY §1: a program's
  derivatives may jump only where its segments meet). A jump of the velocity V moves the
  contact point or turns the contact normal abruptly: the profile has a corner or a cusp
  there, which no follower can trace, so it is an error naming the angle. A jump of the
  acceleration A is a jump of curvature: allowed, as long as the radius of curvature is
  acceptable on both sides (both one-sided limits are checked);
* inside every segment (or every interval of a lift table) it samples a fixed number of
  points *per segment* — so a segment of 10⁻⁶° is sampled as finely as one of 120° — and
  refines around the worst samples of each criterion (undercut margin, pressure angle,
  V < 1 of an oscillating follower, clearance to the pivot) by repeated zooming;
* a conjugate design is checked cam by cam (cam A and cam B, THEORY §2.4), and the error
  names the cam.

The criteria themselves are those of :func:`camtol.analysis.state.check_geometry` (THEORY
§2.1, §2.3): ρ > 0 for a flat face, a convex pitch curve no sharper than the roller for a
roller, |φ| < 90°, V < 1 for an oscillating follower, the cam clear of the pivot.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
import weakref
from typing import Any

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.kinematics import kinematics
from camtol.analysis.state import Kinematics, check_geometry
from camtol.design.cam_design import CamDesign
from camtol.design.motion import SegmentProgram
from camtol.exceptions import DesignError, GeometryError
from camtol.grid import sorted_unique
from camtol.jet import FloatArray

__all__ = ["check_design_geometry", "single_cam_designs", "validation_grid"]

#: Samples per segment (or per lift-table interval), boundaries included. A multiple of
#: 8 plus one, so the piece ends of the modified laws (multiples of 1/8) are samples.
SAMPLES_PER_SEGMENT = 129
#: Samples of the whole revolution beyond which a program with many intervals (a lift
#: table: a cubic per interval) gets fewer samples per interval, at least 3.
MAX_SAMPLES = 65_536
#: Worst candidates refined per criterion, zoom passes, and points per zoom pass.
#: Most segments or lift-table entries checked (a table every 0.0036°).
MAX_INTERVALS = 100_000
_CANDIDATES = 8
_ZOOM_PASSES = 4
_ZOOM_POINTS = 17
#: A velocity jump larger than this fraction of max |V| is a corner of the profile.
_VELOCITY_JUMP_RTOL = 1e-6
TWO_PI = 2.0 * math.pi


def single_cam_designs(design: CamDesign) -> tuple[tuple[str, CamDesign], ...]:
    """Split a design into the single-contact designs to check (cams A and B of a pair).

    Parameters
    ----------
    design : CamDesign
        Any design; a conjugate pair is split into its cams (THEORY §2.4).

    Returns
    -------
    tuple of (str, CamDesign)
        Label (``""``, ``"A"`` or ``"B"``) and the single-contact design.
    """
    return tuple((cam.label, cam.design) for cam in design.cams())


def validation_grid(design: CamDesign) -> tuple[FloatArray, NDArray[np.bool_], NDArray[np.intp]]:
    """θ samples of every segment or table interval, with both limits at each boundary.

    Parameters
    ----------
    design : CamDesign
        The design whose motion program is sampled.

    Returns
    -------
    theta_rad : ndarray
        Angles, interval by interval; an interval's last sample is its end boundary taken
        as a left limit, its first sample the start boundary as a right limit. [rad]
    left_limit : ndarray of bool
        True at the left-limit samples.
    interval : ndarray of intp
        Index of the interval each sample belongs to.
    """
    b = sorted_unique(np.mod(np.asarray(design.program.boundaries_rad, dtype=float), TWO_PI))
    if b.size == 0:
        b = np.array([0.0])
    if b.size > MAX_INTERVALS:  # bound the work: both ends and a midpoint of each
        raise DesignError(
            f"the motion program has {b.size:,} segments or table entries; at most"
            f" {MAX_INTERVALS:,} are supported (a lift table every {360 / MAX_INTERVALS:g}°)"
        )
    ends = np.append(b[1:], b[0] + TWO_PI)
    n = int(min(SAMPLES_PER_SEGMENT, max(3, MAX_SAMPLES // b.size)))
    x = np.linspace(0.0, 1.0, n)
    theta = b[:, None] + x[None, :] * (ends - b)[:, None]
    theta[:, -1] = ends
    left = np.zeros(theta.shape, bool)
    left[:, -1] = True
    interval = np.broadcast_to(np.arange(b.size)[:, None], theta.shape)
    return theta.ravel(), left.ravel(), np.asarray(interval.ravel(), dtype=np.intp)


def _margins(design: CamDesign, kin: Kinematics) -> list[FloatArray]:
    """Criteria that must stay > 0, as continuous functions of θ (for refinement)."""
    mech = design.mechanism
    rho = kin.curvature_radius_mm
    roller = getattr(mech, "roller_radius_mm", None)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if roller is None:
            undercut = rho
        else:  # undercut where 0 < ρ_pitch ≤ r_f, i.e. r_f/ρ_pitch ≥ 1 (continuous in κ)
            undercut = 1.0 - roller / (rho + roller)
    out = [np.asarray(undercut, float), math.pi / 2 - np.abs(kin.pressure_angle_rad)]
    if mech.output == "oscillating":
        out.append(1.0 - kin.velocity)
        pivot = getattr(mech, "pivot_distance_mm", None)
        if pivot is not None:
            out.append(pivot - kin.radius_mm)
    return [np.where(np.isfinite(m), m, -np.inf) for m in out]


def _check_velocity_jumps(
    design: CamDesign, theta: FloatArray, left: NDArray[np.bool_], velocity: FloatArray
) -> None:
    """Raise at a boundary where V's left and right limits differ (corner or cusp)."""
    n_int = int(np.count_nonzero(left))
    per = theta.size // n_int
    v = velocity.reshape(n_int, per)
    v_left = v[:, -1]  # end of interval i (left limit)
    v_right = np.roll(v[:, 0], -1)  # start of interval i + 1 (right limit)
    scale = max(float(np.max(np.abs(velocity))), 1e-300)
    jump = np.abs(v_left - v_right)
    bad = np.flatnonzero(jump > _VELOCITY_JUMP_RTOL * scale)
    if bad.size == 0:
        return
    i = int(bad[np.argmax(jump[bad])])
    at = float(np.mod(theta.reshape(n_int, per)[i, -1], TWO_PI))
    unit = "mm/rad" if design.mechanism.output == "translating" else "rad/rad"
    where = f"θ={math.degrees(at):.6g}°"
    program = design.program
    if isinstance(program, SegmentProgram):
        k = int(program.segment_index(np.array([at]))[0])
        where += f" (start of motion.segments[{k}])"
    raise GeometryError(
        f"the follower's velocity V jumps from {v_left[i]:.4g} to {v_right[i]:.4g} {unit} at"
        f" {where}: the cam profile has a corner or cusp there that no follower can trace;"
        " use a law whose velocity is continuous (e.g. cycloidal, polynomial_345) or blend"
        " the constant-velocity segment into its neighbours"
    )


def _refine(
    design: CamDesign,
    theta: FloatArray,
    interval: NDArray[np.intp],
    margins: list[FloatArray],
) -> FloatArray:
    """Zoom around the lowest local minima of every margin; return the refined angles.

    All criteria are refined together: each pass evaluates the kinematics once on every
    window, and each window shrinks to the two sample spacings around its best point.
    """
    n = theta.size
    same_prev = np.concatenate([[False], interval[1:] == interval[:-1]])
    same_next = np.concatenate([interval[:-1] == interval[1:], [False]])
    inner = same_prev & same_next
    which: list[int] = []
    picks: list[NDArray[np.intp]] = []
    for k, m in enumerate(margins):
        prev = np.roll(m, 1)
        nxt = np.roll(m, -1)
        cand = np.flatnonzero(inner & (m <= prev) & (m <= nxt) & np.isfinite(m))
        cand = cand[np.argsort(m[cand])[:_CANDIDATES]]
        picks.append(cand)
        which += [k] * cand.size
    if not which:
        return np.empty(0)
    cand = np.concatenate(picks)
    crit = np.asarray(which)
    lo = theta[np.clip(cand - 1, 0, n - 1)]
    hi = theta[np.clip(cand + 1, 0, n - 1)]
    s = np.linspace(0.0, 1.0, _ZOOM_POINTS)
    rows = np.arange(cand.size)
    best = theta[cand]
    for _ in range(_ZOOM_PASSES):
        t = lo[:, None] + s[None, :] * (hi - lo)[:, None]
        kin = kinematics(design, t.ravel(), check=False)
        values = np.stack([m.reshape(t.shape) for m in _margins(design, kin)])
        mm = values[crit, rows, :]  # each window's own criterion
        k = np.argmin(mm, axis=1)
        best = t[rows, k]
        width = (hi - lo) / (_ZOOM_POINTS - 1)
        lo = np.maximum(best - width, lo)
        hi = np.minimum(best + width, hi)
    return np.asarray(best, dtype=float)


def _check_single(design: CamDesign) -> None:
    theta, left, interval = validation_grid(design)
    motion = design.program.evaluate(theta, left_limit=left)
    bad = ~(np.isfinite(motion.lift) & np.isfinite(motion.velocity))
    bad |= ~(np.isfinite(motion.acceleration))
    if np.any(bad):
        i = int(np.argmax(bad))
        raise DesignError(
            f"the motion program is not finite at θ={math.degrees(theta[i] % TWO_PI):.6g}°"
            " (S, V or A overflows); check the lifts and segment angles"
        )
    _check_velocity_jumps(design, theta, left, motion.velocity)
    kin = kinematics(design, theta, left_limit=left, check=False)
    # The refinement finds each criterion's worst point between samples (V ≥ 1 of an
    # oscillating follower included); the samples and those points are then checked.
    extra = _refine(design, theta, interval, _margins(design, kin))
    if extra.size:
        more = kinematics(design, extra, check=False)
        joined: dict[str, Any] = {
            f.name: None
            if getattr(kin, f.name) is None
            else np.concatenate([getattr(kin, f.name), getattr(more, f.name)])
            for f in dataclasses.fields(Kinematics)
            if f.name != "contact_points"
        }
        kin = Kinematics(**joined, contact_points=kin.contact_points.joined(more.contact_points))
    check_geometry(design, kin)


def check_design_geometry(design: CamDesign) -> None:
    """Raise unless every cam of the design can produce its motion, whatever the grid.

    Parameters
    ----------
    design : CamDesign
        The design; a conjugate pair is checked cam by cam.

    Raises
    ------
    GeometryError
        A velocity jump at a segment boundary (corner or cusp of the profile), V ≥ 1 of
        an oscillating follower, |pressure angle| ≥ 90°, the cam reaching the pivot, or
        undefined contact geometry; the message names the cam angle (and the cam of a
        conjugate pair).
    UndercutError
        The radius of curvature makes the profile impossible somewhere (THEORY §2.1,
        §2.3), including on either side of a boundary where A jumps.
    DesignError
        The motion program itself is not finite (overflow).

    Notes
    -----
    A design is immutable, so a design object that passed is remembered (weakly) and not
    checked again; its warnings (pressure angle beyond the design limit) are repeated.
    """
    key = id(design)
    seen = _passed.get(key)
    if seen is not None and seen[0]() is design:
        for w in seen[1]:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for label, single in single_cam_designs(design):
            try:
                with np.errstate(all="ignore"):
                    _check_single(single)
            except GeometryError as exc:
                if not label:
                    raise
                raise type(exc)(f"cam {label}: {exc}") from None
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)

    def forget(_ref: weakref.ref[CamDesign], k: int = key) -> None:
        _passed.pop(k, None)

    _passed[key] = (weakref.ref(design, forget), list(caught))


#: Designs that passed, by id: (weak reference, warnings raised by the check).
_passed: dict[int, tuple[weakref.ref[CamDesign], list[warnings.WarningMessage]]] = {}
