"""The single-pass engine, curves computed on read and the extremes refinement (issue 8).

These check results, not speed (speed is measured by bench/run.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camtol.analysis.engine as engine_module
from camtol.analysis.engine import evaluate_engine, shared_dwells
from camtol.analysis.errors import error_analysis
from camtol.analysis.extremes import find_extremes
from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.analysis.result import analyse
from camtol.config.design_file import example_names, load_example
from camtol.design.motion import MotionState
from camtol.jet import Jet

EXAMPLES = example_names()
FIELDS = (
    "lift",
    "velocity",
    "acceleration",
    "jerk",
    "contact_x_mm",
    "contact_y_mm",
    "radius_mm",
    "centre_x_mm",
    "centre_y_mm",
    "q_mm",
    "pressure_angle_rad",
    "shift_angle_rad",
    "curvature_radius_mm",
    "face_contact_mm",
    "follower_angle_rad",
)


@pytest.mark.parametrize("name", EXAMPLES)
def test_chunks_change_nothing(name: str) -> None:
    design = load_example(name).cams()[0].design  # a conjugate pair: cam A
    theta, left = analysis_grid(1.0, design.program.boundaries_rad)
    k1, s1 = evaluate_engine(design, theta, left, chunk=10**9)
    k2, s2 = evaluate_engine(design, theta, left, chunk=37)  # many uneven chunks
    for f in FIELDS:
        a, b = getattr(k1, f), getattr(k2, f)
        assert (a is None) == (b is None), f
        if a is not None:
            np.testing.assert_array_equal(a, b, err_msg=f)  # elementwise formulas: exact
    assert s1.keys() == s2.keys()
    for key in s1:
        for part in ("v", "d1", "d2"):
            np.testing.assert_array_equal(getattr(s1[key], part), getattr(s2[key], part))


@pytest.mark.parametrize("name", EXAMPLES)
def test_engine_agrees_with_kinematics_and_error_analysis(name: str) -> None:
    design = load_example(name).cams()[0].design  # a conjugate pair: cam A
    theta, left = analysis_grid(0.5, design.program.boundaries_rad)
    kin, sens = evaluate_engine(design, theta, left, chunk=500)
    ref = kinematics(design, theta, left_limit=left)
    for f in FIELDS:
        a, b = getattr(kin, f), getattr(ref, f)
        assert (a is None) == (b is None), f
        if a is not None:  # jets and plain arrays: the same values to rounding
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12, err_msg=f)
    tols = design.resolve_tolerances(60.0)
    err = error_analysis(design, tols, theta, left_limit=left)
    for tol in tols:
        src = err.sources[tol.key]
        for part, arr in (("v", src.sensitivity), ("d1", src.sensitivity_d1)):
            np.testing.assert_allclose(
                getattr(sens[tol.key], part) + 0 * arr, arr, rtol=1e-11, atol=1e-11
            )


def test_constant_quantities_are_broadcast_not_stored() -> None:
    design = load_example("cw06-translating")  # constant pressure angle φ = 15°
    theta, left = analysis_grid(0.1, design.program.boundaries_rad)
    kin, sens = evaluate_engine(design, theta, left, chunk=1000)
    assert kin.pressure_angle_rad.strides == (0,)
    assert kin.pressure_angle_rad.shape == theta.shape
    assert kin.pressure_angle_rad[0] == pytest.approx(math.radians(15.0))
    assert sens["e"].v.strides == (0,) and sens["e"].d1.strides == (0,)


def test_curves_are_the_internal_results() -> None:
    a = analyse(load_example("cw06-translating"), step_deg=1.0)
    assert list(a.curves) == list(dict.fromkeys(a.curves))  # keys once each
    assert {q.key for q in a.quantities} <= set(a.curves)
    assert all(a.curves.unit(q.key) == q.unit for q in a.quantities)
    src = a.errors.sources["phi"]
    np.testing.assert_allclose(a.curves["dS_phi"], src.sensitivity * src.deviation)
    np.testing.assert_allclose(a.curves["dS_phi"], src.delta_lift, rtol=1e-15)
    np.testing.assert_allclose(a.curves["dA_phi"], src.delta_acceleration, rtol=1e-15)
    np.testing.assert_array_equal(a.curves["dS_worst"], a.errors.worst_lift)
    assert a.curves["pressure_angle"] is a.kinematics.pressure_angle_rad
    worst = sum(np.abs(s.delta_acceleration) for s in a.errors.sources.values())
    np.testing.assert_allclose(a.errors.worst_acceleration, worst, rtol=1e-15)
    rms = np.sqrt(sum(s.delta_velocity**2 for s in a.errors.sources.values()))
    np.testing.assert_allclose(a.errors.rms_velocity, rms, rtol=1e-15)
    with pytest.raises(KeyError):
        a.curves["nope"]


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_curves_deviation_is_known_without_computing_it(name: str) -> None:
    c = analyse(load_example(name), step_deg=2.0).curves
    for key in c:
        assert c._deviation(key) == c._base(key)[1], key


@pytest.mark.parametrize("name", EXAMPLES)
def test_an_analysis_is_freed_when_dropped_not_by_the_garbage_collector(name: str) -> None:
    """No reference cycle keeps a result alive: its arrays go with the last reference.

    A class defined inside the extremes' search (a class is always in a cycle) held the
    curves in its closure: a loop of analyses at 0.001° grew to 750 MiB before the
    collector ran, and every analysis took fresh pages.
    """
    import gc
    import weakref

    design = load_example(name)
    gc.collect()
    gc.disable()
    try:
        a = analyse(design, step_deg=1.0)
        blocks = [a.kinematics.lift, a.kinematics.radius_mm]
        blocks += [s.sensitivity for s in a.errors.sources.values()]
        refs = [weakref.ref(x if x.base is None else x.base) for x in blocks]
        _ = a.curves["dS_worst"], a.extremes  # what a caller reads
        del a, blocks, _
        assert all(r() is None for r in refs)
    finally:
        gc.enable()


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_radial_factor_is_searched_once_as_the_radial_sensitivity(name: str) -> None:
    """ΔS_r/Δr and ΔS_r share one array: one search, each extreme under its own name."""
    a = analyse(load_example(name), step_deg=0.5)
    assert list(a.extremes) == [q.key for q in a.quantities]  # report order
    hi, lo = a.extremes["radial_factor"]
    assert hi.quantity == lo.quantity == "radial_factor"
    assert (hi.kind, lo.kind) == ("max", "min")
    if "r" not in a.errors.sources:  # no Δr toleranced: nothing shared
        assert "dS_r" not in a.extremes
        return
    dev = a.errors.sources["r"].deviation
    s_hi, s_lo = a.extremes["dS_r"]
    assert s_hi.quantity == "dS_r"
    pairs = ((s_hi, hi), (s_lo, lo)) if dev > 0 else ((s_hi, lo), (s_lo, hi))
    for scaled, radial in pairs:
        assert scaled.value == radial.value * dev
        assert (scaled.theta_deg, scaled.ranges_deg) == (radial.theta_deg, radial.ranges_deg)
    r = a.curves["radial_factor"]
    assert hi.value >= r.max() and lo.value <= r.min()


def test_extremes_at_kinks_smooth_peaks_and_jumps_to_step_over_1000() -> None:
    # A smooth maximum, a kink minimum |sin| and a one-sided maximum at a jump, from a
    # 1° grid: located to 1e-3° (step/1000) or better.
    t_max, t_kink = 1.23456, 4.56789

    calls: list[frozenset[str]] = []

    def f(t: np.ndarray, names: frozenset[str] | None = None) -> dict[str, np.ndarray]:
        if names is not None:
            calls.append(names)
        jump = np.where(np.mod(t, 2 * math.pi) < 2.0, np.mod(t, 2 * math.pi), 0.0)
        return {"smooth": np.cos(t - t_max), "kink": np.abs(np.sin(t - t_kink)), "jump": jump}

    theta = np.radians(np.arange(0.0, 361.0))
    ext = find_extremes(theta, f(theta), f, step_deg=1.0)
    assert ext["smooth"][0].theta_deg == pytest.approx(math.degrees(t_max), abs=1e-3)
    assert ext["smooth"][0].value == pytest.approx(1.0, abs=1e-12)
    kink = ext["kink"][1]
    assert kink.value < 2e-5  # within step/1000 of the zero: |sin| <= 1.75e-5
    # The second (fine) call is asked only for what the coarse one left unrefined.
    assert len(calls) == 2 and "smooth" in calls[0]
    assert "kink" in calls[1] and "smooth" not in calls[1]
    assert min(abs(kink.theta_deg - math.degrees(t_kink) + k * 180) for k in (-1, 0, 1)) < 1e-3
    # sup of θ on [0, 2) is approached from below: the grid's last sample before 2 rad,
    # or a refined one at most step/1000 short of it
    assert ext["jump"][0].value <= 2.0
    assert ext["jump"][0].value > 2.0 - math.radians(1e-3)


def test_max_radius_is_the_refined_radius_extreme() -> None:
    from camtol.analysis.result import max_radius_mm

    for name in ("cw06-translating", "roller-oscillating"):
        design = load_example(name)
        a = analyse(design)
        assert a.max_radius_mm == pytest.approx(max_radius_mm(design), abs=1e-12)
        assert a.max_radius_mm == pytest.approx(a.extremes["radius"][0].value, abs=1e-12)


@pytest.mark.parametrize("name", ["cw06-translating", "roller-oscillating"])
def test_design_level_sources_go_through_the_engine(name: str) -> None:
    from camtol.config.design_file import design_from_mapping, example_text
    from camtol.config.examples import parse_toml

    data = parse_toml(example_text(name), name)
    data["tolerances"]["phase_deg"] = 0.01  # the cam's angular phase (camtol.design.sources)
    design = design_from_mapping(data)
    a = analyse(design, step_deg=1.0)
    k = a.kinematics
    ref = error_analysis(design, a.tolerances, k.theta_rad, left_limit=k.left_limit)
    for key, src in ref.sources.items():
        np.testing.assert_allclose(a.errors.sources[key].delta_lift, src.delta_lift, atol=1e-15)
        np.testing.assert_allclose(
            a.errors.sources[key].delta_acceleration, src.delta_acceleration, atol=1e-12
        )
    # ΔS_phase = −V·Δθ0 (camtol.design.sources)
    np.testing.assert_allclose(
        a.errors.sources["phase"].delta_lift, -k.velocity * math.radians(0.01), atol=1e-15
    )


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
def test_overflow_is_named_by_the_extremes_search() -> None:
    """A curve that overflows is reported by name and angle, not returned as inf.

    The finiteness check rides on the extremes' search (a max and min that are finite
    mean every sample is): here (1e304 mm)² overflows the RMS while the worst case
    (2e304 mm) does not.
    """
    import dataclasses

    from camtol.design.cam_design import ToleranceSpec
    from camtol.exceptions import DesignError

    d = load_example("cw06-translating")
    huge = (ToleranceSpec("r", deviation=1e307), ToleranceSpec("n", deviation=1e307))
    with pytest.raises(DesignError, match=r"ΔS RMS is inf at θ=.*overflows"):
        analyse(dataclasses.replace(d, tolerances=huge))


def test_nonfinite_callback_gets_the_first_bad_index() -> None:
    """find_extremes reports the first non-finite sample and still finds finite extremes."""
    theta = np.radians(np.arange(0.0, 360.0, 1.0))
    v = np.sin(theta)
    v[[40, 7]] = [np.inf, np.nan]
    seen: list[tuple[str, int]] = []
    ext = find_extremes(
        theta,
        {"f": v},
        lambda t, names: {"f": np.sin(t)},
        step_deg=1.0,
        on_nonfinite=lambda k, i: seen.append((k, i)),
    )
    assert seen == [("f", 7)]
    assert ext["f"][0].value == pytest.approx(1.0, abs=1e-9)


def _cams_of_examples() -> list[tuple[str, str]]:
    return [(name, cam.label) for name in EXAMPLES for cam in load_example(name).cams()]


@pytest.mark.parametrize(("name", "label"), _cams_of_examples())
def test_motion_only_followers_do_not_depend_on_theta(name: str, label: str) -> None:
    """A follower that declares ``motion_only`` gives the same numbers at any θ."""
    cam = next(c for c in load_example(name).cams() if c.label == label).design
    mech = cam.mechanism
    assert mech.motion_only, f"{type(mech).__name__} does not declare motion_only"
    theta, left = analysis_grid(2.0, cam.program.boundaries_rad)
    m = cam.program.evaluate(theta, left_limit=left)
    lift, vel = Jet(m.lift, m.velocity, m.acceleration), Jet(m.velocity, m.acceleration, m.jerk)
    turned = theta + 1.234  # the same motion states at other cam angles
    a = mech.error_sensitivities(Jet.variable(theta), lift, vel)
    b = mech.error_sensitivities(Jet.variable(turned), lift, vel)

    def parts(x: object) -> tuple[object, ...]:  # a constant sensitivity is a plain array
        return (x.v, x.d1, x.d2) if isinstance(x, Jet) else (x,)

    for key in a:
        for x, y in zip(parts(a[key]), parts(b[key]), strict=True):
            np.testing.assert_array_equal(
                np.broadcast_to(x, theta.shape), np.broadcast_to(y, theta.shape), err_msg=key
            )
    np.testing.assert_array_equal(
        mech.curvature_radius(theta, m.lift, m.velocity, m.acceleration),
        mech.curvature_radius(turned, m.lift, m.velocity, m.acceleration),
    )


@pytest.mark.parametrize("name", EXAMPLES)
def test_dwells_evaluated_once_give_the_same_numbers(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Evaluating a dwell's motion-only quantities once changes no number (bit for bit)."""
    design = load_example(name).cams()[0].design
    theta, left = analysis_grid(0.1, design.program.boundaries_rad)  # chunks of ≥ 1024 rows
    k1, s1 = evaluate_engine(design, theta, left)
    monkeypatch.setattr(type(design.mechanism), "motion_only", False)
    k2, s2 = evaluate_engine(design, theta, left)
    np.testing.assert_array_equal(k1.curvature_radius_mm, k2.curvature_radius_mm)
    assert s1.keys() == s2.keys()
    for key in s1:
        for part in ("v", "d1", "d2"):
            np.testing.assert_array_equal(getattr(s1[key], part), getattr(s2[key], part))


