"""The dial-indicator record of the conjugate fixture (THEORY §4.4; CW11 §4.2, §5).

Statistical bounds used below (σ = the simulated reading noise, R = 10 revolutions):

* at every grid point the mean Δf_mea carries noise of standard deviation at most σ/√R
  (linear interpolation between two independent samples with weights w, 1 − w has
  variance (w² + (1 − w)²)σ² ≤ σ²), so over 3600 points the largest error stays below
  5σ/√R (a 5-sigma bound, probability ~2e-3 of a false failure for an arbitrary seed; the
  seed is fixed). The interpolation error of the smooth truth is h²/8·max|f''| < 1e-5 µm
  with h = 0.08° between samples, negligible.
* 4500 samples per revolution sit every 0.08°; the 0.1° grid meets a sample every 0.4°
  (w = 0) and falls at w = 1/4, 1/2, 3/4 in between, so the mean of w² + (1 − w)² over the
  grid is 11/16: E[u_f²] = 9σ² there and 9σ²·11/16 over the whole grid (the linear
  interpolation THEORY §4.4 prescribes narrows u_f by about 17 % between samples). With
  9 degrees of freedom at each of 900 or 3600 points, the rms of u_f estimates 3σ (or
  3σ√(11/16)) to about 2 %: the tests allow 5 %.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.exceptions import DesignError, InputFileError
from camtol.inspection import ErrorFunction
from camtol.pair.fixture import inspect_conjugate
from camtol.pair.indicator import (
    IndicatorRecord,
    process_record,
    read_indicator_csv,
    record_estimates,
    to_error_function,
    write_indicator_csv,
)
from camtol.pair.twin import simulate_record

SIGMA = 0.5  # µm


def truth(theta: np.ndarray) -> np.ndarray:
    """The known Δf(θ) of the simulated records. [µm]"""
    return 22.0 + 3.0 * np.sin(theta) + 1.5 * np.cos(3.0 * theta)


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(x))))


# --- processing ---------------------------------------------------------------------------
def test_mean_recovers_truth_and_u_f_is_three_sigma(rng: np.random.Generator) -> None:
    rec = simulate_record(
        truth, revolutions=10, samples_per_revolution=4500, noise_um=SIGMA, rng=rng
    )
    assert rec.df_um.size == 10 * 4500 + 1 and rec.marks.size == 11
    p = process_record(rec)
    assert p.theta_deg.size == 3600 and p.theta_deg[1] == pytest.approx(0.1)
    assert p.revolutions == 10 and list(p.samples_per_revolution) == [4500] * 10
    assert p.resampled_um.shape == (10, 3600)
    err = p.df_mea_um - truth(np.radians(p.theta_deg))
    assert np.abs(err).max() < 5 * SIGMA / math.sqrt(10) + 1e-3
    assert _rms(err) == pytest.approx(SIGMA / math.sqrt(10) * math.sqrt(11 / 16), rel=0.1)
    on_samples = p.u_f_um[::4]  # θ = 0.4°·k coincides with sample 5k
    assert _rms(on_samples) == pytest.approx(3 * SIGMA, rel=0.05)
    assert _rms(p.u_f_um) == pytest.approx(3 * SIGMA * math.sqrt(11 / 16), rel=0.05)
    assert p.u_f_rms_um == pytest.approx(_rms(p.u_f_um))
    assert p.u_f_max_um == pytest.approx(p.u_f_um.max())
    assert p.df_mea_rms_um == pytest.approx(_rms(p.df_mea_um))
    assert p.notes == ()


def test_noise_free_record_is_exact() -> None:
    p = process_record(simulate_record(truth, noise_um=0.0))
    np.testing.assert_allclose(p.df_mea_um, truth(np.radians(p.theta_deg)), atol=1e-5)
    assert np.abs(p.u_f_um).max() < 1e-9


def test_speed_drift_between_revolutions() -> None:
    counts = [4500, 4300, 4700, 4480, 4620, 4390, 4500, 4555, 4410, 4690]
    rec = simulate_record(truth, samples_per_revolution=counts, noise_um=0.0)
    p = process_record(rec)
    assert list(p.samples_per_revolution) == counts
    # every revolution mapped onto 0-360° on its own: all agree with the truth
    np.testing.assert_allclose(
        p.resampled_um, np.broadcast_to(truth(np.radians(p.theta_deg)), (10, 3600)), atol=1e-5
    )
    assert np.abs(p.u_f_um).max() < 1e-4
    assert any("vary from 4300 to 4700" in n for n in p.notes)


def test_samples_outside_complete_revolutions_are_discarded(rng: np.random.Generator) -> None:
    rec = simulate_record(truth, noise_um=0.0, leading_samples=777, trailing_samples=333, rng=rng)
    marks = rec.marks
    assert marks[0] == 777 and rec.df_um.size - marks[-1] == 334
    junk = rec.df_um.copy()
    junk[: marks[0]] = 9e3  # anything (within ±10 mm) outside the complete revolutions
    junk[marks[-1] :] = -9e3  # must not matter
    p = process_record(IndicatorRecord(junk, rec.index, rec.time_s, "junk"))
    ref = process_record(simulate_record(truth, noise_um=0.0))
    np.testing.assert_allclose(p.df_mea_um, ref.df_mea_um, atol=1e-12)
    assert p.revolutions == 10 and p.discarded_samples == 777 + 334
    assert any("777 before the first index mark" in n for n in p.notes)


def test_single_revolution_gives_zero_u_f_with_a_note(rng: np.random.Generator) -> None:
    p = process_record(simulate_record(truth, revolutions=1, noise_um=SIGMA, rng=rng))
    assert p.revolutions == 1
    assert np.all(p.u_f_um == 0.0) and p.u_f_max_um == 0.0
    assert any("single complete revolution" in n and "u_f is 0" in n for n in p.notes)


def test_grid_step_and_error_function() -> None:
    p = process_record(simulate_record(truth, noise_um=0.0), step_deg=0.5)
    assert p.theta_deg.size == 720
    f = to_error_function(p)
    assert isinstance(f, ErrorFunction) and "mean of 10 revolution(s)" in f.description
    t = np.radians(np.array([0.25, 123.4, 359.9]))
    np.testing.assert_allclose(f(t), truth(t), atol=1e-3)  # chords of a 0.5° table
    up = to_error_function(p, offset_u_f=1.0)
    np.testing.assert_allclose(up(t), f(t), atol=1e-9)  # u_f = 0 here
    with pytest.raises(DesignError, match="step_deg=0.7"):
        process_record(simulate_record(truth, noise_um=0.0), step_deg=0.7)


def test_simulate_record_rejects_bad_arguments() -> None:
    with pytest.raises(DesignError, match="revolutions=0"):
        simulate_record(truth, revolutions=0)
    with pytest.raises(DesignError, match="samples_per_revolution"):
        simulate_record(truth, revolutions=2, samples_per_revolution=[4500])
    with pytest.raises(DesignError, match="noise_um"):
        simulate_record(truth, noise_um=-1.0)
    a = simulate_record(truth, revolutions=2, rng=7)
    b = simulate_record(truth, revolutions=2, rng=np.random.default_rng(7))
    np.testing.assert_array_equal(a.df_um, b.df_um)  # a seed or a generator: reproducible
    ef = ErrorFunction.formula("22 + 3*sin(theta) + 1.5*cos(3*theta)")
    p = process_record(simulate_record(ef, noise_um=0.0, samples_per_revolution=900))
    np.testing.assert_allclose(p.df_mea_um, truth(np.radians(p.theta_deg)), atol=1e-3)
    listed = IndicatorRecord([1.0, 2.0, 3.0, 4.0], [1, 0, 0, 1])  # type: ignore[arg-type]
    assert listed.df_um.dtype == np.float64 and listed.index.dtype == bool
    with pytest.raises(InputFileError, match="equal length"):
        IndicatorRecord(np.zeros(3), np.zeros(2, dtype=bool))


# --- files -------------------------------------------------------------------------------
def test_round_trip(tmp_path: Path, rng: np.random.Generator) -> None:
    rec = simulate_record(truth, revolutions=3, noise_um=SIGMA, rng=rng, leading_samples=5)
    path = tmp_path / "rec.csv"
    write_indicator_csv(rec, path)
    back = read_indicator_csv(path)
    np.testing.assert_array_equal(back.df_um, rec.df_um)
    np.testing.assert_array_equal(back.index, rec.index)
    assert back.time_s is not None and rec.time_s is not None
    np.testing.assert_array_equal(back.time_s, rec.time_s)
    assert back.source == str(path)
    no_time = IndicatorRecord(rec.df_um, rec.index)
    write_indicator_csv(no_time, path)
    back = read_indicator_csv(path)
    assert back.time_s is None
    np.testing.assert_array_equal(back.df_um, rec.df_um)


def test_read_comments_extra_columns_and_column_order(tmp_path: Path) -> None:
    path = tmp_path / "rec.csv"
    path.write_text(
        "# fixture run 3\n"
        "index, operator, df_um , time_s\n"
        "0,x,1.5,0.0\n"
        "1,x,2.0,0.2\n"
        "# a comment in the middle\n"
        "\n"
        "0,x,2.5,0.4\n"
        "0,x,3.0,0.6\n"
        "1,x,2.0,0.8\n"
    )
    rec = read_indicator_csv(path)
    np.testing.assert_array_equal(rec.df_um, [1.5, 2.0, 2.5, 3.0, 2.0])
    np.testing.assert_array_equal(rec.index, [False, True, False, False, True])
    assert rec.time_s is not None and rec.time_s[-1] == pytest.approx(0.8)
    p = process_record(rec, step_deg=60.0)
    np.testing.assert_allclose(p.df_mea_um, [2.0, 2.25, 2.5, 2.75, 3.0, 2.5])


@pytest.mark.parametrize(
    ("content", "pattern"),
    [
        (
            "theta,um\n1,2\n",
            r"needs the columns df_um, index.*missing df_um, index; found: theta, um",
        ),
        ("df_um,time_s\n1,0\n", r"missing index; found: df_um, time_s"),
        ("", r"the indicator record is empty"),
        ("df_um,index\n1,1\n2,0\nabc,0\n3,1\n", r"line 4, column df_um: 'abc' is not a number"),
        (
            "df_um,index\n1,1\nnan,0\n2,0\n3,1\n",
            r"line 3, column df_um: 'nan' is not allowed; every value must be a finite",
        ),
        ("df_um,index\n1,1\n2,0\n3,0\n", r"found 1 index mark\(s\) in 3 samples; need at least 2"),
        ("df_um,index\n1,0\n2,0\n", r"found 0 index mark\(s\)"),
        ("df_um,index\n1,1\n2,2\n3,1\n", r"line 3: column index=2 is not allowed; give 1 where"),
        ("df_um,index,time_s\n1,1,0\n2,0\n3,1,1\n", r"line 3: expected 3 cells"),
        (
            "df_um,index\n1,1\n2,0\n3,1\n",
            r"revolution 1 \(samples 1-2\) has 2 sample\(s\); need at least 3",
        ),
        ("df_um,index,time_s\n1,1,0\n2,0,inf\n3,0,2\n4,1,3\n", r"line 3, column time_s: 'inf'"),
    ],
)
def test_read_errors_name_the_file_and_the_problem(
    tmp_path: Path, content: str, pattern: str
) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(InputFileError, match=pattern) as info:
        read_indicator_csv(path)
    assert str(path) in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nope.csv"
    with pytest.raises(InputFileError, match="cannot be read") as info:
        read_indicator_csv(path)
    assert str(path) in str(info.value)


# --- estimates at Δf_mea ± u_f and the command line ---------------------------------------
def test_record_estimates_bracket_the_mean(rng: np.random.Generator) -> None:
    d = load_example("cw11-conjugate")
    spec = d.inspection
    assert spec is not None
    p = process_record(simulate_record(truth, noise_um=SIGMA, rng=rng))
    spec = spec.__class__(
        spec.errors,
        spec.tolerance_a_um,
        spec.tolerance_b_um,
        spec.master_a,
        spec.master_b,
        to_error_function(p),
    )
    res = inspect_conjugate(d, spec, step_deg=0.5)
    est = record_estimates(d, spec, p, res.theta_rad)
    assert res.estimate is not None
    for upper, mean, lower in (
        (est.upper.dr_a_est_um, res.estimate.dr_a_est_um, est.lower.dr_a_est_um),
        (est.upper.dr_b_est_um, res.estimate.dr_b_est_um, est.lower.dr_b_est_um),
    ):
        assert np.all(upper > mean) and np.all(mean > lower)
    # Δf_mea ± u_f shift Δf_r by ± u_f exactly (eq. 19)
    np.testing.assert_allclose(est.upper.df_r_um - res.estimate.df_r_um, est.u_f_um, atol=1e-9)
    mx, mn = est.extremes["dr_A_est_upper"]
    assert mx.value >= est.upper.dr_a_est_um.max() - 1e-9
    assert mn.value <= est.upper.dr_a_est_um.min() + 1e-9


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def _intervals_close(a: list[list[float]], b: list[list[float]], tol: float) -> bool:
    return len(a) == len(b) and all(
        abs(x[0] - y[0]) <= tol and abs(x[1] - y[1]) <= tol for x, y in zip(a, b, strict=True)
    )


def test_cli_record_matches_df_mea_and_brackets(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A constant 22 µm record (THEORY §8.3) with a little noise (0.002 µm: enough for a
    # non-zero u_f, too little to move the failing-interval ends by 0.05°).
    rec = simulate_record(lambda t: np.full(t.shape, 22.0), noise_um=0.002, rng=11)
    path = tmp_path / "rec.csv"
    write_indicator_csv(rec, path)
    curves = tmp_path / "c.csv"
    code, out, err = _run(
        [
            "conjugate",
            "-e",
            "cw11-conjugate",
            "--record",
            str(path),
            "--json",
            "--curves",
            str(curves),
        ],
        capsys,
    )
    assert code == 1, err
    data = json.loads(out)
    code_ref, out_ref, err_ref = _run(
        ["conjugate", "-e", "cw11-conjugate", "--df-mea", "22um", "--json"], capsys
    )
    assert code_ref == 1, err_ref
    ref = json.loads(out_ref)
    assert data["passed"] == ref["passed"]
    for cam in ("A", "B"):
        got, want = data["verdicts"][cam], ref["verdicts"][cam]
        assert got["passed"] == want["passed"]
        assert _intervals_close(got["failing_intervals_deg"], want["failing_intervals_deg"], 0.05)
    r = data["record"]
    assert r["revolutions"] == 10
    assert r["samples_per_revolution"] == {"min": 4500, "max": 4500}
    assert 0 < r["u_f_max_um"] < 0.05 and 0 < r["u_f_rms_um"] <= r["u_f_max_um"]
    assert r["df_mea_rms_um"] == pytest.approx(22.0, abs=1e-3)
    for key in ("dr_A_est", "dr_B_est"):
        up, mean, lo = (data["extremes"][f"{key}{s}_um"] for s in ("_upper", "", "_lower"))
        assert up["max"] > mean["max"] > lo["max"] and up["min"] > mean["min"] > lo["min"]
    rows = np.genfromtxt(curves, delimiter=",", names=True)
    assert rows.dtype.names is not None
    for col in (
        "u_f_um",
        "dr_A_est_upper_um",
        "dr_A_est_lower_um",
        "dr_B_est_upper_um",
        "dr_B_est_lower_um",
    ):
        assert col in rows.dtype.names
    for cam in ("A", "B"):
        mean_col = rows[f"dr_{cam}_est_um"]
        assert np.all(rows[f"dr_{cam}_est_upper_um"] > mean_col)
        assert np.all(rows[f"dr_{cam}_est_lower_um"] < mean_col)


def test_cli_record_terminal_and_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "rec.csv"
    write_indicator_csv(simulate_record(truth, revolutions=1, noise_um=SIGMA, rng=2), path)
    code, out, err = _run(["conjugate", "-e", "cw11-conjugate", "--record", str(path)], capsys)
    assert code in (0, 1), err
    assert "Indicator record" in out and "1 revolution(s)" in out
    assert "u_f is 0" in out and "Δr_A,est at Δf_mea + u_f" in out
    code, out, err = _run(
        ["conjugate", "-e", "cw11-conjugate", "--record", str(path), "--df-mea", "22um"], capsys
    )
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "--record" in err and "--df-mea" in err and "mutually exclusive" in err
    bad = tmp_path / "bad.csv"
    bad.write_text("theta_deg,um\n0,1\n")
    code, out, err = _run(["conjugate", "-e", "cw11-conjugate", "--record", str(bad)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert str(bad) in err and "df_um" in err
    plain = tmp_path / "plain.csv"
    code, out, err = _run(
        ["conjugate", "-e", "cw11-conjugate", "-q", "--curves", str(plain)], capsys
    )
    assert code == 1, err
    with plain.open() as fh:
        header = next(csv.reader(fh))
    assert "u_f_um" not in header  # without --record the columns are as before
