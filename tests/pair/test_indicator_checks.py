"""Indicator records: validation (issue 9 items 11, 13) and missed index marks (issue 12 item 8).

A missed index mark makes one "revolution" of two mapped onto 360°; a spurious one cuts a
revolution short. The rule (documented in :func:`camtol.inspection.process_record`): a
revolution with more than 1.5× or fewer than 1/1.5 ≈ 0.67× the median number of samples is
an error naming its sample range, or with ``drop_bad_revolutions`` is excluded and
reported.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import camtol.tables
from camtol.cli.app import main
from camtol.exceptions import InputFileError
from camtol.pair.indicator import (
    REVOLUTION_RATIO,
    IndicatorRecord,
    process_record,
    read_indicator_csv,
    write_indicator_csv,
)
from camtol.pair.twin import simulate_record


def truth(theta: np.ndarray) -> np.ndarray:
    """The known Δf(θ) of the simulated records. [µm]"""
    return 22.0 + 3.0 * np.sin(theta) + 1.5 * np.cos(3.0 * theta)


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


# --- record validation: time_s, duplicates, magnitudes (issue 9 item 11) --------------------
@pytest.mark.parametrize(
    ("content", "pattern"),
    [
        (
            "time_s,df_um,index\n0,1,1\n0.2,2,0\n0.1,3,0\n0.3,4,1\n",
            r"line 4: time_s=0.1 goes back from 0.2 s .*must increase strictly",
        ),
        (
            "time_s,df_um,index\n5,1,1\n5,2,0\n5,3,0\n5,4,1\n",
            r"line 3: time_s=5 repeats 5 s .*must increase strictly",
        ),
        (
            "time_s,df_um,index\n-1,1,1\n0,2,0\n1,3,0\n2,4,1\n",
            r"line 2: time_s=-1 is not allowed; sample times are finite and ≥ 0 s",
        ),
        (
            "df_um,index,df_um\n1,1,1\n2,0,2\n3,0,3\n4,1,4\n",
            r"line 1: column 'df_um' is given twice",
        ),
        (
            "# header comment\ndf_um,index\n1,1\n1e300,0\n3,0\n4,1\n",
            r"line 4: df_um=1e\+300 is not allowed; an indicator reading must be a finite number"
            r" within ±10000 µm",
        ),
        ("df_um,index\n1,1\n-2e4,0\n3,0\n4,1\n", r"line 3: df_um=-20000 is not allowed"),
    ],
    ids=["time-back", "time-constant", "time-negative", "duplicate-df_um", "1e300", "-2e4"],
)
def test_record_validation_names_the_line(tmp_path: Path, content: str, pattern: str) -> None:
    path = tmp_path / "r.csv"
    path.write_text(content)
    with pytest.raises(InputFileError, match=pattern) as info:
        read_indicator_csv(path)
    assert str(info.value).startswith(str(path))


def test_records_built_in_python_are_checked_too() -> None:
    with pytest.raises(InputFileError, match=r"py: sample 3: time_s=1 repeats 1 s"):
        IndicatorRecord(np.zeros(4), np.array([1, 0, 0, 1], bool), np.array([0, 1, 1, 2.0]), "py")
    with pytest.raises(InputFileError, match=r"py: sample 2: df_um=inf is not allowed"):
        IndicatorRecord(np.array([0, np.inf, 0, 0]), np.array([1, 0, 0, 1], bool), source="py")


@pytest.mark.parametrize("value", ["1e300", "nan", "-inf"])
def test_cli_record_absurd_values_exit_2(
    tmp_path: Path, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "r.csv"
    path.write_text(f"df_um,index\n1,1\n{value},0\n3,0\n4,1\n")
    code, out, err = _run(["conjugate", "-e", "cw11-conjugate", "--record", str(path)], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert f"{path}, line 3" in err


# --- long records: the vectorised reader from the file (issue 9 item 13) --------------------
def test_large_file_path_reads_and_locates_errors(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Files above the in-memory size are parsed from the file: same numbers, same errors."""
    rec = simulate_record(truth, revolutions=3, samples_per_revolution=500, noise_um=0.5, rng=1)
    path = tmp_path / "r.csv"
    write_indicator_csv(rec, path)
    small = read_indicator_csv(path)
    monkeypatch.setattr(camtol.tables, "_KEEP_TEXT_CHARS", 64)  # force the streaming path
    big = read_indicator_csv(path)
    np.testing.assert_array_equal(big.df_um, small.df_um)
    np.testing.assert_array_equal(big.index, small.index)
    assert big.time_s is not None and small.time_s is not None
    np.testing.assert_array_equal(big.time_s, small.time_s)
    # UTF-16 with BOM, CRLF and an ignored text column, through the streaming path
    lines = path.read_text().splitlines()
    lines[1] += ",operator"
    lines[2:] = [line + ",anna" for line in lines[2:]]
    u16 = tmp_path / "u16.csv"
    u16.write_bytes("\r\n".join(lines).encode("utf-16"))
    np.testing.assert_array_equal(read_indicator_csv(u16).df_um, small.df_um)
    # an error deep in the file is located (file, line, column)
    lines = path.read_text().splitlines()
    lines[700] = lines[700].replace(",0", ",x", 1)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputFileError, match=r"bad\.csv, line 701, column .*'x' is not a number"):
        read_indicator_csv(bad)


