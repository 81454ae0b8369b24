"""Tolerance band (lower/upper curves of ΔS) from a file, in Monte Carlo and allocation."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from camtol.cli.app import main
from camtol.config.design_file import load_example
from camtol.exceptions import DesignError, InputFileError
from camtol.tolerancing import allocate, monte_carlo
from camtol.tolerancing.allocation import _with_grades
from camtol.tolerancing.band import ToleranceBand, band_curves, read_band_csv
from camtol.tolerancing.study import prepare, sample_matrix

CW06 = load_example("cw06-translating")
STEP = 1.0


def _write(tmp_path: Path, text: str, name: str = "band.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _symmetric_band(tmp_path: Path, spec_um: float) -> Path:
    return _write(
        tmp_path, f"theta_deg,lower_um,upper_um\n0,{-spec_um},{spec_um}\n180,{-spec_um},{spec_um}\n"
    )


# --- the reader ------------------------------------------------------------------------


def test_reader_units_separators_comments_and_periodic_interpolation(tmp_path: Path):
    p = _write(
        tmp_path,
        "# band of a lift\n"
        "theta_deg; lower_um; upper_um   # units in the names\n"
        "\n"
        "0; -10; 20\n"
        "90; -30; 40\n"
        "270; -10; 20\n",
    )
    b = read_band_csv(p, "translating")
    assert b.source == "band.csv"
    np.testing.assert_array_equal(b.theta_deg, [0.0, 90.0, 270.0])
    np.testing.assert_allclose(b.lower, [-0.010, -0.030, -0.010], rtol=1e-15)
    np.testing.assert_allclose(b.upper, [0.020, 0.040, 0.020], rtol=1e-15)
    lo, hi = b.on_grid(np.radians([45.0, 180.0, 315.0, 360.0, 405.0]))
    # linear between rows; periodic: 315° lies between 270° and 360° (= the 0° row)
    np.testing.assert_allclose(lo * 1e3, [-20.0, -20.0, -10.0, -10.0, -20.0], atol=1e-12)
    np.testing.assert_allclose(hi * 1e3, [30.0, 30.0, 20.0, 20.0, 30.0], atol=1e-12)


def test_reader_ignores_other_columns(tmp_path: Path):
    p = _write(tmp_path, "note,theta_deg,upper_um,lower_um\nrise,0,5,-4\nreturn,180,6,-3\n")
    b = read_band_csv(p, "translating")
    np.testing.assert_allclose(b.upper * 1e3, [5.0, 6.0], rtol=1e-15)
    np.testing.assert_allclose(b.lower * 1e3, [-4.0, -3.0], rtol=1e-15)


def test_reader_oscillating_in_degrees(tmp_path: Path):
    p = _write(tmp_path, "theta_deg lower_deg upper_deg\n0 -0.05 0.1\n180 -0.02 0.03\n")
    b = read_band_csv(p, "oscillating")
    np.testing.assert_allclose(b.lower, np.radians([-0.05, -0.02]), rtol=1e-15)
    np.testing.assert_allclose(b.upper, np.radians([0.1, 0.03]), rtol=1e-15)


BAD = [
    ("theta_deg,lower_deg,upper_deg\n0,-1,1\n90,-1,1\n", "band.csv: the band is given in deg"),
    ("theta_deg,lower_um\n0,-1\n90,-1\n", "band.csv: the tolerance band needs the columns"),
    ("angle,lower_um,upper_um\n0,-1,1\n90,-1,1\n", "missing theta_deg; found: angle, lower_um"),
    ("theta_deg,lower_um,upper_um\n0,-1,1\n90,abc,1\n", "band.csv, line 3, column lower_um:"),
    ("theta_deg,lower_um,upper_um\n0,-1,1\n90,-1\n", "band.csv, line 3: expected 3 cells"),
    ("theta_deg,lower_um,upper_um\n0,-1,nan\n90,-1,1\n", "band.csv, line 2, column upper_um:"),
    ("theta_deg,lower_um,upper_um\n0,-1,1\n", "band.csv: the tolerance band has 1 row"),
    ("theta_deg,lower_um,upper_um\n0,-1,1\n360,-1,1\n", "line 3, column theta_deg: 360"),
    ("theta_deg,lower_um,upper_um\n-5,-1,1\n90,-1,1\n", "line 2, column theta_deg: -5"),
    (
        "theta_deg,lower_um,upper_um\n0,-1,1\n# c\n90,-1,1\n90,-1,1\n",
        "line 5, column theta_deg: 90 does not follow 90",
    ),
    (
        "theta_deg,lower_um,upper_um\n0,-1,1\n120,2,5\n",
        "line 3, column lower_um: 2 at theta_deg=120 is not allowed; it must be < 0",
    ),
    (
        "theta_deg,lower_um,upper_um\n0,-1,1\n120,-3,0\n",
        "line 3, column upper_um: 0 at theta_deg=120 is not allowed; it must be > 0",
    ),
    ("", "band.csv: the tolerance band is empty"),
]


@pytest.mark.parametrize("command", ["montecarlo", "allocate"])
@pytest.mark.parametrize("text, message", BAD, ids=[m for _, m in BAD])
def test_cli_bad_band_file(tmp_path: Path, capsys, command, text, message):
    band = _write(tmp_path, text)
    out = tmp_path / "out.csv"
    argv = [command, "-e", "cw06-translating", "--band", str(band)]
    if command == "montecarlo":
        argv += ["--samples", "100", "--step", "1", "--curves", str(out)]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert not out.exists()


def test_cli_band_refusals(tmp_path: Path, capsys):
    band = _symmetric_band(tmp_path, 20)
    base = ["montecarlo", "-e", "cw06-translating", "--samples", "100", "--step", "1"]
    for argv, message in (
        ([*base, "--band", str(band), "--spec-um", "20"], "give --band or --spec-um/--spec-deg"),
        (
            ["allocate", "-e", "cw06-translating", "--band", str(band), "--spec-um", "20"],
            "not both",
        ),
        (
            ["allocate", "-e", "cw06-oscillating", "--band", str(band)],
            "the band is given in um, but this design's output is a swing",
        ),
        ([*base, "--band", str(tmp_path / "missing.csv")], "missing.csv: cannot be read"),
    ):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and message in err, err


def test_python_band_refusals():
    st = prepare(CW06, step_deg=STEP)
    n = st.theta_rad.size
    band = (np.full(n, -0.02), np.full(n, 0.02))
    with pytest.raises(DesignError, match="not both"):
        monte_carlo(CW06, 10, spec=0.02, band=band, step_deg=STEP)
    with pytest.raises(DesignError, match="exactly one of them"):
        allocate(CW06, step_deg=STEP)
    with pytest.raises(DesignError, match="exactly one of them"):
        allocate(CW06, 0.02, band=band, step_deg=STEP)
    lo = band[0].copy()
    lo[10] = 0.0  # excludes the nominal motion at the 11th grid angle
    with pytest.raises(DesignError, match=r"band at theta=10\.00°: lower=0"):
        allocate(CW06, band=(lo, band[1]), step_deg=STEP)
    with pytest.raises(DesignError, match="one per grid angle"):
        band_curves((lo[:-1], band[1][:-1]), st.theta_rad)
    with pytest.raises(InputFileError):
        read_band_csv("/nonexistent/band.csv", "translating")


# --- a band equal to ±spec is the spec ----------------------------------------------------


@pytest.mark.parametrize("mode, samples", [("linear", 5000), ("exact", 12)])
def test_cli_symmetric_band_gives_the_spec_yield(tmp_path: Path, capsys, mode, samples):
    band = _symmetric_band(tmp_path, 12)
    base = ["montecarlo", "-e", "cw06-translating", "--samples", str(samples), "--seed", "5"]
    base += ["--mode", mode, "--step", "1", "--json"]
    assert main([*base, "--spec-um", "12"]) == 0
    by_spec = json.loads(capsys.readouterr().out)
    assert main([*base, "--band", str(band)]) == 0
    by_band = json.loads(capsys.readouterr().out)
    assert 0.0 < by_spec["yield"]["value"] < 1.0  # the spec actually bites
    assert by_band["yield"]["value"] == by_spec["yield"]["value"]
    assert by_band["yield"]["ci95"] == by_spec["yield"]["ci95"]
    assert by_band["yield"]["spec"] == "lower <= dS <= upper at every angle, band band.csv"


@pytest.mark.parametrize(
    "criterion, spec_um", [("worst_case", 20.0), ("rss", 15.0), ("monte_carlo", 15.0)]
)
def test_symmetric_band_gives_the_spec_allocation(tmp_path: Path, criterion, spec_um):
    band = read_band_csv(_symmetric_band(tmp_path, spec_um), "translating")
    kw = {"criterion": criterion, "step_deg": STEP, "samples": 4000, "verify_samples": 4000}
    a = allocate(CW06, spec_um * 1e-3, **kw)
    b = allocate(CW06, band=band, **kw)
    assert b.grades == a.grades and b.cost == a.cost
    assert b.coarser_fails == a.coarser_fails and b.evaluated == a.evaluated
    assert b.verified == dataclass_replace_spec(a.verified, b.verified)
    assert b.spec is None and b.band == "band.csv" and a.band is None
    if criterion == "monte_carlo":
        assert b.achieved == a.achieved
    else:  # the figure relative to the band: worst case (or RSS) / spec
        # a.achieved is in mm (internal unit): × 1e3 gives the µm of the spec
        assert b.achieved == pytest.approx(a.achieved * 1e3 / spec_um, rel=1e-12)


def dataclass_replace_spec(y, other):
    """y judged against other's spec or band (the yield's figures stay y's)."""
    import dataclasses

    return dataclasses.replace(y, spec=other.spec, band=other.band)


