"""`camtol dynamics`: the fixed --json keys and --curves columns, and bad input (issue 33)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from camtol.cli.app import main

TRAIN = ["--mass-kg", "1", "--spring-rate-n-per-mm", "10", "--preload-n", "100"]
KEYS = [
    "schema_version",
    "command",
    "camtol_version",
    "rpm",
    "contact_force_min_n",
    "contact_force_min_at_deg",
    "contact_force_max_n",
    "jump_speed_rpm",
    "torque_min_nm",
    "torque_max_nm",
    "hertz_stress_max_mpa",
    "residual_vibration_um",
    "separation",
]
COLUMNS = [
    "theta_deg",
    "lift_mm",
    "mass_mm",
    "dynamic_error_um",
    "contact_force_n",
    "torque_nm",
    "hertz_stress_mpa",
]


def _json(args: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    assert main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)  # type: ignore[no-any-return]


def test_popa_json_is_the_closed_form(capsys: pytest.CaptureFixture[str]) -> None:
    # rigid: F = F0 + k_s s + m s̈; jump at √((F0 + 2 k_s e)/(m e)) = 1909.859 rpm
    doc = _json(["dynamics", "-e", "popa-eccentric", "--rpm", "1200", *TRAIN], capsys)
    assert list(doc) == KEYS
    w2 = (1200 * 3.141592653589793 / 30) ** 2
    assert doc["contact_force_min_n"] == pytest.approx(100 + 100 - 1e-3 * w2 * 5, rel=1e-6)
    assert doc["contact_force_min_at_deg"] == 180.0
    assert doc["contact_force_max_n"] == pytest.approx(100 + 1e-3 * w2 * 5, rel=1e-6)
    assert doc["jump_speed_rpm"] == pytest.approx(1909.859317, rel=1e-6)
    assert doc["residual_vibration_um"] is None  # no dwell
    assert doc["separation"] == [] and doc["hertz_stress_max_mpa"] is None


def test_oscillating_keys_and_separations(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    args = ["dynamics", "-e", "roller-oscillating", "--inertia-kg-mm2", "3000"]
    args += ["--spring-rate-nm-per-rad", "20", "--preload-nm", "2", "--face-width-mm", "10"]
    doc = _json([*args, "--rpm", "300"], capsys)
    assert "residual_vibration_deg" in doc and "residual_vibration_um" not in doc
    jump = doc["jump_speed_rpm"]
    assert isinstance(jump, float)
    above = _json([*args, "--rpm", str(1.5 * jump)], capsys)
    seps = above["separation"]
    assert isinstance(seps, list) and seps
    assert set(seps[0]) == {"start_deg", "end_deg", "impact_velocity_deg_per_s"}
    curves = tmp_path / "c.csv"
    assert main([*args, "--rpm", "300", "--curves", str(curves)]) == 0
    lines = curves.read_text().splitlines()
    header = next(r for r in csv.reader(lines) if not r[0].startswith("#"))
    assert header == ["theta_deg", "lift_deg", "mass_deg", "dynamic_error_deg"] + COLUMNS[4:]


def test_curves_columns_and_plot(tmp_path: Path) -> None:
    curves, plot = tmp_path / "c.csv", tmp_path / "p.png"
    args = ["dynamics", "-e", "roller-translating", *TRAIN, "--follower-stiffness-n-per-mm"]
    args += ["1e4", "--face-width-mm", "10", "--curves", str(curves), "--plot", str(plot)]
    assert main(args) == 0
    rows = [r for r in csv.reader(curves.read_text().splitlines()) if not r[0].startswith("#")]
    assert rows[0] == COLUMNS
    assert len(rows) == 3602 and rows[1][0] == "0" and rows[-1][0] == "360"
    assert plot.stat().st_size > 10_000


def test_the_cut_and_the_scan(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    stiff = [*TRAIN, "--follower-stiffness-n-per-mm", "1e4"]
    cut = _json(
        ["dynamics", "-e", "popa-eccentric", "--rpm", "1200", *stiff, "--cut-step", "2"], capsys
    )
    nominal = _json(["dynamics", "-e", "popa-eccentric", "--rpm", "1200", *stiff], capsys)
    assert cut["contact_force_max_n"] != nominal["contact_force_max_n"]
    scan = tmp_path / "s.csv"
    assert (
        main(["simulate", "cmm", "-e", "popa-eccentric", "-o", str(scan), "--noise-um", "0"]) == 0
    )
    capsys.readouterr()
    made = _json(
        ["dynamics", "-e", "popa-eccentric", "--rpm", "1200", *TRAIN, "--points", str(scan)], capsys
    )
    rigid = _json(["dynamics", "-e", "popa-eccentric", "--rpm", "1200", *TRAIN], capsys)
    assert made["contact_force_min_n"] == pytest.approx(rigid["contact_force_min_n"], rel=1e-4)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--mass-kg", "0"], "--mass-kg=0 is not allowed; give a number > 0 in kg"),
        (["--mass-kg", "-2"], "--mass-kg=-2 is not allowed"),
        (["--follower-stiffness-n-per-mm", "0"], "--follower-stiffness-n-per-mm=0 is not allowed"),
        (["--spring-rate-n-per-mm", "0"], "--spring-rate-n-per-mm=0 is not allowed"),
        (["--rpm", "0"], "--rpm=0 is not allowed; give a number > 0 in rpm"),
        (["--rpm", "-100"], "--rpm=-100 is not allowed"),
        (["--damping-ratio", "2"], "--damping-ratio=2 is not allowed; give a number ≥ 0 and < 2"),
        (["--damping-ratio", "-0.1"], "--damping-ratio=-0.1 is not allowed"),
        (["--inertia-kg-mm2", "5"], "dynamics.inertia_kg_mm2 does not apply to a"),
        (["--cut-step", "2"], "dynamics.follower_stiffness_n_per_mm is missing"),
        (["--step", "0.7"], "--step=0.7 is not allowed"),
        (
            ["--follower-stiffness-n-per-mm", "1e6", "--rpm", "100", "--step", "0.5"],
            "harmonic .* beyond the .* 0.5° grid resolves .*use --step 0.01 or finer",
        ),
        (["--cut-step", "2", "--points", "x.csv"], "--cut-step and --points"),
    ],
)
def test_bad_input_is_one_line_exit_2_and_nothing_written(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    import re

    curves = tmp_path / "c.csv"
    base = [
        "dynamics",
        "-e",
        "roller-translating",
        "--mass-kg",
        "1",
        "--spring-rate-n-per-mm",
        "10",
        "--preload-n",
        "100",
        "--curves",
        str(curves),
    ]
    assert main([*base, *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert re.search(message, err), err
    assert not curves.exists()


def test_no_speed_and_no_mass_are_named(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["dynamics", "-e", "popa-eccentric", *TRAIN]) == 2
    assert "--rpm is missing" in capsys.readouterr().err
    assert main(["dynamics", "-e", "roller-translating"]) == 2
    assert "dynamics.mass_kg is missing" in capsys.readouterr().err


def test_a_table_the_design_cannot_take(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from camtol.config.design_file import example_text

    for name, table, message in [
        ("cw06-oscillating", "mass_kg = 1\n", "dynamics.mass_kg does not apply to a"),
        (
            "cw11-conjugate",
            "inertia_kg_mm2 = 1\nfollower_stiffness_nm_per_rad = 5\n",
            "form-closed",
        ),
        ("roller-oscillating", "inertia_kg_mm2 = 1\ngravity = true\n", "dynamics.gravity"),
        ("popa-eccentric", "mass_kg = -1\n", r"dynamics.mass_kg=-1"),
    ]:
        f = tmp_path / f"{name}.toml"
        f.write_text(example_text(name) + "\n[dynamics]\n" + table)
        assert main(["dynamics", str(f), "--rpm", "100"]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err


def test_report_gains_a_dynamics_section(tmp_path: Path) -> None:
    from camtol.config.design_file import example_text

    table = "\n[dynamics]\nmass_kg = 1\nspring_rate_n_per_mm = 10\npreload_n = 100\n"
    f = tmp_path / "cam.toml"
    f.write_text(example_text("roller-translating") + table)  # speed_rpm = 300
    out = tmp_path / "r.html"
    assert main(["report", str(f), "-o", str(out)]) == 0
    html = out.read_text(encoding="utf-8")
    assert "<h2>Dynamics at speed</h2>" in html and 'id="figure-dynamics"' in html
    assert "jump speed" in html
    g = tmp_path / "slow.toml"
    g.write_text(example_text("popa-eccentric") + table)  # no speed: a note, still written
    assert main(["report", str(g), "-o", str(out)]) == 0
    assert "Not computed: the design gives no operation.speed_rpm" in out.read_text()
    plain = tmp_path / "plain.html"
    assert main(["report", "-e", "roller-translating", "-o", str(plain)]) == 0
    assert "Dynamics at speed" not in plain.read_text()
