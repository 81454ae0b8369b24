"""`camtol precision`, `camtol cut`, `camtol derive`, `camtol profile -o cam.nc`."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.manufacturing.gcode import path_deviation, read_gcode

PRECISION_KEYS = {
    "decimals",
    "quantum_mm",
    "max_abs_dV_central",
    "max_abs_dA_central",
    "max_abs_dA_spline",
    "bound_alternating",
    "bound_dip",
}
CUT_KEYS = {
    "cut_step_deg",
    "tool",
    "read_step_deg",
    "max_abs_lift_error_um",
    "max_abs_dA_central",
    "scallop_height_um",
    "rule_rho_delta2_over_8_um",
}


def test_precision_json_keys(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["precision", "-e", "popa-eccentric", "--accel-budget", "1", "--json"])
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert [t["decimals"] for t in doc["tables"]] == [3, 4, 5, 6]
    for t in doc["tables"]:
        assert PRECISION_KEYS <= set(t)
    assert doc["recommended_decimals"] == 6
    assert doc["tables"][0]["max_abs_dA_central"] == pytest.approx(5.12, abs=0.01)


def test_precision_per_second_keys_with_a_speed(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["precision", "-e", "roller-translating", "--decimals", "4", "--json"]) == 0
    t = json.loads(capsys.readouterr().out)["tables"][0]
    w = 300 * 2 * np.pi / 60
    assert t["max_abs_dA_central_mm_per_s2"] == pytest.approx(t["max_abs_dA_central"] * w**2)
    assert t["max_abs_dV_central_mm_per_s"] == pytest.approx(t["max_abs_dV_central"] * w)


def test_cut_json_and_curves(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    curves = tmp_path / "cut.csv"
    args = ["cut", "-e", "popa-eccentric", "--cut-step", "1,2,5,10", "--json"]
    assert main([*args, "--curves", str(curves), "--lift-tolerance-um", "5"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [c["cut_step_deg"] for c in doc["cuts"]] == [1, 2, 5, 10]
    for c in doc["cuts"]:
        assert CUT_KEYS <= set(c)
    assert doc["cuts"][1]["max_abs_lift_error_um"] == pytest.approx(4.570, abs=1e-3)
    assert doc["coarsest_cut_step_deg"] == 2.0
    with curves.open() as fh:
        header = next(csv.reader(fh))
    assert header == ["theta_deg"] + [f"lift_error_um_{s}deg" for s in (1, 2, 5, 10)]


def test_cut_oscillating_reports_degrees(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["cut", "-e", "cw06-oscillating", "--cut-step", "2", "--tool", "cylinder"]
    assert main([*args, "--tool-radius", "5", "--json"]) == 0
    c = json.loads(capsys.readouterr().out)["cuts"][0]
    assert "max_abs_lift_error_deg" in c and c["tool"] == "cylinder"


def test_cut_text(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["cut", "-e", "popa-eccentric", "--cut-step", "2,5", "--read-step", "1"]) == 0
    out = capsys.readouterr().out
    assert "4.57" in out and "27.44" in out  # 4 significant digits (issue 32)
    assert max(len(line) for line in out.splitlines()) <= 80


def test_derive(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "lift.csv"
    th = np.arange(0.0, 361.0, 1.0)
    lift = 5 * (1 - np.cos(np.radians(th)))
    rows = "\n".join(f"{a:g};{b:.6f}" for a, b in zip(th, lift, strict=True))
    src.write_text("# dial indicator\ntheta_deg;lift_mm\n" + rows + "\n")
    out = tmp_path / "derived.csv"
    assert main(["derive", str(src), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "noise amplification" in text and "generalised cross-validation" in text
    with out.open() as fh:
        header = next(csv.reader(fh))
    assert header == [
        "theta_deg", "lift_mm", "lift_smoothed_mm", "V_mm_per_rad", "A_mm_per_rad2",
        "J_mm_per_rad3",
    ]  # fmt: skip
    assert main(["derive", str(src), "--method", "savgol", "--noise-um", "1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["selection"] == "noise" and doc["samples"] == 360


def test_tool_radius_bound_of_the_command_line_is_the_librarys() -> None:
    # The command line writes the bound out (its --help loads no numpy).
    from camtol.analysis import profile
    from camtol.cli import options as cli_options

    assert cli_options.MAX_TOOL_RADIUS_MM == profile.MAX_TOOL_RADIUS_MM


def test_profile_gcode(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from camtol.config.design_file import load_example

    out = tmp_path / "cam.nc"
    args = ["profile", "-e", "cw06-translating", "-o", str(out), "--cutter-radius", "4"]
    assert main([*args, "--tolerance", "1", "--feed", "300", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["format"] == "gcode" and doc["mode"] == "arcs"
    path = read_gcode(out.read_text())[0]
    assert path_deviation(path, load_example("cw06-translating"), 4.0) <= 1e-3


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["cut", "-e", "popa-eccentric", "--cut-step", "7"], "--cut-step=7"),
        (["cut", "-e", "popa-eccentric", "--cut-step", "1", "--read-step", "2"], "coarser"),
        (["cut", "-e", "popa-eccentric", "--tool", "cylinder"], "--tool-radius"),
        (["cut", "-e", "popa-eccentric", "--tool", "cylinder", "--tool-radius", "-1"], "-1"),
        (["precision", "-e", "popa-eccentric", "--table-step", "7"], "--table-step=7"),
        (["precision", "-e", "popa-eccentric", "--decimals", "3,x"], "--decimals"),
        (["profile", "-e", "popa-eccentric", "-o", "OUT.nc"], "--cutter-radius"),
        # Tool radii beyond 100 m: a typo, whose path would be absurd or exhaust the memory
        # (a 1e30 mm cutter's G-code was killed for lack of memory before the bound).
        (["cut", "-e", "popa-eccentric", "--tool", "cylinder", "--tool-radius", "1e30"], "≤ 1000"),
        (["profile", "-e", "popa-eccentric", "-o", "OUT.nc", "--cutter-radius", "1e30"], "100000"),
        (["profile", "-e", "popa-eccentric", "-o", "OUT.csv", "--cutter-radius", "2e5"], "to 1000"),
        (["profile", "-e", "popa-eccentric", "-o", "OUT.nc", "--wire-radius", "1e6"], "100000"),
        (
            ["profile", "-e", "popa-eccentric", "-o", "OUT.nc", "--wire-radius", "0.1"]
            + ["--spark-gap", "1e30"],
            "the offset may be at most 100000 mm",
        ),
        (
            ["profile", "-e", "popa-eccentric", "-o", "OUT.nc", "--wire-radius", "99999"]
            + ["--spark-gap", "2"],
            "--wire-radius + --spark-gap = 100001 mm",
        ),
    ],
)
def test_bad_input_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    args = [a.replace("OUT", str(tmp_path / "out")) for a in args]
    curves = tmp_path / "c.csv"
    extra = ["--curves", str(curves)] if args[0] == "cut" else []
    assert main(args + extra) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_gouging_tool_exit_2_and_says_where(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from manufacturing_designs import CONCAVE_ROLLER_TOML

    design = tmp_path / "concave.toml"
    design.write_text(CONCAVE_ROLLER_TOML)
    curves = tmp_path / "c.csv"
    args = [
        "cut",
        str(design),
        "--tool",
        "cylinder",
        "--tool-radius",
        "20",
        "--curves",
        str(curves),
    ]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "gouge" in err and "θ=23" in err and err.count("\n") == 1
    assert not curves.exists()
    nc = tmp_path / "cam.nc"
    assert (
        main(["profile", str(design), "-o", str(nc), "--cutter-radius", "20", "--feed", "99"]) == 2
    )
    assert "gouge" in capsys.readouterr().err and not nc.exists()


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        # Issue 32: the line and what is wrong with it, not "rows 1-2" of a guessed step.
        ("0,0\n1,0.1\n3,0.2\n", "line 4: theta_deg jumps from 1° to 3°; 1 row missing (2°"),
        ("0,0\n1,0.1\n2,0.2\n3.5,0.3\n", "line 5: theta_deg steps from 2° to 3.5° (1.5°)"),
    ],
)
def test_derive_refuses_gaps_and_unequal_steps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], rows: str, message: str
) -> None:
    src = tmp_path / "lift.csv"
    src.write_text("theta_deg,lift_mm\n" + rows)
    out = tmp_path / "d.csv"
    assert main(["derive", str(src), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


def test_derive_oscillating_lift_in_degrees(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    src = tmp_path / "angle.csv"
    th = np.arange(0.0, 360.0, 0.5)
    ang = 10 * (1 - np.cos(np.radians(th)))  # deg
    src.write_text(
        "theta_deg,lift_deg\r\n"
        + "\r\n".join(f"{a:g},{b:.5f}" for a, b in zip(th, ang, strict=True))
    )
    assert main(["derive", str(src), "--noise-deg", "0.00001", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["lift_unit"] == "deg" and "A_deg_per_rad2" in doc["noise_gain_per_mdeg"]
    assert doc["max_abs_A"] == pytest.approx(10.0, rel=1e-3)
    assert main(["derive", str(src), "--noise-um", "1"]) == 2
    assert "--noise-um is for lift_mm files" in capsys.readouterr().err