def test_cli_allocate_band_json(tmp_path: Path, capsys):
    band = _symmetric_band(tmp_path, 20)
    base = ["allocate", "-e", "cw06-translating", "--verify-samples", "2000", "--json"]
    assert main([*base, "--spec-um", "20"]) == 0
    by_spec = json.loads(capsys.readouterr().out)
    assert main([*base, "--band", str(band)]) == 0
    by_band = json.loads(capsys.readouterr().out)
    assert by_band["grades"] == by_spec["grades"]
    assert by_band["spec"] is None and by_band["band"] == "band.csv"
    assert by_spec["spec"] == 20 and by_spec["band"] is None
    assert by_band["achieved"] == pytest.approx(by_spec["achieved"] / 20, rel=1e-12)
    assert main(base[:-1] + ["--band", str(band)]) == 0
    text = capsys.readouterr().out
    assert "band band.csv (lower <= dS <= upper)" in text and "/ band half-width" in text


# --- an asymmetric band: the allocation meets it (brute force over the full grid) --------


def _asymmetric(tmp_path: Path) -> ToleranceBand:
    rows = "\n".join(
        f"{t},{-22 - 4 * math.sin(math.radians(t)):.6f},{40 + 10 * math.cos(math.radians(t)):.6f}"
        for t in range(0, 360, 15)
    )
    return read_band_csv(
        _write(tmp_path, "theta_deg,lower_um,upper_um\n" + rows + "\n"), "translating"
    )


