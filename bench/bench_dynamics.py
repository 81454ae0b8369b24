"""Dynamics at speed (issue 33, THEORY §9): ``python bench/bench_dynamics.py``.

Targets, each against a plain numpy or scipy baseline measured in the same run:

- steady state of an elastic train on roller-translating at 36,001 angles (0.01°: the
  periodic response, contact force, torque, Hertz stress and residual vibration) ≤ 10 ms.
  Baselines: the bare numpy FFT of the same transfer (no checks, no bound, no contact
  geometry), and scipy ``solve_ivp`` run to periodicity (the transient integration the
  frequency domain replaces: one revolution at rtol 1e-8, timed and scaled to the four
  that a damping ratio of 0.05 needs to settle);
- ``jump_speed_rpm`` of that train at 0.01° ≤ 0.2 s. Baseline: the minimum contact force
  swept over speeds in 0.1% steps by plain numpy FFTs up to the same speed;
- 10⁴ Monte Carlo samples of roller-translating's tolerances with dynamics at 0.1°
  (peak and minimum force, residual vibration, a jump-margin check) ≤ 10 s. Baseline: a
  plain numpy steady state per sample (one FFT each), timed on 500 samples and scaled.

Times are wall clock with the thread's CPU time beside (the machine is shared).
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(__file__))
from common import Figure, best_of_both  # noqa: E402

from camtol.config.design_file import load_example
from camtol.dynamics.jump import jump_speed_rpm
from camtol.dynamics.lift import nominal_lift
from camtol.dynamics.montecarlo import column_responses, sample_dynamics, tolerance_columns
from camtol.dynamics.steady import residual_vibration, steady_state
from camtol.dynamics.stress import cam_contacts, camshaft_torque_nm
from camtol.dynamics.train import ContactMaterials, FollowerTrain

RPM = 300.0
TRAIN = FollowerTrain(
    "translating",
    mass=1e-3,
    spring_rate=10.0,
    preload=100.0,
    stiffness=1e4,
    damping_ratio=0.05,
    materials=ContactMaterials(face_width_mm=10.0),
)


def _plain_force(s: np.ndarray, a: np.ndarray, omega: float) -> np.ndarray:
    """The same contact force by a bare numpy FFT (no checks, no bound)."""
    n = s.size
    m, ks, kf, c, p = TRAIN.mass, TRAIN.spring_rate, 1e4, TRAIN.damping, TRAIN.preload
    w = np.arange(n // 2 + 1) * omega
    g = (kf + 1j * c * w) / (kf + ks - m * w * w + 1j * c * w)
    return np.fft.irfft(g * np.fft.rfft(p + ks * s + m * omega * omega * a), n)


def bench_steady() -> list[Figure]:
    d = load_example("roller-translating")
    lift = nominal_lift(d, 0.01)
    omega = RPM * math.pi / 30

    def camtol() -> object:
        s = steady_state(TRAIN, lift, RPM)
        c = cam_contacts(d, lift, TRAIN, s.train_force)
        return (
            s,
            c,
            camshaft_torque_nm(TRAIN, s.train_force, lift.velocity),
            (residual_vibration(TRAIN, lift, s)),
        )

    wall, cpu = best_of_both(camtol, 20)
    s_ = lift.smooth_lift
    a_ = lift.smooth_acceleration
    plain_wall, plain_cpu = best_of_both(lambda: _plain_force(s_, a_, omega), 20)
    q = steady_state(TRAIN, lift, RPM).train_force
    assert np.max(np.abs(q - _plain_force(s_, a_, omega))) < 1e-9 * np.max(q)
    # the transient integration it replaces: scipy from rest, to periodicity
    h = 2 * math.pi / lift.angles
    kf, c = 1e4, TRAIN.damping

    v_ = lift.velocity

    def ivp() -> object:  # one revolution; periodicity needs four (ζ = 0.05): scaled below
        def rhs(t: float, z: np.ndarray) -> list[float]:
            u = (t % (2 * math.pi)) / h
            i = int(u) % lift.angles
            f_ = u - int(u)
            j = (i + 1) % lift.angles
            y = s_[i] + f_ * (s_[j] - s_[i])
            dy = v_[i] + f_ * (v_[j] - v_[i])
            f = kf * (y - z[0]) + c * omega * (dy - z[1])
            return [z[1], (f - TRAIN.spring_rate * z[0] - TRAIN.preload) / (TRAIN.mass * omega**2)]

        return solve_ivp(rhs, (0.0, 2 * math.pi), [-0.01, 0.0], rtol=1e-8, atol=1e-12)

    ivp_wall = 4 * best_of_both(ivp, 1)[0]
    print(f"steady state, 36,001 angles: camtol {wall * 1e3:.2f} ms (CPU {cpu * 1e3:.2f} ms)")
    print(f"  bare numpy FFT of the same transfer: {plain_wall * 1e3:.2f} ms")
    print(f"  scipy solve_ivp to periodicity (4 rev, from 1 timed): {ivp_wall:.2f} s")
    return [
        Figure("steady state at 36,001 angles (all outputs)", wall * 1e3, "ms", 10.0),
        Figure("  same, CPU time", cpu * 1e3, "ms", 10.0),
        Figure("  / bare numpy FFT of the force alone", wall / plain_wall, "x", 20.0),
        Figure("  solve_ivp to periodicity / camtol", ivp_wall / wall, "x", 10.0, True),
    ]


def bench_jump() -> list[Figure]:
    d = load_example("roller-translating")
    lift = nominal_lift(d, 0.01)
    wall, cpu = best_of_both(lambda: jump_speed_rpm(TRAIN, lift), 3)
    jump = jump_speed_rpm(TRAIN, lift)
    assert jump is not None

    def sweep() -> float:
        s_, a_ = lift.smooth_lift, lift.smooth_acceleration
        rpm = 0.05 * jump
        while rpm <= jump * 1.001:
            if np.min(_plain_force(s_, a_, rpm * math.pi / 30)) < 0:
                return rpm
            rpm *= 1.001
        return rpm

    sweep_wall, _ = best_of_both(sweep, 1)
    found = sweep()
    assert abs(found / jump - 1) < 2e-3, (found, jump)
    print(f"jump speed {jump:.6g} rpm: camtol {wall:.3f} s (CPU {cpu:.3f} s)")
    print(f"  plain numpy sweep in 0.1% steps: {sweep_wall:.2f} s (finds {found:.6g} rpm)")
    return [
        Figure("jump_speed_rpm at 0.01°", wall, "s", 0.2),
        Figure("  same, CPU time", cpu, "s", 0.2),
        Figure("  plain 0.1% sweep / camtol", sweep_wall / wall, "x", 1.0, True),
    ]


def bench_montecarlo() -> list[Figure]:
    d = load_example("roller-translating")
    labels, ds, da, dev = tolerance_columns(d, 0.1)
    rows = np.random.default_rng(1).uniform(-1, 1, (10_000, len(labels))) * np.array(dev)

    def camtol() -> object:
        resp = column_responses(d, TRAIN, RPM, labels, ds, da, step_deg=0.1, jump_margin=1.3)
        return sample_dynamics(resp, rows, force_min_spec_n=50.0)

    wall, cpu = best_of_both(camtol, 2)
    out = camtol()
    lift = nominal_lift(d, 0.1)
    omega = RPM * math.pi / 30

    def plain(k: int) -> np.ndarray:
        peaks = np.empty(k)
        for i in range(k):
            s = lift.smooth_lift + ds @ rows[i]
            a = lift.smooth_acceleration + da @ rows[i]
            peaks[i] = _plain_force(s, a, omega).max()
        return peaks

    k = 500
    plain_wall, _ = best_of_both(lambda: plain(k), 1)
    scaled = plain_wall * 10_000 / k
    factor = np.abs(cam_contacts(d, lift, TRAIN, np.ones(lift.angles))[0].normal_factor)
    for i in range(3):  # the same peak force, sample by sample
        s = lift.smooth_lift + ds @ rows[i]
        a = lift.smooth_acceleration + da @ rows[i]
        peak = float(np.max(_plain_force(s, a, omega) * factor))
        assert abs(peak - out.peak_force_n[i]) < 1e-9 * peak, (peak, out.peak_force_n[i])
    print(f"Monte Carlo 10^4 samples at 0.1° with dynamics: camtol {wall:.2f} s (CPU {cpu:.2f} s)")
    print(f"  plain numpy FFT per sample (peak force only): {scaled:.1f} s (from {k})")
    return [
        Figure("10^4 Monte Carlo samples with dynamics", wall, "s", 10.0),
        Figure("  same, CPU time", cpu, "s", 10.0),
        Figure("  plain per-sample FFT / camtol", scaled / wall, "x", 1.0, True),
    ]


def main() -> list[Figure]:
    """Run the dynamics benchmarks and return their figures."""
    figures = bench_steady() + bench_jump() + bench_montecarlo()
    for f in figures:
        print(f.line())
    return figures


if __name__ == "__main__":
    main()
