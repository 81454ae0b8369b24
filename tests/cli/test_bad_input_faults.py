"""Regression tests for the reproductions of issue 9 (bad input and faults).

Every command either succeeds with valid outputs, exits 1 for a failed part, or exits 2
with ONE stderr line naming the problem; never a traceback, never an impossible cam
accepted, never an input overwritten, never a NaN in an output.
"""

from __future__ import annotations

import errno
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest

from camtol.analysis.validity import check_design_geometry
from camtol.cli.app import main
from camtol.config.design_file import design_from_mapping, example_text, load_design
from camtol.exceptions import GeometryError, OutputError, UndercutError

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ALL_WRITERS = ("analyze", "profile", "report", "verify")


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """Run the CLI in process; return (exit code, stdout, stderr)."""
    code = main(list(args))
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def assert_one_error(code: int, err: str, *needles: str) -> None:
    """Exit 2 with exactly one ``camtol: error:`` line containing every needle."""
    assert code == 2, err
    assert "Traceback" not in err
    lines = [ln for ln in err.splitlines() if ln.startswith("camtol: error:")]
    assert len(lines) == 1, err
    for n in needles:
        assert n in lines[0], lines[0]


def write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def command_args(cmd: str, design: Path, tmp_path: Path) -> list[str]:
    if cmd == "profile":
        return [cmd, str(design), "-o", str(tmp_path / "out.csv")]
    if cmd == "report":
        return [cmd, str(design), "-o", str(tmp_path / "out.html")]
    if cmd == "montecarlo":
        return [cmd, str(design), "--samples", "200"]
    if cmd == "allocate":
        return [cmd, str(design), "--spec-deg", "0.05"]
    return [cmd, str(design)]


# --- item 1: velocity jumps (constant velocity next to dwells) -----------------------------
# Issue 32 retired the pure constant velocity (it always met its neighbours with a velocity
# jump): every command now refuses it by name when the design is read, naming the law that
# works, instead of the corner check refusing it once the geometry was computed.
@pytest.mark.parametrize(
    ("example", "law"), [("cw06-translating", "cycloidal"), ("roller-translating", "modified_sine")]
)
@pytest.mark.parametrize("cmd", ALL_WRITERS)
def test_constant_velocity_is_refused_naming_the_law_that_works(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, example: str, law: str, cmd: str
) -> None:
    text = example_text(example).replace(f'"{law}"', '"constant_velocity"')
    design = write(tmp_path, "cv.toml", text)
    code, _, err = run(capsys, *command_args(cmd, design, tmp_path))
    assert_one_error(code, err, "'constant_velocity' is not allowed", "modified_constant_velocity")
    assert not list(tmp_path.glob("out.*"))


