"""Design identity: dump_design round trip and CamDesign.content_hash (issue 8).

load → dump → load gives an equal design with the same hash, for every built-in example
and for random valid designs of every follower type (segments and lift tables, grades
and explicit deviations, operating data).
"""

from __future__ import annotations

import math
import subprocess
import sys
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from camtol.config.design_file import design_from_mapping, dump_design, example_names, example_text
from camtol.design.cam_design import CamDesign
from camtol.design.motion import MOTION_LAWS
from camtol.exceptions import DesignError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib


def _roundtrip(design: CamDesign) -> CamDesign:
    return design_from_mapping(tomllib.loads(dump_design(design)))


@pytest.mark.parametrize("name", example_names())
def test_every_example_round_trips(name: str) -> None:
    design = design_from_mapping(tomllib.loads(example_text(name)))
    again = _roundtrip(design)
    assert again == design
    assert again.content_hash == design.content_hash
    assert again.extras == design.extras  # the [inspection] table too
    # and the written text is a fixed point
    assert dump_design(again) == dump_design(design)


def test_hash_is_sha256_hex_and_independent_of_spelling_and_comments() -> None:
    text = example_text("cw06-translating")
    a = design_from_mapping(tomllib.loads(text))
    b = design_from_mapping(
        tomllib.loads(
            "# a comment\n" + text.replace("base_radius_mm = 40.0", "base_radius_mm = 4e1")
        )
    )
    assert "base_radius_mm = 40.0" in text
    assert len(a.content_hash) == 64 and int(a.content_hash, 16) >= 0
    assert a.content_hash == b.content_hash


def test_hash_changes_with_any_content() -> None:
    data = tomllib.loads(example_text("cw06-translating"))
    base = design_from_mapping(data).content_hash
    changes: list[tuple[str, str, Any]] = [
        ("follower", "base_radius_mm", 40.000001),
        ("follower", "offset_mm", 10.5),
        ("tolerances", "r", "IT7"),
        ("operation", "speed_rpm", 301.0),
    ]
    for table, key, value in changes:
        d = tomllib.loads(example_text("cw06-translating"))
        d.setdefault(table, {})[key] = value
        assert design_from_mapping(d).content_hash != base, (table, key)
    d = tomllib.loads(example_text("cw06-translating"))
    d["motion"]["segments"][0]["lift_mm"] = 22.5
    d["motion"]["segments"][2]["lift_mm"] = 22.5
    assert design_from_mapping(d).content_hash != base
    d = tomllib.loads(example_text("cw06-translating"))
    d["name"] = "other"
    assert design_from_mapping(d).content_hash != base


def test_hash_is_the_same_in_a_fresh_interpreter() -> None:
    """No dependence on hash randomisation or on state of this process."""
    here = design_from_mapping(tomllib.loads(example_text("cw11-conjugate"))).content_hash
    code = (
        "from camtol.config.design_file import load_example;"
        "print(load_example('cw11-conjugate').content_hash)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=None
    ).stdout.strip()
    assert out == here


# ---------------------------------------------------------------------------------------
# Random valid designs of every follower type
# ---------------------------------------------------------------------------------------
_num = st.floats(allow_nan=False, allow_infinity=False)