@pytest.mark.parametrize(("name", "label"), _cams_of_examples())
def test_motion_only_geometry_is_the_frame_geometry_turned(name: str, label: str) -> None:
    """The engine's cam-frame geometry of a motion-only follower equals its formulas at θ.

    The engine evaluates the contact geometry once per motion state at θ = 0 and turns
    the points by θ (kinematic inversion, THEORY §0); the mechanism's own formulas at
    every θ must agree: points to 1e-12 of the cam's size, angles to 1e-12 rad.
    """
    cam = next(c for c in load_example(name).cams() if c.label == label).design
    mech = cam.mechanism
    theta, left = analysis_grid(0.1, cam.program.boundaries_rad)
    m = cam.program.evaluate(theta, left_limit=left)
    kin, _ = evaluate_engine(cam, theta, left, chunk=1_500)  # chunks, dwells compressed
    g = mech.contact(theta, m.lift, m.velocity)
    size = float(np.max(kin.radius_mm))
    for ours, direct in (
        (kin.contact_x_mm, g.contact_x),
        (kin.contact_y_mm, g.contact_y),
        (kin.centre_x_mm, g.centre_x),
        (kin.centre_y_mm, g.centre_y),
        (kin.radius_mm, np.hypot(g.contact_x, g.contact_y)),
        (kin.q_mm, g.q),
    ):
        np.testing.assert_allclose(
            ours, np.broadcast_to(direct, theta.shape), rtol=0, atol=1e-12 * size
        )
    for ours, direct in (
        (kin.pressure_angle_rad, g.pressure_angle),
        (kin.shift_angle_rad, g.shift_angle),
    ):
        np.testing.assert_allclose(ours, np.broadcast_to(direct, theta.shape), rtol=0, atol=1e-12)
    if "face_contact" in g.extras:
        assert kin.face_contact_mm is not None
        np.testing.assert_allclose(kin.face_contact_mm, g.extras["face_contact"], atol=1e-12 * size)


