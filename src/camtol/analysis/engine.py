"""One evaluation of the analytic engine on a grid, in cache-sized chunks (THEORY §2, §3).

:func:`evaluate_engine` returns what :func:`camtol.analysis.result.analyse` needs from a mechanism
at every angle: the kinematics (THEORY §2) and the sensitivity of the output to every
error source with its first and second θ-derivatives (THEORY §3.1-3.5), from a single
evaluation of the mechanism's closed forms:

- a mechanism with a lean closed form for its sensitivities (every follower type) gets
  its contact geometry as plain arrays and its sensitivities as jets; a motion-only one
  (:attr:`~camtol.mechanisms.base.Mechanism.motion_only`) is evaluated once per motion
  state at θ = 0, in the frame of the line of centres, and its points are turned by θ
  when first read (kinematic inversion, THEORY §0): a dwell costs one row, and an
  analysis that never reads the profile never turns it;
- otherwise one evaluation of the contact geometry as jets serves both (the kinematics
  are its values).

Long grids are evaluated in chunks (the mechanism's
:attr:`~camtol.mechanisms.base.Mechanism.chunk_angles` angles) written into the result
arrays, so the many intermediate arrays of the formulas stay in cache and never exist at
full length: time and peak memory grow with what the result holds, not with the number
of intermediate steps.

Why one module: everything here serves the one loop of :func:`evaluate_engine` over the
grid's chunks. :class:`_Columns` and :class:`_Spread` are where a chunk's rows land, the
dwell chunks decide which rows are evaluated, and :func:`shared_dwells` keeps those for a
pair's next cam; they pass the loop's private chunk types (``_Chunk``, ``_State``,
``_Spread``) between them, which a split would have to publish between modules.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol import jet
from camtol.analysis.state import ContactPoints, Kinematics, check_geometry, check_velocity_ratio
from camtol.design.cam_design import CamDesign
from camtol.design.motion import MotionState
from camtol.design.sources import DESIGN_SOURCES
from camtol.grid import run_bounds
from camtol.jet import FloatArray, Jet, JetLike
from camtol.mechanisms.base import ContactGeometry, Mechanism

__all__ = ["MOTION_CHUNK", "evaluate_engine", "shared_dwells"]

#: Angles the motion program is evaluated at once: its formulas have few intermediate
#: arrays, and one call on 36,001 angles costs less than three.
MOTION_CHUNK = 65_536

#: The contact point A and the instant centre Q (:class:`~camtol.analysis.state.ContactPoints`).
_POINTS = ("contact_x", "contact_y", "centre_x", "centre_y")
_GEOMETRY = (
    *_POINTS,
    "q",
    "pressure_angle",
    "shift_angle",
)
_EXTRAS = ("face_contact", "follower_angle")


class _Columns:
    """Full-length result arrays filled chunk by chunk.

    A quantity that is the same constant in every chunk (e.g. the pressure angle of a
    translating flat face) is kept as a read-only broadcast view instead of an array.
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self._full: dict[str, FloatArray] = {}
        self._const: dict[str, float] = {}

    def put_chunk(
        self,
        values: dict[str, FloatArray],
        where: slice,
        spread: _Spread | None = None,
    ) -> None:
        """Write one chunk of every quantity (the first chunk also classifies them).

        With ``spread``, a value shorter than the chunk holds the chunk's evaluated rows
        only (dwells compressed), spread straight into the result.
        """
        if where.start != 0:
            for key, v in values.items():
                self._put(key, v, where, spread)
            return
        varying = []
        for key, v in values.items():
            c = float(v.flat[0]) if v.size else math.nan
            # A broadcast is constant by construction; an array whose ends differ is not
            # (a scalar test that spares most columns the full comparison).
            if v.size and (v.strides == (0,) or (v.flat[-1] == c and bool(np.all(v == c)))):
                self._const[key] = c
            elif where.stop >= self.n and v.shape == (self.n,):
                self._full[key] = v  # a single chunk: keep the array itself
            else:
                varying.append(key)
        # One block for all the full-length columns: a large allocation gets huge pages
        # (numpy asks for them), so filling it costs far fewer page faults.
        block = np.empty((len(varying), self.n))
        for row, key in zip(block, varying, strict=True):
            self._full[key] = row
            _write(row[where], values[key], spread)

    def _put(self, key: str, v: FloatArray, where: slice, spread: _Spread | None) -> None:
        out = self._full.get(key)
        if out is None:
            if key in self._const and v.size and bool(np.all(v == self._const[key])):
                return
            out = self._full[key] = np.empty(self.n)
            if key in self._const:
                out[: where.start] = self._const.pop(key)
        _write(out[where], v, spread)

    def get(self, key: str) -> FloatArray | None:
        """Return the full-length array (or broadcast constant) of a quantity, if it was put."""
        if key in self._const:
            return np.broadcast_to(self._const[key], (self.n,))
        return self._full.get(key)

    def __getitem__(self, key: str) -> FloatArray:
        out = self.get(key)
        if out is None:
            raise KeyError(key)
        return out

    def keys(self) -> list[str]:
        """Keys put so far."""
        return [*self._full, *self._const]


