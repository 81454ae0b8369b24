"""`camtol verify` and camtol.verify: the contact engine checks the analytic engine."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.design.cam_design import CamDesign, ToleranceSpec
from camtol.design.motion import Segment, SegmentProgram
from camtol.mechanisms import RollerOscillating, RollerTranslating
from camtol.mechanisms.base import Mechanism
from camtol.verify import ROUNDTRIP_LIMIT, verify


def _program(h: float) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0.0, r(130), "cycloidal", h),
            Segment("dwell", r(130), r(180)),
            Segment("return", r(180), r(300), "polynomial_345", h),
            Segment("dwell", r(300), 2 * math.pi),
        )
    )


def _roller_design(mech: Mechanism, h: float) -> CamDesign:
    keys = [s.key for s in mech.sources if s.key != "n"]
    return CamDesign("roller", mech, _program(h), tuple(ToleranceSpec(k, "IT6") for k in keys))


@pytest.mark.parametrize("name", ["cw06-translating", "cw06-oscillating"])
def test_builtin_flat_examples_pass(name: str) -> None:
    v = verify(load_example(name))
    assert v.ok
    assert v.roundtrip_max_error <= ROUNDTRIP_LIMIT
    assert v.polyline is not None and v.polyline.ok
    # The polyline's lift error is the chordal sag (≤ 0.1 µm tolerance) over cos φ or u.
    assert 0 < v.polyline.chordal_sag_max_mm <= 1e-4
    for c in v.linearisation.values():
        # Acceptance: within 1 % of the linear value at the IT6 tolerances...
        assert c.max_difference <= 0.01 * c.linear_max
        # ...and of second order (halving the tolerance divides it by about 4).
        assert c.exact_to_rounding or 3.8 < c.halving_ratio < 4.2


def test_translating_sources_and_which_are_exact() -> None:
    v = verify(load_example("cw06-translating"), polyline=False)
    assert set(v.linearisation) == {"r", "e", "phi"}
    # ΔS_e = −Δe tan φ is exact (a shift of the translation line); r and φ are not.
    assert v.linearisation["e"].exact_to_rounding
    assert not v.linearisation["phi"].exact_to_rounding
    # THEORY §8.1: ΔS_e = −2.41 µm, ΔS_r max 19.67 µm, ΔS_φ max 4.704 µm (printed values).
    assert v.linearisation["e"].linear_max == pytest.approx(2.41, abs=0.005)
    assert v.linearisation["r"].linear_max == pytest.approx(19.67, abs=0.005)
    assert v.linearisation["phi"].linear_max == pytest.approx(4.704, abs=0.0005)


@pytest.mark.parametrize(
    "design",
    [
        _roller_design(RollerTranslating(40.0, 10.0, 6.0), 18.0),
        _roller_design(RollerOscillating(60.0, 16.0, 120.0, 66.0), math.radians(25.0)),
    ],
    ids=["translating", "oscillating"],
)
def test_roller_designs_pass(design: CamDesign) -> None:
    # The roller sensitivities of THEORY §3.3 (WC05) against exact re-simulation.
    v = verify(design, step_deg=0.5)
    assert v.ok, v.to_dict()
    assert set(v.linearisation) == {t.key for t in design.tolerances}


def test_conjugate_example_uses_the_fixture() -> None:
    v = verify(load_example("cw11-conjugate"), step_deg=0.5)
    assert v.ok
    assert set(v.linearisation) == {"r_a", "r_b", "rf", "l", "eta", "all"}
    assert v.extras["roundtrip_delta_f_max_mm"] <= 1e-9
    # Δf_est of THEORY §8.3's errors reaches about 27 µm.
    assert 20 < v.linearisation["all"].linear_max < 35


def test_cli_json_object(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", "--example", "cw06-oscillating", "--json", "--step", "0.5"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["roundtrip_max_error"] <= 1e-9
    assert isinstance(out["polyline"]["max_error"], float)
    assert out["polyline"]["ok"] is True
    for key in ("r", "f", "e"):
        entry = out["linearisation"][key]
        assert {"linear_max", "exact_max", "max_difference"} <= set(entry)
        assert entry["max_difference"] <= 0.01 * entry["linear_max"]


def test_cli_summary_and_exit_status(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["verify", "--example", "cw06-translating", "--no-polyline"]) == 0
    text = capsys.readouterr().out
    assert "round trip" in text and "all checks passed" in text


def test_cli_bad_input_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["verify", "--example", "cw06-translating", "--step", "7"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--step=7" in err[0]
    assert main(["verify", "--example", "no-such-example"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_json_is_strict() -> None:
    d = verify(load_example("cw11-conjugate"), step_deg=1.0, polyline=False).to_dict()
    text = json.dumps(d, allow_nan=False)
    assert "NaN" not in text
    assert math.isfinite(d["roundtrip_max_error"])


def test_normal_error_source_is_checked() -> None:
    # THEORY §3.1: ΔS_n = Δn / cos φ is exact for a translating flat face (the support
    # function of a normally offset convex profile moves by Δn).
    d = load_example("cw06-translating")
    d = CamDesign(d.name, d.mechanism, d.program, (ToleranceSpec("n", "IT6"),))
    v = verify(d, step_deg=1.0, polyline=False)
    assert v.ok
    assert v.linearisation["n"].exact_to_rounding
    assert v.linearisation["n"].linear_max == pytest.approx(19.0 / math.cos(math.radians(15)))


def _example_names() -> list[str]:
    from camtol.config.design_file import example_names

    return example_names()


@pytest.mark.parametrize("name", _example_names())
def test_every_builtin_example_verifies(name: str) -> None:
    # Acceptance: round trip within 1e-9 and closed forms within 1 % of the exact
    # re-simulation, of second order, on every built-in example.
    v = verify(load_example(name), step_deg=0.5)
    assert v.ok, json.dumps(v.to_dict(), indent=1)


def test_polyline_check_on_a_lift_table_design(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A spline's piecewise-constant jerk moves the contact to a chord's vertex: the error
    is then below the mid-chord sag prediction, which must not count as a failure."""
    import numpy as np

    from camtol.config.design_file import load_example
    from camtol.design.motion import LiftTable
    from camtol.verify import verify as run_verify

    base = load_example("cw06-translating")
    t = np.radians(np.arange(360.0))
    lift = np.round(base.program.evaluate(t).lift, 3)  # a table printed to 1 µm
    design = dataclasses.replace(base, program=LiftTable(t, lift))
    check = run_verify(design, step_deg=1.0).to_dict()["polyline"]
    assert check["ok"] is True
    assert 0 < check["max_error"] <= 1.1 * check["expected_max_error"]


def test_polyline_check_in_a_concave_stretch() -> None:
    """In a concave stretch of a roller cam the chord adds material: the sag is signed."""
    import math

    import numpy as np

    from camtol.analysis.kinematics import kinematics
    from camtol.design.cam_design import CamDesign
    from camtol.design.motion import Segment, SegmentProgram
    from camtol.mechanisms import MECHANISMS
    from camtol.verify import verify as run_verify

    r = math.radians
    program = SegmentProgram(
        (
            Segment("rise", 0, r(80), "cycloidal", 25.0),
            Segment("dwell", r(80), r(180)),
            Segment("return", r(180), r(260), "cycloidal", 25.0),
            Segment("dwell", r(260), r(360)),
        )
    )
    design = CamDesign("concave", MECHANISMS["roller_translating"](25.0, 6.0, 0.0), program)
    kin = kinematics(design, np.radians(np.linspace(0, 360, 3601)))
    assert kin.curvature_radius_mm.min() < 0  # the profile has a concave stretch
    assert run_verify(design, step_deg=1.0).to_dict()["polyline"]["ok"] is True
