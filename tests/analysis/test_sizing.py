"""`camtol size` and the sizing aid (issue 13 item 4): minimum base radius, computed."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from camtol.analysis.kinematics import analysis_grid
from camtol.analysis.sizing import (
    _cam_kinematics,
    _pressure_angle_problem,
    _problems,
    minimum_base_radius,
)
from camtol.analysis.summary import cam_geometry
from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError


def test_flat_translating_matches_closed_form() -> None:
    # THEORY §2.1: rho = r_b + (S + A) cos(phi), so rho >= rho_min needs
    # r_b >= rho_min - min(S + A) cos(phi): the search must land there to its resolution.
    d = load_example("cw06-translating")
    theta, left = analysis_grid(0.1, d.program.boundaries_rad)
    m = d.program.evaluate(theta, left_limit=left)
    cphi = math.cos(d.mechanism.face_angle_rad)
    for rho_min in (None, 5.0, 20.0):
        r = minimum_base_radius(d, min_radius_mm=rho_min, tolerance_mm=1e-4)
        expected = (rho_min or 0.0) - float(np.min(m.lift + m.acceleration)) * cphi
        assert r.base_radius_mm == pytest.approx(expected, abs=2e-4)
        assert r.base_radius_mm >= expected


@pytest.mark.parametrize(
    "name", ["roller-translating", "roller-oscillating", "cw06-oscillating", "cw06-translating"]
)
def test_bracket_answer_works_and_one_tolerance_less_does_not(name: str) -> None:
    d = load_example(name)
    limit = 32.0
    r = minimum_base_radius(d, pressure_angle_limit_deg=limit, tolerance_mm=1e-3)
    for c in r.cams:
        assert c.max_abs_pressure_angle_deg <= limit
        assert c.min_convex_radius_mm > 0
    smaller = dataclasses.replace(
        d, mechanism=dataclasses.replace(d.mechanism, base_radius_mm=r.base_radius_mm - 1e-3)
    )
    assert _fails(smaller, limit), "one resolution below the answer, a requirement must fail"


def _fails(design: CamDesign, limit: float) -> bool:
    theta, left = analysis_grid(0.1, design.program.boundaries_rad)
    for label, mech, kin in _cam_kinematics(design, theta, left):
        s = cam_geometry(label, mech, kin)
        if _problems(s, kin) or s.max_abs_pressure_angle_deg > limit:
            return True
    return False


def test_roller_pressure_angle_limit_is_met_exactly() -> None:
    d = load_example("roller-translating")
    r = minimum_base_radius(d, pressure_angle_limit_deg=30.0, tolerance_mm=1e-4)
    assert r.limiting == "pressure angle"
    assert r.cams[0].max_abs_pressure_angle_deg == pytest.approx(30.0, abs=0.01)


def test_offset_optimisation_never_worse() -> None:
    d = load_example("roller-translating")
    plain = minimum_base_radius(d, pressure_angle_limit_deg=30.0)
    best = minimum_base_radius(d, pressure_angle_limit_deg=30.0, optimise_offset=True)
    assert best.offset_mm is not None
    assert best.base_radius_mm <= plain.base_radius_mm + 1e-3


def test_cutter_radius_limits_concave_stretches() -> None:
    d = load_example("roller-translating")
    r = minimum_base_radius(d, pressure_angle_limit_deg=30.0, cutter_radius_mm=50.0)
    assert all(c.min_concave_radius_mm >= 50.0 for c in r.cams)


def test_no_radius_cures_v_at_least_one() -> None:
    d = load_example("cw06-oscillating")
    from camtol.design.motion import Segment, SegmentProgram

    fast = SegmentProgram(
        (
            Segment("rise", 0.0, math.radians(5.0), "cycloidal", math.radians(15.0)),
            Segment("dwell", math.radians(5.0), math.radians(180.0), "cycloidal", 0.0),
            Segment(
                "return", math.radians(180.0), math.radians(300.0), "cycloidal", math.radians(15.0)
            ),
            Segment("dwell", math.radians(300.0), math.radians(360.0), "cycloidal", 0.0),
        )
    )
    with pytest.raises(DesignError, match="no base radius helps.*V reaches"):
        minimum_base_radius(dataclasses.replace(d, program=fast))


def test_no_radius_works_names_the_limits_given() -> None:
    # A convex radius of 1e30 mm cannot be met; the message said which criteria failed but
    # not the limits the user gave, so a mistyped limit was hard to spot.
    d = load_example("roller-translating")
    stated = r"\(\|φ\| ≤ 20°, convex ρ ≥ 1e\+30 mm\)"
    with pytest.raises(DesignError, match=rf"no base radius .* {stated}"):
        minimum_base_radius(d, pressure_angle_limit_deg=20.0, min_radius_mm=1e30)


def test_cli_size_text_and_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["size", "--example", "roller-translating", "--pressure-angle-limit", "30"]) == 0
    out = capsys.readouterr().out
    assert "base radius r_b" in out and "mm minimum" in out and "max |φ| 30.00°" in out
    assert main(["size", "--example", "cw11-conjugate", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {c["cam"] for c in doc["cams"]} == {"A", "B"}
    assert doc["base_radius_mm"] > 0 and isinstance(doc["limiting"], str)


@pytest.mark.parametrize(
    ("flag", "value"),
    [("--pressure-angle-limit", "-3"), ("--pressure-angle-limit", "95"), ("--min-radius", "nan")],
)
def test_cli_size_bad_flags(flag: str, value: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["size", "--example", "cw06-translating", flag, value]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{flag}=" in err and "Traceback" not in err


def test_analyze_failure_says_which_radius_works(
    tmp_path: object, capsys: pytest.CaptureFixture[str]
) -> None:
    from pathlib import Path

    from camtol.config.design_file import example_text

    p = Path(str(tmp_path)) / "small.toml"
    p.write_text(
        example_text("cw06-translating").replace("base_radius_mm = 40.0", "base_radius_mm = 20.0")
    )
    assert main(["analyze", str(p)]) == 2
    err = capsys.readouterr().err
    assert "a base radius of at least 24.66 mm would work" in err
    assert err.count("\n") == 1


@pytest.mark.parametrize(
    ("max_abs_deg", "limit_deg", "problem"),
    [
        (30.0, 30.0, False),  # equal to the limit meets it, as the reports say
        (30.0 * (1 + 1e-13), 30.0, False),  # rounding noise of the limit
        (30.0 + 1e-9, 30.0, True),
        (89.0, None, False),
        (90.0, None, True),  # no cam works at 90°, with or without a limit
        (90.0, 90.0, True),
    ],
)
def test_pressure_angle_requirement_agrees_with_the_reports(
    max_abs_deg: float, limit_deg: float | None, problem: bool
) -> None:
    """Sizing and the reports apply one rule (kinematics.beyond_pressure_angle_limit)."""
    assert _pressure_angle_problem(max_abs_deg, limit_deg) is problem


# --- oscillating followers: the linkage sized too (issue 32 item 5) --------------------
def _with(design: CamDesign, rb: float, dims: dict[str, float]) -> CamDesign:
    mech = dataclasses.replace(design.mechanism, base_radius_mm=rb, **dims)
    return dataclasses.replace(design, mechanism=mech)


def _max_phi(design: CamDesign) -> float:
    theta, left = analysis_grid(0.1, design.program.boundaries_rad)
    return max(
        cam_geometry(label, mech, kin).max_abs_pressure_angle_deg
        for label, mech, kin in _cam_kinematics(design, theta, left)
    )


@pytest.mark.parametrize(
    ("name", "limit"), [("roller-oscillating", 30.0), ("cw06-oscillating", 25.0)]
)
def test_pivot_linkage_chooses_the_pivot_distance_and_keeps_the_arm(
    name: str, limit: float
) -> None:
    d = load_example(name)
    fixed = minimum_base_radius(d, pressure_angle_limit_deg=limit)
    r = minimum_base_radius(d, pressure_angle_limit_deg=limit, linkage="pivot")
    assert r.linkage == "pivot" and "pivot_distance_mm" in r.dimensions_mm
    # the pivot is a design freedom: never a larger cam than with the pivot fixed
    assert r.base_radius_mm <= fixed.base_radius_mm + r.tolerance_mm
    kept = {k: v for k, v in r.dimensions_mm.items() if k != "pivot_distance_mm"}
    assert kept == {k: r.given_dimensions_mm[k] for k in kept}  # arm (or face offset) kept
    chosen = _with(d, r.base_radius_mm, r.dimensions_mm)
    assert not _fails(chosen, limit), "the answer, rebuilt from its dimensions, works"
    if r.limiting != "pressure angle":  # e.g. undercut: f is then held by that, not by |φ|
        return
    # the chosen f is a minimum of max |φ|: moving the pivot 1 % either way is no better
    phi = _max_phi(chosen)
    f = r.dimensions_mm["pivot_distance_mm"]
    for factor in (0.99, 1.01):
        moved = _with(d, r.base_radius_mm, {**r.dimensions_mm, "pivot_distance_mm": f * factor})
        try:
            assert _max_phi(moved) >= phi - 0.05
        except DesignError:  # the moved pivot no longer reaches the cam: worse still
            pass


def test_scale_linkage_keeps_the_proportions() -> None:
    d = load_example("roller-oscillating")
    r = minimum_base_radius(d, pressure_angle_limit_deg=30.0, linkage="scale")
    k = r.base_radius_mm / r.given_base_radius_mm
    for key, value in r.dimensions_mm.items():
        assert value == pytest.approx(r.given_dimensions_mm[key] * k, rel=1e-12)
    assert not _fails(_with(d, r.base_radius_mm, r.dimensions_mm), 30.0)
    # the arm never shrinks to its roller: that requirement is checked
    assert r.dimensions_mm["arm_length_mm"] > d.mechanism.roller_radius_mm  # type: ignore[attr-defined]


def test_linkage_messages_name_the_followers_own_parameters(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with pytest.raises(
        DesignError, match=r"follower\.pivot_distance_mm and follower\.arm_length_mm"
    ):
        minimum_base_radius(load_example("roller-oscillating"), optimise_offset=True)
    with pytest.raises(DesignError, match="--optimise-offset for its offset e"):
        minimum_base_radius(load_example("roller-translating"), linkage="pivot")
    assert main(["size", "-e", "cw06-oscillating", "--optimise-offset"]) == 2
    err = capsys.readouterr().err
    assert "follower.pivot_distance_mm" in err and "a flat face's" not in err
    assert err.count("\n") == 1
    assert main(["size", "-e", "roller-oscillating", "--linkage", "pivot"]) == 0
    out = capsys.readouterr().out
    assert "pivot distance f" in out and "arm length l" in out and "kept" in out
    assert max(len(line) for line in out.splitlines()) <= 80