def test_constant_velocity_conjugate(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    text = example_text("cw11-conjugate").replace('"cycloidal"', '"constant_velocity"')
    design = write(tmp_path, "cv.toml", text)
    code, _, err = run(capsys, "conjugate", str(design))
    assert_one_error(code, err, "'constant_velocity' is not allowed", "velocity jump")


# --- item 2: validity does not depend on the grid ----------------------------------------
def _tiny_rise(example: str, unit: str) -> str:
    text = example_text(example)
    text = re.sub(
        r"start_deg = 0,\s+end_deg = 120,", "start_deg = 0, end_deg = 1e-06,", text, count=1
    )
    return re.sub(r"start_deg = 120,", "start_deg = 1e-06,", text, count=1)


@pytest.mark.parametrize("step", ["45", "0.1"])
def test_tiny_oscillating_rise_is_rejected_on_every_grid(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, step: str
) -> None:
    design = write(tmp_path, "repro.toml", _tiny_rise("roller-oscillating", "deg"))
    assert "end_deg = 1e-06" in design.read_text()
    code, _, err = run(capsys, "analyze", str(design), "--step", step)
    assert_one_error(code, err, "V reaches", "V < 1")


@pytest.mark.parametrize("cmd", ["analyze", "verify", "conjugate", "profile"])
def test_tiny_conjugate_rise(capsys: pytest.CaptureFixture[str], tmp_path: Path, cmd: str) -> None:
    design = write(tmp_path, "c.toml", _tiny_rise("cw11-conjugate", "deg"))
    code, _, err = run(capsys, *command_args(cmd, design, tmp_path))
    assert_one_error(code, err, "cam A", "V reaches")


def test_segment_shorter_than_the_grid_step_is_checked() -> None:
    """A 0.05° rise of 2 mm: between two 1° grid points, it must still be seen."""
    raw = tomllib.loads(example_text("cw06-translating"))
    raw["motion"]["segments"] = [
        {"kind": "dwell", "start_deg": 0, "end_deg": 100.02},
        {"kind": "rise", "law": "cycloidal", "start_deg": 100.02, "end_deg": 100.07, "lift_mm": 2},
        {"kind": "dwell", "start_deg": 100.07, "end_deg": 200},
        {"kind": "return", "law": "cycloidal", "start_deg": 200, "end_deg": 300, "lift_mm": 2},
        {"kind": "dwell", "start_deg": 300, "end_deg": 360},
    ]
    with pytest.raises(UndercutError, match="not convex"):
        check_design_geometry(design_from_mapping(raw))


def test_geometry_check_is_grid_independent_for_every_example() -> None:
    """The built-in examples pass, and the check does not take a step at all."""
    for name in ("cw06-translating", "cw06-oscillating", "roller-translating"):
        check_design_geometry(design_from_mapping(tomllib.loads(example_text(name))))


# --- item 3: every command checks cam B; no NaN in any output -----------------------------
def _conjugate(**follower: float) -> str:
    raw = example_text("cw11-conjugate")
    for key, value in follower.items():
        raw = re.sub(rf"^{key} = .*$", f"{key} = {value!r}", raw, flags=re.M)
    return raw


@pytest.mark.parametrize(
    "cmd", ["analyze", "profile", "report", "verify", "conjugate", "montecarlo", "allocate"]
)
def test_cam_b_that_jams_is_rejected_by_every_command(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, cmd: str
) -> None:
    design = write(tmp_path, "b.toml", _conjugate(arm_angle_deg=60.0))
    code, _, err = run(capsys, *command_args(cmd, design, tmp_path))
    assert_one_error(code, err, "cam B", "pressure angle")


def test_huge_arm_b_writes_no_nan(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    design = write(tmp_path, "b.toml", _conjugate(arm_b_mm=1e300))
    curves = tmp_path / "c.csv"
    code, out, err = run(capsys, "analyze", str(design), "--json", "--curves", str(curves))
    assert_one_error(code, err)  # cam B's geometry, or the schema's bound on arm_b_mm
    assert "cam B" in err or "arm_b_mm" in err
    assert "NaN" not in out and not curves.exists()


def test_json_output_refuses_nan() -> None:
    from camtol.report.finite import json_text, require_finite_columns

    with pytest.raises(OutputError, match=r"extremes\[1\]\.value is nan"):
        json_text({"extremes": [{"value": 1.0}, {"value": float("nan")}]})
    with pytest.raises(OutputError, match=r"x_mm is inf at θ=2°"):
        require_finite_columns(
            {"theta_deg": np.array([0.0, 1.0, 2.0]), "x_mm": np.array([1.0, 2.0, np.inf])}
        )
    assert json.loads(json_text({"a": np.float64(1.5), "b": [np.int64(2)]})) == {
        "a": 1.5,
        "b": [2],
    }


# --- item 4: an output never replaces an input --------------------------------------------
def _df_table(tmp_path: Path) -> Path:
    return write(tmp_path, "m.csv", "theta_deg,um\n0,20\n180,22\n")


def test_curves_equal_to_df_mea_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    m = _df_table(tmp_path)
    before = m.read_bytes()
    code, _, err = run(
        capsys, "conjugate", "--example", "cw11-conjugate", "--df-mea", str(m), "--curves", str(m)
    )
    assert_one_error(code, err, "--curves", "same file as the input --df-mea")
    assert m.read_bytes() == before


def test_symlink_and_dotdot_are_resolved(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    m = _df_table(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "link.csv").symlink_to(m)
    before = m.read_bytes()
    for target in (tmp_path / "sub" / ".." / "m.csv", tmp_path / "link.csv"):
        code, _, err = run(
            capsys, "conjugate", "-e", "cw11-conjugate", "--df-mea", str(m), "--curves", str(target)
        )
        assert_one_error(code, err, "same file as the input")
    assert m.read_bytes() == before


def test_record_equal_to_curves_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    r = write(tmp_path, "r.csv", "df_um,index\n1,1\n2,0\n3,1\n")
    before = r.read_bytes()
    code, _, err = run(
        capsys, "conjugate", "-e", "cw11-conjugate", "--record", str(r), "--curves", str(r)
    )
    assert_one_error(code, err, "same file as the input --record")
    assert r.read_bytes() == before


@pytest.mark.parametrize(
    ("cmd", "option", "suffix"),
    [("analyze", "--curves", ".csv"), ("report", "-o", ".html"), ("profile", "-o", ".csv")],
)
def test_output_equal_to_design_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, cmd: str, option: str, suffix: str
) -> None:
    design = write(tmp_path, f"d{suffix}", example_text("cw06-translating"))
    before = design.read_bytes()
    code, _, err = run(capsys, cmd, str(design), option, str(design))
    assert_one_error(code, err, "same file as the input DESIGN")
    assert design.read_bytes() == before


def test_output_equal_to_a_lift_table_named_in_the_design_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    theta = np.arange(0, 360, 5.0)
    lift = 10 * (1 - np.cos(np.radians(theta))) / 2
    table = tmp_path / "lift.csv"
    table.write_text(
        "theta_deg,lift_mm\n"
        + "".join(f"{t:g},{s:.9f}\n" for t, s in zip(theta, lift, strict=True))
    )
    text = example_text("roller-translating")
    text = re.sub(r"\[motion\].*?\]\n", '[motion]\ntable_file = "lift.csv"\n', text, flags=re.S)
    design = write(tmp_path, "d.toml", text)
    before = table.read_bytes()
    code, _, err = run(capsys, "analyze", str(design), "--curves", str(table))
    assert_one_error(code, err, "lift.csv", "input")
    assert table.read_bytes() == before


def test_two_outputs_on_one_file_are_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "x.csv"
    code, _, err = run(
        capsys, "analyze", "-e", "cw06-translating", "--curves", str(out), "--plot", str(out)
    )
    assert_one_error(code, err, "--plot")
    assert not out.exists()


# --- item 5: temp files: recognisable, cleaned on signals, stale ones removed --------------
def test_stale_temporaries_of_dead_processes_are_removed(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    dead = 2**22 + 12345  # above pid_max on common systems: never alive
    stale = tmp_path / f".out.csv.camtol-tmp-{dead}-abc123.csv"
    stale.write_text("partial")
    mine = tmp_path / f".out.csv.camtol-tmp-{os.getpid()}-live01.csv"
    mine.write_text("in use")
    other = tmp_path / ".out.csv.XYZ.csv"
    other.write_text("not ours")
    code, _, _ = run(capsys, "profile", "-e", "cw06-translating", "-o", str(tmp_path / "out.csv"))
    assert code == 0
    assert not stale.exists() and mine.exists() and other.exists()


def test_temporary_name_is_recognisable(tmp_path: Path) -> None:
    from camtol.files import atomic_output

    with atomic_output(tmp_path / "a.csv") as tmp:
        assert tmp.name.startswith(f".a.csv.camtol-tmp-{os.getpid()}-")
        tmp.write_text("x")
    assert (tmp_path / "a.csv").read_text() == "x"
    assert [p.name for p in tmp_path.iterdir()] == ["a.csv"]


# --- item 6: encodings -------------------------------------------------------------------
def test_non_utf8_design(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b'name = "x\xff"\n')
    code, _, err = run(capsys, "analyze", str(bad))
    assert_one_error(code, err, "bad.toml", "not UTF-8", "line 1, column 10")


def test_utf16_and_utf32_design(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """UTF-16 with a BOM is read as the table reader reads it; UTF-32 is one clear line."""
    p = tmp_path / "u16.toml"
    p.write_bytes(example_text("cw06-translating").encode("utf-16"))
    code, _, err = run(capsys, "analyze", str(p), "-q")
    assert code == 0, err
    p.write_bytes(example_text("cw06-translating").encode("utf-16")[:-1])  # odd length
    code, _, err = run(capsys, "analyze", str(p))
    assert_one_error(code, err, "u16.toml", "not valid UTF-16")
    p.write_bytes(example_text("cw06-translating").encode("utf-32"))
    code, _, err = run(capsys, "analyze", str(p))
    assert_one_error(code, err, "u16.toml", "UTF-32")


def test_utf8_bom_design_is_accepted(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + example_text("cw06-translating").encode())
    code, _, err = run(capsys, "analyze", str(p), "-q")
    assert code == 0, err


def test_df_mea_csv_encodings(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    p = tmp_path / "m.csv"
    p.write_bytes(b"theta_deg,um\n0,2\xe9\n")
    code, _, err = run(capsys, "conjugate", "-e", "cw11-conjugate", "--df-mea", str(p))
    assert_one_error(code, err, "m.csv", "not UTF-8")
    p.write_bytes(b"\xef\xbb\xbftheta_deg,um\n0,20\n180,22\n")
    code, _, err = run(capsys, "conjugate", "-e", "cw11-conjugate", "--df-mea", str(p), "-q")
    assert code in (0, 1) and "error" not in err, err


def test_lift_table_encoding(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    (tmp_path / "lift.csv").write_bytes(b"theta_deg,lift_mm\n0,0\n5,\xff\n")
    text = re.sub(
        r"\[motion\].*?\]\n",
        '[motion]\ntable_file = "lift.csv"\n',
        example_text("roller-translating"),
        flags=re.S,
    )
    design = write(tmp_path, "d.toml", text)
    code, _, err = run(capsys, "analyze", str(design))
    assert_one_error(code, err, "motion.table_file", "not UTF-8")


def test_record_encoding(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    r = tmp_path / "r.csv"
    r.write_bytes(b"df_um,index\n1,1\n\xff,0\n")
    code, _, err = run(capsys, "conjugate", "-e", "cw11-conjugate", "--record", str(r))
    assert_one_error(code, err, "r.csv", "not UTF-8", "line 3")


# --- item 7: write errors, checked before computing ---------------------------------------
def test_output_is_a_directory(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    d = tmp_path / "dir.csv"
    d.mkdir()
    for args in (
        ["profile", "-e", "cw06-translating", "-o", str(d)],
        ["analyze", "-e", "cw06-translating", "--curves", str(d)],
        ["report", "-e", "cw06-translating", "-o", str(tmp_path)],
    ):
        code, _, err = run(capsys, *args)
        assert_one_error(code, err, "directory")


def test_proc_path(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "profile", "-e", "cw06-translating", "-o", "/proc/x.dxf")
    assert_one_error(code, err, "/proc/x.dxf")


def test_read_only_directory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Permission denied (simulated: the tests may run as root, who may write anywhere)."""
    import tempfile

    def refuse(*args: object, **kwargs: object) -> tuple[int, str]:
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    code, out, err = run(capsys, "profile", "-e", "cw06-translating", "-o", str(tmp_path / "x.csv"))
    assert_one_error(code, err, "permission denied")
    assert out == ""  # refused before computing


def test_disk_full(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def full(fd: int) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    old = tmp_path / "x.csv"
    old.write_text("old")
    code, _, err = run(capsys, "profile", "-e", "cw06-translating", "-o", str(old))
    assert_one_error(code, err, "disk is full")
    assert old.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["x.csv"]


# --- item 10: numerical failures get a message --------------------------------------------
@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("base_radius_mm = 40.0", "base_radius_mm = 1e300"),
        ('r = "IT6"', "r_um = 1e300"),
        ("[tolerances]", "[operation]\nspeed_rpm = 1e300\n\n[tolerances]"),
        ("lift_mm = 22.0", "lift_mm = 1e6"),
    ],
)
@pytest.mark.parametrize("cmd", ["analyze", "profile", "verify"])
def test_huge_values_give_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, old: str, new: str, cmd: str
) -> None:
    text = example_text("cw06-translating")
    assert old in text
    design = write(tmp_path, "d.toml", text.replace(old, new))
    code, out, err = run(capsys, *command_args(cmd, design, tmp_path))
    assert "Traceback" not in err
    if code != 0:
        assert_one_error(code, err)
    assert "nan" not in out.lower()


def test_profile_vertex_count_is_bounded(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    text = example_text("cw06-translating").replace("base_radius_mm = 40.0", "base_radius_mm = 9e4")
    design = write(tmp_path, "d.toml", text.replace("lift_mm = 22.0", "lift_mm = 1e4"))
    out = tmp_path / "p.csv"
    code, _, err = run(capsys, "profile", str(design), "-o", str(out), "--tolerance", "0.0001")
    assert_one_error(code, err, "vertices", "--tolerance")
    assert not out.exists()


def test_error_lines_are_short(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    raw = example_text("cw06-translating")
    design = write(tmp_path, "d.toml", raw.replace('name = "cw06-translating"', "name = [[1]]" * 1))
    nested = "[" * 20 + "]" * 20
    design.write_text(raw.replace('"cw06-translating"', nested))
    code, _, err = run(capsys, "analyze", str(design))
    assert_one_error(code, err)
    assert len(err.splitlines()[0]) <= 700


def test_loaded_design_roundtrip_still_works(tmp_path: Path) -> None:
    d = write(tmp_path, "d.toml", example_text("roller-oscillating"))
    check_design_geometry(load_design(d))


def test_geometry_error_names_cam_b() -> None:
    raw = tomllib.loads(_conjugate(arm_angle_deg=60.0))
    with pytest.raises(GeometryError, match="^cam B: pressure angle"):
        check_design_geometry(design_from_mapping(raw))


def test_program_size_is_bounded() -> None:
    import dataclasses

    from camtol.design.motion import LiftTable
    from camtol.exceptions import DesignError

    d = design_from_mapping(tomllib.loads(example_text("roller-translating")))
    n = 100_001
    theta = np.arange(n) * 2 * np.pi / n
    table = LiftTable(theta, 5 * (1 - np.cos(theta)))
    with pytest.raises(DesignError, match="100,001 segments or table entries"):
        check_design_geometry(dataclasses.replace(d, program=table))


def test_nul_byte_and_directory_inputs(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    p = tmp_path / "nul.toml"
    p.write_bytes(b'name = "x"\n\x00\n')
    code, _, err = run(capsys, "analyze", str(p))
    assert_one_error(code, err, "NUL byte", "line 2")
    code, _, err = run(capsys, "analyze", str(tmp_path))
    assert code == 2 and "Traceback" not in err


def test_check_writable(tmp_path: Path) -> None:
    from camtol.files import check_writable

    check_writable(tmp_path / "ok.csv")
    assert list(tmp_path.iterdir()) == []  # the probe file is removed
    with pytest.raises(OutputError, match="is a directory"):
        check_writable(tmp_path)
    with pytest.raises(OutputError, match="does not exist"):
        check_writable(tmp_path / "missing" / "x.csv")