def test_scaled_extremes_swap_for_a_negative_factor_and_name_an_overflow() -> None:
    """One rule for a source's deviation (analysis) and a display unit (report)."""
    from camtol.analysis.extremes import Extreme, scaled_extremes
    from camtol.exceptions import DesignError

    pair = (Extreme("q", "max", 2.0, 10.0), Extreme("q", "min", -1.0, 200.0))
    hi, lo = scaled_extremes(pair, -3.0, "Q")
    assert (hi.kind, hi.value, hi.theta_deg) == ("max", 3.0, 200.0)
    assert (lo.kind, lo.value, lo.theta_deg) == ("min", -6.0, 10.0)
    with pytest.raises(DesignError, match=r"Q is inf at θ=10°: the computation overflows"):
        scaled_extremes(pair, 1e308, "Q")


@pytest.mark.parametrize("name", EXAMPLES)
def test_sensitivities_without_derivatives_are_the_jets_values(name: str) -> None:
    # A design with no tolerances needs the radial factor alone: plain values, a quarter
    # of the work. Same formulas, so the same values to rounding; the derivatives are
    # NaN (not computed), never a zero that would pass for a constant sensitivity.
    design = load_example(name).cams()[0].design
    theta, left = analysis_grid(0.5, design.program.boundaries_rad)
    _, jets = evaluate_engine(design, theta, left, chunk=300)
    _, plain = evaluate_engine(design, theta, left, chunk=300, derivatives=False)
    assert plain.keys() == jets.keys()
    for key, j in jets.items():
        np.testing.assert_allclose(plain[key].v, j.v, rtol=1e-13, atol=1e-15, err_msg=key)
        assert np.isnan(plain[key].d1).all() and np.isnan(plain[key].d2).all()