def _final(grades: dict[str, str]):
    d = _with_grades(CW06, list(grades), tuple(grades.values()))
    return prepare(d, step_deg=STEP)


def _inside(study, seed: int, samples: int, lo, hi) -> float:
    """Fraction of samples inside the band at every grid angle (full grid, no reduction)."""
    x = sample_matrix(study.plan, seed, samples)
    ds = x @ study.sens["lift"].T
    return float(np.mean(np.all((ds >= lo) & (ds <= hi), axis=1)))


@pytest.mark.parametrize("criterion", ["worst_case", "rss", "monte_carlo"])
def test_asymmetric_band_allocation_meets_the_band(tmp_path: Path, criterion):
    band = _asymmetric(tmp_path)
    a = allocate(CW06, band=band, criterion=criterion, step_deg=STEP, samples=4000)
    st = _final(a.grades)
    lo, hi = band.on_grid(st.theta_rad)
    m = np.minimum(hi, -lo)
    t = np.array(st.plan.deviations)
    g = st.sens["lift"]
    worst = np.abs(g) @ t
    rss = np.sqrt((g * g) @ (t * t))
    target = 0.9973
    if criterion == "worst_case":
        # a symmetric bound inside the band at every angle; so every sample is inside
        assert np.all(worst <= m) and a.achieved == pytest.approx(np.max(worst / m), rel=1e-12)
        assert _inside(st, 77, 20000, lo, hi) == 1.0
    elif criterion == "rss":
        assert np.all(rss <= m) and a.achieved == pytest.approx(np.max(rss / m), rel=1e-12)
        assert _inside(st, 77, 20000, lo, hi) >= target  # RSS = 3σ at Cp = 1
    else:
        # the same samples over the full grid give the allocation's yield (the hull
        # reduction is exact; one sample may flip on rounding at an edge) ...
        assert abs(_inside(st, 0, 4000, lo, hi) - a.achieved) <= 1 / 4000
        assert a.achieved >= target
        # ... and fresh samples agree within the allocation's sampling error (3σ of a
        # binomial of 4000 samples at the target)
        fresh = _inside(st, 77, 40000, lo, hi)
        assert fresh >= target - 3 * math.sqrt(target * (1 - target) / 4000)
        assert a.verified.ci95[1] >= target
    # one grade coarser breaks it (brute force for the closed-form criteria)
    for k, fails in a.coarser_fails.items():
        assert fails in (True, None)
        if fails and criterion != "monte_carlo":
            grades = dict(a.grades)
            grades[k] = f"IT{int(grades[k][2:]) + 1}"
            s2 = _final(grades)
            t2 = np.array(s2.plan.deviations)
            g2 = s2.sens["lift"]
            fig = np.abs(g2) @ t2 if criterion == "worst_case" else np.sqrt((g2 * g2) @ (t2 * t2))
            assert np.any(fig > m)
    # the asymmetry is used: the wide upper side does not let the allocation coarsen past
    # what the narrow lower side allows (m = min(upper, -lower) is the lower side here)
    assert np.all(m == -lo)