def _write(out: FloatArray, v: FloatArray, spread: _Spread | None) -> None:
    """Fill ``out`` (a chunk's rows) with ``v``, spreading compressed rows by ``spread``."""
    if spread is None or v.shape == out.shape:
        out[...] = v
    elif spread.runs is None:
        np.take(v, spread.index, out=out, mode="clip")  # "clip": unbuffered; in range
    else:
        for start, stop, source, copied in spread.runs:
            if copied:
                out[start:stop] = v[source : source + stop - start]
            else:
                out[start:stop] = v[source]


def _full_length(x: JetLike, shape: tuple[int, ...]) -> FloatArray:
    """Return the value of ``x`` as an array of ``shape`` (a scalar broadcast, read-only).

    A one-dimensional array of another length (a chunk's compressed rows) is returned
    as it is, for :meth:`_Columns.put_chunk` to spread.
    """
    v = np.asarray(jet.value(x))
    if v.shape == shape or (v.ndim == 1 and v.size > 1 and v.strides != (0,)):
        return v
    return np.broadcast_to(v.reshape(-1)[0] if v.ndim else v, shape)


def _motion(
    design: CamDesign, theta: FloatArray, left: NDArray[np.bool_], chunk: int
) -> MotionState:
    """S, V, A, J of the design's program, evaluated chunk by chunk into full arrays."""
    n = theta.size
    if n <= chunk:
        return design.program.evaluate(theta, left_limit=left)
    out = np.empty((4, n))  # one block: huge pages, fewer page faults
    for a in range(0, n, chunk):
        at = slice(a, min(n, a + chunk))
        design.program.evaluate(theta[at], left_limit=left[at], out=out[:, at])  # in place
    return MotionState(*out)


def _repeated_states(motion: MotionState) -> NDArray[np.bool_]:
    """Mark the rows whose S, V, A and J all equal the previous row's (never the first)."""
    s, v, a, j = motion.lift, motion.velocity, motion.acceleration, motion.jerk
    same = np.zeros(s.shape, bool)
    same[1:] = (s[1:] == s[:-1]) & (v[1:] == v[:-1]) & (a[1:] == a[:-1]) & (j[1:] == j[:-1])
    return same


#: (θ, S, V, A, J) of a chunk of the grid, or of its evaluated rows.
_State = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]
#: A chunk whose runs are shorter than this on average spreads by a gather instead (a
#: run's slicing costs what gathering a few hundred rows does).
_ROWS_PER_RUN = 256


@dataclass(frozen=True)
class _Spread:
    """How a chunk's evaluated rows spread over all its rows.

    ``index`` gives each row its evaluated row. ``runs`` says the same in runs of rows
    (start, stop, source, copied): a copied run takes the evaluated rows from
    ``source`` on, one each, a repeated run (a dwell) repeats evaluated row ``source``.
    A dwell is one or two runs, so slices copy and fill a chunk at memory speed where a
    gather reads an index per row; ``runs`` is None when there are too many of them.
    """

    index: NDArray[np.intp]
    runs: tuple[tuple[int, int, int, bool], ...] | None


#: A chunk: its rows of the grid, its state, the state at the rows evaluated, how those
#: spread over the chunk's rows and the mask of evaluated rows (both None: every row is
#: evaluated).
_Chunk = tuple[slice, _State, _State, _Spread | None, NDArray[np.bool_] | None]


#: Inside a :func:`shared_dwells` block: the chunks found for each grid and motion
#: ((θ, S, V, A, J) arrays, chunk size, chunks).
_SHARED_DWELLS: ContextVar[list[tuple[_State, int, list[_Chunk]]] | None] = ContextVar(
    "camtol_shared_dwells", default=None
)


