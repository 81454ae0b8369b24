"""The command line, in process (STYLE point 15): exit codes, one-line errors, files."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from camtol.cli.app import main


def test_analyze_example_prints_extremes(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "--example", "cw06-translating"]) == 0
    out = capsys.readouterr().out
    assert "25.567" in out and "71.50°" in out
    assert "between IT7 (21 µm) and IT8 (33 µm)" in " ".join(out.split())  # 80 columns
    assert "120.00-190.00°" in out and "290.00-360.00°" in out  # one range a line


def test_analyze_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", "-e", "cw06-oscillating", "--json", "--step", "0.5"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["max_radius_mm"] == pytest.approx(58.934, abs=1e-3)
    worst = next(e for e in data["extremes"] if e["quantity"] == "dS_worst")
    assert worst["unit"] == "deg"
    assert data["accuracy"]["text"].startswith("between IT8")
    assert data["accuracy"]["lower_grade"] == "IT8"
    assert any("not defined by ISO 286" in c for c in data["conventions"])


@pytest.mark.parametrize(
    ("example", "unit", "sources"),
    [("cw06-translating", "um", ["r", "e", "phi"]), ("cw06-oscillating", "deg", ["r", "f", "e"])],
)
def test_curves_csv_columns(tmp_path: Path, example: str, unit: str, sources: list[str]) -> None:
    out = tmp_path / "c.csv"
    assert main(["analyze", "-e", example, "--curves", str(out), "--quiet"]) == 0
    with out.open() as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    for col in ["theta_deg", "x_mm", "y_mm", "radius_mm", "pressure_angle_deg", "shift_angle_deg"]:
        assert col in header
    for s in [*sources, "worst", "rms"]:
        assert f"dS_{s}_{unit}" in header
        assert f"dV_{s}_{unit}_per_rad" in header
        assert f"dA_{s}_{unit}_per_rad2" in header
    # 3601 grid angles plus one extra (left-limit) row per segment boundary
    assert len(rows) - 1 == 3601 + 4
    theta = [float(r[0]) for r in rows[1:]]
    assert theta == sorted(theta)


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "cam.toml"
    p.write_text(text)
    return p


GOOD = """
name = "t"
[follower]
type = "flat_translating"
base_radius_mm = {rb}
[motion]
segments = [
  {{ kind = "rise", law = "{law}", start_deg = 0, end_deg = {rise}, lift_mm = 22 }},
  {{ kind = "return", law = "cycloidal", start_deg = {rise}, end_deg = {end}, lift_mm = 22 }},
]
[tolerances]
r = "IT6"
"""


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"rb": 5, "law": "cycloidal", "rise": 40, "end": 360}, "not convex: radius of curvature"),
        (
            {"rb": 40, "law": "wobble", "rise": 180, "end": 360},
            "is not allowed; give a known motion law",
        ),
        ({"rb": -4, "law": "cycloidal", "rise": 180, "end": 360}, "base_radius_mm=-4"),
        ({"rb": 40, "law": "cycloidal", "rise": 180, "end": 350}, "must cover exactly 360°"),
    ],
)
def test_invalid_design_one_line_exit_2_nothing_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], params: dict[str, object], message: str
) -> None:
    design = _write(tmp_path, GOOD.format(**params))
    out = tmp_path / "c.csv"
    code = main(["analyze", str(design), "--curves", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err
    assert err.count("\n") == 1 and err.startswith("camtol: error: ")
    assert "Traceback" not in err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [design]


def test_oscillating_v_at_least_one_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    design = _write(
        tmp_path,
        """
