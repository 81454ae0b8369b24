"""Benchmark of the manufacturing checks (issue 10, THEORY §6).

Run ``python bench/bench_manufacturing.py``. Targets:

- cutting simulation: a cylindrical tool (R = 5 mm) set every 1° on a cam whose design is a
  3,600-entry lift table (CW06 Example 1 tabulated every 0.1°, flat translating follower),
  the exact lift read every 0.05° (7,200 readings): ≤ 0.2 s. Baseline in the same run: the
  same readings by brute-force support over every vertex and arc, O(N·M).
- table precision for four decimals (Popa's eccentric cam, 1° table): ≤ 50 ms. Baseline:
  the same central differences in a plain Python loop over the table (a spreadsheet).
- G-code biarcs at 1 µm for CW06 Example 1 (R = 5 mm): ≤ 0.5 s. Baseline: G01 chords at the
  same tolerance (time and number of blocks).
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from camtol.config.design_file import design_from_mapping, load_example
from camtol.manufacturing.cutting import cut_cam, simulate_cut
from camtol.manufacturing.gcode import write_gcode
from camtol.manufacturing.precision import table_precision


def best_of(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def table_design() -> Any:
    d = load_example("cw06-translating")
    theta = np.arange(3600) * (2 * math.pi / 3600)
    lift = d.program.evaluate(theta).lift
    m = d.mechanism
    return design_from_mapping(
        {
            "name": "cw06-table-3600",
            "follower": {
                "type": "flat_translating",
                "base_radius_mm": m.base_radius_mm,  # type: ignore[attr-defined]
                "offset_mm": m.offset_mm,  # type: ignore[attr-defined]
                "face_angle_deg": math.degrees(m.face_angle_rad),  # type: ignore[attr-defined]
            },
            "motion": {"table_step_deg": 0.1, "table_lift_mm": lift.tolist()},
        }
    )


def main() -> int:
    ok = True
    # --- cutting simulation -------------------------------------------------------------
    d = table_design()
    d.program.evaluate(np.zeros(1))  # build the spline outside the timing
    t_cut, res = best_of(
        lambda: simulate_cut(d, 1.0, tool="cylinder", tool_radius_mm=5.0, read_step_deg=0.05), 5
    )
    shape = cut_cam(d, 1.0, tool="cylinder", tool_radius_mm=5.0).shape
    psi = res.theta_rad + d.mechanism.face_angle_rad  # type: ignore[attr-defined]
    t_brute, brute = best_of(lambda: shape.support_bruteforce(psi), 1)
    fast = shape.support(psi)
    diff = float(np.max(np.abs(fast.h_mm - brute.h_mm)))
    print("cutting simulation: cylinder R = 5 mm every 1°, 3,600-entry lift-table cam,")
    print(f"  exact lift at 0.05° ({res.theta_rad.size} readings, {shape.size} arcs)")
    print(f"  camtol cut + follow + scallops: {t_cut * 1e3:8.1f} ms  (target <= 200 ms)")
    print(
        f"  brute-force support alone:      {t_brute * 1e3:8.1f} ms  ratio {t_brute / t_cut:.1f} x"
    )
    print(f"  max |sweep - brute| support:    {diff:.2e} mm")
    ok &= t_cut <= 0.2
    # Informational: roller followers need the true distance to the arcs (contact engine's
    # windowed O(pairs) solver), not a hull.
    for name in ("roller-translating", "roller-oscillating"):
        rd = load_example(name)
        t_r, _ = best_of(
            lambda: simulate_cut(rd, 1.0, tool="cylinder", tool_radius_mm=5.0, read_step_deg=0.05),  # noqa: B023
            2,
        )
        print(f"  {name} (informational, same cut and reading): {t_r * 1e3:8.1f} ms")
    # --- table precision ----------------------------------------------------------------
    pe = load_example("popa-eccentric")
    t_prec, st = best_of(lambda: table_precision(pe, decimals=[3, 4, 5, 6]), 7)

    def spreadsheet() -> float:
        h = math.radians(1.0)
        worst = 0.0
        for k in (3, 4, 5, 6):
            y = [round(5.0 * (1 - math.cos(i * h)), k) for i in range(360)]
            for i in range(360):
                a = (y[i - 1] + y[(i + 1) % 360] - 2 * y[i]) / h**2
                worst = max(worst, abs(a - 5.0 * math.cos(i * h)))
        return worst

    t_sheet, worst = best_of(spreadsheet, 3)
    assert abs(worst - st.rows[0].max_abs_dA_central) < 1e-9
    print("table precision: popa-eccentric, 1° table, 4 decimals (central differences + spline)")
    print(f"  camtol:                    {t_prec * 1e3:8.2f} ms  (target <= 50 ms)")
    print(f"  plain Python loop (c.d.):  {t_sheet * 1e3:8.2f} ms  (central differences only)")
    ok &= t_prec <= 0.05
    # --- G-code ---------------------------------------------------------------------------
    cw = load_example("cw06-translating")
    t_arcs, arcs = best_of(
        lambda: write_gcode(cw, feed_mm_min=200.0, tool_radius_mm=5.0, tolerance_mm=1e-3), 3
    )
    t_lines, lines = best_of(
        lambda: write_gcode(
            cw, feed_mm_min=200.0, tool_radius_mm=5.0, tolerance_mm=1e-3, mode="lines"
        ),
        3,
    )
    print("G-code: cw06-translating, cutter R = 5 mm, tolerance 1 µm")
    print(
        f"  biarcs (G02/G03): {t_arcs * 1e3:8.1f} ms, {arcs.blocks:6d} blocks  (target <= 500 ms)"
    )
    print(f"  chords (G01):     {t_lines * 1e3:8.1f} ms, {lines.blocks:6d} blocks")
    print(f"  blocks ratio:     {lines.blocks / arcs.blocks:8.1f} x fewer with biarcs")
    ok &= t_arcs <= 0.5
    print("all targets met" if ok else "TARGET MISSED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
