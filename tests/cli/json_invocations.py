"""Invocations whose ``--json`` output tests/cli/test_json_schemas.py validates (issue 13 item 6).

Each command with a ``--json`` flag needs at least one entry here and a schema file
``src/camtol/data/schemas/<command>.schema.json`` (a subcommand ``records list``:
``records-list.schema.json``). ``{tmp}`` is a scratch directory, ``{scan}`` a simulated CMM
scan of cam B of cw11-experiment, ``{band}`` a tolerance band (theta_deg, lower_um,
upper_um) and ``{store}`` an inspection store holding two CMM records of that scan and a
fixture record of cams A and B.
"""

from __future__ import annotations

INVOCATIONS: dict[str, list[list[str]]] = {
    "montecarlo": [
        ["montecarlo", "-e", "cw06-translating", "--samples", "2000", "--spec-um", "25", "--json"],
        ["montecarlo", "-e", "roller-translating", "--samples", "50", "--mode", "exact", "--json"],
        ["montecarlo", "-e", "cw06-translating", "--samples", "2000", "--band", "{band}", "--json"],
        ["montecarlo", "-e", "popa-eccentric", "--samples", "500", "--dynamics", "--rpm"]
        + ["600", "--mass-kg", "0.5", "--spring-rate-n-per-mm", "10", "--preload-n", "50"]
        + ["--force-min-n", "55", "--json"],  # every sample at speed (issue 33)
        ["montecarlo", "-e", "cw06-translating", "--samples", "1000", "--sobol", "64", "--json"],
        [  # a conjugate pair as a pair, with its pair yield
            "montecarlo",
            "-e",
            "cw11-conjugate",
            "--samples",
            "2000",
            "--interference-max-um",
            "30",
            "--backlash-max-um",
            "30",
            "--json",
        ],
    ],
    "allocate": [
        ["allocate", "-e", "cw06-translating", "--spec-um", "30", "--json"],
        [
            "allocate",
            "-e",
            "cw06-oscillating",
            "--spec-deg",
            "0.05",
            "--criterion",
            "rss",
            "--json",
        ],
        ["allocate", "-e", "cw06-translating", "--band", "{band}", "--json"],
        ["allocate", "-e", "cw11-conjugate", "--criterion", "pair_yield"]
        + ["--interference-max-um", "200", "--backlash-max-um", "200", "--samples", "500"]
        + ["--json"],
    ],
    "analyze": [
        ["analyze", "-e", "cw06-translating", "--step", "0.5", "--json"],
        ["analyze", "-e", "cw06-oscillating", "--step", "0.5", "--json"],
        ["analyze", "-e", "roller-translating", "--step", "0.5", "--json"],
        ["analyze", "-e", "roller-oscillating", "--step", "0.5", "--json"],
        ["analyze", "-e", "cw11-conjugate", "--step", "0.5", "--json"],
        ["analyze", "-e", "popa-eccentric", "--step", "0.5", "--json"],
        ["analyze", "-e", "cw11-experiment", "--step", "0.5", "--json"],  # no tolerances
    ],
    "conjugate": [
        ["conjugate", "-e", "cw11-conjugate", "--step", "0.5", "--json"],
        ["conjugate", "-e", "cw11-experiment", "--step", "0.5", "--json"],
    ],
    "profile": [
        ["profile", "-e", "roller-translating", "-o", "{tmp}/p.csv", "--json"],
        ["profile", "-e", "cw11-conjugate", "-o", "{tmp}/p.dxf", "--json"],
        ["profile", "-e", "cw06-translating", "-o", "{tmp}/p.nc", "--cutter-radius", "5"]
        + ["--feed", "300", "--json"],  # a G-code program, 2D
        ["profile", "-e", "cw11-conjugate", "-o", "{tmp}/p.ngc", "--cutter-radius", "4"]
        + ["--feed", "300", "--safe-z", "5", "--cut-z", "-3", "--plunge-feed", "40", "--json"],
    ],
    "report": [["report", "-e", "cw06-translating", "-o", "{tmp}/r.html", "--json"]],
    "verify": [
        ["verify", "-e", "cw06-translating", "--step", "0.5", "--json"],
        ["verify", "-e", "cw11-conjugate", "--step", "0.5", "--json", "--no-polyline"],
        ["verify", "-e", "cw11-conjugate", "--step", "1", "--json"],  # polyline_b
    ],
    "size": [
        ["size", "-e", "roller-translating", "--json"],
        ["size", "-e", "cw06-translating", "--json"],
        ["size", "-e", "roller-translating", "--jump-margin", "1.3", "--mass-kg", "0.5", "--json"],
        ["size", "-e", "roller-oscillating", "--linkage", "pivot", "--json"],
        ["size", "-e", "cw11-conjugate", "--linkage", "scale", "--json"],
    ],
    "precision": [
        ["precision", "-e", "roller-translating", "--decimals", "4", "--json"],
        ["precision", "-e", "popa-eccentric", "--accel-budget", "1", "--json"],
        ["precision", "{turning}", "--decimals", "4", "--json"],  # quantum_deg, deg_per_s
    ],
    "dynamics": [  # the fixed keys of issue 33: rigid, elastic above its jump, oscillating
        ["dynamics", "-e", "popa-eccentric", "--rpm", "1200", "--mass-kg", "1"]
        + ["--spring-rate-n-per-mm", "10", "--preload-n", "100", "--json"],
        ["dynamics", "-e", "roller-translating", "--rpm", "1300", "--mass-kg", "1"]
        + ["--spring-rate-n-per-mm", "10", "--preload-n", "100", "--face-width-mm", "10"]
        + ["--follower-stiffness-n-per-mm", "1e4", "--json"],
        ["dynamics", "-e", "roller-oscillating", "--rpm", "1000", "--inertia-kg-mm2", "3000"]
        + ["--spring-rate-nm-per-rad", "20", "--preload-nm", "2", "--json"],
    ],
    "cut": [
        ["cut", "-e", "popa-eccentric", "--cut-step", "1,5", "--json"],
        ["cut", "-e", "cw11-conjugate", "--cut-step", "1", "--json"],  # cam "A", degrees
        ["cut", "-e", "popa-eccentric", "--cut-step", "1,2", "--lift-tolerance-um", "3"]
        + ["--json"],  # the recommendation among the listed steps
    ],
    "derive": [
        ["derive", "{tmp}/lift.csv", "--json"],
        ["derive", "{tmp}/lift_deg.csv", "--json"],  # an oscillating follower's lift
    ],
    "inspect": [
        [
            "inspect",
            "-e",
            "cw11-experiment",
            "--points",
            "{scan}",
            "--cam",
            "B",
            "--stylus-radius-mm",
            "1",
            "--json",
        ]
    ],
    "records list": [
        ["records", "list", "--store", "{store}", "--json"],
        ["records", "list", "--store", "{store}", "--method", "cmm", "--json"],
    ],
    "records show": [["records", "show", "1", "--store", "{store}", "--json"]],
    "records rerun": [  # a CMM record and a fixture record, judged again from their raw data
        ["records", "rerun", rid, "--store", "{store}", "--json"] for rid in ("1", "4")
    ],
    "records stats": [  # cam A has one record: a lot of one is refused (no σ)
        ["records", "stats", "--store", "{store}", "--design", "cw11-experiment", "--json"]
        + ["--cam", "B", "--method", "cmm", *extra]
        for extra in ([], ["--characteristic", "form", "--rules", "nelson"])
    ],
}