# --- a band tighter at one angle: the allocation tightens ------------------------------------


@pytest.mark.parametrize("criterion", ["worst_case", "rss", "monte_carlo"])
def test_band_tighter_at_one_angle_tightens_the_allocation(criterion):
    st = prepare(CW06, step_deg=STEP)
    theta = np.degrees(st.theta_rad)
    spec = 40e-3
    # phi (the cam phase) dominates ΔS near 62° (its sensitivity peak): tighten there
    phi = st.plan.labels.index("phi")
    g = st.sens["lift"]
    peak = float(theta[np.argmax(np.abs(g[:, phi]))])
    assert 55 < peak < 70
    notch = np.abs((theta - peak + 180) % 360 - 180) <= 3
    hi = np.where(notch, 0.8 * spec, spec)
    kw = {"criterion": criterion, "step_deg": STEP, "samples": 4000, "verify_samples": 4000}
    loose = allocate(CW06, spec, **kw)
    tight = allocate(CW06, band=(-hi, hi), **kw)
    order = [f"IT{k}" for k in range(5, 13)]
    finer = {k: order.index(tight.grades[k]) < order.index(loose.grades[k]) for k in loose.grades}
    assert any(finer.values())  # something had to be made finer ...
    assert tight.cost > loose.cost  # ... at a higher cost

    def figure(grades):
        s = _final(grades)
        t = np.array(s.plan.deviations)
        gg = s.sens["lift"]
        return np.abs(gg) @ t if criterion == "worst_case" else np.sqrt((gg * gg) @ (t * t))

    if criterion != "monte_carlo":
        # the loose choice breaks the band only inside the notch; the tight one meets it
        assert np.any(figure(loose.grades)[notch] > 0.8 * spec)
        assert np.all(figure(loose.grades)[~notch] <= spec)
        assert np.all(figure(tight.grades) <= hi)
    else:
        lo_y = _inside(_final(loose.grades), 0, 4000, -hi, hi)
        assert lo_y < 0.9973 <= tight.achieved


def test_band_hull_reduction_is_exact(tmp_path: Path, rng):
    from camtol.tolerancing.allocation import _hull_angles

    st = prepare(CW06, step_deg=STEP)
    g = st.sens["lift"]
    lo, hi = _asymmetric(tmp_path).on_grid(st.theta_rad)
    sel = _hull_angles(g, lo, hi)
    assert 0 < sel.size < g.shape[0] // 2  # a real reduction (3 sources: qhull in 3-D)
    x = rng.standard_normal((500, g.shape[1])) * 0.02
    rows = np.vstack([g / hi[:, None], g / lo[:, None]])
    kept = np.vstack([g[sel] / hi[sel, None], g[sel] / lo[sel, None]])
    np.testing.assert_allclose((x @ kept.T).max(axis=1), (x @ rows.T).max(axis=1), rtol=1e-13)


def test_cli_oscillating_band_in_degrees(tmp_path: Path, capsys):
    band = _write(tmp_path, "theta_deg,lower_deg,upper_deg\n0,-0.05,0.05\n90,-0.05,0.05\n")
    base = ["allocate", "-e", "cw06-oscillating", "--criterion", "rss"]
    base += ["--verify-samples", "2000", "--json"]
    assert main([*base, "--spec-deg", "0.05"]) == 0
    by_spec = json.loads(capsys.readouterr().out)
    assert main([*base, "--band", str(band)]) == 0
    by_band = json.loads(capsys.readouterr().out)
    assert by_band["grades"] == by_spec["grades"] and by_band["unit"] == "deg"
    assert by_band["achieved"] == pytest.approx(by_spec["achieved"] / 0.05, rel=1e-9)