def test_only_the_sources_asked_for_are_returned() -> None:
    design = load_example("roller-oscillating")
    theta, left = analysis_grid(1.0, design.program.boundaries_rad)
    _, every = evaluate_engine(design, theta, left)
    assert set(every) == {"r", "n", "rf", "l", "f"}
    _, some = evaluate_engine(design, theta, left, sources={"r", "l", "phase"})
    assert set(some) == {"r", "l"}  # "phase" is not toleranced: ignored
    for key in some:
        for part in ("v", "d1", "d2"):
            np.testing.assert_array_equal(getattr(some[key], part), getattr(every[key], part))


def test_a_design_without_tolerances_reports_its_radial_factor() -> None:
    # cw11-experiment has no tolerances: analyse takes the values-only path. Its radial
    # factor must be the same as with a toleranced source (which takes the jets).
    from camtol.config.design_file import design_from_mapping, example_text
    from camtol.config.examples import parse_toml

    bare = load_example("cw11-experiment")
    assert not bare.tolerances
    data = parse_toml(example_text("cw11-experiment"), "cw11-experiment")
    data["tolerances"] = {"l_um": 5.0}
    toleranced = design_from_mapping(data)
    a, b = analyse(bare, step_deg=1.0), analyse(toleranced, step_deg=1.0)
    np.testing.assert_allclose(
        a.curves["radial_factor"], b.curves["radial_factor"], rtol=1e-13, atol=0.0
    )
    assert a.extremes["radial_factor"][0].value == pytest.approx(
        b.extremes["radial_factor"][0].value, rel=1e-12
    )
    assert float(np.max(a.curves["dS_worst"])) == 0.0