@st.composite
def followers(draw: st.DrawFn) -> dict[str, Any]:
    kind = draw(
        st.sampled_from(
            ["flat_translating", "flat_oscillating", "roller_translating", "roller_oscillating"]
            + ["conjugate"]
        )
    )
    rb = draw(st.floats(20.0, 80.0))
    if kind == "flat_translating":
        return {
            "type": kind,
            "base_radius_mm": rb,
            "offset_mm": draw(st.floats(-20, 20)),
            "face_angle_deg": draw(st.floats(-30, 30)),
        }
    if kind == "flat_oscillating":
        return {
            "type": kind,
            "base_radius_mm": rb,
            "pivot_distance_mm": rb + draw(st.floats(30, 80)),
            "face_offset_mm": draw(st.floats(-10, 10)),
        }
    rf = draw(st.floats(3.0, 15.0))
    if kind == "roller_translating":
        return {
            "type": kind,
            "base_radius_mm": rb,
            "roller_radius_mm": rf,
            "offset_mm": draw(st.floats(-0.5, 0.5)) * (rb + rf),
        }
    f = rb + rf + draw(st.floats(30, 80))
    arm = f - (rb + rf) + draw(st.floats(5, 30))
    out: dict[str, Any] = {
        "type": kind,
        "base_radius_mm": rb,
        "roller_radius_mm": rf,
        "pivot_distance_mm": f,
    }
    if kind == "roller_oscillating":
        out["arm_length_mm"] = arm
        return out
    out.update(
        arm_a_mm=arm,
        arm_b_mm=arm * draw(st.floats(0.9, 1.1)),
        arm_angle_deg=draw(st.floats(60, 120)),
    )
    if draw(st.booleans()):
        out["roller_b_radius_mm"] = draw(st.floats(3.0, 15.0))
    return out


@st.composite
def motions(draw: st.DrawFn, oscillating: bool) -> dict[str, Any]:
    unit = "deg" if oscillating else "mm"
    if draw(st.booleans()):
        n = draw(st.sampled_from([8, 36, 72, 360]))
        decimals = draw(st.sampled_from([2, 4, 16]))
        height = draw(st.floats(1.0, 20.0))
        phase = np.arange(n) * 2 * math.pi / n
        lifts = height * 0.5 * (1 - np.cos(phase)) * draw(st.floats(0.5, 1.0))
        return {
            "table_step_deg": 360.0 / n,
            f"table_lift_{unit}": [round(float(v), decimals) for v in lifts],
        }
    # rise, dwell, return, dwell with random (irrational-in-radians) boundaries
    a = draw(st.floats(60.0, 150.0))
    b = a + draw(st.floats(0.0, 60.0))
    c = b + draw(st.floats(60.0, 150.0))
    c = min(c, 359.0)
    h = draw(st.floats(1.0, 20.0))
    law = draw(st.sampled_from([m for m in MOTION_LAWS if m != "constant_velocity"]))
    segs: list[dict[str, Any]] = [
        {"kind": "rise", "law": law, "start_deg": 0.0, "end_deg": a, f"lift_{unit}": h}
    ]
    if b > a:
        segs.append({"kind": "dwell", "start_deg": a, "end_deg": b})
    segs.append({"kind": "return", "law": law, "start_deg": b, "end_deg": c, f"lift_{unit}": h})
    segs.append({"kind": "dwell", "start_deg": c, "end_deg": 360.0})
    return {"segments": segs}


@st.composite
def designs(draw: st.DrawFn) -> dict[str, Any]:
    follower = draw(followers())
    oscillating = follower["type"] in ("flat_oscillating", "roller_oscillating", "conjugate")
    data: dict[str, Any] = {
        "name": draw(st.text(min_size=1, max_size=20)),
        "description": draw(st.text(max_size=40)),
        "follower": follower,
        "motion": draw(motions(oscillating)),
    }
    tol: dict[str, Any] = {}
    if draw(st.booleans()):
        tol["r"] = draw(st.sampled_from(["IT5", "IT6", "IT7"]))
    if draw(st.booleans()):
        tol["n_um"] = draw(st.floats(0.1, 50.0))
    if draw(st.booleans()):
        tol["phase_deg"] = draw(st.floats(0.001, 0.1))
    if tol:
        data["tolerances"] = tol
    if draw(st.booleans()):
        data["operation"] = {
            "speed_rpm": draw(st.floats(1.0, 5000.0)),
            "pressure_angle_limit_deg": draw(st.floats(10.0, 60.0)),
        }
    return data


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(designs())
def test_random_designs_round_trip(data: dict[str, Any]) -> None:
    try:
        design = design_from_mapping(data)
    except DesignError:
        return  # an invalid combination drawn (e.g. a face that cannot reach the cam)
    again = _roundtrip(design)
    assert again == design
    assert again.content_hash == design.content_hash
    assert dump_design(again) == dump_design(design)
