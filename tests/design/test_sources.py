"""Mechanism.perturbed, CamDesign.cams and design-level error sources (issue 8).

The exact-against-closed-form checks of every follower's sources through ``perturbed`` and
the contact engine are in tests/mechanisms/contract.py
(``test_sensitivities_match_contact_engine``); here: the API contract itself.
"""

from __future__ import annotations

import dataclasses
import math
import sys

import numpy as np
import pytest

from camtol.analysis.errors import error_analysis
from camtol.config.design_file import example_names, load_example
from camtol.design.cam_design import Cam, CamDesign, ResolvedTolerance, ToleranceSpec
from camtol.design.sources import DESIGN_SOURCES, AngularPhase, register_design_source
from camtol.exceptions import DesignError
from camtol.mechanisms import FlatOscillating, FlatTranslating, RollerOscillating, RollerTranslating
from camtol.mechanisms.conjugate import ConjugateCamB, ConjugatePair
from camtol.verify import verify

PAIR = ConjugatePair(60.0, 16.0, 120.0, 66.0, 70.0, math.radians(100.0))
MECHS = [
    FlatTranslating(40.0, 5.0, math.radians(10.0)),
    FlatOscillating(40.0, 100.0, 5.0),
    RollerTranslating(40.0, 10.0, 8.0),
    RollerOscillating(60.0, 16.0, 120.0, 66.0),
    PAIR.cam_b,
    PAIR,
]


@pytest.mark.parametrize("mech", MECHS, ids=lambda m: m.kind)
def test_perturbed_moves_exactly_the_declared_parameter(mech: object) -> None:
    from camtol.mechanisms.base import Mechanism

    assert isinstance(mech, Mechanism)
    params = [s for s in mech.sources if s.parameter is not None]
    assert params, "every follower has at least one follower-parameter source"
    for src in params:
        assert src.parameter is not None
        out = mech.perturbed(src.key, 1e-3)
        assert type(out) is type(mech)
        if isinstance(mech, ConjugatePair) and src.key == "rf_d":
            # r_D defaulted to r_C: roller D alone moves from r_C
            assert out.roller_d_mm == mech.roller_d_mm + 1e-3  # type: ignore[attr-defined]
            assert out.roller_radius_mm == mech.roller_radius_mm  # type: ignore[attr-defined]
            continue
        assert getattr(out, src.parameter) == getattr(mech, src.parameter) + 1e-3
        changed = {
            f.name
            for f in dataclasses.fields(mech)  # type: ignore[arg-type]
            if getattr(out, f.name) != getattr(mech, f.name)
        }
        if isinstance(mech, ConjugatePair) and src.key in ("rf", "rf_c"):
            # r_D defaulted to r_C: pinned at the nominal value so that only roller C moves
            assert changed == {src.parameter, "roller_b_radius_mm"}
            assert out.roller_d_mm == mech.roller_d_mm  # type: ignore[attr-defined]
        else:
            assert changed == {src.parameter}


@pytest.mark.parametrize("mech", MECHS, ids=lambda m: m.kind)
@pytest.mark.parametrize("key", ["r", "n", "nonsense", "phase"])
def test_perturbed_refuses_non_parameters(mech: object, key: str) -> None:
    from camtol.mechanisms.base import Mechanism

    assert isinstance(mech, Mechanism)
    with pytest.raises(DesignError) as exc:
        mech.perturbed(key, 1e-3)
    msg = str(exc.value)
    assert repr(key) in msg and mech.kind in msg
    allowed = {k.strip() for k in msg.split("of:")[-1].split(",")}
    assert allowed == {s.key for s in mech.sources if s.parameter is not None}


def test_conjugate_cam_b_perturbs_eta() -> None:
    out = PAIR.cam_b.perturbed("eta", 1e-4)
    assert isinstance(out, ConjugateCamB)
    assert out.arm_angle_rad == PAIR.arm_angle_rad + 1e-4
    assert out.initial_angle_rad == PAIR.cam_b.initial_angle_rad


@pytest.mark.parametrize("name", example_names())
def test_cams_of_every_example(name: str) -> None:
    design = load_example(name)
    cams = design.cams()
    assert all(isinstance(c, Cam) for c in cams)
    if isinstance(design.mechanism, ConjugatePair):
        assert [c.label for c in cams] == ["A", "B"]
        a, b = cams
        assert a.mechanism == design.mechanism.cam_a
        assert b.mechanism == design.mechanism.cam_b
        for c in cams:
            assert c.design.mechanism is c.mechanism
            assert c.design.program is design.program
            assert c.design.speed_rpm == design.speed_rpm
            assert c.design.pressure_angle_limit_deg == design.pressure_angle_limit_deg
            # each cam gets the pair's tolerances of its own sources, under its own keys
            keys = design.mechanism.cam_source_keys(c.label)
            mine = [t for t in design.tolerances if t.key in keys]
            assert [t.key for t in c.design.tolerances] == [keys[t.key] for t in mine]
            assert [t.grade for t in c.design.tolerances] == [t.grade for t in mine]
            assert len(c.mechanism.cams()) == 1
    else:
        assert len(cams) == 1
        assert cams[0].label == ""
        assert cams[0].mechanism is design.mechanism
        assert cams[0].design is design


