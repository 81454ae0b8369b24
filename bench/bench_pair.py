"""Benchmark of a conjugate pair toleranced as a pair (issue 28, docs/tolerancing.md).

Run ``python bench/bench_pair.py [SAMPLES]`` (default 100,000 pairs of cw11-conjugate at
3,600 angles, linear mode):

* ``pair``: :func:`camtol.tolerancing.pair.pair_monte_carlo` whole (preparation,
  deterministic per-angle distributions of Δf, ΔS_A, ΔS_B, and the sampled maxima,
  interference, backlash and both cams' fixture verdicts), target ≤ 10 s;
* ``plain numpy``: the same sampled work written directly in numpy in the same run (the
  sensitivity matrices given: three matrix products per block of rows, each row's maxima,
  the fixture readings and their band check), the floor the library is compared with;
* ``distributions``: the deterministic per-angle distribution of one output (Δf) at
  3,600 angles, target ≤ 0.5 s.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, best_of, print_figures  # noqa: E402


def main(samples: int = 100_000) -> list[Figure]:
    from camtol.config import load_example
    from camtol.tolerancing.convolution import angle_distributions
    from camtol.tolerancing.pair import pair_monte_carlo, prepare_pair
    from camtol.tolerancing.plan import CHUNK, chunk_uniforms

    design = load_example("cw11-conjugate")
    study = prepare_pair(design, step_deg=0.1)
    plan = study.plan
    assert study.bands is not None

    def library() -> object:
        return pair_monte_carlo(
            design, samples, interference_max_mm=0.03, backlash_max_mm=0.03, step_deg=0.1
        )

    # the floor: the same per-sample work, the matrices given, in plain numpy
    ga, gb, gdf = study.motion["A"].T, study.motion["B"].T, study.df.T
    fixture = []
    for letter, (r0, r1, at) in study.readings.items():
        up, lo = study.bands.band_um(letter)
        fixture.append((r0, r1.T, (up[at], lo[at])))
    centre = study.centre_column

    def plain() -> object:
        out = np.empty((samples, 4))
        for c in range(-(-samples // CHUNK)):
            size = min(CHUNK, samples - c * CHUNK)
            x_all = plan.sample(chunk_uniforms(0, c, size, plan.uniforms))
            for a in range(0, size, 1024):
                x = x_all[a : a + 1024]
                rows = slice(c * CHUNK + a, c * CHUNK + a + x.shape[0])
                ya, yb = x @ ga, x @ gb
                out[rows, 0] = np.maximum(ya.max(1), -ya.min(1))
                out[rows, 1] = np.maximum(yb.max(1), -yb.min(1))
                df = x @ gdf
                if centre is not None:
                    df -= x[:, centre][:, None]
                out[rows, 2] = df.max(1) - df.min(1)
                ok = np.ones(x.shape[0], bool)
                for r0, r1, (up, lo) in fixture:
                    reading = x @ r1 + r0
                    ok &= ((reading >= lo) & (reading <= up)).all(axis=1)
                out[rows, 3] = ok
        return out

    t_lib = best_of(library, 1)
    t_plain = best_of(plain, 1)
    t_dist = best_of(lambda: angle_distributions(study.df, plan), 3)
    figures = [
        Figure(f"pair Monte Carlo, {samples:,} pairs × 3,600 angles", t_lib, "s", 10.0),
        Figure("pair Monte Carlo / plain numpy of its sampled work", t_lib / t_plain, "x", 3.0),
        Figure("deterministic distribution of Δf, 3,600 angles", t_dist, "s", 0.5),
    ]
    print_figures(f"conjugate pair (plain numpy {t_plain:.2f} s)", figures)
    return figures


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
