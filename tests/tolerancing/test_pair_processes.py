"""A conjugate pair's random profile processes, per cam (issue 28 item 1)."""

from __future__ import annotations

import numpy as np
import pytest

from camtol.config import design_from_mapping
from camtol.config.examples import example_text, parse_toml
from camtol.exceptions import CamtolError
from camtol.pair.as_made import follow_pair_as_made
from camtol.tolerancing.model import statistical_model
from camtol.tolerancing.pair import _process_errors, pair_monte_carlo, prepare_pair
from camtol.tolerancing.plan import chunk_uniforms
from camtol.tolerancing.study import prepare

HARMONIC = "harmonics = [{ order = 3, amplitude_um = 6.0 }, { order = 7, amplitude_um = 3.0 }]"


def _pair(statistics: str, tolerances: str = 'r_a = "IT6"\nr_b = "IT6"') -> object:
    """cw11-conjugate with the given [tolerances] and [statistics] tables."""
    raw = example_text("cw11-conjugate")
    head, _, rest = raw.partition("[tolerances]")
    _, _, tail = rest.partition("\n[inspection]")
    text = head + "[tolerances]\n" + tolerances + "\n[inspection]" + tail + "\n" + statistics
    return design_from_mapping(parse_toml(text, "test design"))


def test_each_cam_takes_its_own_process_and_the_common_one_means_both() -> None:
    d = _pair(f"[statistics.profile_process_a]\n{HARMONIC}\n")
    study = prepare_pair(d, step_deg=2.0)
    assert study.plan.labels[-1] == "r_a_process"
    assert [letter for letter, _ in study.cam_processes] == ["A"]
    both = _pair(f'[statistics.profile_process]\ntarget = "r"\n{HARMONIC}\n')
    study2 = prepare_pair(both, step_deg=2.0)
    assert study2.plan.labels[-2:] == ("r_a_process", "r_b_process")
    # independent: two groups of columns, each with its own uniforms
    assert study2.plan.uniforms == len(study2.plan.distributions) + 4


def test_a_cam_process_on_a_single_cam_is_refused() -> None:
    raw = example_text("cw06-translating") + f"\n[statistics.profile_process_a]\n{HARMONIC}\n"
    with pytest.raises(CamtolError, match=r"profile_process_a.*conjugate pair"):
        design_from_mapping(parse_toml(raw, "test design"))


def test_a_bad_cam_process_names_its_table() -> None:
    with pytest.raises(CamtolError, match=r"statistics\.profile_process_b\.target='x'"):
        _pair('[statistics.profile_process_b]\ntarget = "x"\nsigma_um = 1\ncorrelation_deg = 9\n')


def test_cam_a_process_moves_delta_s_a_as_the_single_cam_study_of_cam_a() -> None:
    """Process columns of ΔS_A equal those of cam A's own single-cam plan (THEORY §3)."""
    d = _pair(f"[statistics.profile_process_a]\n{HARMONIC}\n")
    study = prepare_pair(d, step_deg=1.0)
    (a, b) = study.plan.process_groups[0]
    cam_a = d.cam("A").design
    model = statistical_model(d)
    single = prepare(
        cam_a,
        model=type(model)(process=model.cam_processes["A"]),
        step_deg=1.0,
    )
    g_single = single.sens["lift"][:, -(b - a) :]
    np.testing.assert_allclose(study.motion["A"][:, a:b], g_single, rtol=1e-10, atol=1e-14)
    assert not np.any(study.motion["B"][:, a:b])  # cam A's process does not move cam B's ΔS


def test_process_exact_and_linear_agree_to_second_order() -> None:
    """The exact pair with a sampled process on each cam against the linear model."""
    d = _pair(f'[statistics.profile_process]\ntarget = "r"\n{HARMONIC}\n', tolerances="f_um = 5")
    study = prepare_pair(d, step_deg=1.0)
    x = study.plan.sample(chunk_uniforms(3, 0, 2, study.plan.uniforms))
    gaps = []
    for k in (1.0, 0.5):
        worst = 0.0
        for row in x * k:
            out = follow_pair_as_made(
                d,
                study.sources,
                {"f": float(row[0])},
                study.theta_rad,
                profile_errors=_process_errors(study, row),
            )
            linear = row @ study.df.T
            assert np.abs(linear).max() > 1e-3  # the process moves Δf by µm
            worst = max(worst, float(np.abs(out.df_mm - linear).max()))
            for letter in ("A", "B"):
                lin_s = row @ study.motion[letter].T
                ex_s = out.motion[letter]
                assert np.abs(ex_s - lin_s).max() < 0.02 * np.abs(lin_s).max()
        gaps.append(worst)
    # second order: the gap falls by about 4 when the process halves
    assert 3.0 < gaps[0] / gaps[1] < 5.0, gaps


def test_process_pair_monte_carlo_linear_and_exact() -> None:
    d = _pair(f"[statistics.profile_process_b]\n{HARMONIC}\n")
    lin = pair_monte_carlo(d, 10, step_deg=2.0, seed=2)
    ex = pair_monte_carlo(d, 10, step_deg=2.0, seed=2, mode="exact")
    assert ex.interference_mm.max == pytest.approx(lin.interference_mm.max, abs=2e-4)
    assert "r_b_process" in lin.df_contributions
    assert lin.df_contributions["r_b_process"] > 0.0


def test_the_common_process_on_a_pair_is_noted() -> None:
    d = _pair(f'[statistics.profile_process]\ntarget = "r"\n{HARMONIC}\n')
    res = pair_monte_carlo(d, 50, step_deg=2.0)
    assert any("same process on cam A and cam B" in n for n in res.notes)


def test_json_sources_list_each_cams_process() -> None:
    d = _pair(f"[statistics.profile_process_b]\n{HARMONIC}\n")
    doc = pair_monte_carlo(d, 50, step_deg=2.0).to_dict()
    proc = [s for s in doc["sources"] if s["key"].endswith("_process")]
    assert proc == [
        {
            "key": "r_b_process",
            "tolerance_key": "profile_process_b",
            "cams": ["B"],
            "unit": "mm",
            "deviation": pytest.approx(0.009),
            "distribution": "harmonics",
            "mean": 0.0,
            # σ of Σ A_k cos(kψ + φ_k), φ_k uniform: sqrt(Σ A_k² / 2)
            "sigma": pytest.approx(np.sqrt((0.006**2 + 0.003**2) / 2)),
            "limits": [pytest.approx(-0.009), pytest.approx(0.009)],
            "target": "r",
        }
    ]
