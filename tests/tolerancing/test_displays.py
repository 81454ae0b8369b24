"""Displays that cannot be misread (issue 28, item 7): words, warnings, JSON, allocation."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.exceptions import DesignError
from camtol.report.tolerancing_display import display_montecarlo, source_numbers
from camtol.tolerancing import (
    ProfileProcess,
    SourceDistribution,
    StatisticalModel,
    allocate,
    monte_carlo,
)
from camtol.tolerancing.results import quantile_ci_ranks

CW06 = load_example("cw06-translating")
BASE = ["montecarlo", "-e", "cw06-translating", "--step", "2"]


def test_few_samples_warn_once_on_stderr(capsys: pytest.CaptureFixture[str]) -> None:
    # -n 1 used to print a "99.73 %" band from one sample without a word.
    assert main([*BASE, "-n", "1"]) == 0
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("warning:") and "from 1 sample " in err[0]
    assert "fewer than 1,000" in err[0]
    assert "deterministic" in captured.out  # the per-angle band needs no samples
    assert main([*BASE, "-n", "1000"]) == 0
    assert capsys.readouterr().err == ""
    assert main([*BASE, "-n", "5", "--json"]) == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert doc["warnings"] and len(captured.err.strip().splitlines()) == 1
    # Exact mode: every quantile is sampled, per angle too.
    assert main([*BASE, "-n", "3", "--mode", "exact", "--json"]) == 0
    captured = capsys.readouterr()
    assert "dS at each angle" in captured.err
    assert json.loads(captured.out)["per_angle"]["method"] == "sampled"


def test_exact_minus_linear_says_it_is_a_difference(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*BASE, "-n", "4", "--mode", "exact"]) == 0
    out = capsys.readouterr().out
    assert "exact - linear (max over θ)" not in out  # read as a contradictory distribution
    assert "linearisation error, exact minus linear on the same samples" in out
    assert "differences, not a distribution" in out
    assert "largest |exact - linear| over θ of the per-angle mean" in out
    assert main([*BASE, "-n", "4", "--mode", "exact", "--json"]) == 0
    lve = json.loads(capsys.readouterr().out)["linear_vs_exact"]
    assert "largest |difference| over the angles" in lve["definition"]


def test_sources_are_numbers() -> None:
    res = monte_carlo(CW06, 200, step_deg=2.0)
    doc = display_montecarlo(res, CW06).to_dict()
    r = doc["sources"]["r"]
    dev_um = res.sources["r"].upper * 1e3  # type: ignore[union-attr]
    assert r["distribution"] == "normal" and r["unit"] == "um"
    assert r["lower"] == pytest.approx(-dev_um) and r["upper"] == pytest.approx(dev_um)
    assert r["mean"] == 0.0 and r["truncated"] is True and r["cp"] == 1.0
    # σ of a normal truncated at ±3σ: 0.9866 of Δ/3
    assert r["std"] == pytest.approx(dev_um / 3 * 0.98658, rel=1e-4)
    assert isinstance(r["text"], str) and "truncated" in r["text"]
    phi = doc["sources"]["phi"]
    assert phi["unit"] == "deg"
    uni = source_numbers(SourceDistribution("uniform").resolve(0.01))
    assert uni["std"] == pytest.approx(20 / math.sqrt(12)) and uni["zone"] == [-10.0, 10.0]
    loose = source_numbers(SourceDistribution("normal", truncate=False).resolve(0.01))
    assert loose["lower"] is None and loose["upper"] is None  # unbounded
    harm = source_numbers(ProfileProcess("r", harmonics=((2, 3.0), (5, 4.0))))
    assert harm["distribution"] == "harmonics" and harm["upper"] == 7.0
    assert harm["std"] == pytest.approx(math.sqrt((9 + 16) / 2))
    gp = source_numbers(ProfileProcess("r", sigma_um=2.0, correlation_deg=10.0))
    assert gp["std"] == 2.0 and gp["lower"] is None


def test_quantile_intervals_are_distribution_free_order_statistics() -> None:
    # n = 1: the only sample is below the 99.865 % quantile w.p. 0.99865 (a lower bound
    # at 95 %), and no upper bound exists.
    assert quantile_ci_ranks(1, 0.99865) == (1, 2)
    lo, hi = quantile_ci_ranks(100_000, 0.5)
    assert 49_600 < lo < 50_000 < hi < 50_400  # ±1.96 √(n/4) ≈ ±310
    # Coverage by simulation: uniform samples, the true median 0.5.
    rng = np.random.default_rng(3)
    lo, hi = quantile_ci_ranks(200, 0.5)
    x = np.sort(rng.random((4000, 200)), axis=1)
    covered = np.mean((x[:, lo - 1] <= 0.5) & (0.5 <= x[:, hi - 1]))
    assert covered >= 0.94


def test_allocate_says_when_the_target_is_missed(capsys: pytest.CaptureFixture[str]) -> None:
    # RSS at 20 µm is far from a 99.99 % yield: the verification proves it.
    argv = ["allocate", "-e", "cw06-translating", "--spec-um", "20", "--criterion", "rss"]
    argv += ["--yield", "0.9999", "--verify-samples", "20000", "--json"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert doc["met"] is False and doc["target_yield"] == 0.9999
    assert doc["yield"]["ci95"][1] < 0.9999
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("warning:") and "does not meet" in err[0]
    a = allocate(CW06, 0.02, criterion="rss", target_yield=0.9999, step_deg=2.0)
    assert a.met is False and a.verdict == "not met"
    ok = allocate(CW06, 0.03, step_deg=2.0, verify_samples=2000)
    assert ok.met is True and ok.verdict == "met"
    argv = ["allocate", "-e", "cw06-translating", "--spec-um", "30", "--verify-samples", "2000"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "target 99.73 %: met" in captured.out and captured.err == ""  # 80 columns


@pytest.mark.parametrize("flag", ["--samples", "--verify-samples"])
def test_allocate_samples_have_the_montecarlo_upper_bound(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], flag: str
) -> None:
    # 1e11 ran out of memory; now one line, exit status 2, before any work.
    argv = ["allocate", "-e", "cw06-translating", "--spec-um", "30", flag, "100000000000"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "at most 1e+10 samples, as for camtol montecarlo" in err[0]
    with pytest.raises(DesignError, match="at most 1e"):
        allocate(CW06, 0.03, samples=10**11)


def test_allocate_streams_samples_beyond_its_memory_budget(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Held or drawn again chunk by chunk: the same choice and the same figures.
    import camtol.tolerancing.allocation as alloc

    kw = {"criterion": "monte_carlo", "samples": 5000, "verify_samples": 2000, "step_deg": 2.0}
    held = allocate(CW06, 0.015, **kw)  # type: ignore[arg-type]
    monkeypatch.setattr(alloc, "MAX_HELD_BYTES", 1024)
    streamed = allocate(CW06, 0.015, **kw)  # type: ignore[arg-type]
    assert streamed.grades == held.grades and streamed.achieved == held.achieved
    assert streamed.coarser_fails == held.coarser_fails
    assert streamed.evaluated == held.evaluated


def test_json_of_processes_and_derivatives_matches_the_schema() -> None:
    # Sources as numbers for every kind (untruncated normal, harmonics, Gaussian process),
    # a sampled process row in the comparison, and --derivatives' keys.
    from importlib.resources import files

    jsonschema = pytest.importorskip("jsonschema")
    text = (files("camtol") / "data" / "schemas" / "montecarlo.schema.json").read_text()
    validator = jsonschema.Draft202012Validator(json.loads(text))
    d = load_example("roller-oscillating")
    for model in (
        StatisticalModel(
            process=ProfileProcess("r", harmonics=((2, 3.0),)),
            default=SourceDistribution("normal", truncate=False),
        ),
        StatisticalModel(
            process=ProfileProcess("n", sigma_um=2.0, correlation_deg=15.0),
            sources={"rf": SourceDistribution("triangular")},
        ),
    ):
        qs = ("lift", "velocity", "acceleration")
        r = monte_carlo(d, 300, model=model, spec=0.001, quantities=qs, step_deg=2.0)
        doc = display_montecarlo(r, d).to_dict()
        head = {"schema_version": "1.0", "command": "montecarlo", "camtol_version": "0"}
        errors = [e.message for e in validator.iter_errors({**head, **doc})]
        assert not errors, errors[:3]
        methods = doc["methods"]["comparison_mc_9973"]
        assert methods["r"] == "deterministic" and methods["combined"] == "deterministic"
        assert [m for k, m in methods.items() if k.endswith("_process")] == ["sampled"]
