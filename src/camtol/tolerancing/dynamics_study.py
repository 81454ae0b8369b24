"""Monte Carlo of the tolerances at speed: the forces of the cams as made (issue 33 item 4).

``camtol montecarlo --dynamics``: each sampled mechanism's lift is the nominal one plus
Σ_j g_j(θ) x_j (THEORY §3: the study's own sources, sensitivities and samples,
:func:`camtol.tolerancing.study.prepare`), and the follower train's steady state is
linear in the lift, so each sample's contact force is the nominal force plus Σ_j x_j Q_j
(:mod:`camtol.dynamics.montecarlo`, THEORY §9.7). The result is the distribution of the
peak and the smallest contact force and of the residual vibration over the samples, and
the yield against a force spec or a jump margin. The samples are the study's (same seed,
same rows as ``camtol montecarlo``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.montecarlo import column_responses, sample_dynamics
from camtol.dynamics.steady import check_rpm
from camtol.dynamics.train import follower_train
from camtol.exceptions import DesignError
from camtol.jet import FloatArray
from camtol.tolerancing.plan import sensitivity_matrices
from camtol.tolerancing.results import YieldEstimate
from camtol.tolerancing.study import prepare, sample_matrix

__all__ = ["monte_carlo_dynamics"]

#: Largest number of samples at speed (each holds a force curve per block of rows).
MAX_DYNAMICS_SAMPLES = 10**7


def _summary(values: FloatArray, scale: float = 1.0) -> dict[str, float]:
    v = np.asarray(values, dtype=float) * scale
    q = np.quantile(v, [0.00135, 0.5, 0.99865])
    return {
        "mean": float(v.mean()),
        "min": float(v.min()),
        "q00135": float(q[0]),
        "q50": float(q[1]),
        "q99865": float(q[2]),
        "max": float(v.max()),
    }


def monte_carlo_dynamics(
    design: CamDesign,
    samples: int,
    *,
    rpm: float | None = None,
    overrides: Mapping[str, Any] | None = None,
    seed: int = 0,
    step_deg: float = 0.1,
    force_min_n: float | None = None,
    force_max_n: float | None = None,
    jump_margin: float | None = None,
) -> dict[str, Any]:
    """Sample the tolerances and run every sample at speed (THEORY §3, §9.7).

    Parameters
    ----------
    design : CamDesign
        A single-cam, force-closed design with a ``[dynamics]`` table (or overrides).
    samples : int
        Mechanisms sampled (≥ 1).
    rpm : float, optional
        Cam speed; default the design's ``operation.speed_rpm``. [rpm]
    overrides : mapping, optional
        ``[dynamics]`` fields given on the command line (file units).
    seed : int
        Seed (the same rows as the tolerance study's).
    step_deg : float
        Grid step of the dynamics; must divide 360°. [deg]
    force_min_n, force_max_n : float, optional
        A sample passes only if its contact force stays within these. [N]
    jump_margin : float, optional
        A sample passes only if it keeps contact at ``jump_margin`` × ``rpm`` (> 1). [-]

    Returns
    -------
    dict
        The ``dynamics`` object of ``camtol montecarlo --json``: ``rpm``, ``samples``,
        ``peak_force_n``, ``min_force_n`` and ``residual_vibration_um`` (or ``_deg``),
        each ``{mean, min, q00135, q50, q99865, max}`` over the samples (null without a
        dwell), the specs and ``yield`` (``{value, ci95}``, null without a spec).

    Raises
    ------
    DesignError
        No speed, a conjugate pair, a bad train or spec, too many samples.
    """
    if isinstance(samples, bool) or not 1 <= int(samples) <= MAX_DYNAMICS_SAMPLES:
        raise DesignError(
            f"--samples={samples!r} is not allowed with --dynamics; give 1 to"
            f" {MAX_DYNAMICS_SAMPLES:.0e}"
        )
    speed = rpm if rpm is not None else design.speed_rpm
    if speed is None:
        raise DesignError("--dynamics needs a cam speed: give --rpm or operation.speed_rpm")
    speed = check_rpm(speed)
    for name, value in (("--force-min-n", force_min_n), ("--force-max-n", force_max_n)):
        if value is not None and not math.isfinite(value):
            raise DesignError(f"{name}={value!r} is not allowed; give a finite number of N")
    study = prepare(design, step_deg=step_deg)
    cam = study.design
    train = follower_train(cam, overrides)
    theta = nominal_lift(cam, step_deg).theta_rad
    sens = sensitivity_matrices(cam, study.plan, theta, np.zeros(theta.size, dtype=bool))
    labels = [
        lab if b - a == 1 else f"{lab}[{j}]"
        for lab, (a, b) in zip(study.plan.labels, study.plan.groups, strict=True)
        for j in range(b - a)
    ]
    responses = column_responses(
        cam,
        train,
        speed,
        labels,
        sens["lift"],
        sens["acceleration"],
        step_deg=step_deg,
        jump_margin=jump_margin,
    )
    rows = sample_matrix(study.plan, int(seed), int(samples))
    res = sample_dynamics(
        responses, rows, force_min_spec_n=force_min_n, force_max_spec_n=force_max_n
    )
    oscillating = cam.mechanism.output == "oscillating"
    vib_key = "residual_vibration_deg" if oscillating else "residual_vibration_um"
    vib_scale = math.degrees(1.0) if oscillating else 1e3
    has_spec = any(v is not None for v in (force_min_n, force_max_n, jump_margin))
    y = YieldEstimate.of(int(res.passed.sum()), int(samples)) if has_spec else None
    return {
        "rpm": speed,
        "samples": int(samples),
        "peak_force_n": _summary(res.peak_force_n),
        "min_force_n": _summary(res.min_force_n),
        vib_key: None
        if res.residual_vibration is None
        else _summary(res.residual_vibration, vib_scale),
        "force_min_n": force_min_n,
        "force_max_n": force_max_n,
        "jump_margin": jump_margin,
        "yield": None if y is None else {"value": y.value, "ci95": list(y.ci95)},
        "note": "linear in the tolerances (THEORY §3, §9.7): each sample's force is the"
        " nominal force plus its sources' responses",
    }