def prepare(tmp: str) -> dict[str, str]:
    """Write the input files the invocations read; return the ``{name}`` substitutions."""
    import math
    from pathlib import Path

    from camtol.cli.app import main

    lift = Path(tmp) / "lift.csv"
    rows = "\n".join(f"{t:g},{5 * (1 - math.cos(math.radians(t))):.6f}" for t in range(0, 360))
    lift.write_text("theta_deg,lift_mm\n" + rows + "\n")
    (Path(tmp) / "lift_deg.csv").write_text("theta_deg,lift_deg\n" + rows + "\n")
    scan = Path(tmp) / "b.csv"
    args = ["simulate", "cmm", "-e", "cw11-experiment", "-o", str(scan), "--cam", "B"]
    assert main([*args, "--noise-um", "1", "--seed", "3", "--stylus-radius-mm", "1"]) == 0
    band = Path(tmp) / "band.csv"
    band.write_text("theta_deg,lower_um,upper_um\n0,-25,40\n180,-30,30\n")
    from camtol.config.design_file import example_text

    turning = Path(tmp) / "turning.toml"  # an oscillating follower with a cam speed
    raw = example_text("roller-oscillating").replace(
        "[operation]\n", "[operation]\nspeed_rpm = 300\n"
    )
    turning.write_text(raw)
    subs = {"tmp": tmp, "scan": str(scan), "band": str(band), "turning": str(turning)}
    store = Path(tmp) / "records.db"
    subs["store"] = str(store)
    try:
        import sqlalchemy  # noqa: F401
    except ImportError:  # the records invocations are skipped without camtol[store]
        return subs
    for serial in ("1", "2"):  # two CMM records of cam B and a fixture record of A and B
        insp = ["inspect", "-e", "cw11-experiment", "--points", str(scan), "--cam", "B"]
        opts = ["--stylus-radius-mm", "1", "--store", str(store), "--serial", serial, "-q"]
        assert main([*insp, *opts, "--lot", "L1"]) in (0, 1)
    fixture = ["conjugate", "-e", "cw11-experiment", "--df-mea", "20", "--step", "1", "-q"]
    fixture += ["--store", str(store)]
    assert main([*fixture, "--serial", "3", "--lot", "L1"]) in (0, 1)
    return subs
