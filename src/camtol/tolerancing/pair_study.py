"""A conjugate pair's linear tolerance model on a θ grid (THEORY §3, §4.1, §4.3).

:func:`prepare_pair` turns a conjugate design and its statistical model into a
:class:`PairStudy`: the pair's independent sources (:func:`camtol.pair.sources
.pair_sources`) and random profile processes as the columns of a sampling plan, and per
column the sensitivities of every output the pair study samples (ΔS_A, ΔS_B, Δf, each
cam's radial profile error) and the fixture's affine reading of each cam with the few
grid angles that decide its verdict. :mod:`camtol.tolerancing.pair` samples it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.errors import error_analysis
from camtol.analysis.kinematics import analysis_grid
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.pair.acceptance import AcceptanceBands, acceptance_bands
from camtol.pair.fixture_spec import FixtureSpec, fixture_spec
from camtol.pair.sources import PairSource, pair_sources
from camtol.pair.variation import (
    ConjugateFactors,
    conjugate_factors,
    df_sensitivities,
    fixture_reading_um,
)
from camtol.tolerancing.model import StatisticalModel, statistical_model
from camtol.tolerancing.plan import SamplingPlan
from camtol.tolerancing.processes import ProfileProcess, contact_polar_angle

__all__ = ["PairStudy", "prepare_pair"]


@dataclass(frozen=True)
class PairStudy:
    """A conjugate pair prepared for sampling.

    Attributes
    ----------
    design : CamDesign
        The pair's design.
    theta_rad : ndarray
        Cam angles. [rad]
    sources : tuple of PairSource
        The independent sources, one column each.
    plan : SamplingPlan
        Their distributions (the design's ``[statistics]``), one column per source.
    motion : dict of str to ndarray
        By cam letter: ∂ΔS/∂p of the follower when that cam holds its roller, shape
        (angles, columns). [rad per mm, or per rad]
    df : ndarray
        ∂Δf/∂p, shape (angles, columns). [mm per mm, or per rad]
    radial : dict of str to ndarray
        By cam letter: ∂Δr/∂p of that cam's profile (Δr = Δn / cos λ for a normal error),
        shape (angles, columns). [mm per mm]
    centre_column : int or None
        The column of the machine's centre-distance error Δf₀ (source ``f``).
    spec : FixtureSpec or None
        The fixture's inputs (``[inspection]``), for its yield.
    factors : ConjugateFactors
        The pair's geometry on the grid.
    bands : AcceptanceBands or None
        The fixture's acceptance bands on the grid.
    readings : dict of str to (ndarray, ndarray, ndarray)
        By cam letter: the fixture's reading of the nominal cam and its change per unit
        of each source (angles, columns), both from
        :func:`camtol.pair.variation.fixture_reading_um` (linear in Δr), at the grid
        angles that decide every verdict (the third array; :func:`_deciding_angles`). [µm]
    cam_processes : tuple of (str, ProfileProcess)
        The random profile processes by cam letter, in the order of the plan's process
        column groups.
    """

    design: CamDesign
    theta_rad: FloatArray
    sources: tuple[PairSource, ...]
    plan: SamplingPlan
    motion: dict[str, FloatArray]
    df: FloatArray
    radial: dict[str, FloatArray]
    centre_column: int | None
    spec: FixtureSpec | None
    factors: ConjugateFactors
    bands: AcceptanceBands | None
    readings: dict[str, tuple[FloatArray, FloatArray, NDArray[np.intp]]] = field(
        default_factory=dict
    )
    cam_processes: tuple[tuple[str, ProfileProcess], ...] = ()

    @property
    def letters(self) -> tuple[str, ...]:
        """The cams' letters, in order."""
        return tuple(self.motion)


def prepare_pair(
    design: CamDesign, *, model: StatisticalModel | None = None, step_deg: float = 0.1
) -> PairStudy:
    """Prepare a conjugate pair: its sources, distributions and sensitivities on a θ grid.

    Parameters
    ----------
    design : CamDesign
        A conjugate design with ``[tolerances]``.
    model : StatisticalModel, optional
        Distributions; default the design's ``[statistics]`` table (normal, Cp = 1).
    step_deg : float
        θ grid step. [deg]

    Returns
    -------
    PairStudy

    Raises
    ------
    DesignError
        Not a conjugate design, no toleranced source, or a tolerance that cannot be
        resolved.
    """
    from camtol.analysis.validity import check_design_geometry

    check_design_geometry(design)
    sources = pair_sources(design)
    if not sources:
        raise DesignError(f"design {design.name!r} has no [tolerances]: nothing to sample")
    model = statistical_model(design) if model is None else model
    theta, left = analysis_grid(step_deg, design.program.boundaries_rad)
    processes = [
        (cam.letter, p) for cam in design.cams() if (p := model.process_of(cam.letter)) is not None
    ]
    labels = [s.key for s in sources]
    groups = [(j, j + 1) for j in range(len(sources))]
    for letter, p in processes:
        labels.append(f"{p.target}_{letter.lower()}_process")
        groups.append(
            (groups[-1][1] if groups else 0, (groups[-1][1] if groups else 0) + p.columns)
        )
    plan = SamplingPlan(
        labels=tuple(labels),
        groups=tuple(groups),
        distributions=tuple(
            model.distribution(s.design_key).resolve(s.tolerance.deviation, s.tolerance.unit)
            for s in sources
        ),
        deviations=tuple(abs(s.tolerance.deviation) for s in sources)
        + tuple(p.deviation_mm() for _, p in processes),
        units=tuple(s.tolerance.unit for s in sources) + ("mm",) * len(processes),
        processes=tuple(p for _, p in processes),
    )
    factors = conjugate_factors(design, theta)
    cols = plan.columns
    motion: dict[str, FloatArray] = {}
    radial: dict[str, FloatArray] = {}
    tols_of: dict[str, Any] = {}
    for cam in design.cams():
        own = {key for s in sources for letter, key in s.cams if letter == cam.letter}
        own |= {p.target for letter, p in processes if letter == cam.letter}
        unit = {s.key: s.unit for s in cam.design.sources}
        tols = tuple(ResolvedTolerance(k, 1.0, unit[k], "unit") for k in sorted(own))
        err = error_analysis(cam.design, tols, theta, left_limit=left)
        tols_of[cam.letter] = err
        g = np.zeros((theta.size, cols))
        r = np.zeros((theta.size, cols))
        cos_shift = np.cos(factors.shift_rad(cam.letter))
        for j, s in enumerate(sources):
            for letter, key in s.cams:
                if letter != cam.letter:
                    continue
                g[:, j] = err.sources[key].delta_lift
                profile = cam.design.source(key).profile
                if profile == "radial":
                    r[:, j] = 1.0
                elif profile == "normal":
                    r[:, j] = 1.0 / cos_shift
        motion[cam.letter] = g
        radial[cam.letter] = r
    per_key = df_sensitivities(factors)
    df = np.zeros((theta.size, cols))
    for j, s in enumerate(sources):
        if s.key in per_key:
            df[:, j] = per_key[s.key]
    for (letter, p), (a, b) in zip(processes, plan.process_groups, strict=True):
        # A profile process of one cam: at angle θ the follower, the fixture and Δf feel
        # the error at the contact point's polar angle ψ(θ) (camtol.tolerancing.processes),
        # with the sensitivities of a constant error of that cam's profile there.
        cam = design.cam(letter)
        psi = contact_polar_angle(cam.mechanism, design.program, theta, left_limit=left)
        harmonics = np.hstack(
            [np.cos(np.outer(psi.v, p.orders)), np.sin(np.outer(psi.v, p.orders))]
        )
        key = f"{p.target}_{letter.lower()}"
        per_unit = tols_of[letter].sources[p.target].delta_lift
        motion[letter][:, a:b] = per_unit[:, None] * harmonics
        profile_gain = 1.0 if p.target == "r" else 1.0 / np.cos(factors.shift_rad(letter))
        radial[letter][:, a:b] = np.asarray(profile_gain)[..., None] * harmonics
        df[:, a:b] = per_key[key][:, None] * harmonics
    centre = next((j for j, s in enumerate(sources) if s.key == "f"), None)
    spec = fixture_spec(design)
    bands = None
    readings: dict[str, tuple[FloatArray, FloatArray, NDArray[np.intp]]] = {}
    if spec is not None:
        bands = acceptance_bands(
            factors,
            spec.tolerance_a_um,
            spec.tolerance_b_um,
            spec.master_a,
            spec.master_b,
            spec.errors,
        )
        for letter, g in radial.items():
            # the reading is affine in the cam's radial error: nominal + Σ x_j ∂/∂x_j
            nominal = fixture_reading_um(factors, spec, letter, np.zeros_like(theta))
            per_unit = fixture_reading_um(factors, spec, letter, g.T * 1e3) - nominal
            at = _deciding_angles(per_unit.T, nominal, bands.band_um(letter))
            readings[letter] = (nominal[at], np.ascontiguousarray(per_unit.T[at]), at)
    return PairStudy(
        design,
        theta,
        sources,
        plan,
        motion,
        df,
        radial,
        centre,
        spec,
        factors,
        bands,
        readings,
        tuple(processes),
    )


def _deciding_angles(
    per_unit: FloatArray, nominal: FloatArray, band: tuple[FloatArray, FloatArray]
) -> NDArray[np.intp]:
    """Return the grid angles that decide the fixture's verdict on any sampled cam (exact).

    The reading is affine in the few columns that move the cam's profile: r(θ) = R0(θ) +
    Σ_j x_j R_j(θ). The cam passes iff min over θ of r − lower and of upper − r is ≥ 0;
    each is the minimum over θ of a linear function of (x_J, 1) in the points
    (±R_J(θ), ±R0(θ) ∓ limit(θ)), which is reached at a vertex of their convex hull. So
    only the hull's vertex angles decide; the others never do (a reduction, not an
    approximation). With more than two profile columns, or a flat hull, every angle.
    """
    every = np.arange(per_unit.shape[0])
    cols = np.flatnonzero(np.any(per_unit != 0.0, axis=0))
    if cols.size == 0:
        return every
    if cols.size > 2:
        return every

    up, lo = band
    keep: list[NDArray[np.intp]] = []
    for sign, offset in ((1.0, nominal - lo), (-1.0, up - nominal)):
        vertices = _hull_vertices(np.column_stack([sign * per_unit[:, cols], offset]))
        if vertices is None:
            return every
        keep.append(vertices)
    return np.unique(np.concatenate(keep))


def _hull_vertices(points: FloatArray) -> NDArray[np.intp] | None:
    """Vertices of the convex hull of points in their affine span (None: qhull failed).

    Points on a line (a cam judged on Δr alone: its reading and band are proportional)
    have the two ends as vertices; in a plane or space, qhull's vertices.
    """
    centred = points - points.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    rank = int(np.count_nonzero(sv > 1e-12 * max(sv[0], 1e-300))) if sv.size else 0
    if rank == 0:
        return np.array([0])
    p = centred @ vt[:rank].T
    if rank == 1:
        return np.unique([int(np.argmin(p[:, 0])), int(np.argmax(p[:, 0]))])
    from scipy.spatial import ConvexHull, QhullError

    try:
        return np.asarray(ConvexHull(p).vertices)
    except (QhullError, ValueError):
        return None