def test_design_level_sources_without_derivatives() -> None:
    from camtol.config.design_file import design_from_mapping, example_text
    from camtol.config.examples import parse_toml

    data = parse_toml(example_text("roller-oscillating"), "roller-oscillating")
    data["tolerances"]["phase_deg"] = 0.01
    design = design_from_mapping(data)
    theta, left = analysis_grid(1.0, design.program.boundaries_rad)
    kin, jets = evaluate_engine(design, theta, left)
    _, plain = evaluate_engine(design, theta, left, derivatives=False)
    np.testing.assert_array_equal(plain["phase"].v, -kin.velocity)  # ΔS/Δθ0 = −V
    np.testing.assert_array_equal(plain["phase"].v, jets["phase"].v)


def test_a_design_without_tolerances_has_no_accuracy_grade() -> None:
    # ΔS is zero by construction without tolerances: no grade ("finer than IT01" was
    # printed before), and every report says so in the same words.
    from camtol.report.display import ACCURACY_NOT_ASSESSED, accuracy_words
    from camtol.report.qa import overall_verdict

    bare = analyse(load_example("cw11-experiment"), step_deg=1.0)
    assert bare.accuracy is None
    assert accuracy_words(bare.accuracy) == ACCURACY_NOT_ASSESSED
    assert f"output accuracy {ACCURACY_NOT_ASSESSED}" in overall_verdict(bare, None).reasons
    toleranced = analyse(load_example("cw11-conjugate"), step_deg=1.0)
    assert toleranced.accuracy is not None
    assert accuracy_words(toleranced.accuracy) == toleranced.accuracy.describe()