def test_cams_drop_tolerances_a_cam_does_not_have() -> None:
    design = load_example("cw11-conjugate")
    # cam B has η, cam A does not: a pair tolerance on a key only one cam has is kept there
    keys_a = {s.key for s in design.cams()[0].mechanism.sources}
    keys_b = {s.key for s in design.cams()[1].mechanism.sources}
    assert keys_b - keys_a == {"eta"}


# ---------------------------------------------------------------------------------------
# Design-level sources: the cam's angular phase on its shaft
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", example_names())
def test_phase_closed_form_against_exact(name: str) -> None:
    """ΔS = −V·Δθ0 against S(θ − Δθ0) − S(θ): second-order remainder (halving → ¼)."""
    design = load_example(name).cams()[0].design  # a conjugate pair: cam A
    theta = np.radians(np.linspace(0.0, 359.9, 3600))
    phase = DESIGN_SOURCES["phase"]
    nominal = design.program.evaluate(theta).lift
    diffs = []
    for dev in (math.radians(0.02), math.radians(0.01)):
        tol = ResolvedTolerance("phase", dev, "rad", "test")
        lin = error_analysis(design, (tol,), theta).sources["phase"]
        exact = phase.exact_lift(design.mechanism, design.program, theta, dev) - nominal
        assert np.max(np.abs(lin.delta_lift)) > 0
        diffs.append(np.max(np.abs(exact - lin.delta_lift)))
        # the linear term is ≥ 99 % of the answer at 0.02°
        assert diffs[-1] <= 0.01 * np.max(np.abs(lin.delta_lift))
        # ΔV, ΔA are −A·Δθ0 and −J·Δθ0
        m = design.program.evaluate(theta)
        np.testing.assert_allclose(lin.delta_velocity, -m.acceleration * dev, atol=1e-15)
        np.testing.assert_allclose(lin.delta_acceleration, -m.jerk * dev, atol=1e-12)
    if diffs[1] > 1e-13:  # lift tables with a smooth spline: second order
        assert 3.0 <= diffs[0] / diffs[1] <= 5.0


def test_phase_in_a_design_file_and_verify() -> None:
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib

    from camtol.config.design_file import design_from_mapping, example_text

    data = tomllib.loads(example_text("roller-translating"))
    data["tolerances"]["phase_deg"] = 0.05
    design = design_from_mapping(data)
    assert ToleranceSpec("phase", deviation=0.05) in design.tolerances
    res = design.resolve_tolerances(60.0)
    assert res[-1].key == "phase" and res[-1].deviation == pytest.approx(math.radians(0.05))
    assert design.source("phase").description.startswith("angular phase")
    v = verify(design, step_deg=1.0, polyline=False)
    assert v.linearisation["phase"].ok
    assert not v.linearisation["phase"].exact_to_rounding


def test_phase_takes_no_it_grade() -> None:
    # Issue 32: refused when the design is made (every command alike), not only when an
    # analysis resolves the tolerances.
    design = load_example("roller-translating")
    with pytest.raises(DesignError, match="tolerances.phase='IT7' cannot be applied"):
        dataclasses.replace(design, tolerances=(ToleranceSpec("phase", grade="IT7"),))


def test_register_design_source_refuses_duplicates() -> None:
    with pytest.raises(ValueError, match="already registered"):
        register_design_source(AngularPhase())


def test_unknown_tolerance_key_lists_design_sources() -> None:
    design = load_example("roller-translating")
    with pytest.raises(DesignError, match="phase"):
        CamDesign("x", design.mechanism, design.program, (ToleranceSpec("zz", deviation=1.0),))


def test_the_pair_is_not_a_single_cam() -> None:
    """ConjugatePair no longer stands for cam A: single-contact evaluation goes by cams()."""
    from camtol.analysis.kinematics import kinematics

    design = load_example("cw11-conjugate")
    theta = np.radians([10.0, 200.0])
    with pytest.raises(DesignError, match="design.cams"):
        kinematics(design, theta)
    a, b = (kinematics(c.design, theta) for c in design.cams())
    assert np.all(np.isfinite(a.pressure_angle_rad)) and np.all(np.isfinite(b.radius_mm))


def test_analyze_checks_every_cam() -> None:
    """Issue 9 item 3: a conjugate design whose cam B cannot work fails analyze, naming B."""
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - Python 3.10
        import tomli as tomllib

    from camtol.analysis.result import analyze
    from camtol.config.design_file import design_from_mapping, example_text
    from camtol.exceptions import GeometryError

    data = tomllib.loads(example_text("cw11-conjugate"))
    data["follower"]["arm_b_mm"] = 150.0  # cam B would reach the pivot
    with pytest.raises(GeometryError, match=r"^cam B: "):
        analyze(design_from_mapping(data), step_deg=1.0)
    ok = analyze(load_example("cw11-conjugate"), step_deg=1.0)
    assert ok.cam_kinematics("B").radius_mm.max() < 120.0