# --- missed and spurious index marks (issue 12 item 8) --------------------------------------
def _with_missed_mark(rec: IndicatorRecord, which: int) -> IndicatorRecord:
    index = rec.index.copy()
    index[rec.marks[which]] = False
    return IndicatorRecord(rec.df_um, index, rec.time_s, "missed")


def test_missed_index_mark_is_an_error_naming_the_samples() -> None:
    rec = simulate_record(truth, revolutions=10, samples_per_revolution=4500, noise_um=0.5)
    bad = _with_missed_mark(rec, 4)  # revolutions 4 and 5 merge into samples 13501-22500
    with pytest.raises(InputFileError, match=r"revolution 4 \(samples 13501-22500\) has 9000"):
        process_record(bad)
    with pytest.raises(InputFileError, match=r"2\.00× the median 4500 \(a missed index mark\?\)"):
        process_record(bad)


def test_spurious_index_mark_is_an_error() -> None:
    rec = simulate_record(truth, revolutions=10, samples_per_revolution=4500, noise_um=0.5)
    index = rec.index.copy()
    index[rec.marks[2] + 1000] = True  # revolution 3 cut at 1000 samples
    with pytest.raises(InputFileError, match=r"revolution 3 \(samples 9001-10000\) has 1000"):
        process_record(IndicatorRecord(rec.df_um, index, rec.time_s, "spurious"))


def test_dropping_bad_revolutions_recovers_the_clean_mean() -> None:
    rec = simulate_record(truth, revolutions=10, samples_per_revolution=4500, noise_um=0.5)
    p = process_record(_with_missed_mark(rec, 4), drop_bad_revolutions=True)
    assert p.revolutions == 8 and p.dropped_revolutions == ((4, 13501, 22500),)
    assert any("revolution 4 (samples 13501-22500)" in n for n in p.notes)
    # the same as the clean record without revolutions 4 and 5 (the same samples)
    clean = process_record(rec)
    keep = [0, 1, 2, 5, 6, 7, 8, 9]
    np.testing.assert_allclose(p.df_mea_um, clean.resampled_um[keep].mean(axis=0), atol=1e-12)
    # the missed mark would have made the mean far worse than the record's noise
    merged_error = np.abs(clean.df_mea_um - p.df_mea_um).max()
    assert merged_error < 1.0  # µm: both are clean means of 8-10 revolutions


def test_speed_drift_within_the_ratio_is_accepted() -> None:
    counts = [4000, 4500, 5000, 4200, 4800]  # ±11 %: ordinary drift, well inside 1.5×
    rec = simulate_record(truth, revolutions=5, samples_per_revolution=counts, noise_um=0.0)
    assert process_record(rec).revolutions == 5
    assert REVOLUTION_RATIO == 1.5


def test_two_revolutions_too_far_apart_cannot_be_told() -> None:
    rec = simulate_record(truth, revolutions=2, samples_per_revolution=[1000, 1600], noise_um=0)
    for drop in (False, True):
        with pytest.raises(InputFileError, match=r"two revolutions .* 1000 and 1600 samples"):
            process_record(rec, drop_bad_revolutions=drop)
    ok = simulate_record(truth, revolutions=2, samples_per_revolution=[1000, 1400], noise_um=0)
    assert process_record(ok).revolutions == 2


def test_cli_drop_bad_revolutions(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rec = simulate_record(truth, revolutions=6, samples_per_revolution=900, noise_um=0.5)
    path = tmp_path / "r.csv"
    write_indicator_csv(_with_missed_mark(rec, 2), path)
    args = ["conjugate", "-e", "cw11-conjugate", "--step", "1", "--record", str(path)]
    code, out, err = _run(args, capsys)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "revolution 2 (samples 901-2700)" in err and "--drop-bad-revolutions" in err
    code, out, err = _run([*args, "--drop-bad-revolutions", "--json"], capsys)
    assert code in (0, 1), err
    record = json.loads(out)["record"]
    assert record["revolutions"] == 4
    assert record["dropped_revolutions"] == [
        {"revolution": 2, "first_sample": 901, "last_sample": 2700}
    ]
    code, out, err = _run([*args, "--drop-bad-revolutions"], capsys)
    flat = " ".join(out.split())  # the terminal wraps long notes
    assert "excluded" in flat and "revolution 2 (samples 901-2700)" in flat
    code, out, err = _run(["conjugate", "-e", "cw11-conjugate", "--drop-bad-revolutions"], capsys)
    assert code == 2 and "--drop-bad-revolutions applies to --record" in err