def test_the_cams_of_a_pair_find_their_dwells_once_with_the_same_numbers(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Inside ``shared_dwells`` cam B takes cam A's dwells: found once, the same numbers."""
    pair = load_example("cw11-conjugate")
    a, b = (c.design for c in pair.cams())
    theta, left = analysis_grid(0.05, pair.program.boundaries_rad)
    alone_a, _ = evaluate_engine(a, theta, left, check=False)
    motion = MotionState(alone_a.lift, alone_a.velocity, alone_a.acceleration, alone_a.jerk)
    alone_b = kinematics(b, theta, left_limit=left, check=False, motion=motion)
    found: list[int] = []
    repeated = engine_module._repeated_states

    def counted(m: MotionState) -> np.ndarray:
        found.append(m.lift.size)
        return repeated(m)

    monkeypatch.setattr(engine_module, "_repeated_states", counted)
    with shared_dwells():
        kin_a, _ = evaluate_engine(a, theta, left, check=False, motion=motion)
        kin_b = kinematics(b, theta, left_limit=left, check=False, motion=motion)
        # Another grid is not confused with the first.
        kinematics(b, theta[::2].copy(), left_limit=left[::2], check=False)
    assert found == [theta.size, theta[::2].size]
    for ours, alone in ((kin_a, alone_a), (kin_b, alone_b)):
        for field in ("radius_mm", "q_mm", "pressure_angle_rad", "curvature_radius_mm"):
            np.testing.assert_array_equal(getattr(ours, field), getattr(alone, field))
        np.testing.assert_array_equal(ours.contact_x_mm, alone.contact_x_mm)
    assert kin_b.contact_points.rows is not None  # the pair dwells: the rows were shared


@pytest.mark.parametrize("kind", ["dwells", "scattered"])
def test_spreading_by_runs_is_the_gather(kind: str) -> None:
    """A chunk's evaluated rows spread by slices (runs) or by a gather: the same rows."""
    rng = np.random.default_rng(11)
    n = 5000
    if kind == "dwells":  # two dwells and the chunk's last row repeating
        repeats = np.zeros(n, bool)
        repeats[1201:2000] = repeats[3001:3500] = repeats[-1] = True
    else:  # many short repeats: too many runs, spread by the gather
        repeats = rng.random(n) < 0.3
    fresh = ~repeats
    fresh[0] = True
    index = np.cumsum(fresh) - 1
    runs = engine_module._runs(fresh, index)
    assert (runs is None) == (kind == "scattered")
    values = rng.random(int(fresh.sum()))
    for spread in (engine_module._Spread(index, runs), engine_module._Spread(index, None)):
        out = np.full(n, np.nan)
        engine_module._write(out, values, spread)
        np.testing.assert_array_equal(out, values[index])


def test_a_dwells_rows_spread_by_gather_or_runs_give_the_same_engine(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    design = load_example("roller-oscillating")
    theta, left = analysis_grid(0.1, design.program.boundaries_rad)
    runs, s_runs = evaluate_engine(design, theta, left)
    monkeypatch.setattr(engine_module, "_ROWS_PER_RUN", 10**9)  # always the gather
    gather, s_gather = evaluate_engine(design, theta, left)
    for f in FIELDS:
        a, b = getattr(runs, f), getattr(gather, f)
        if a is not None:
            np.testing.assert_array_equal(a, b, err_msg=f)
    for key in s_runs:
        for part in ("v", "d1", "d2"):
            np.testing.assert_array_equal(getattr(s_runs[key], part), getattr(s_gather[key], part))