@contextmanager
def shared_dwells() -> Iterator[None]:
    """Within the block, cams on the same grid and motion find their dwells once.

    The cams of a conjugate pair share one follower, hence one motion: which rows repeat
    the motion state before them, and the state at the rows evaluated, are the same for
    both cams. Inside the block the engine keeps them for the grid and motion arrays it
    was given (the same objects, the same chunk size) and the next cam's evaluation
    takes them instead of finding them again. The kept arrays are read-only.

    Yields
    ------
    None
    """
    token = _SHARED_DWELLS.set([])
    try:
        yield
    finally:
        _SHARED_DWELLS.reset(token)


def _chunks(theta: FloatArray, motion: MotionState, chunk: int) -> Iterator[_Chunk]:
    """Yield the grid in chunks of ``chunk`` rows, every row evaluated."""
    grid = (theta, motion.lift, motion.velocity, motion.acceleration, motion.jerk)
    for a in range(0, theta.size, chunk):
        at = slice(a, min(theta.size, a + chunk))
        t, s, v, acc, jerk = (x[at] for x in grid)
        yield at, (t, s, v, acc, jerk), (t, s, v, acc, jerk), None, None


def _dwell_chunks(theta: FloatArray, motion: MotionState, chunk: int) -> Iterator[_Chunk]:
    """Yield the grid in chunks of ``chunk`` rows, repeated motion states evaluated once.

    Rows that repeat the previous row's motion state (a dwell) are not evaluated: the
    chunk's state holds the evaluated rows only, its index gives each row its evaluated
    row. Inside :func:`shared_dwells`, the chunks of the same grid and motion are found
    once.
    """
    grid = (theta, motion.lift, motion.velocity, motion.acceleration, motion.jerk)
    kept = _SHARED_DWELLS.get()
    for arrays, size, chunks in kept or ():
        if size == chunk and all(a is b for a, b in zip(arrays, grid, strict=True)):
            yield from chunks
            return
    repeats = _repeated_states(motion)
    found: list[_Chunk] = []
    for at, state, _, _, _ in _chunks(theta, motion, chunk):
        item = (at, state, *_evaluated_rows(state, repeats[at]))
        found.append(item)
        yield item
    if kept is not None:
        kept.append((grid, chunk, found))


def _runs(
    fresh: NDArray[np.bool_], index: NDArray[np.intp]
) -> tuple[tuple[int, int, int, bool], ...] | None:
    """Return the runs of :class:`_Spread` of a chunk's mask of evaluated rows, or None."""
    bounds = run_bounds(fresh)
    if (len(bounds) - 1) * _ROWS_PER_RUN > fresh.size:
        return None
    return tuple(
        (a, b, int(index[a]), bool(fresh[a])) for a, b in zip(bounds[:-1], bounds[1:], strict=True)
    )


def _evaluated_rows(
    state: _State, repeats: NDArray[np.bool_]
) -> tuple[_State, _Spread | None, NDArray[np.bool_] | None]:
    """Return a chunk's state at the rows to evaluate, each row's evaluated row, the mask."""
    if repeats.size >= 1024:  # shorter: bookkeeping ≈ saving
        fresh = ~repeats
        fresh[0] = True
        if np.count_nonzero(fresh) < 0.9 * fresh.size:  # else the gather costs more
            index = np.cumsum(fresh) - 1  # row -> its evaluated row
            runs = _runs(fresh, index)
            if runs is None:
                keep = np.flatnonzero(fresh)
                t, s, v, acc, jerk = (x[keep] for x in state)
            else:  # the copied runs' slices, joined at memory speed
                t, s, v, acc, jerk = (
                    np.concatenate([x[a:b] for a, b, _, copied in runs if copied]) for x in state
                )
            for x in (t, s, v, acc, jerk, index, fresh):
                x.flags.writeable = False  # shared by the cams of a pair
            return (t, s, v, acc, jerk), _Spread(index, runs), fresh
    return state, None, None


def _motion_quantities(
    mech: Mechanism,
    state: _State,
    *,
    sources: bool = True,
    derivatives: bool = True,
) -> tuple[dict[str, JetLike], dict[str, JetLike]]:
    """Contact geometry with ρ, and lean sensitivities (unless not ``sources``), of a chunk.

    ``state`` is (θ, S, V, A, J) of the rows evaluated; the sensitivities are jets, or
    plain values without ``derivatives``. The geometry of a
    :attr:`Mechanism.motion_only` mechanism is taken at θ = 0 (the frame of the line of
    centres, THEORY §0): its points are turned to the chunk's angles when first read
    (:class:`~camtol.analysis.kinematics.ContactPoints`).
    """
    t, s, v, acc, jerk = state
    geometry = _geometry_values(
        mech, mech.contact(0.0 if mech.motion_only else t, s, v), (t, s, v, acc)
    )
    out: dict[str, JetLike] = {}
    if sources and derivatives:
        out = dict(mech.error_sensitivities(Jet.variable(t), Jet(s, v, acc), Jet(v, acc, jerk)))
    elif sources:
        out = dict(mech.error_sensitivities(t, s, v))
    return geometry, out


