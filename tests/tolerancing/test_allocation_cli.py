"""Tolerance allocation and the montecarlo/allocate commands (issue 11)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol import iso286
from camtol.cli.app import main
from camtol.config.design_file import example_text, load_example
from camtol.exceptions import DesignError
from camtol.tolerancing import allocate
from camtol.tolerancing.montecarlo import prepare

CW06 = load_example("cw06-translating")


def _figure(design, grades, criterion):
    from camtol.tolerancing.allocation import _with_grades

    d = _with_grades(design, list(grades), tuple(grades.values()))
    st = prepare(d, step_deg=1.0)
    g = st.sens["lift"] * np.array(st.plan.deviations)
    if criterion == "rss":
        return float(np.sqrt((g * g).sum(axis=1)).max() * 1e3)
    return float(np.abs(g).sum(axis=1).max() * 1e3)


@pytest.mark.parametrize("criterion, spec_um", [("worst_case", 20.0), ("rss", 15.0)])
def test_allocation_is_minimal(criterion, spec_um):
    a = allocate(CW06, spec_um * 1e-3, criterion=criterion, step_deg=1.0, verify_samples=5000)
    assert _figure(CW06, a.grades, criterion) <= spec_um
    grades = iso286.GRADES
    for k, g in a.grades.items():
        coarser = dict(a.grades)
        if g == "IT12":
            assert a.coarser_fails[k] is None
            continue
        coarser[k] = grades[grades.index(g) + 1]
        assert _figure(CW06, coarser, criterion) > spec_um  # one grade coarser breaks it
        assert a.coarser_fails[k] is True
    # Verified by Monte Carlo: bounded zones never exceed the worst case; RSS is the
    # 99.73 % band of normals at Cp = 1 (fewer fail with truncation).
    if criterion == "worst_case":
        assert a.verified.value == 1.0
    else:
        assert a.verified.ci95[1] >= 0.9973


def test_allocation_monte_carlo_yield():
    a = allocate(
        CW06, 15e-3, criterion="monte_carlo", samples=4000, verify_samples=20000, step_deg=1.0
    )
    assert a.achieved >= 0.9973
    assert all(v in (True, None) for v in a.coarser_fails.values())
    assert a.verified.ci95[1] >= 0.9973


def test_spec_no_grade_can_meet():
    with pytest.raises(DesignError, match="cannot be met .* source 'r' dominates"):
        allocate(CW06, 2e-3, step_deg=1.0)


def test_cli_montecarlo_files(tmp_path: Path, capsys):
    csv, png = tmp_path / "c.csv", tmp_path / "p.png"
    code = main(
        [
            "montecarlo",
            "-e",
            "cw06-translating",
            "--samples",
            "3000",
            "--spec-um",
            "20",
            "--step",
            "1",
            "--json",
            "--curves",
            str(csv),
            "--plot",
            str(png),
        ]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("samples", "seed", "mode", "max_abs_dS", "yield", "contributions", "comparison"):
        assert key in out
    assert set(out["max_abs_dS"]) == {
        "mean",
        "std",
        "q00135",
        "q50",
        "q99865",
        "method",  # sampled (issue 28): with its 95 % intervals
        "ci95",
    }
    assert len(out["yield"]["ci95"]) == 2
    assert {c["source"] for c in out["contributions"]} == {"r", "e", "phi"}
    assert out["comparison"][-1]["source"] == "combined"
    header = csv.read_text().splitlines()[0].split(",")
    assert header == [
        "theta_deg",
        "dS_mean_um",
        "dS_std_um",
        "dS_q00135_um",
        "dS_q50_um",
        "dS_q99865_um",
        "share_r",
        "share_e",
        "share_phi",
        "dS_tolerance_um",  # issue 28: the bound on the deterministic quantiles' error
        "p_out",  # and the probability of leaving the spec at each angle
    ]
    assert png.stat().st_size > 0


def _design(tmp_path: Path, extra: str) -> Path:
    p = tmp_path / "d.toml"
    p.write_text(example_text("cw06-translating") + "\n" + extra)
    return p


@pytest.mark.parametrize(
    "extra, args, message",
    [
        ('[statistics]\ne = { distribution = "weibull" }', [], "distribution='weibull' is unknown"),
        ("[statistics]\ne = { cp = 0 }", [], "Cp must be > 0"),
        ("[statistics]\ne = { zone_lower_um = 5, zone_upper_um = -5 }", [], "zone lower"),
        ("[statistics]\nq = { cp = 1 }", [], "statistics.q is not a toleranced source"),
        ("", ["--samples", "0"], "--samples=0"),
        ("", ["--samples", "1000000", "--mode", "exact"], "too large for exact mode"),
    ],
)
def test_cli_bad_input(tmp_path: Path, capsys, extra, args, message):
    d = _design(tmp_path, extra)
    csv = tmp_path / "out.csv"
    argv = ["montecarlo", str(d), "--curves", str(csv), "--step", "1"]
    if "--samples" not in args:
        argv += ["--samples", "100"]
    code = main(argv + args)
    err = capsys.readouterr().err
    assert code == 2
    assert message in err and len(err.strip().splitlines()) == 1
    assert not csv.exists()


def test_cli_allocate_unmeetable(capsys):
    code = main(["allocate", "-e", "cw06-translating", "--spec-um", "2"])
    err = capsys.readouterr().err
    assert code == 2 and "dominates" in err and "IT5" in err


def test_cli_allocate(capsys):
    code = main(
        [
            "allocate",
            "-e",
            "cw06-translating",
            "--spec-um",
            "20",
            "--json",
            "--verify-samples",
            "2000",
        ]
    )
    out = json.loads(capsys.readouterr().out)
    assert code == 0
    assert set(out["grades"]) == {"r", "e", "phi"}
    assert out["achieved"] <= 20 and math.isfinite(out["cost"])


def test_report_montecarlo_section(tmp_path: Path, capsys):
    out = tmp_path / "r.html"
    assert (
        main(
            [
                "report",
                "-e",
                "cw06-translating",
                "-o",
                str(out),
                "--step",
                "1",
                "--montecarlo",
                "1000",
                "-q",
            ]
        )
        == 0
    )
    html = out.read_text()
    assert "Monte Carlo (linear mode, 1000 samples" in html
    assert "Worst case, RSS and Monte Carlo" in html
    bad = tmp_path / "bad.html"
    assert main(["report", "-e", "cw06-translating", "-o", str(bad), "--montecarlo", "0"]) == 2
    assert "--montecarlo=0" in capsys.readouterr().err and not bad.exists()


def test_pareto_and_hull_reductions_are_exact(rng):
    from camtol.tolerancing.allocation import _hull_angles, _pareto_rows

    st = prepare(load_example("roller-oscillating"), step_deg=1.0)
    g = st.sens["lift"]
    t = rng.uniform(0.1, 1.0, size=(200, g.shape[1]))
    p = np.abs(g)
    np.testing.assert_allclose(
        (_pareto_rows(p) @ t.T).max(axis=0), (p @ t.T).max(axis=0), rtol=1e-15
    )
    g3 = prepare(CW06, step_deg=1.0).sens["lift"]
    x = rng.standard_normal((200, 3))
    np.testing.assert_allclose(
        np.abs(x @ g3[_hull_angles(g3)].T).max(axis=1), np.abs(x @ g3.T).max(axis=1), rtol=1e-13
    )
    assert _hull_angles(g3).size < g3.shape[0]


@pytest.mark.parametrize(
    "extra, criterion, message",
    [
        (
            "[statistics]\ne = { zone_lower_um = -3, zone_upper_um = 5 }",
            "worst_case",
            "statistics.e: a fixed zone",
        ),
        ("[statistics]\nr = { bias_um = 2 }", "monte_carlo", "statistics.r: a bias"),
    ],
)
def test_cli_allocate_refuses_statistics_it_cannot_scale(
    tmp_path: Path, capsys, extra, criterion, message
):
    """A fixed zone or bias does not scale with the candidate grade: one line, exit 2."""
    d = _design(tmp_path, extra)
    argv = ["allocate", str(d), "--spec-um", "30", "--criterion", criterion, "--samples", "500"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_allocate_worst_case_accepts_a_bias(tmp_path: Path):
    """Worst case and RSS use ±T only: a bias inside the zone does not change them."""
    from camtol.config.design_file import load_design
    from camtol.tolerancing import allocate

    plain = allocate(load_design(_design(tmp_path, "")), 0.03, verify_samples=500)
    biased = allocate(
        load_design(_design(tmp_path, "[statistics]\nr = { bias_um = 2 }")),
        0.03,
        verify_samples=500,
    )
    assert biased.grades == plain.grades


def test_report_montecarlo_section_with_a_spec_or_band(tmp_path: Path, capsys):
    """--mc-spec-um / --mc-band give the report's Monte Carlo section its yield, the same
    yield `camtol montecarlo` gives with the same seed (0), samples and grid."""
    import json

    base = ["-e", "cw06-translating", "--step", "1"]
    out = tmp_path / "r.html"
    argv = ["report", *base, "-o", str(out), "--montecarlo", "2000", "--mc-spec-um", "18", "-q"]
    assert main(argv) == 0
    assert main(["montecarlo", *base, "--samples", "2000", "--spec-um", "18", "--json"]) == 0
    y = json.loads(capsys.readouterr().out)["yield"]["value"]
    assert f"Yield (max |dS| &lt;= 18 um): {y:.4%}" in out.read_text()
    band = tmp_path / "b.csv"
    band.write_text("theta_deg,lower_um,upper_um\n0,-15,20\n180,-15,20\n")
    out2 = tmp_path / "r2.html"
    argv = ["report", *base, "-o", str(out2), "--montecarlo", "2000", "--mc-band", str(band)]
    assert main([*argv, "-q"]) == 0
    assert "lower &lt;= dS &lt;= upper at every angle, band b.csv" in out2.read_text()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--mc-spec-um", "18"], "--mc-spec-um is only allowed with --montecarlo N"),
        (["--montecarlo", "10", "--mc-spec-deg", "0.1"], "--mc-spec-deg=0.1 is not allowed: the"),
        (["--montecarlo", "10", "--mc-spec-um", "-1"], "--mc-spec-um=-1.0 is not allowed; give"),
    ],
)
def test_report_montecarlo_limit_refusals(tmp_path: Path, capsys, args, message):
    out = tmp_path / "r.html"
    assert main(["report", "-e", "cw06-translating", "-o", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and not out.exists()
