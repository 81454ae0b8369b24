"""The return spring for a jump margin: rate and preload (THEORY §9.8).

A force-closed follower keeps contact up to the speed ω_t = margin × ω when the train
force stays ≥ 0 there: Q(θ) = P g₀ + k_s q_S(θ) + q_A(θ) ≥ 0 at every angle, with q_S and
q_A the train's responses to the lift S and to the inertia load M ω_t² A (for a rigid
train simply S and M ω_t² A; g₀ = k_f/(k_f + k_s)). The constraints are linear in the
preload P and the rate k_s, and camtol chooses the spring that meets them with the
smallest mean spring force P + k_s mean(S) over the revolution (less wear and friction
torque), by linear programming. Zero preload would meet the constraints with no force at
all in the dwell at zero lift, which any vibration opens: the spring must also hold the
follower at rest and at the running speed with at least :data:`FLOOR_FRACTION` of the largest
inertia load M ω² max(−A) at every angle; for an elastic train the responses depend a little on
k_s, so the programme is solved again with the new rate until it settles. The proposal is
then checked by the jump-speed search (THEORY §9.3), and stiffened by 1% steps if a
resonance below ω_t makes the follower jump earlier.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.fft as sfft
from scipy.optimize import linprog

from camtol.design.cam_design import CamDesign
from camtol.dynamics.jump import jump_speed_rpm
from camtol.dynamics.lift import CamLift
from camtol.dynamics.steady import check_rpm, rpm_to_rad_s, transfer
from camtol.dynamics.train import FollowerTrain
from camtol.exceptions import DesignError

__all__ = ["FLOOR_FRACTION", "SpringProposal", "propose_spring", "size_spring"]

#: Smallest contact force at the running speed, as a fraction of the largest inertia load.
FLOOR_FRACTION = 0.1


@dataclass(frozen=True)
class SpringProposal:
    """A return spring that keeps contact up to a margin over the running speed.

    Attributes
    ----------
    spring_rate : float
        Proposed rate k_s. [N/mm, or N·m/rad]
    preload : float
        Proposed force at zero lift P (the weight, if any, included). [N, or N·m]
    rpm : float
        Running speed. [rpm]
    margin : float
        Jump speed wanted over the running speed. [-]
    jump_speed_rpm : float or None
        The jump speed with the proposed spring (None: none found). [rpm]
    train : FollowerTrain
        The train with the proposed spring.
    """

    spring_rate: float
    preload: float
    rpm: float
    margin: float
    jump_speed_rpm: float | None
    train: FollowerTrain

    @property
    def target_rpm(self) -> float:
        """Margin × rpm. [rpm]"""
        return self.margin * self.rpm


def _responses(
    train: FollowerTrain, lift: CamLift, omega: float, spring_rate: float
) -> tuple[float, np.ndarray, np.ndarray]:
    """g₀, q_S(θ), q_A(θ) at ω for a train with this spring rate."""
    s = lift.smooth_lift
    inertia = train.mass * omega * omega * lift.smooth_acceleration
    if train.rigid:
        return 1.0, s, inertia
    t = dataclasses.replace(train, spring_rate=spring_rate)
    n = lift.angles
    half = n // 2
    g, _ = transfer(t, omega, half + 1)
    if n % 2 == 0:
        g[half] = 0.0
    q_s = sfft.irfft(g * sfft.rfft(s), n)
    q_a = sfft.irfft(g * sfft.rfft(inertia), n)
    return float(g[0].real), q_s, q_a


def propose_spring(
    train: FollowerTrain, lift: CamLift, rpm: float, margin: float
) -> SpringProposal:
    """Propose the return spring (rate and preload) for a jump margin (THEORY §9.8).

    Parameters
    ----------
    train : FollowerTrain
        The train (mass, stiffness, damping; its spring is replaced).
    lift : CamLift
        The cam's lift (nominal, or a scan's smooth lift).
    rpm : float
        Running speed. [rpm]
    margin : float
        Wanted jump speed over the running speed, > 1 (e.g. 1.3). [-]

    Returns
    -------
    SpringProposal

    Raises
    ------
    DesignError
        A form-closed pair, a margin ≤ 1, a rough lift, or no spring that can meet it.
    """
    rpm = check_rpm(rpm)
    if train.form_closed:
        raise DesignError("--jump-margin: a conjugate pair is form-closed; it has no spring")
    if isinstance(margin, bool) or not (math.isfinite(margin) and margin > 1.0):
        raise DesignError(f"--jump-margin={margin:g} is not allowed; give a number > 1")
    if lift.rough_lift is not None:
        raise DesignError("--jump-margin sizes the spring on the nominal cam or a scan")
    omega, omega_t = rpm_to_rad_s(rpm), rpm_to_rad_s(rpm * margin)
    k_s = train.spring_rate
    mean_s = float(np.mean(lift.smooth_lift))
    preload = train.preload
    floor = FLOOR_FRACTION * train.mass * omega**2 * float(np.max(-lift.smooth_acceleration))
    for _ in range(8):
        g0, q_s, q_a = _responses(train, lift, omega_t, k_s)
        g1, r_s, r_a = _responses(train, lift, omega, k_s)
        g2, z_s, _ = _responses(train, lift, 0.0, k_s)
        # minimise P + k_s mean(S) subject to Q ≥ 0 at ω_t and Q ≥ floor at ω and at rest
        res = linprog(
            c=[1.0, mean_s],
            A_ub=-np.vstack(
                [
                    np.column_stack([np.full(q_s.size, g0), q_s]),
                    np.column_stack([np.full(r_s.size, g1), r_s]),
                    np.column_stack([np.full(z_s.size, g2), z_s]),
                ]
            ),
            b_ub=np.concatenate([q_a, r_a - floor, np.full(z_s.size, -floor)]),
            bounds=[(0.0, None), (0.0, None)],
            method="highs",
        )
        if res.status != 0:
            raise DesignError(
                f"--jump-margin={margin:g}: no return spring keeps the follower on the cam"
                f" at {rpm * margin:g} rpm ({res.message})"
            )
        new_p, new_k = float(res.x[0]), float(res.x[1])
        converged = abs(new_k - k_s) <= 1e-9 * max(new_k, 1e-12) and abs(
            new_p - preload
        ) <= 1e-9 * max(new_p, 1e-12)
        preload, k_s = new_p, new_k
        if train.rigid or converged:
            break
    # the programme holds Q ≥ 0 at ω_t exactly: a hair more so that the root lies above it
    preload *= 1.0 + 1e-9
    k_s = max(k_s, 1e-9 * max(preload, 1.0))  # a spring, not a constant force
    proposed = dataclasses.replace(train, spring_rate=k_s, preload=preload)
    jump = jump_speed_rpm(proposed, lift)
    for _ in range(200):
        if jump is None or jump >= rpm * margin * (1.0 - 1e-9):
            break
        proposed = dataclasses.replace(
            proposed, spring_rate=proposed.spring_rate * 1.01, preload=proposed.preload * 1.01
        )
        jump = jump_speed_rpm(proposed, lift)
    return SpringProposal(
        spring_rate=proposed.spring_rate,
        preload=proposed.preload,
        rpm=rpm,
        margin=margin,
        jump_speed_rpm=jump,
        train=proposed,
    )


def size_spring(
    design: CamDesign,
    rpm: float | None,
    margin: float,
    *,
    overrides: Mapping[str, Any] | None = None,
    step_deg: float = 0.1,
) -> SpringProposal:
    """Propose the return spring of a design for a jump margin (``camtol size``).

    Parameters
    ----------
    design : CamDesign
        A force-closed design; its ``[dynamics]`` table (with ``overrides``) gives the
        train's mass, stiffness and damping. Its spring, if any, is replaced.
    rpm : float or None
        Running speed (None: the design's ``operation.speed_rpm``). [rpm]
    margin : float
        Wanted jump speed over the running speed, > 1. [-]
    overrides : mapping of str to object, optional
        ``[dynamics]`` fields given on the command line (file units).
    step_deg : float
        Grid step. [deg]

    Returns
    -------
    SpringProposal

    Raises
    ------
    DesignError
        No speed, a missing mass, a pair, or what :func:`propose_spring` refuses.
    """
    from camtol.dynamics.lift import nominal_lift
    from camtol.dynamics.train import follower_train, train_fields
    from camtol.pair.kinematics import is_pair

    if is_pair(design):
        raise DesignError("--jump-margin: a conjugate pair is form-closed; it has no spring")
    if rpm is None and design.speed_rpm is None:
        raise DesignError(
            "--rpm is missing: --jump-margin needs the running speed (or operation.speed_rpm)"
        )
    values = dict(overrides or {})
    spring = train_fields(design.mechanism.output)[1]
    values[spring] = values.get(spring) or 1.0  # replaced by the proposal
    train = follower_train(design, values)
    speed = rpm if rpm is not None else design.speed_rpm
    assert speed is not None  # checked above
    return propose_spring(train, nominal_lift(design, step_deg), float(speed), margin)