name = "fast"
[follower]
type = "flat_oscillating"
base_radius_mm = 40
pivot_distance_mm = 80
face_offset_mm = 16
[motion]
segments = [
  { kind = "rise", law = "cycloidal", start_deg = 0, end_deg = 30, lift_deg = 60 },
  { kind = "return", law = "cycloidal", start_deg = 30, end_deg = 360, lift_deg = 60 },
]
""",
    )
    assert main(["analyze", str(design)]) == 2
    assert "needs V < 1 everywhere" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["analyze"], "give either a DESIGN.toml file or --example NAME"),
        (["analyze", "-e", "nope"], "example 'nope' does not exist"),
        (["analyze", "-e", "cw06-translating", "--step", "0.7"], "--step=0.7 is not allowed"),
        (["analyze", "-e", "cw06-translating", "--curves", "x.txt"], "must end in .csv"),
        (["analyze", "-e", "cw06-translating", "--curves", "/no/such/dir/x.csv"], "does not exist"),
        (["analyze", "-e", "cw06-translating", "--step", "abc"], "'abc' is not a valid float"),
        (["frobnicate"], "No such command"),
    ],
)
def test_usage_errors(capsys: pytest.CaptureFixture[str], args: list[str], message: str) -> None:
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err
    assert "Traceback" not in err


def test_examples_list_and_show(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["examples"]) == 0
    assert "cw06-translating" in capsys.readouterr().out
    assert main(["examples", "show", "cw06-oscillating"]) == 0
    assert 'type = "flat_oscillating"' in capsys.readouterr().out
    assert main(["examples", "show", "nope"]) == 2


def test_example_toml_round_trips_through_a_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    main(["examples", "show", "cw06-translating"])
    design = _write(tmp_path, capsys.readouterr().out)
    assert main(["analyze", str(design), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["design"]["name"] == "cw06-translating"


def test_core_import_is_light() -> None:
    import subprocess
    import sys

    code = (
        "import sys, camtol, camtol.analysis.result, camtol.config.design_file, camtol.cli.app;"
        "bad=[m for m in ('matplotlib','ezdxf','scipy','rich') if m in sys.modules];"
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_outputs_get_ordinary_permissions(tmp_path: Path) -> None:
    """Atomic writes must not leave files readable by the owner only (mkstemp's 0600)."""
    import os

    umask = os.umask(0o022)
    try:
        out = tmp_path / "c.csv"
        assert main(["analyze", "-e", "cw06-translating", "--curves", str(out), "-q"]) == 0
        assert out.stat().st_mode & 0o777 == 0o644
        assert [p.name for p in tmp_path.iterdir()] == ["c.csv"]  # no temporary left
    finally:
        os.umask(umask)


def test_pressure_angle_limit_warns_once(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from camtol.config.design_file import example_text

    text = example_text("roller-translating").replace(
        "pressure_angle_limit_deg = 30", "pressure_angle_limit_deg = 10"
    )
    design = _write(tmp_path, text)
    assert main(["analyze", str(design), "-q"]) == 0  # a warning, not an error
    err = capsys.readouterr().err
    assert err.count("camtol: warning: pressure angle reaches") == 1
    assert "beyond the design limit 10°" in err


def test_plot_at_a_chosen_angle(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "f.svg"
    args = ["analyze", "-e", "cw06-oscillating", "--step", "1", "--plot", str(out), "-q"]
    assert main([*args, "--plot-angle", "60"]) == 0
    assert "follower at θ = 60° (cam frame)" in out.read_text()  # the cam panel's title
    bad = tmp_path / "g.svg"
    bad_args = ["analyze", "-e", "cw06-oscillating", "--plot", str(bad), "--plot-angle", "nan"]
    assert main(bad_args) == 2
    assert "--plot-angle=nan is not allowed; give a cam angle from 0" in capsys.readouterr().err
    assert not bad.exists()


@pytest.mark.parametrize(
    "args",
    [
        ["analyze", "--example", "cw06-translating"],  # tables printed by rich
        ["montecarlo", "--example", "cw06-oscillating", "--samples", "1000"],  # click.echo
    ],
)
def test_reader_leaving_early_is_quiet(args: list[str]) -> None:
    """`camtol ... | head`: no error line, no traceback, status 1 (rich's convention)."""
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-m", "camtol", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None
    proc.stdout.close()  # the reader leaves before the first line: every write fails
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 1
    assert err.decode() == "", err.decode()


#: Every command with a grid step, its other required arguments, and the finest step it
#: takes: the library's bound (analyse: MAX_GRID_POINTS; sizing, verify and the fixture:
#: 360,000 points), so the option and the library agree.
_STEP_COMMANDS = [
    (["analyze"], 0.0001),
    (["size"], 0.001),
    (["report", "-o", "r.html"], 0.0001),
    (["montecarlo", "-n", "10"], 0.0001),
    (["verify"], 0.001),
    (["conjugate"], 0.001),
    (["inspect", "--points", "p.csv"], 0.0001),
]


@pytest.mark.parametrize(("command", "finest_deg"), _STEP_COMMANDS)
@pytest.mark.parametrize("step", ["0.7", "-1", "0", "nan", "400"])
def test_every_step_option_names_the_flag(
    capsys: pytest.CaptureFixture[str], command: list[str], finest_deg: float, step: str
) -> None:
    # Checked as the line is parsed, before any file is read (p.csv does not exist).
    assert main([*command, "-e", "cw11-conjugate", "--step", step]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camtol: error: --step=") and err.count("\n") == 1
    assert f"between {finest_deg:g}°" in err
    assert "step_deg" not in err


def test_step_option_bounds_are_the_libraries() -> None:
    from camtol.grid import MAX_GRID_POINTS
    from camtol.pair.fixture import MAX_FIXTURE_POINTS

    assert {round(360 / f) for _, f in _STEP_COMMANDS} == {MAX_GRID_POINTS, MAX_FIXTURE_POINTS}
    # the sizing library refuses what `camtol size` refuses
    from camtol.analysis.sizing import minimum_base_radius
    from camtol.config.design_file import load_example
    from camtol.exceptions import DesignError

    with pytest.raises(DesignError, match=r"step_deg=0.0005 .* between 0.001°"):
        minimum_base_radius(load_example("roller-oscillating"), step_deg=0.0005)


def test_library_grids_refuse_a_step_that_does_not_divide_360() -> None:
    # Before, Monte Carlo and max_radius_mm built 514 steps of 0.7004° for a 0.7° step.
    from camtol.analysis.kinematics import analysis_grid
    from camtol.analysis.result import max_radius_mm
    from camtol.config.design_file import load_example
    from camtol.exceptions import DesignError
    from camtol.tolerancing import monte_carlo

    design = load_example("roller-oscillating")
    for call in (
        lambda: analysis_grid(0.7),
        lambda: max_radius_mm(design, step_deg=0.7),
        lambda: monte_carlo(design, 10, step_deg=0.7),
        lambda: monte_carlo(design, 10, step_deg=-1.0),
    ):
        with pytest.raises(DesignError, match=r"step_deg=.* is not allowed; it must divide 360°"):
            call()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # each of these named the library's parameter, a converted value, or raised
        (
            ["allocate", "--spec-deg", "0.05", "--yield", "1"],
            "--yield=1 is not allowed; give a number > 0 and < 1",
        ),
        (
            ["allocate", "--spec-deg", "0.05", "--seed", "-1"],
            "--seed=-1 is not allowed; give a whole number ≥ 0",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--seed", "-1"],
            "--seed=-1 is not allowed; give a whole number ≥ 0",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--n-points", "10"],  # was --points (issue 31)
            "--n-points=10 is not allowed; give a whole number ≥ 36",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--outliers", "361"],
            "--outliers=361 is not allowed; give a whole number from 0 to 360",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--noise-um", "nan"],
            "--noise-um=nan is not allowed; give a number from 0 to 1000 in µm",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--n-points", "1.5"],
            "--n-points='1.5' is not a whole number",
        ),
        (  # named the library parameter
            ["inspect", "--points", "p.csv", "--harmonics", "0"],
            "--harmonics=0 is not allowed; give a whole number ≥ 1",
        ),
        (  # cos(1e30°) is no direction: ran, with an arbitrary one
            ["simulate", "cmm", "-o", "s.csv", "--rotation-deg", "1e30"],
            "--rotation-deg=1e+30 is not allowed; give a number from -360 to 360 in deg",
        ),
        (
            ["simulate", "cmm", "-o", "s.csv", "--eccentricity-deg", "-400"],
            "--eccentricity-deg=-400 is not allowed; give a number from -360 to 360 in deg",
        ),
        (
            ["cut", "--lift-tolerance-um", "-1"],
            "--lift-tolerance-um=-1 is not allowed; give a number > 0",
        ),
        (
            ["cut", "--accel-budget", "nan"],
            "--accel-budget=nan is not allowed; give a percentage > 0",
        ),
        (
            ["precision", "--accel-budget", "0"],
            "--accel-budget=0 is not allowed; give a percentage > 0",
        ),
        (["precision", "--decimals", "nan"], "--decimals='nan' is not allowed; give whole numbers"),
        (
            ["precision", "--decimals", "3,40"],
            "--decimals='3,40' is not allowed; give whole numbers from 0 to 12",
        ),
        (
            ["inspect", "--points", "p.csv", "--stylus-radius-mm", "-1"],
            "--stylus-radius-mm=-1 is not allowed; give a number ≥ 0 in mm",
        ),
        (
            ["profile", "-o", "p.csv", "--tolerance", "1e308"],
            "--tolerance=1e+308 is not allowed; give a number from 0.0001 to 1000 in µm",
        ),
        (
            ["profile", "-o", "p.csv", "--spark-gap", "nan"],
            "--spark-gap=nan is not allowed; give a number ≥ 0 in mm",
        ),
        (
            ["profile", "-o", "p.csv", "--spark-gap", "0.1"],
            "--wire-radius and --spark-gap are only allowed for G-code output",
        ),
        (
            ["profile", "-o", "p.nc", "--cutter-radius", "5", "--spark-gap", "0.1"],
            "--spark-gap is the wire-EDM overcut: give --wire-radius MM as well",
        ),
    ],
)
def test_number_options_name_the_flag(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    args: list[str],
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main([*args, "-e", "roller-oscillating"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []  # nothing written


@pytest.mark.parametrize(
    ("args", "message"),
    [  # said noise=-0.001 (converted to mm) and smoothing=0, the library's names
        (["--noise-um", "-1"], "--noise-um=-1 is not allowed; give a number > 0 in µm"),
        (["--noise-deg", "nan"], "--noise-deg=nan is not allowed; give a number > 0 in deg"),
        (["--smoothing", "0"], "--smoothing=0 is not allowed; give a number > 0"),
    ],
)
def test_derive_number_options_name_the_flag(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, args: list[str], message: str
) -> None:
    lift = tmp_path / "lift.csv"
    lift.write_text("theta_deg,lift_mm\n" + "".join(f"{t},{t / 100}\n" for t in range(360)))
    assert main(["derive", str(lift), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_number_type_bounds_and_text() -> None:
    import click

    from camtol.cli.options import Number

    opt = click.Option(["--x"], type=Number(low=0, low_open=True, high=5, unit="mm"))
    assert opt.type.convert("5", opt, None) == 5.0
    assert Number(low=1, integer=True).convert("3", None, None) == 3
    for bad in ("0", "5.5", "inf", "-inf", "nan"):
        with pytest.raises(
            click.UsageError, match=r"--x=.* is not allowed; give a number > 0 and ≤ 5 in mm"
        ):
            opt.type.convert(bad, opt, None)
    assert Number(low=0, low_open=True, unit="%").allowed == "a percentage > 0"
    assert Number(high=3, integer=True).allowed == "a whole number ≤ 3"
    open_both = Number(low=0, low_open=True, high=1, high_open=True)
    assert open_both.allowed == "a number > 0 and < 1"
    for bad in ("0", "1"):
        with pytest.raises(click.UsageError, match="give a number > 0 and < 1"):
            open_both.convert(bad, None, None)
