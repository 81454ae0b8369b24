"""Benchmark of reading a long dial-indicator record (THEORY §4.4; issue 9 item 13).

Run ``python bench/bench_record.py [ROWS]`` (default 10,000,000 rows, about 0.3 GB of
CSV: ``time_s, df_um, index`` as :func:`camtol.inspection.write_indicator_csv` writes
them). Each reader runs in a fresh Python process so that its peak memory (maximum
resident set size) is its own:

* ``camtol``: :func:`camtol.inspection.read_indicator_csv` (the shared table reader,
  validation of every column, index marks and revolutions) then
  :func:`camtol.inspection.process_record` at 0.1°;
* ``baseline``: a plain :func:`numpy.loadtxt` of the same file (no validation), the
  fair floor of a vectorised reader.

Targets (issue 9 item 13: before, 66-81 s and 2.7-3.7 GB): read and process 10 million
rows in ≤ 10 s wall with a peak resident memory ≤ 1 GiB.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import Figure, print_figures  # noqa: E402

TARGET_S = 10.0
TARGET_MIB = 1024.0
SAMPLES_PER_REV = 4500

_CHILD = r"""
import json, resource, sys, time
t = time.perf_counter()
if sys.argv[1] == "camtol":
    from camtol.pair.indicator import process_record, read_indicator_csv
    rec = read_indicator_csv(sys.argv[2])
    p = process_record(rec)
    rows = rec.df_um.size
else:
    import numpy as np
    rows = np.loadtxt(sys.argv[2], delimiter=",", skiprows=2, ndmin=2).shape[0]
wall = time.perf_counter() - t
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps({"rows": rows, "wall_s": wall, "peak_mib": peak}))
"""


def write_record(path: Path, rows: int) -> None:
    """Write a record of ``rows`` samples (one index mark every 4,500 samples)."""
    rng = np.random.default_rng(0)
    k = np.arange(rows)
    theta = 2 * np.pi * (k % SAMPLES_PER_REV) / SAMPLES_PER_REV
    df = 22.0 + 3.0 * np.sin(theta) + rng.normal(0.0, 0.5, rows)
    with path.open("w") as fh:
        fh.write("# camtol bench record\ntime_s,df_um,index\n")
        chunk = 1_000_000
        for a in range(0, rows, chunk):
            b = min(rows, a + chunk)
            block = np.column_stack([k[a:b] / 5.0, df[a:b], (k[a:b] % SAMPLES_PER_REV) == 0])
            np.savetxt(fh, block, fmt=["%.1f", "%.6f", "%d"], delimiter=",")


def run(kind: str, path: Path) -> dict[str, float]:
    out = subprocess.run(
        [sys.executable, "-c", _CHILD, kind, str(path)],
        check=True,
        capture_output=True,
        text=True,
    )
    return dict(json.loads(out.stdout))


def main(rows: int | None = None) -> list[Figure]:
    """Run the benchmark, print its table, return its figures."""
    if rows is None:
        rows = int(sys.argv[1]) if len(sys.argv) > 1 and sys.argv[1].isdigit() else 10_000_000
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "record.csv"
        t = time.perf_counter()
        write_record(path, rows)
        wrote_s = time.perf_counter() - t
        size_mib = path.stat().st_size / 2**20
        print(f"record: {rows:,} rows, {size_mib:.0f} MiB (written in {wrote_s:.1f} s)")
        base = run("baseline", path)
        cam = run("camtol", path)
    print(f"  plain np.loadtxt   : {base['wall_s']:6.2f} s, peak {base['peak_mib']:6.0f} MiB")
    print(f"  camtol read+process: {cam['wall_s']:6.2f} s, peak {cam['peak_mib']:6.0f} MiB")
    print(
        f"  ratio camtol / plain loadtxt: time {cam['wall_s'] / base['wall_s']:.2f}×,"
        f" memory {cam['peak_mib'] / base['peak_mib']:.2f}×"
    )
    print(f"load average while measuring: {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    note = f"{rows:,} rows"
    figures = [
        Figure("indicator record read+process, wall", cam["wall_s"], "s", TARGET_S, note=note),
        Figure("indicator record read+process, peak RSS", cam["peak_mib"], "MiB", TARGET_MIB),
    ]
    print_figures("indicator record (bench_record.py)", figures)
    return figures


if __name__ == "__main__":
    main()
