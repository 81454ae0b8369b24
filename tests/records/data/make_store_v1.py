"""Write ``store-v1.db``: an inspection store of schema version 1, as camtol made it.

The file is the fixture of tests/records/test_migrations.py (an old store upgraded by
Alembic on open). It was written by camtol at commit bcb84ab (the last one with schema
version 1, before issue 29), with that checkout's ``src`` first on the path::

    git archive bcb84ab src | tar -x -C /tmp/v1
    PYTHONPATH=/tmp/v1/src python tests/records/data/make_store_v1.py tests/records/data/store-v1.db

Six records: the fixture's cams A and B of two parts (``--df-mea``, 1° grid), one CMM
inspection of cam B (a simulated scan, 1° grid) and one record made through the Python
API without a design text.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.records.store import SCHEMA_VERSION, Traceability, record_inspection


def make(out: Path) -> None:
    assert SCHEMA_VERSION == 1, "run with camtol at commit bcb84ab (schema version 1)"
    out.unlink(missing_ok=True)
    url = str(out)
    trace = ["--lot", "L1", "--part", "CAM-7", "--inspector", "ana"]
    for serial, df in (("1", "20"), ("2", "21 + 2*sin(theta)")):
        args = ["conjugate", "-e", "cw11-conjugate", "--df-mea", df, "--step", "1", "-q"]
        at = f"2026-11-2{serial}T08:00:00Z"
        code = main([*args, "--store", url, "--serial", serial, *trace, "--inspected-at", at])
        assert code in (0, 1)
    with tempfile.TemporaryDirectory() as tmp:
        scan = Path(tmp) / "b.csv"
        sim = ["simulate", "cmm", "-e", "cw11-experiment", "-o", str(scan), "--cam", "B"]
        assert main([*sim, "--seed", "2", "--noise-um", "0.5", "--error-rms-um", "5"]) == 0
        args = ["inspect", "-e", "cw11-experiment", "--points", str(scan), "--cam", "B"]
        args += ["--step", "1", "-q", "--store", url, "--serial", "3", "--lot", "L1"]
        assert main([*args, "--inspected-at", "2026-11-23T08:00:00Z"]) in (0, 1)
    theta = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)
    record_inspection(
        url,
        load_example("roller-translating"),
        method="cmm",
        cam="",
        dr_um=4.0 * np.sin(theta),
        verdict="pass",
        tolerance_um=(-10.0, 10.0),
        traceability=Traceability(serial="4", lot="L2"),
    )


if __name__ == "__main__":
    make(Path(sys.argv[1]))
