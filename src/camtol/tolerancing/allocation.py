"""Tolerance allocation: the cheapest IT grade per source that meets a motion spec.

Given a spec on max_θ |ΔS| (or a band lower(θ) ≤ ΔS(θ) ≤ upper(θ), reduced to weights
on the same computations: see :func:`allocate`) and a criterion (worst case Σ|ΔS_p|, RSS
sqrt(ΣΔS_p²) of THEORY §3.4, or a Monte Carlo yield target such as 99.73 %), every
combination of grades (default IT5-IT12 for every toleranced source) is ranked by a
reciprocal-power cost

    cost = Σ_k a_k (T_k(coarsest grade) / T_k)^b      (a_k = 1, b = 1 by default)

(each source's cost relative to its own coarsest tolerance, so sources in µm and in
degrees compare), and the cheapest combination that meets the spec is returned. Worst case
and RSS are evaluated for all combinations at once (one matrix product per block).
Monte Carlo walks the combinations in increasing cost with common random numbers, skipping
every combination at least as coarse as one already found to fail (the yield falls when a
tolerance grows), and stops at the first that meets the target. max_θ |ΔS| of a sample is
the largest of x·v over the vertices v of the convex hull of the sensitivity curve {±g(θ)}
(exact: a linear function peaks at a vertex), so it costs a few hundred angles, not 3600.
The choice is then verified by a fresh linear Monte Carlo run.

Why one module: it is the one search of :func:`allocate` over grade combinations. The
Pareto rows and hull angles are exact reductions of that search's sensitivity matrix, the
Monte Carlo screening reuses its common random numbers, and ``_no_grade`` and
``_require_scalable`` state what the search cannot do; none of the helpers is used
elsewhere.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal, NoReturn

import numpy as np
from numpy.typing import NDArray

from camtol import iso286
from camtol.design.cam_design import CamDesign, ResolvedTolerance, ToleranceSpec
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.band import ToleranceBand, band_curves, band_label
from camtol.tolerancing.model import StatisticalModel, statistical_model
from camtol.tolerancing.results import YieldEstimate

__all__ = ["Allocation", "Criterion", "allocate"]

Criterion = Literal["worst_case", "rss", "monte_carlo"]
DEFAULT_GRADES = tuple(f"IT{k}" for k in range(5, 13))
#: Largest sample matrix the Monte Carlo criterion holds in memory. [bytes]
MAX_HELD_BYTES = 512 * 2**20


@dataclass(frozen=True)
class Allocation:
    """Result of :func:`allocate` (internal units: mm, or rad for an oscillating output).

    The CLI shows ``spec`` and ``achieved`` in µm or degrees (``camtol allocate``,
    :class:`camtol.report.display.DisplayUnits`).

    Attributes
    ----------
    grades : dict of str to str
        Chosen grade per source.
    deviations : tuple of ResolvedTolerance
        The resulting deviation per source in internal units, with how each was
        obtained (its ``display``, e.g. ``19 µm``, says it as a design file would). [mm, rad]
    criterion : str
        ``worst_case``, ``rss`` or ``monte_carlo``.
    spec : float or None
        Spec on max |ΔS| (None when a band was given). [unit]
    unit : str
        Internal unit of ΔS: ``mm`` (translating follower) or ``rad`` (oscillating).
    achieved : float
        The criterion's figure at the chosen grades: max worst case or RSS [unit], or the
        Monte Carlo yield (0-1) [-]. With a band, worst case and RSS give the largest
        ratio over θ of the figure to the band half-width min(upper, −lower) (≤ 1). [-]
    cost : float
        Cost of the choice. [-]
    accuracy : iso286.GradeBracket
        IT grades of the travel that bracket the worst case at the chosen grades.
    verified : YieldEstimate
        Yield of max |ΔS| ≤ spec (or of the band) from a fresh linear Monte Carlo run.
    coarser_fails : dict of str to bool or None
        For each source, whether one grade coarser breaks the spec (None: already at the
        coarsest grade).
    evaluated : int
        Combinations evaluated.
    band : str or None
        The band, when one was given instead of a spec: its file name, or
        ``curves given in Python``.
    target_yield : float
        The yield the verification is judged against (the ``monte_carlo`` criterion's
        target; the same figure for the others). [-]
    met : bool
        False when the verified yield's 95 % interval lies wholly below
        ``target_yield`` (the allocation demonstrably misses it); True otherwise.
    """

    grades: dict[str, str]
    deviations: tuple[ResolvedTolerance, ...]
    criterion: str
    spec: float | None
    unit: str
    achieved: float
    cost: float
    accuracy: iso286.GradeBracket
    verified: YieldEstimate
    coarser_fails: dict[str, bool | None]
    evaluated: int
    band: str | None = None
    target_yield: float = 0.9973
    met: bool = True

    @property
    def verdict(self) -> str:
        """``met``, ``not met`` (interval below the target) or ``inconclusive``.

        Inconclusive: the verified yield is below the target but its 95 % interval
        reaches it (more ``verify_samples`` would tell).
        """
        if not self.met:
            return "not met"
        return "met" if self.verified.value >= self.target_yield else "inconclusive"


def _with_grades(design: CamDesign, keys: list[str], grades: tuple[str, ...]) -> CamDesign:
    specs = tuple(ToleranceSpec(k, grade=g) for k, g in zip(keys, grades, strict=True))
    return dataclasses.replace(design, tolerances=specs)


def _hull_angles(
    g: FloatArray, lower: FloatArray | None = None, upper: FloatArray | None = None
) -> NDArray[np.intp]:
    """Angles whose rows g/upper or g/lower are vertices of the hull of all of them.

    A sample x leaves the band somewhere iff max over the rows R of {g(θ)/upper(θ),
    g(θ)/lower(θ)} of x · R > 1 (lower < 0 flips the inequality), and that maximum is
    reached at a vertex of the convex hull of the rows (exact). Without a band the rows
    are {±g} (lower = −1, upper = 1): max |x · g(θ)| is reached at such a vertex. Returns
    the indices of those angles (every angle when the rows span more than 3 dimensions,
    where qhull gets slow on these dense curves, or when qhull fails).
    """
    n = g.shape[0]
    every = np.arange(n)
    # Coordinates in the span of the rows (two sources may have equal sensitivities,
    # e.g. Δn and Δr_f of a roller, which would make the hull flat).
    _, sv, vt = np.linalg.svd(g, full_matrices=False)
    rank = int(np.count_nonzero(sv > 1e-10 * sv[0])) if sv.size and sv[0] > 0 else 0
    if not 2 <= rank <= 3:
        return every
    try:
        from scipy.spatial import ConvexHull, QhullError

        p = g @ vt[:rank].T
        hi = p if upper is None else p / upper[:, None]
        lo = -p if lower is None else p / lower[:, None]
        hull = ConvexHull(np.vstack([hi, lo]))
        return np.unique(np.asarray(hull.vertices) % n)
    except (QhullError, ValueError):
        return every


def _pareto_rows(p: FloatArray) -> FloatArray:
    """Return the non-dominated rows of a non-negative matrix (the Pareto front).

    For t ≥ 0, max over rows of row · t is reached at a row that no other row dominates
    (≥ in every column), so only those rows are needed (exact). Each step takes the
    remaining row of largest sum (never dominated) and drops the rows it dominates.
    """
    rest = p
    keep = []
    while rest.shape[0]:
        i = int(np.argmax(rest.sum(axis=1)))
        top = rest[i]
        keep.append(top)
        rest = rest[~np.all(rest <= top, axis=1)]
    return np.asarray(keep)


def allocate(
    design: CamDesign,
    spec: float | None = None,
    *,
    band: ToleranceBand | tuple[FloatArray, FloatArray] | None = None,
    criterion: Criterion = "worst_case",
    grades: tuple[str, ...] = DEFAULT_GRADES,
    target_yield: float = 0.9973,
    cost_exponent: float = 1.0,
    cost_coefficients: dict[str, float] | None = None,
    samples: int = 20000,
    verify_samples: int = 20000,
    seed: int = 0,
    model: StatisticalModel | None = None,
    step_deg: float = 0.1,
) -> Allocation:
    """Choose the cheapest IT grade per toleranced source meeting a spec or a band.

    Parameters
    ----------
    design : CamDesign
        The design; its toleranced sources are allocated (their current values ignored).
    spec : float, optional
        Spec on max_θ |ΔS|. [mm, or rad for an oscillating follower]
    band : ToleranceBand or (ndarray, ndarray), optional
        Instead of ``spec``: lower(θ) ≤ ΔS(θ) ≤ upper(θ) at every angle, a
        :class:`~camtol.tolerancing.band.ToleranceBand` (:func:`read_band_csv`) or two
        curves on the grid of ``step_deg``, with lower < 0 < upper everywhere.
        [mm or rad]
    criterion : {"worst_case", "rss", "monte_carlo"}
        How the output error is combined (THEORY §3.4) or sampled.
    grades : tuple of str
        Candidate grades, e.g. IT5..IT12.
    target_yield : float
        Yield required by the Monte Carlo criterion (0-1), and the yield the
        verification of any criterion is judged against (``Allocation.met``). [-]
    cost_exponent : float
        b of the reciprocal-power cost (> 0). [-]
    cost_coefficients : dict of str to float, optional
        a_k per source (default 1 each). [-]
    samples, verify_samples : int
        Monte Carlo samples per candidate and for the final verification, each at most
        :data:`~camtol.tolerancing.montecarlo.MAX_LINEAR_SAMPLES` (as ``monte_carlo``);
        beyond :data:`MAX_HELD_BYTES` the candidates' samples are drawn again chunk by
        chunk instead of being held (same numbers, bounded memory).
    seed : int
        Seed of both Monte Carlo runs.
    model : StatisticalModel, optional
        Distributions (default: the design's ``[statistics]`` or normal Cp = 1).
    step_deg : float
        θ grid step. [deg]

    Returns
    -------
    Allocation

    Raises
    ------
    DesignError
        A bad argument, both or neither of ``spec`` and ``band``, a band not containing
        ΔS = 0 at some angle, or a spec no grade can meet (naming the dominant source and
        what the finest grade achieves; for a band, ratios to the band and the angle).

    Notes
    -----
    A band reduces exactly to the computations of a spec by weighting the sensitivity
    rows g(θ) (the fixed process part included) at each angle; with a spec the weight is
    1 and the limit the spec, with a band (lower < 0 < upper):

    - worst case, zones symmetric (±t_k): Σ_k |g_k(θ)| t_k ≤ min(upper(θ), −lower(θ)) at
      every θ ⇔ max_θ Σ_k (|g_k(θ)| / m(θ)) t_k ≤ 1 with m = min(upper, −lower): the
      rows divided by m, limit 1. A symmetric bound must fit the nearer limit, so an
      asymmetric band is used by its narrower side;
    - RSS: sqrt(Σ_k g_k² t_k²) ≤ m(θ) ⇔ max_θ Σ_k (g_k² / m²) t_k² ≤ 1: rows g²/m²;
    - Monte Carlo: a sample x fails iff x·g(θ) > upper(θ) or x·g(θ) < lower(θ) at some θ
      ⇔ max over the rows {g/upper, g/lower} of x · row > 1 (no absolute value: lower < 0
      flips the second inequality). With a spec the rows are {g/spec, −g/spec}, i.e.
      max |x·g| > spec. Only the angles whose rows are vertices of the convex hull of
      those rows are needed (exact, when they span at most 3 dimensions).
    """
    from camtol.tolerancing.montecarlo import single_threaded_blas

    with single_threaded_blas():
        return _allocate(
            design,
            spec,
            band,
            criterion,
            grades,
            target_yield,
            cost_exponent,
            cost_coefficients,
            samples,
            verify_samples,
            seed,
            model,
            step_deg,
        )


def _allocate(
    design: CamDesign,
    spec: float | None,
    band: ToleranceBand | tuple[FloatArray, FloatArray] | None,
    criterion: Criterion,
    grades: tuple[str, ...],
    target_yield: float,
    cost_exponent: float,
    cost_coefficients: dict[str, float] | None,
    samples: int,
    verify_samples: int,
    seed: int,
    model: StatisticalModel | None,
    step_deg: float,
) -> Allocation:
    from camtol.tolerancing.montecarlo import monte_carlo
    from camtol.tolerancing.plan import CHUNK, chunk_uniforms
    from camtol.tolerancing.study import prepare, sample_matrix

    if criterion not in ("worst_case", "rss", "monte_carlo"):
        raise DesignError(
            f"criterion={criterion!r} is unknown; allowed: worst_case, rss, monte_carlo"
        )
    if (spec is None) == (band is None):
        raise DesignError(
            "give spec (on max |ΔS|) or band (lower/upper curves of ΔS): exactly one of them"
        )
    if spec is not None and not (math.isfinite(spec) and spec > 0):
        raise DesignError(f"spec={spec!r} is not allowed; it must be > 0")
    if not 0 < target_yield < 1:
        raise DesignError(f"target_yield={target_yield!r} must lie in (0, 1)")
    for name, value in (("samples", samples), ("verify_samples", verify_samples)):
        _check_samples(name, value)
    if not (math.isfinite(cost_exponent) and cost_exponent > 0):
        raise DesignError(f"cost_exponent={cost_exponent!r} must be > 0")
    grades = tuple(iso286.parse_grade(g) for g in grades)
    grades = tuple(sorted(set(grades), key=iso286.GRADES.index))
    # The output error of a design is its first cam's (a pair's cam A, as analyze and
    # prepare): its own sources are allocated, under its own keys.
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)  # every cam, as analyze: a pair whose cam B jams fails
    design = design.cams()[0].design
    keys = [t.key for t in design.tolerances]
    if not keys:
        raise DesignError(f"design {design.name!r} has no [tolerances]: nothing to allocate")
    coef = {k: 1.0 for k in keys}
    for k, v in (cost_coefficients or {}).items():
        if k not in coef:
            raise DesignError(
                f"cost coefficient for {k!r}: not a toleranced source ({', '.join(keys)})"
            )
        if not (math.isfinite(v) and v > 0):
            raise DesignError(f"cost coefficient {k}={v!r} must be > 0")
        coef[k] = float(v)
    model = statistical_model(design) if model is None else model
    _require_scalable(model, keys, criterion)
    base = prepare(
        _with_grades(design, keys, (grades[0],) * len(keys)), model=model, step_deg=step_deg
    )
    curves = None if band is None else band_curves(band, base.theta_rad)
    from camtol.analysis.result import max_radius_mm

    rmax = max_radius_mm(design)
    # dev[k, i]: deviation of source k at grade i (internal units).
    rows = [_with_grades(design, keys, (g,) * len(keys)).resolve_tolerances(rmax) for g in grades]
    dev = np.array([[abs(r.deviation) for r in row] for row in rows]).T
    g_all = base.sens["lift"]
    nk = len(keys)
    g = g_all[:, :nk]
    n_ang = g.shape[0]
    fixed_wc = np.zeros(n_ang)
    fixed_rss = np.zeros(n_ang)
    if base.plan.process is not None:
        pg = g_all[:, nk:]
        b = base.plan.column_bounds()[1][nk:]
        fixed_wc = np.abs(pg) @ b
        fixed_rss = fixed_wc * fixed_wc
    # The spec as weights w(θ) on the rows and a limit: max |ΔS| ≤ spec is w = 1 and
    # limit = spec; a band is w = 1/m(θ), m = min(upper, −lower), and limit = 1 (exact for
    # symmetric zones; see the allocate docstring).
    if curves is not None:
        w = 1.0 / np.minimum(curves[1], -curves[0])
        limit = 1.0
    else:
        assert spec is not None
        w = np.ones(n_ang)
        limit = float(spec)
    combos = np.array(list(itertools.product(range(len(grades)), repeat=nk)), dtype=np.int64)
    t_comb = dev[np.arange(nk)[None, :], combos]  # (C, nk)
    ref = dev[:, -1]
    cost = ((ref[None, :] / t_comb) ** cost_exponent * np.array([coef[k] for k in keys])).sum(
        axis=1
    )

    # max_θ of w(θ)(Σ|g_k| t_k + a fixed process part) is a maximum of linear functions of
    # (t, 1) with non-negative coefficients: only the non-dominated rows w·(|g|, fixed) can
    # reach it, and likewise w²·(g², fixed) for Σ g_k² t_k² (exact).
    wc_rows = _pareto_rows(np.hstack([np.abs(g), fixed_wc[:, None]]) * w[:, None])
    rss_rows = _pareto_rows(np.hstack([g * g, fixed_rss[:, None]]) * (w * w)[:, None])

    def figure(t: FloatArray) -> FloatArray:
        """max_θ worst case or RSS (times w) for rows of tolerances t (internal units)."""
        ones = np.ones((t.shape[0], 1))
        if criterion == "rss":
            return np.asarray(np.sqrt((rss_rows @ np.hstack([t * t, ones]).T).max(axis=0)))
        return np.asarray((wc_rows @ np.hstack([t, ones]).T).max(axis=0))

    def no_grade(achieved: str) -> NoReturn:
        _no_grade(base.theta_rad, keys, grades, g, dev[:, 0], w, spec, band, base.unit, achieved)

    finest = dev[:, 0][None, :]
    evaluated = 0
    wc = figure(t_comb) if criterion != "monte_carlo" else None
    if criterion == "monte_carlo":
        u_plan = base.plan
        # Samples at the finest grades: held when they fit in MAX_HELD_BYTES, else drawn
        # again chunk by chunk for each candidate (the same numbers: 512-sample blocks
        # never straddle a 4096-sample chunk).
        held = samples * max(u_plan.columns, 1) * 8 <= MAX_HELD_BYTES
        x_unit = sample_matrix(u_plan, seed, samples) if held else None

        def sample_blocks() -> Iterator[FloatArray]:
            if x_unit is not None:
                yield x_unit
                return
            for c in range(-(-samples // CHUNK)):
                size = min(CHUNK, samples - c * CHUNK)
                yield u_plan.sample(chunk_uniforms(seed, c, size, u_plan.uniforms))

        g_full = np.hstack([g, g_all[:, nk:]])
        if curves is None:
            verts = g_full[_hull_angles(g_full)]
            v_lo = np.full(verts.shape[0], -limit)
            v_hi = np.full(verts.shape[0], limit)
            v_w = np.ones(verts.shape[0])
        else:
            sel = _hull_angles(g_full, curves[0], curves[1])
            verts, v_lo, v_hi, v_w = g_full[sel], curves[0][sel], curves[1][sel], w[sel]
        ones = np.ones((t_comb.shape[0], 1))
        wc_ok = (wc_rows @ np.hstack([t_comb, ones]).T).max(axis=0) <= limit
        bounded = bool(np.all(base.plan.column_bounds()[2]))

        allowed = int(math.floor((1.0 - target_yield) * samples))

        # Screening angles: a sample failing at a subset of the angles fails, so a
        # candidate whose failures on the subset already exceed the allowance is
        # rejected without the full grid (exact). Subset: each column's peak and the 64
        # angles of largest worst case (relative to the band) at the finest grades.
        wc_fine = (np.abs(verts[:, :nk]) @ dev[:, 0]) * v_w
        pick = set(np.argsort(wc_fine)[-64:].tolist())
        pick |= set(np.argmax(np.abs(verts) * v_w[:, None], axis=0).tolist())
        ix = sorted(pick)
        screen, s_lo, s_hi = verts[ix], v_lo[ix], v_hi[ix]

        def failing(y: FloatArray, lo: FloatArray, hi: FloatArray) -> int:
            """Count the samples (rows of y, ΔS at some angles) outside [lo, hi] somewhere."""
            if curves is None:  # symmetric: max |ΔS| > spec
                return int(np.count_nonzero(np.max(np.abs(y), axis=1) > limit))
            return int(np.count_nonzero(np.any((y > hi) | (y < lo), axis=1)))

        def yield_of(t: FloatArray, *, early: bool = True) -> float:
            """Yield with common random numbers; stops once the target is out of reach."""
            f = np.ones(u_plan.columns)
            f[:nk] = t / dev[:, 0]
            if early:
                st = screen.T * f[:, None]
                lower_failures = sum(failing(xb @ st, s_lo, s_hi) for xb in sample_blocks())
                if lower_failures > allowed:
                    return 1.0 - lower_failures / samples  # an upper bound, below target
            vt = verts.T * f[:, None]
            failures = 0
            for xb in sample_blocks():
                for s0 in range(0, xb.shape[0], 512):
                    failures += failing(xb[s0 : s0 + 512] @ vt, v_lo, v_hi)
                    if early and failures > allowed:
                        return 1.0 - failures / samples  # an upper bound, below the target
            return 1.0 - failures / samples

        order = np.argsort(cost, kind="stable")
        # dominated[c]: combination c is at least as coarse as one that failed (one
        # vectorised pass per failure, not a Python loop over the failures per candidate).
        dominated = np.zeros(combos.shape[0], dtype=bool)
        choice = -1
        for c in order.tolist():
            if dominated[c]:
                continue
            if bounded and wc_ok[c]:
                choice = int(c)
                break
            evaluated += 1
            if yield_of(t_comb[c]) >= target_yield:
                choice = int(c)
                break
            dominated |= np.all(combos >= combos[c], axis=1)
        if choice < 0:
            y = yield_of(finest[0])
            no_grade(f"the Monte Carlo yield is {y:.4%} (target {target_yield:.4%})")
        achieved = yield_of(t_comb[choice], early=False)
        fails: dict[str, bool | None] = {}
        for j, k in enumerate(keys):
            idx = combos[choice].copy()
            if idx[j] == len(grades) - 1:
                fails[k] = None
                continue
            idx[j] += 1
            fails[k] = yield_of(dev[np.arange(nk), idx]) < target_yield
    else:
        assert wc is not None
        evaluated = combos.shape[0]
        ok = wc <= limit
        if not ok.any():
            what = "worst case" if criterion == "worst_case" else "RSS"
            if curves is None:
                unit, scale = _message_unit(base.unit)
                no_grade(f"the {what} is {figure(finest)[0] * scale:.4g} {unit}")
            t0 = dev[:, 0]
            if criterion == "rss":
                per = np.sqrt((g * g) @ (t0 * t0) + fixed_rss) * w
            else:
                per = (np.abs(g) @ t0 + fixed_wc) * w
            i = int(np.argmax(per))
            no_grade(
                f"the {what} reaches {per[i]:.4g} times the band half-width"
                f" min(upper, -lower) at {math.degrees(float(base.theta_rad[i])):.1f}°"
            )
        cand = np.flatnonzero(ok)
        choice = int(cand[np.argmin(cost[cand])])
        achieved = float(wc[choice])
        fails = {}
        for j, k in enumerate(keys):
            idx = combos[choice].copy()
            if idx[j] == len(grades) - 1:
                fails[k] = None
                continue
            idx[j] += 1
            fails[k] = bool(figure(dev[np.arange(nk), idx][None, :])[0] > limit)
    chosen = tuple(grades[i] for i in combos[choice])
    final = _with_grades(design, keys, chosen)
    tols = final.resolve_tolerances(rmax)
    worst = float((np.abs(g) @ t_comb[choice] + fixed_wc).max())  # [mm or rad]
    # iso286 takes the deviation in µm (lengths) or degrees (angles, its table's unit).
    if design.mechanism.output == "translating":
        accuracy = iso286.grade_of_deviation(worst * 1e3, design.program.total_travel)
    else:
        accuracy = iso286.grade_of_angle_deviation(
            worst * (180.0 / math.pi), math.degrees(design.program.total_travel)
        )
    check = monte_carlo(
        final,
        verify_samples,
        seed=seed + 1,
        model=model,
        spec=spec,
        band=curves,
        step_deg=step_deg,
    )
    assert check.yield_estimate is not None
    verified = check.yield_estimate
    return Allocation(
        grades=dict(zip(keys, chosen, strict=True)),
        deviations=tuple(tols),
        criterion=criterion,
        spec=spec,
        unit=base.unit,
        achieved=achieved,
        cost=float(cost[choice]),
        accuracy=accuracy,
        verified=verified,
        coarser_fails=fails,
        evaluated=evaluated,
        band=None if band is None else band_label(band),
        target_yield=target_yield,
        met=verified.ci95[1] >= target_yield,
    )


def _check_samples(name: str, value: int) -> None:
    """Refuse a number of samples monte_carlo would refuse (the same upper bound)."""
    from camtol.tolerancing.montecarlo import MAX_LINEAR_SAMPLES

    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
        raise DesignError(f"{name}={value!r} is not allowed; give a whole number ≥ 1")
    if value > MAX_LINEAR_SAMPLES:
        raise DesignError(
            f"{name}={value} is not allowed; at most {MAX_LINEAR_SAMPLES:.0e} samples, as"
            " for camtol montecarlo"
        )


def _require_scalable(model: StatisticalModel, keys: list[str], criterion: str) -> None:
    """Refuse statistics that allocation cannot scale with the grade (no silent error).

    Allocation chooses each source's zone: every candidate's zone is ±T of its grade and
    its samples are those of the finest grade scaled by T/T_finest. A zone given in
    [statistics] is fixed whatever the grade, and a bias (mean shift) in µm or degrees
    does not scale with T: both would make the figures of every other grade wrong.
    """
    for key in keys:
        d = model.distribution(key)
        if d.zone_lower is not None or d.zone_upper is not None:
            raise DesignError(
                f"statistics.{key}: a fixed zone (zone_lower/zone_upper) cannot be allocated;"
                " allocate chooses the zone (±T of the grade): remove the zone for"
                " this source"
            )
        if criterion == "monte_carlo" and d.bias != 0.0:
            raise DesignError(
                f"statistics.{key}: a bias (bias_um or bias_deg) is a fixed mean shift and would be"
                " scaled with the candidate grades; allocate with criterion monte_carlo"
                " needs unbiased sources (run `camtol montecarlo` on the chosen grades"
                " with the bias to check them)"
            )


def _message_unit(internal_unit: str) -> tuple[str, float]:
    """Return the unit and factor in which an error message states ΔS (the spec's unit).

    The spec is given in µm (``--spec-um``, a lift) or degrees (``--spec-deg``, a
    swing), so a message about it speaks those units; results stay in mm or rad.
    """
    return ("um", 1e3) if internal_unit == "mm" else ("deg", 180.0 / math.pi)


def _no_grade(
    theta_rad: FloatArray,
    keys: list[str],
    grades: tuple[str, ...],
    g: FloatArray,
    finest: FloatArray,
    w: FloatArray,
    spec: float | None,
    band: ToleranceBand | tuple[FloatArray, FloatArray] | None,
    internal_unit: str,
    achieved: str,
) -> NoReturn:
    """Raise the "no grade can meet it" error (dominant source at the worst angle)."""
    unit, scale = _message_unit(internal_unit)
    part = np.abs(g) * finest[None, :] * w[:, None]
    i = int(np.argmax(part.sum(axis=1)))
    j = int(np.argmax(part[i]))
    where = f"{math.degrees(float(theta_rad[i])):.1f}°"
    if band is None:
        assert spec is not None
        raise DesignError(
            f"spec max |dS| <= {spec * scale:g} {unit} cannot be met with grades"
            f" {grades[0]}-{grades[-1]}: with every source at {grades[0]} {achieved};"
            f" source {keys[j]!r} dominates ({part[i, j] * scale:.4g} {unit} at {where})"
        )
    raise DesignError(
        f"band {band_label(band)} cannot be met with grades {grades[0]}-{grades[-1]}: with"
        f" every source at {grades[0]} {achieved}; source {keys[j]!r} dominates (its worst"
        f" case alone is {part[i, j]:.4g} times the band half-width at {where})"
    )
