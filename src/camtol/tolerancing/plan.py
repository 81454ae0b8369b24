"""The sampling plan: columns of the sample matrix and their sensitivities (THEORY §3).

Linear model: ΔS(θ) = Σ_j g_j(θ) x_j, with x the sample row (one column per constant
error source, two per Fourier order of a profile process) and g_j(θ) the closed-form
sensitivity (:func:`camtol.analysis.errors.error_analysis` at a unit deviation), times cos kψ(θ)
or sin kψ(θ) for the process columns, ψ(θ) being the polar angle of the contact point
(:func:`camtol.tolerancing.processes.contact_polar_angle`).

Random streams: sample ``i`` belongs to chunk ``i // CHUNK``; chunk ``c`` draws its
uniforms from ``SeedSequence(seed, spawn_key=(c,))`` (the c-th child of
``SeedSequence(seed).spawn(...)``), so the samples do not depend on how chunks are
grouped into tasks or spread over workers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from camtol.analysis.errors import error_analysis
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.distributions import ResolvedDistribution
from camtol.tolerancing.model import StatisticalModel
from camtol.tolerancing.processes import ProfileProcess, contact_polar_angle

__all__ = ["CHUNK", "Quantity", "SamplingPlan", "chunk_uniforms", "make_plan"]

#: Samples per random stream (fixed: part of the definition of a seed's samples).
CHUNK = 4096
Quantity = Literal["lift", "velocity", "acceleration"]


def chunk_uniforms(seed: int, index: int, size: int, uniforms: int) -> FloatArray:
    """Uniform variates in (0, 1) of chunk ``index``, shape (size, uniforms).

    Parameters
    ----------
    seed : int
        Study seed (≥ 0).
    index : int
        Chunk index.
    size : int
        Samples in the chunk.
    uniforms : int
        Variates per sample.
    """
    rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=(index,))))
    u = rng.random((size, uniforms))
    u[u == 0.0] = 2.0**-54  # ppf(0) would be −∞
    return u


@dataclass(frozen=True)
class SamplingPlan:
    """Columns of the sample matrix of a design.

    Attributes
    ----------
    labels : tuple of str
        Source labels in report order (tolerance keys; ``r_process``/``n_process``).
    groups : tuple of (int, int)
        Column range [start, stop) of each label.
    distributions : tuple of ResolvedDistribution
        One per constant source (the first labels).
    deviations : tuple of float
        Resolved tolerance Δ of each label (3σ or Σ amplitudes for a process). [mm, rad]
    units : tuple of str
        Internal unit of each label's deviation.
    processes : tuple of ProfileProcess
        The profile processes, their column groups last and in this order: a single
        cam's one process, or one per cam of a conjugate pair.
    """

    labels: tuple[str, ...]
    groups: tuple[tuple[int, int], ...]
    distributions: tuple[ResolvedDistribution, ...]
    deviations: tuple[float, ...]
    units: tuple[str, ...]
    processes: tuple[ProfileProcess, ...] = ()

    @property
    def process(self) -> ProfileProcess | None:
        """A single cam's profile process (its columns come last), or None.

        Raises
        ------
        DesignError
            The plan has several processes (a pair's): use :attr:`processes`.
        """
        if len(self.processes) > 1:
            raise DesignError("this plan has one profile process per cam: use .processes")
        return self.processes[0] if self.processes else None

    @property
    def process_groups(self) -> tuple[tuple[int, int], ...]:
        """Column range [start, stop) of each process, in :attr:`processes` order."""
        return self.groups[len(self.groups) - len(self.processes) :]

    @property
    def columns(self) -> int:
        """Columns of a sample row."""
        return self.groups[-1][1] if self.groups else 0

    @property
    def uniforms(self) -> int:
        """Uniform variates per sample."""
        return len(self.distributions) + sum(p.uniforms for p in self.processes)

    def sample(self, u: FloatArray) -> FloatArray:
        """Sample rows from uniforms. [mm or rad]

        Parameters
        ----------
        u : ndarray, shape (samples, uniforms)
            Uniform variates in (0, 1). [-]
        """
        nd = len(self.distributions)
        cols = [d.ppf(u[:, j]) for j, d in enumerate(self.distributions)]
        x = np.column_stack(cols) if cols else np.empty((u.shape[0], 0))
        start = nd
        for p in self.processes:  # each process draws from its own uniforms, in order
            x = np.hstack([x, p.sample(u[:, start : start + p.uniforms])])
            start += p.uniforms
        return np.ascontiguousarray(x)

    def column_mean(self) -> FloatArray:
        """Mean of every column. [mm or rad]"""
        m = [d.mean() for d in self.distributions]
        for p in self.processes:
            m += [0.0] * p.columns
        return np.asarray(m, dtype=float)

    def column_variance(self) -> FloatArray:
        """Variance of every column. [mm² or rad²]"""
        v = [d.variance() for d in self.distributions]
        for p in self.processes:
            pv = p.coefficient_variance_mm2()
            v += [*pv, *pv]
        return np.asarray(v, dtype=float)

    def column_bounds(self) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
        """(lower, upper, bounded) of every column (±8σ where unbounded). [mm or rad]"""
        lo = [d.support()[0] for d in self.distributions]
        hi = [d.support()[1] for d in self.distributions]
        bd = [d.bounded for d in self.distributions]
        for p in self.processes:
            b = p.coefficient_bounds_mm()
            lo += [*(-b), *(-b)]
            hi += [*b, *b]
            bd += [not p.gaussian] * p.columns
        return np.asarray(lo), np.asarray(hi), np.asarray(bd, dtype=bool)


def make_plan(
    design: CamDesign, model: StatisticalModel, tolerances: tuple[ResolvedTolerance, ...]
) -> SamplingPlan:
    """Build the sampling plan of a design's toleranced sources and its process.

    Parameters
    ----------
    design : CamDesign
        The design.
    model : StatisticalModel
        Distributions and process.
    tolerances : tuple of ResolvedTolerance
        Resolved tolerances (:meth:`CamDesign.resolve_tolerances`).
    """
    labels: list[str] = []
    groups: list[tuple[int, int]] = []
    dists: list[ResolvedDistribution] = []
    devs: list[float] = []
    units: list[str] = []
    for j, t in enumerate(tolerances):
        labels.append(t.key)
        groups.append((j, j + 1))
        dists.append(model.distribution(t.key).resolve(t.deviation, t.unit))
        devs.append(abs(t.deviation))
        units.append(t.unit)
    p = model.process
    if p is not None:
        labels.append(f"{p.target}_process")
        groups.append((len(dists), len(dists) + p.columns))
        devs.append(p.deviation_mm())
        units.append("mm")
    return SamplingPlan(
        tuple(labels), tuple(groups), tuple(dists), tuple(devs), tuple(units), (p,) if p else ()
    )


def sensitivity_matrices(
    design: CamDesign,
    plan: SamplingPlan,
    theta_rad: FloatArray,
    left_limit: NDArray[np.bool_],
) -> dict[str, FloatArray]:
    """Sensitivities g_j(θ) of every column for ΔS, ΔV and ΔA, shape (angles, columns).

    Parameters
    ----------
    design : CamDesign
        The design.
    plan : SamplingPlan
        Its columns.
    theta_rad : ndarray
        Cam angles. [rad]
    left_limit : ndarray of bool
        Rows taking left limits at segment boundaries.

    Returns
    -------
    dict
        ``lift``, ``velocity``, ``acceleration`` → ndarray (angles, columns), in output
        unit per column unit (per rad^k of cam angle for ΔV, ΔA).
    """
    keys = [lab for lab in plan.labels if not lab.endswith("_process")]
    unit = {s.key: s.unit for s in design.sources}
    p = plan.process
    wanted = list(keys) + ([p.target] if p is not None and p.target not in keys else [])
    unit_tols = tuple(ResolvedTolerance(k, 1.0, unit[k], "unit") for k in wanted)
    err = error_analysis(design, unit_tols, theta_rad, left_limit=left_limit)
    out: dict[str, list[FloatArray]] = {"lift": [], "velocity": [], "acceleration": []}
    for k in keys:
        s = err.sources[k]
        out["lift"].append(s.delta_lift[:, None])
        out["velocity"].append(s.delta_velocity[:, None])
        out["acceleration"].append(s.delta_acceleration[:, None])
    if p is not None:
        s = err.sources[p.target]
        g0, g1, g2 = (a[:, None] for a in (s.delta_lift, s.delta_velocity, s.delta_acceleration))
        psi = contact_polar_angle(
            design.mechanism, design.program, theta_rad, left_limit=left_limit
        )
        order = p.orders[None, :]
        kp = order * psi.v[:, None]
        p1, p2 = psi.d1[:, None], psi.d2[:, None]
        for which in ("cos", "sin"):
            if which == "cos":
                h0, dh = np.cos(kp), -np.sin(kp)
            else:
                h0, dh = np.sin(kp), np.cos(kp)
            h1 = order * dh * p1
            h2 = -order * order * h0 * p1 * p1 + order * dh * p2
            out["lift"].append(g0 * h0)
            out["velocity"].append(g1 * h0 + g0 * h1)
            out["acceleration"].append(g2 * h0 + 2 * g1 * h1 + g0 * h2)
    n = theta_rad.size
    return {q: (np.hstack(v) if v else np.zeros((n, 0))) for q, v in out.items()}