def _geometry_values(
    mech: Mechanism,
    g: ContactGeometry,
    state: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
) -> dict[str, JetLike]:
    """Return a chunk's geometry columns from its contact geometry and (θ, S, V, A).

    ``q`` is left out when it is V itself (the kinematics then share the velocity array);
    the radial dimension |O2A| and the radius of curvature ρ are added.
    """
    t, s, v, acc = state
    values: dict[str, JetLike] = {
        key: getattr(g, key) for key in _GEOMETRY if not (key == "q" and g.q is v)
    }
    values.update({key: g.extras[key] for key in _EXTRAS if key in g.extras})
    radius = g.extras.get("radius")  # |O2A| in closed form, when the follower has one
    values["radius"] = (
        jet.hypot(jet.value(g.contact_x), jet.value(g.contact_y))
        if radius is None
        else jet.value(radius)
    )
    values["curvature_radius"] = mech.curvature_radius(t, s, v, acc)
    return values


def evaluate_engine(
    design: CamDesign,
    theta_rad: ArrayLike,
    left_limit: ArrayLike | None = None,
    *,
    check: bool = True,
    chunk: int | None = None,
    sensitivities: bool = True,
    motion: MotionState | None = None,
    sources: Collection[str] | None = None,
    derivatives: bool = True,
) -> tuple[Kinematics, dict[str, Jet]]:
    """Kinematics and per-unit-deviation sensitivities (jets) on a grid, in one pass.

    Parameters
    ----------
    design : CamDesign
        The design.
    theta_rad : array_like
        Cam angles. [rad]
    left_limit : array_like of bool, optional
        Rows that take the left limit at a segment boundary.
    check : bool
        Raise if the geometry cannot work, as :func:`camtol.analysis.kinematics.kinematics`.
    chunk : int, optional
        Angles evaluated at once (default: the mechanism's
        :attr:`~camtol.mechanisms.base.Mechanism.chunk_angles`). [-]
    sensitivities : bool
        Also the sensitivities; without them, the kinematics alone (what
        :func:`camtol.analysis.kinematics.kinematics` returns).
    motion : MotionState, optional
        The design's S, V, A, J at ``theta_rad`` when the caller has them (the cams of a
        conjugate pair share one program); evaluated otherwise.
    sources : collection of str, optional
        The error sources whose sensitivities are returned (default: all, as below);
        the others are not stored. Keys that are not sources of the design are ignored.
    derivatives : bool
        Compute the sensitivities' θ-derivatives. Without them (what a design with no
        tolerances needs: the radial factor alone) the sensitivities are evaluated as
        plain values, about a quarter of the work, and each returned jet's ``d1`` and
        ``d2`` are NaN (broadcast): not computed, never mistaken for zero.

    Returns
    -------
    kinematics : Kinematics
        As :func:`camtol.analysis.kinematics.kinematics` returns it.
    sensitivities : dict of str to Jet
        ∂S/∂p of every source of the mechanism, and of every design-level source
        (:mod:`camtol.design.sources`) the design tolerances, with its θ-derivatives; a constant
        sensitivity has broadcast (read-only) zero derivatives. [output unit per mm or
        per rad, per rad^k]

    Raises
    ------
    GeometryError, UndercutError
        With ``check``, as :func:`camtol.analysis.kinematics.kinematics`.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    left = np.zeros(theta.shape, bool) if left_limit is None else np.asarray(left_limit, bool)
    mech = design.mechanism
    if motion is None:
        motion = _motion(design, theta, left, MOTION_CHUNK if chunk is None else max(int(chunk), 1))
    if check:
        check_velocity_ratio(design, theta, motion)
    shared = type(mech).error_sensitivities is Mechanism.error_sensitivities
    own = {src.key for src in mech.sources}
    wanted = None if sources is None else set(sources)
    design_keys = [
        t.key
        for t in design.tolerances
        if t.key not in own and t.key in DESIGN_SOURCES and (wanted is None or t.key in wanted)
    ]
    if not sensitivities:
        shared, design_keys = False, []
    n = theta.size
    cols = _Columns(n)
    plain: set[str] = set()
    q_is_velocity = False
    # Rows whose motion state repeats the previous row's (dwells): what depends on the
    # motion alone is evaluated once per run of them.
    dwells = mech.motion_only and not shared
    # Their points are stored once per evaluated row too, and spread (and turned into
    # the cam frame) when first read: an analysis never reads them.
    points = _Columns(n) if dwells else cols
    stored = 0  # rows of ``points`` written
    rows = np.ones(n, bool) if dwells else None
    chunk_sens: dict[str, JetLike]
    step = max(int(mech.chunk_angles if chunk is None else chunk), 1)
    chunks = _dwell_chunks(theta, motion, step) if dwells else _chunks(theta, motion, step)
    for at, (t, s, v, acc, jerk), evaluated_state, spread, evaluated in chunks:
        th: JetLike
        lift: JetLike
        vel: JetLike
        if derivatives and (shared or design_keys):
            th, lift, vel = Jet.variable(t), Jet(s, v, acc), Jet(v, acc, jerk)
        else:
            th, lift, vel = t, s, v
        # A follower's formulas take the sine and cosine of the same angles several
        # times (an oscillating arm's angle): once per chunk.
        with jet.reused_sincos():
            if shared:
                g = mech.contact(th, lift, vel)
                chunk_sens = dict(mech.sensitivities(g, th))
                values = _geometry_values(mech, g, (t, s, v, acc))
            else:
                values, chunk_sens = _motion_quantities(
                    mech,
                    evaluated_state,
                    sources=sensitivities,
                    derivatives=derivatives,
                )
        for key in design_keys:  # design-level sources the design tolerances
            chunk_sens[key] = DESIGN_SOURCES[key].sensitivity(mech, th, lift, vel)
        for key, x in chunk_sens.items():
            if wanted is not None and key not in wanted:
                continue
            if not derivatives:
                values[f"s:{key}"] = np.asarray(jet.value(x), dtype=float)
            elif isinstance(x, Jet):
                values[f"s:{key}"], values[f"s:{key}'"], values[f"s:{key}''"] = x.v, x.d1, x.d2
            else:
                plain.add(key)
                values[f"s:{key}"] = np.asarray(x, dtype=float)
        q_is_velocity = "q" not in values
        if rows is not None:
            m = evaluated_state[0].shape[0]  # rows evaluated
            if evaluated is not None:
                rows[at] = evaluated
            chunk_points = {k: _full_length(values.pop(k), (m,)) for k in _POINTS}
            points.put_chunk(chunk_points, slice(stored, stored + m))
            stored += m
        cols.put_chunk({k: _full_length(x, t.shape) for k, x in values.items()}, at, spread)
        del chunk_sens, values
    c = cols
    xa, ya, xq, yq = (points[k] if rows is None else points[k][:stored] for k in _POINTS)
    kin = Kinematics(
        theta_rad=theta,
        left_limit=left,
        lift=motion.lift,
        velocity=motion.velocity,
        acceleration=motion.acceleration,
        jerk=motion.jerk,
        radius_mm=c["radius"],
        q_mm=motion.velocity if q_is_velocity else c["q"],
        pressure_angle_rad=c["pressure_angle"],
        shift_angle_rad=c["shift_angle"],
        curvature_radius_mm=c["curvature_radius"],
        # A motion-only mechanism's points are in the frame of the line of centres,
        # one per evaluated row.
        contact_points=ContactPoints(
            xa,
            ya,
            xq,
            yq,
            turn_rad=None if rows is None else theta,
            rows=None if stored == n else rows,
        ),
        face_contact_mm=c.get("face_contact"),
        follower_angle_rad=c.get("follower_angle"),
    )
    if check:
        check_geometry(design, kin)
    zero: NDArray[np.float64] = np.broadcast_to(0.0, theta.shape)
    not_computed: NDArray[np.float64] = np.broadcast_to(math.nan, theta.shape)
    out: dict[str, Jet] = {}
    for key in (k[2:] for k in c.keys() if k.startswith("s:") and not k.endswith("'")):
        if not derivatives:
            out[key] = Jet(c[f"s:{key}"], not_computed, not_computed)
        elif key in plain:
            out[key] = Jet(c[f"s:{key}"], zero, zero)
        else:
            out[key] = Jet(c[f"s:{key}"], c[f"s:{key}'"], c[f"s:{key}''"])
    return kin, out
