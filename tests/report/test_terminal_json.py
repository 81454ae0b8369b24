"""What a designer sees from `camtol analyze` (issue 13 items 1, 2, 3, 5, 7)."""

from __future__ import annotations

import csv
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

from camtol.analysis.result import analyse
from camtol.analysis.summary import STANDARD_GRAVITY
from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.config.examples import example_text
from camtol.report.display import display_extremes


def _limited(tmp_path: Path, limit_deg: float) -> Path:
    """roller-translating with another pressure-angle limit (its φ reaches -16.8°)."""
    text = example_text("roller-translating").replace(
        "pressure_angle_limit_deg = 30", f"pressure_angle_limit_deg = {limit_deg:g}"
    )
    p = tmp_path / "cam.toml"
    p.write_text(text)
    return p


def test_motion_peaks_at_speed_in_terminal_and_json(capsys: pytest.CaptureFixture[str]) -> None:
    a = analyse(load_example("roller-translating"), step_deg=0.5)
    w = a.design.omega_rad_s
    assert w is not None
    amax = float(np.max(np.abs(a.kinematics.acceleration))) * w**2 * 1e-3  # [m/s²]
    assert main(["analyze", "-e", "roller-translating", "--step", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "peak |V| at 300 rpm" in out and "m/s²" in out and " g)" in out
    assert main(["analyze", "-e", "roller-translating", "--step", "0.5", "--json"]) == 0
    m = json.loads(capsys.readouterr().out)["motion"]
    assert max(m["acceleration_max_m_per_s2"], -m["acceleration_min_m_per_s2"]) == (
        pytest.approx(amax, rel=1e-9)
    )
    assert m["acceleration_abs_max_g"] == pytest.approx(amax / STANDARD_GRAVITY, rel=1e-9)
    assert m["speed_rpm"] == 300


def test_motion_per_radian_without_speed(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "-e", "cw06-oscillating", "--step", "0.5", "--json"]) == 0
    m = json.loads(capsys.readouterr().out)["motion"]
    assert "velocity_max_rad_per_rad" in m and m["speed_rpm"] is None


def test_curves_have_velocity_acceleration_jerk(tmp_path: Path) -> None:
    out = tmp_path / "c.csv"
    assert main(["analyze", "-e", "roller-translating", "--curves", str(out), "-q"]) == 0
    with out.open() as fh:
        header = next(csv.reader(fh))
    for col in ("lift_mm", "velocity_m_per_s", "acceleration_m_per_s2", "jerk_m_per_s3"):
        assert col in header
    assert "curvature_radius_mm" in header
    out2 = tmp_path / "d.csv"
    assert main(["analyze", "-e", "cw06-translating", "--curves", str(out2), "-q"]) == 0
    with out2.open() as fh:
        assert "velocity_mm_per_rad" in next(csv.reader(fh))


def test_convex_and_concave_radii_replace_min_curvature(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["analyze", "-e", "roller-translating", "--step", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "min radius of curvature" not in out
    assert "smallest convex radius" in out and "smallest concave radius" in out
    assert "roller radius" in out  # what limits the convex radius
    assert main(["analyze", "-e", "cw11-conjugate", "--step", "0.5", "--json"]) == 0
    cams = json.loads(capsys.readouterr().out)["cams"]
    assert [c["cam"] for c in cams] == ["A", "B"]
    for c in cams:
        assert c["min_convex_radius_mm"] > 0
        assert c["min_concave_radius_mm"] is None or c["min_concave_radius_mm"] > 0


def test_pressure_angle_limit_flagged_and_strict(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    design = str(_limited(tmp_path, 10))
    assert main(["analyze", design, "--step", "0.5"]) == 0
    out = " ".join(capsys.readouterr().out.split())  # as read, whatever the wrapping
    assert "> 10° LIMIT" in out and "EXCEEDS the 10° limit" in out
    assert main(["analyze", design, "--step", "0.5", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["pressure_angle_exceeds_limit"] is True
    assert data["cams"][0]["pressure_angle_exceeds_limit"] is True
    assert main(["analyze", design, "--step", "0.5", "--strict"]) == 1
    assert "--strict" in capsys.readouterr().err
    ok = str(_limited(tmp_path, 30))
    assert main(["analyze", ok, "--step", "0.5", "--strict", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["pressure_angle_exceeds_limit"] is False


@pytest.mark.parametrize("example", ["roller-translating", "cw06-translating", "cw11-conjugate"])
def test_fits_80_columns(example: str) -> None:
    from camtol.report.tables import print_analysis
    from camtol.report.terminal import Terminal

    out = io.StringIO()
    a = analyse(load_example(example), step_deg=0.5)
    print_analysis(a, terminal=Terminal(out, width=80))
    text = out.getvalue()
    lines = text.splitlines()
    assert max(len(line) for line in lines) <= 80
    # every angle range of the table is whole on one line
    wheres = {
        w
        for key, (mx, mn) in display_extremes(a).items()
        if key != "curvature_radius"  # not in the table: see the convex/concave rows
        for w in (*mx.where.split(", "), *mn.where.split(", "))
    }
    assert any("-" in w[1:] for w in wheres), "the dwells' ranges are shown"
    for w in wheres:
        assert w in text, w  # never split over lines
    assert "Conventions:" not in text


def test_conventions_only_verbose(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "-e", "cw06-translating", "--step", "0.5"]) == 0
    assert "Conventions:" not in capsys.readouterr().out
    assert main(["analyze", "-e", "cw06-translating", "--step", "0.5", "--verbose"]) == 0
    assert "Conventions:" in capsys.readouterr().out


def test_units_by_magnitude_and_spelling(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "-e", "roller-translating", "--step", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "modified sine" in out and "modified_sine" not in out
    assert "rad2" not in out and "[um]" not in out
    row = next(line for line in out.splitlines() if "ΔA worst case" in line)
    assert "mm/s²" in row  # 18966 µm/s² is shown as 18.966 mm/s²
    assert max(len(n.split(".")[0].lstrip("-")) for n in re.findall(r"-?\d+\.\d+", row)) <= 4


def test_json_numbers_are_rounded_and_structured(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "-e", "cw06-translating", "--step", "0.5", "--json"]) == 0
    text = capsys.readouterr().out
    data = json.loads(text)
    assert data["schema_version"] and data["command"] == "analyze"
    assert data["accuracy"]["lower_grade"] == "IT7" and data["accuracy"]["upper_um"] == 33
    assert all(
        isinstance(t.get("deviation_um", t.get("deviation_deg")), float) for t in data["tolerances"]
    )
    assert not re.search(r"\d\.\d{11,}", text)  # 10 significant digits at most
    assert 'µm"' not in text.split('"tolerances"')[1].split("origin")[0]


def test_conjugate_table_has_labels_and_units(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["conjugate", "-e", "cw11-experiment", "--step", "0.5", "--df-mea", "22um"])
    assert code == 1  # the masters' Δf_mea = 22 µm everywhere fails (a documented example)
    out = capsys.readouterr().out
    table = out[out.index("Extremes") :]
    for raw in ("df_A_upper", "dr_B_est", "df_eta", "df_r "):
        assert raw not in table
    assert "cam A band: upper Δf" in table and "Δr_B,est (cam B)" in table
    header = next(line for line in table.splitlines() if "quantity" in line)
    assert "unit" in header.split()
    rows = [line for line in table.splitlines() if line.strip().startswith(("Δ", "cam"))]
    assert rows and all(" µm " in line for line in rows if "band" in line or "Δr" in line)
    assert max(len(line) for line in out.splitlines()) <= 80


def test_display_unit_rule() -> None:
    from camtol.report.units import file_unit, fmt, json_number, magnitude_unit, pretty_unit

    assert magnitude_unit("um/s2", 1_468_273.0) == ("mm/s2", 1e-3)
    assert magnitude_unit("um/s2", 2.5e7) == ("m/s2", 1e-6)
    assert magnitude_unit("um", 9999.0) == ("um", 1.0)
    assert magnitude_unit("deg", 1e9) == ("deg", 1.0)
    assert pretty_unit("um/rad2") == "µm/rad²" and pretty_unit("m/s3") == "m/s³"
    assert pretty_unit("deg") == "°" and file_unit("µm/rad²") == "um_per_rad2"
    assert fmt(14.999999999999998) == "15.000" and fmt(1468273.2) == "1468273"
    assert json_number(14.999999999999998) == 15.0
    assert json_number(float("inf")) is None and json_number(float("nan")) is None


def test_verify_fits_80_columns_and_spells_units(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["verify", "-e", "cw06-translating", "--step", "0.5"]) == 0
    out = capsys.readouterr().out
    assert max(len(line) for line in out.splitlines()) <= 80
    assert "[um]" not in out and "rad2" not in out and "(µm)" in out
