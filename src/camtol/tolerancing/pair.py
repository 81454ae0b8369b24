"""A conjugate pair toleranced as a pair: motion errors, interference, backlash, yields.

Before making a thousand pairs a production engineer asks how far the follower's motion
strays when cam A holds roller C and when cam B holds roller D, how much interference or
backlash the assembled follower sees, and what fraction of cams the measuring fixture
accepts ([CW11]). Every source of the pair is an independent random variable
(:func:`camtol.pair.sources.pair_sources`: each cam's profile, each roller, each arm, the
arm angle η, the machine's centre distance f, the shaft's phase), and in the linear model
(THEORY §3, §4.1) each output at one angle is a weighted sum of them:

* ΔS_A(θ), ΔS_B(θ): the follower's motion error with cam A (B) holding its roller, from
  each cam's closed-form sensitivities (:func:`camtol.analysis.errors.error_analysis`);
* Δf(θ) = f* − f: the conjugate variation of the assembled pair, the change of centre
  distance at which both rollers just touch (:func:`camtol.pair.variation
  .df_sensitivities`). With the machine's centre-distance error Δf₀ (source ``f``),
  Δf − Δf₀ > 0 is interference (the rollers forced into the cams) and < 0 backlash; per
  sample ``interference`` = max_θ max(Δf − Δf₀, 0), ``backlash`` = max_θ max(Δf₀ − Δf, 0),
  both as centre distance.
* the fixture's verdict on each sampled cam (THEORY §4.3): cam A measured against master
  B, cam B against master A, with the masters and the fixture's constant errors of the
  ``[inspection]`` table, judged by the bands' one rule
  (:meth:`camtol.pair.acceptance.AcceptanceBands.margin_um`) as a measured cam is.

Per-angle mean and σ follow from the sources' moments without sampling; what couples the
angles (each sample's maxima, interference, backlash, yields) is sampled, chunk by chunk
with the same random streams as single-cam studies (:func:`~camtol.tolerancing.plan
.chunk_uniforms`), so the same seed gives the same numbers at any chunking.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.pair.as_made import CamProfileErrors
from camtol.tolerancing.model import StatisticalModel, statistical_model
from camtol.tolerancing.pair_results import (
    PairMonteCarloResult,
    SampledSummary,
    moments,
)
from camtol.tolerancing.pair_study import PairStudy, prepare_pair
from camtol.tolerancing.plan import CHUNK, chunk_uniforms
from camtol.tolerancing.processes import ContactAngleError
from camtol.tolerancing.results import YieldEstimate

__all__ = [
    "PairMonteCarloResult",
    "PairStudy",
    "SampledSummary",
    "pair_monte_carlo",
    "prepare_pair",
]

#: Largest number of samples of a pair study (memory is bounded; this bounds time).
MAX_PAIR_SAMPLES = 10**9
#: Largest number of samples in exact mode (each follows both cams and the fixture).
MAX_EXACT_PAIR_SAMPLES = 100_000
#: Rows evaluated at once (four angle-by-row blocks of this many rows fit in cache-sized
#: memory: 1,024 × 3,600 doubles are 29 MB).
_ROWS = 1024


def pair_monte_carlo(
    design: CamDesign,
    samples: int,
    *,
    seed: int = 0,
    model: StatisticalModel | None = None,
    step_deg: float = 0.1,
    interference_max_mm: float | None = None,
    backlash_max_mm: float | None = None,
    mode: str = "linear",
    quantiles: bool = True,
    fixture_yield: bool = True,
) -> PairMonteCarloResult:
    """Tolerance a conjugate pair as a pair, in the linear model (module docstring).

    Parameters
    ----------
    design : CamDesign
        A conjugate design; its ``[inspection]`` table, when given, makes the fixture
        yield.
    samples : int
        Pairs sampled (≥ 1).
    seed : int
        Seed; chunk c of 4096 samples uses ``SeedSequence(seed, spawn_key=(c,))``.
    model : StatisticalModel, optional
        Distributions; default the design's ``[statistics]`` table.
    step_deg : float
        θ grid step. [deg]
    interference_max_mm, backlash_max_mm : float, optional
        Limits of the pair yield (both or neither). [mm]
    mode : {"linear", "exact"}
        How each sample's maxima, interference, backlash and fixture verdicts are found:
        from the closed-form sensitivities, or by following the pair as made exactly
        (:mod:`camtol.pair.as_made`; per-angle moments stay the linear model's).
    quantiles : bool
        Compute the per-angle quantiles (the convolution); an allocation's candidates
        need only the sampled figures and leave them out (NaN).
    fixture_yield : bool
        Judge every sampled cam as the fixture would (THEORY §4.3). It needs the
        fixture's bands (``[inspection]``): without them the study is refused rather
        than reported without a fixture yield; False leaves the fixture out.

    Returns
    -------
    PairMonteCarloResult

    Raises
    ------
    DesignError
        Bad samples, seed or limits, a fixture yield asked of a design without
        ``[inspection]`` bands, or a design that cannot be sampled as a pair.
    """
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 1:
        raise DesignError(f"samples={samples!r} is not allowed; give a whole number ≥ 1")
    if samples > MAX_PAIR_SAMPLES:
        raise DesignError(f"samples={samples} is not allowed; at most {MAX_PAIR_SAMPLES:.0e}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise DesignError(f"seed={seed!r} is not allowed; give a whole number ≥ 0")
    if mode not in ("linear", "exact"):
        raise DesignError(f"mode={mode!r} is unknown; allowed: linear, exact")
    if mode == "exact" and samples > MAX_EXACT_PAIR_SAMPLES:
        raise DesignError(
            f"samples={samples} is too large for exact mode (at most"
            f" {MAX_EXACT_PAIR_SAMPLES}: each sample follows the pair exactly); use linear mode"
        )
    limits = (interference_max_mm, backlash_max_mm)
    if (limits[0] is None) != (limits[1] is None):
        raise DesignError(
            "the pair yield needs both limits: give the largest interference and the largest"
            " backlash (--interference-max-um and --backlash-max-um)"
        )
    for name, value in zip(("interference", "backlash"), limits, strict=True):
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise DesignError(f"the largest {name} {value!r} is not allowed; it must be ≥ 0")
    study = prepare_pair(design, model=model, step_deg=step_deg)
    if fixture_yield and study.bands is None:
        raise DesignError(
            f"[inspection]: design {design.name!r} has no fixture bands (tolerance_a_um,"
            " tolerance_b_um), so the fixture's yield cannot be judged; add the table, or"
            " leave the fixture out (--no-fixture-yield)"
        )
    if not fixture_yield:
        study = dataclasses.replace(study, bands=None, readings={})
    letters = study.letters
    n = int(samples)
    max_abs = {letter: np.empty(n) for letter in letters}
    interference = np.empty(n)
    backlash = np.empty(n)
    accepted = {letter: np.zeros(n, dtype=bool) for letter in letters}
    plan = study.plan
    for c in range(-(-n // CHUNK)):
        size = min(CHUNK, n - c * CHUNK)
        x_chunk = plan.sample(chunk_uniforms(int(seed), c, size, plan.uniforms))
        for a in range(0, size, _ROWS):
            x = x_chunk[a : a + _ROWS]
            rows = slice(c * CHUNK + a, c * CHUNK + a + x.shape[0])
            evaluate = _evaluate_rows if mode == "linear" else _exact_rows
            evaluate(study, x, rows, max_abs, interference, backlash, accepted)
    df = moments(study.df, plan, quantiles=quantiles)
    worst = int(np.argmax(np.abs(df.mean) + 3.0 * df.std))
    contributions = dict(
        sorted(
            ((lab, float(v[worst])) for lab, v in df.shares.items()),
            key=lambda kv: -kv[1],
        )
    )
    fixture_yields = {}
    if study.bands is not None:
        fixture_yields = {k: YieldEstimate.of(int(v.sum()), n) for k, v in accepted.items()}
    pair_yield = None
    if interference_max_mm is not None and backlash_max_mm is not None:
        ok = (interference <= interference_max_mm) & (backlash <= backlash_max_mm)
        pair_yield = YieldEstimate.of(int(ok.sum()), n)
    notes = [
        "deterministic (no sampling noise): per-angle mean, σ and quantiles of ΔS_A,"
        " ΔS_B and Δf (quantiles by convolution of the source densities, within a stated"
        " tolerance), and Δf's variance shares",
        f"sampled ({n} pairs): max |ΔS| per cam, interference, backlash, fixture and pair"
        " yields (yields with Clopper-Pearson 95 % intervals)",
        "linear model (THEORY §3, §4.1): each source varies in ±Δ of its resolved tolerance"
        if mode == "linear"
        else "exact mode: each sampled pair followed as made (THEORY §5); the per-angle"
        " figures are the linear model's",
    ]
    common = (statistical_model(design) if model is None else model).process
    shared = [letter for letter, p in study.cam_processes if p is common]
    if common is not None and shared:
        notes.append(
            "statistics.profile_process on a pair: the same process on cam "
            + " and cam ".join(shared)
            + ", sampled independently for each"
        )
    if n < 1000:
        notes.append(f"only {n} samples: the sampled quantiles and yields are rough")
    if study.bands is None:
        notes.append("fixture yield left out (--no-fixture-yield)")
    return PairMonteCarloResult(
        design_name=design.name,
        samples=n,
        seed=int(seed),
        theta_deg=np.degrees(study.theta_rad),
        motion={
            letter: moments(g, plan, quantiles=quantiles) for letter, g in study.motion.items()
        },
        df=df,
        max_abs_motion={k: SampledSummary.of(v) for k, v in max_abs.items()},
        interference_mm=SampledSummary.of(interference),
        backlash_mm=SampledSummary.of(backlash),
        fixture_yield=fixture_yields,
        pair_yield=pair_yield,
        interference_max_mm=interference_max_mm,
        backlash_max_mm=backlash_max_mm,
        df_worst_angle_deg=float(np.degrees(study.theta_rad[worst])),
        df_contributions=contributions,
        sources=study.sources,
        plan=plan,
        notes=tuple(notes),
        process_cams=tuple(
            (letter, "profile_process" if p is common else f"profile_process_{letter.lower()}")
            for letter, p in study.cam_processes
        ),
    )


def _evaluate_rows(
    study: PairStudy,
    x: FloatArray,
    rows: slice,
    max_abs: dict[str, FloatArray],
    interference: FloatArray,
    backlash: FloatArray,
    accepted: dict[str, NDArray[np.bool_]],
) -> None:
    """Evaluate a block of sampled pairs (rows of ``x``) into the per-sample arrays."""
    for letter, g in study.motion.items():
        y = x @ g.T
        max_abs[letter][rows] = np.maximum(y.max(axis=1), -y.min(axis=1))
    df = x @ study.df.T
    if study.centre_column is not None:
        df -= x[:, study.centre_column][:, None]  # Δf − Δf₀
    interference[rows] = np.maximum(df.max(axis=1), 0.0)
    backlash[rows] = np.maximum(-df.min(axis=1), 0.0)
    if study.bands is None:
        return
    for letter, (nominal, per_unit, at) in study.readings.items():
        reading = x @ per_unit.T
        reading += nominal
        margin = study.bands.margin_um(letter, reading, at=at)
        accepted[letter][rows] = margin.min(axis=1) >= 0.0


def _exact_rows(
    study: PairStudy,
    x: FloatArray,
    rows: slice,
    max_abs: dict[str, FloatArray],
    interference: FloatArray,
    backlash: FloatArray,
    accepted: dict[str, NDArray[np.bool_]],
) -> None:
    """As :func:`_evaluate_rows`, each sample followed as made (exact)."""
    from camtol.pair.as_made import fixture_reading_as_made_um, follow_pair_as_made

    start = rows.start
    plan = study.plan
    constant = len(plan.distributions)
    for i, row in enumerate(x):
        values = dict(zip(plan.labels[:constant], row[:constant].tolist(), strict=True))
        errors = _process_errors(study, row)
        out = follow_pair_as_made(
            study.design, study.sources, values, study.theta_rad, profile_errors=errors
        )
        for letter, ds in out.motion.items():
            max_abs[letter][start + i] = float(np.abs(ds).max())
        df = out.df_mm - (0.0 if study.centre_column is None else row[study.centre_column])
        interference[start + i] = max(float(df.max()), 0.0)
        backlash[start + i] = max(float(-df.min()), 0.0)
        if study.bands is None or study.spec is None:
            continue
        readings = fixture_reading_as_made_um(
            study.design, study.sources, values, study.spec, study.theta_rad, profile_errors=errors
        )
        for letter, reading in readings.items():
            accepted[letter][start + i] = study.bands.margin_um(letter, reading).min() >= 0.0


def _process_errors(study: PairStudy, row: FloatArray) -> dict[str, CamProfileErrors]:
    """One sample's profile processes as each cam's further profile errors (exact mode)."""
    out: dict[str, CamProfileErrors] = {}
    plan = study.plan
    for (letter, p), (a, b) in zip(study.cam_processes, plan.process_groups, strict=True):
        k = p.orders.size
        cam = study.design.cam(letter)
        error = ContactAngleError(
            cam.mechanism, study.design.program, p.orders, row[a : a + k], row[a + k : b]
        )
        out[letter] = CamProfileErrors(
            radial=(error,) if p.target == "r" else (), normal=(error,) if p.target == "n" else ()
        )
    return out
