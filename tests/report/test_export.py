"""Profile exports: adaptive sampling, CSV/DXF/SVG writers, cutter path, CLI `camtol profile`."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import ezdxf
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from camtol.analysis.kinematics import analysis_grid, kinematics
from camtol.analysis.profile import profile_points
from camtol.cli.app import main
from camtol.config.design_file import example_names, load_example
from camtol.design.cam_design import CamDesign
from camtol.design.motion import Segment, SegmentProgram
from camtol.exceptions import UndercutError
from camtol.export import write_profile
from camtol.mechanisms import FlatTranslating, RollerOscillating, RollerTranslating
from camtol.report.drawing_marks import MARK_COLOURS
from camtol.report.export import EXPORT_SUFFIXES, ExportError

EXAMPLES = example_names()
#: Dense analytic reference: 0.001° steps. Its own chords sag by < 1e-7 µm·(100/ρ[mm])
#: (Δs ≤ 2e-3 mm), negligible against the 0.1 µm under test.
DENSE_STEP_DEG = 0.001


def _program(height: float) -> SegmentProgram:
    r = math.radians
    return SegmentProgram(
        (
            Segment("rise", 0.0, r(120), "cycloidal", height),
            Segment("dwell", r(120), r(190)),
            Segment("return", r(190), r(290), "cycloidal", height),
            Segment("dwell", r(290), r(360)),
        )
    )


def _distinct(xy: np.ndarray) -> np.ndarray:
    """Drop repeated points (boundary rows, and θ = 360° which repeats θ = 0°)."""
    keep = np.r_[True, np.any(np.diff(xy, axis=0) != 0, axis=1)]
    xy = xy[keep]
    return xy[:-1] if np.allclose(xy[-1], xy[0], rtol=0, atol=1e-12) else xy


def analytic_curves(design: CamDesign) -> dict[str, np.ndarray]:
    """Every exported curve of a design evaluated densely, independently of export.py."""
    return {k: _distinct(v) for k, v in _analytic_curves(design).items()}


def _analytic_curves(design: CamDesign) -> dict[str, np.ndarray]:
    theta, left = analysis_grid(DENSE_STEP_DEG, design.program.boundaries_rad)
    if design.mechanism.kind == "conjugate":
        from camtol.pair.kinematics import conjugate_kinematics

        k = conjugate_kinematics(design, theta, left_limit=left, check=False)
        return {
            "CAM_A_PROFILE": np.column_stack([k.a.contact_x_mm, k.a.contact_y_mm]),
            "CAM_B_PROFILE": np.column_stack([k.b.contact_x_mm, k.b.contact_y_mm]),
            "CAM_A_PITCH_CURVE": np.column_stack([k.pitch_a_x_mm, k.pitch_a_y_mm]),
            "CAM_B_PITCH_CURVE": np.column_stack([k.pitch_b_x_mm, k.pitch_b_y_mm]),
        }
    k = kinematics(design, theta, left_limit=left, check=False)
    out = {"CAM_PROFILE": np.column_stack([k.contact_x_mm, k.contact_y_mm])}
    g = design.mechanism.contact(theta, k.lift, k.velocity)
    if "pitch_x" in g.extras:
        out["CAM_PITCH_CURVE"] = np.column_stack([g.extras["pitch_x"], g.extras["pitch_y"]])
    return out


def distance_to_polyline(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of each point to a closed polyline (nearest vertex and its two segments)."""
    tree = cKDTree(poly)
    _, i = tree.query(points)
    n = len(poly)
    best = np.full(len(points), np.inf)
    for j0, j1 in ((i - 1) % n, i), (i, (i + 1) % n):
        a, b = poly[j0], poly[j1]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", points - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
        d = np.hypot(*(points - (a + t[:, None] * ab)).T)
        best = np.minimum(best, d)
    return best


def chord_points(poly: np.ndarray, per_chord: int = 8) -> np.ndarray:
    """Points along every chord of a closed polyline, vertices included."""
    nxt = np.roll(poly, -1, axis=0)
    f = np.arange(per_chord) / per_chord
    return (poly[:, None, :] + f[None, :, None] * (nxt - poly)[:, None, :]).reshape(-1, 2)


def hausdorff_mm(poly: np.ndarray, dense: np.ndarray) -> float:
    """Two-sided distance between an exported closed polyline and the dense analytic curve."""
    there = distance_to_polyline(chord_points(poly), dense).max()
    back = distance_to_polyline(dense, poly).max()
    return float(max(there, back))


def read_dxf_polylines(path: Path) -> dict[str, np.ndarray]:
    doc = ezdxf.readfile(path)
    out = {}
    for e in doc.modelspace().query("LWPOLYLINE"):
        if e.dxf.layer in MARK_COLOURS:  # annotations (timing mark, rotation arrow)
            continue
        assert e.closed, e.dxf.layer
        out[e.dxf.layer] = np.array(e.get_points("xy"), dtype=float)
    return out


# ---------------------------------------------------------------------------------------
# DXF: the acceptance test of the issue
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", EXAMPLES)
def test_dxf_of_each_example_lies_on_analytic_profile(name: str, tmp_path: Path) -> None:
    design = load_example(name)
    path = tmp_path / f"{name}.dxf"
    write_profile(design, path)  # default tolerance 0.1 µm
    polys = read_dxf_polylines(path)
    dense = analytic_curves(design)
    assert set(dense) <= set(polys)
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4  # millimetres
    for layer, ref in dense.items():
        # Both ways: polyline to curve and curve to polyline, within the requested 0.1 µm.
        assert hausdorff_mm(polys[layer], ref) <= 1e-4, layer


def test_dxf_tolerance_option_is_honoured(tmp_path: Path) -> None:
    design = load_example("cw06-translating")
    ref = analytic_curves(design)["CAM_PROFILE"]
    counts = {}
    for tol in (1e-3, 1e-4):
        path = tmp_path / f"t{tol:g}.dxf"
        write_profile(design, path, tolerance_mm=tol)
        poly = read_dxf_polylines(path)["CAM_PROFILE"]
        d = hausdorff_mm(poly, ref)
        assert d <= tol
        assert d > 0.3 * tol  # not needlessly dense: the sampling uses the tolerance
        counts[tol] = len(poly)
    # Chord count scales as 1/sqrt(tolerance): a factor sqrt(10) ≈ 3.16 (±20 %).
    assert counts[1e-4] / counts[1e-3] == pytest.approx(math.sqrt(10), rel=0.2)


@settings(max_examples=6, deadline=None)
@given(st.floats(min_value=2e-5, max_value=5e-3))
def test_profile_points_verified_deviation_below_tolerance(tol: float) -> None:
    design = load_example("cw06-oscillating")
    pts = profile_points(design, tolerance_mm=tol)
    assert pts.profile.max_deviation_mm <= tol
    ref = analytic_curves(design)["CAM_PROFILE"]
    poly = np.column_stack([pts.profile.x_mm, pts.profile.y_mm])
    assert hausdorff_mm(poly, ref) <= tol


def test_profile_vertices_are_exact_and_include_segment_boundaries() -> None:
    design = load_example("cw06-translating")
    pts = profile_points(design)
    c = pts.profile
    k = kinematics(design, c.theta_rad, check=False)
    np.testing.assert_allclose(c.x_mm, k.contact_x_mm, rtol=0, atol=1e-12)
    np.testing.assert_allclose(c.y_mm, k.contact_y_mm, rtol=0, atol=1e-12)
    deg = np.degrees(c.theta_rad)
    for b in (0.0, 120.0, 190.0, 290.0):
        assert np.min(np.abs(deg - b)) < 1e-9
    assert np.all(np.diff(c.theta_rad) > 0) and c.theta_rad[-1] < 2 * math.pi
    # Steps never exceed 1°.
    assert np.max(np.diff(np.append(c.theta_rad, 2 * math.pi))) <= math.radians(1.0) + 1e-12


# ---------------------------------------------------------------------------------------
# CSV and SVG
# ---------------------------------------------------------------------------------------
def test_csv_columns_units_and_values(tmp_path: Path) -> None:
    design = load_example("cw06-translating")
    path = tmp_path / "p.csv"
    write_profile(design, path, cutter_radius_mm=6.0)
    header = path.read_text().splitlines()[0].split(",")
    assert header == [
        "theta_deg",
        "cam_profile_x_mm",
        "cam_profile_y_mm",
        "cam_cutter_path_x_mm",
        "cam_cutter_path_y_mm",
    ]
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    k = kinematics(design, np.radians(data[:, 0]), check=False)
    # 12 significant digits on ~60 mm: 1e-9 mm.
    np.testing.assert_allclose(data[:, 1], k.contact_x_mm, atol=1e-8)
    np.testing.assert_allclose(data[:, 2], k.contact_y_mm, atol=1e-8)
    # The cutter centre is at the cutter radius from the profile, along its normal.
    dense = analytic_curves(design)["CAM_PROFILE"]
    d = distance_to_polyline(data[:, 3:5], dense)
    np.testing.assert_allclose(d, 6.0, atol=1e-6)


def test_cutter_path_of_roller_radius_is_the_pitch_curve(tmp_path: Path) -> None:
    # Independent check of the offset direction: a cutter of the roller's radius follows
    # the roller centre (THEORY §2.3-2.4: C = A + r_f n).
    design = load_example("cw11-conjugate")
    path = tmp_path / "c.csv"
    rf = design.mechanism.roller_radius_mm  # type: ignore[attr-defined]
    write_profile(design, path, cutter_radius_mm=rf)
    names = path.read_text().splitlines()[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    col = {n: data[:, i] for i, n in enumerate(names)}
    for cam in ("a", "b"):
        for xy in ("x", "y"):
            np.testing.assert_allclose(
                col[f"cam_{cam}_cutter_path_{xy}_mm"],
                col[f"cam_{cam}_pitch_curve_{xy}_mm"],
                atol=1e-9,
            )


def test_svg_paths_match_profile(tmp_path: Path) -> None:
    design = load_example("cw11-conjugate")
    path = tmp_path / "p.svg"
    pts = write_profile(design, path)
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    assert root.attrib["width"].endswith("mm")
    groups = {g.attrib["id"]: g for g in root.findall("s:g", ns)}
    for c in pts.curves:
        d = groups[c.layer].find("s:path", ns).attrib["d"]  # type: ignore[union-attr]
        xy = np.array(
            [tuple(map(float, tok[1:].split(","))) for tok in d.split() if tok[0] in "ML"]
        )
        np.testing.assert_allclose(xy[:, 0], c.x_mm, atol=1e-6)
        np.testing.assert_allclose(-xy[:, 1], c.y_mm, atol=1e-6)  # SVG y points down


# ---------------------------------------------------------------------------------------
# Bad input: clear errors, nothing written
# ---------------------------------------------------------------------------------------
def test_unknown_suffix_lists_allowed_and_writes_nothing(tmp_path: Path) -> None:
    with pytest.raises(ExportError, match=r"\.csv, \.dxf, \.svg"):
        write_profile(load_example("cw06-translating"), tmp_path / "p.step")
    assert list(tmp_path.iterdir()) == []
    assert EXPORT_SUFFIXES == (".csv", ".dxf", ".svg")


def test_missing_directory_is_reported(tmp_path: Path) -> None:
    with pytest.raises(ExportError, match="does not exist"):
        write_profile(load_example("cw06-translating"), tmp_path / "nope" / "p.dxf")


@pytest.mark.parametrize("tol", [0.0, -1e-3, 2.0, float("nan")])
def test_tolerance_out_of_range(tol: float) -> None:
    with pytest.raises(ExportError, match="tolerance_mm"):
        profile_points(load_example("cw06-translating"), tolerance_mm=tol)


def test_undercut_design_writes_nothing(tmp_path: Path) -> None:
    design = CamDesign("cusp", FlatTranslating(base_radius_mm=5.0), _program(22.0))
    with pytest.raises(UndercutError, match="θ="):
        write_profile(design, tmp_path / "p.dxf")
    assert list(tmp_path.iterdir()) == []


def test_cutter_larger_than_concave_radius_is_refused() -> None:
    # A small translating-roller cam has a concave flank; find its smallest concave radius.
    design = CamDesign("concave", RollerTranslating(20.0, 8.0, 0.0), _program(22.0))
    theta, left = analysis_grid(0.01, design.program.boundaries_rad)
    rho = kinematics(design, theta, left_limit=left).curvature_radius_mm
    concave = -rho[rho < 0]
    assert concave.size > 0, "the test design must have a concave region"
    smallest = float(concave.min())
    pts = profile_points(design, cutter_radius_mm=0.9 * smallest)
    assert pts.curve("CAM_CUTTER_PATH").max_deviation_mm <= 1e-4
    with pytest.raises(UndercutError, match="gouge"):
        profile_points(design, cutter_radius_mm=1.1 * smallest)


@pytest.mark.parametrize("radius", [0.0, -1.0, math.inf, 100_000.5, 1e30])
def test_cutter_radius_outside_its_range_is_refused(radius: float) -> None:
    # 1e30 mm overflowed the offset's sampling ("the curve is undefined at 0°").
    with pytest.raises(ExportError, match="cutter_radius_mm=.* at most 100000 mm"):
        profile_points(load_example("cw06-translating"), cutter_radius_mm=radius)


# ---------------------------------------------------------------------------------------
# CLI
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", EXPORT_SUFFIXES)
def test_cli_profile_writes_each_format(
    suffix: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / f"p{suffix}"
    assert main(["profile", "--example", "cw06-oscillating", "-o", str(out)]) == 0
    assert out.stat().st_size > 1000
    assert "CAM_PROFILE" in capsys.readouterr().out


def test_cli_profile_bad_suffix_exit_2_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["profile", "--example", "cw06-translating", "-o", str(tmp_path / "p.iges")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and ".dxf" in err
    assert list(tmp_path.iterdir()) == []


def test_cli_profile_json_and_quiet(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import json

    out = tmp_path / "p.dxf"
    args = ["profile", "-e", "cw11-conjugate", "-o", str(out), "--cutter-radius", "10"]
    assert main([*args, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    layers = [c["layer"] for c in doc["curves"]]
    assert layers == [
        "CAM_A_PROFILE",
        "CAM_A_PITCH_CURVE",
        "CAM_A_CUTTER_PATH",
        "CAM_B_PROFILE",
        "CAM_B_PITCH_CURVE",
        "CAM_B_CUTTER_PATH",
    ]
    assert all(c["max_deviation_um"] <= 0.1 for c in doc["curves"])
    assert main([*args, "--quiet"]) == 0
    assert capsys.readouterr().out == ""
    assert main(["profile", "-e", "cw11-conjugate", "-o", str(out), "--cutter-radius", "0"]) == 2


ROLLER_DESIGNS = {
    "roller_translating": lambda: CamDesign(
        "rt", RollerTranslating(40.0, 10.0, 5.0), _program(22.0)
    ),
    "roller_oscillating": lambda: CamDesign(
        "ro", RollerOscillating(40.0, 10.0, 80.0, 60.0), _program(math.radians(15.0))
    ),
}


@pytest.mark.parametrize("kind", sorted(ROLLER_DESIGNS))
def test_roller_dxf_has_profile_and_pitch_curve_layers(kind: str, tmp_path: Path) -> None:
    design = ROLLER_DESIGNS[kind]()
    path = tmp_path / "r.dxf"
    write_profile(design, path, cutter_radius_mm=4.0)
    polys = read_dxf_polylines(path)
    assert set(polys) == {"CAM_PROFILE", "CAM_PITCH_CURVE", "CAM_CUTTER_PATH"}
    layers = {layer.dxf.name for layer in ezdxf.readfile(path).layers}
    assert {"CAM_PROFILE", "CAM_PITCH_CURVE", "CAM_CUTTER_PATH"} <= layers
    dense = analytic_curves(design)
    for layer in ("CAM_PROFILE", "CAM_PITCH_CURVE"):
        assert hausdorff_mm(polys[layer], dense[layer]) <= 1e-4, layer
    # The pitch curve is the roller radius outside the profile.
    d = distance_to_polyline(polys["CAM_PITCH_CURVE"], dense["CAM_PROFILE"])
    np.testing.assert_allclose(d, design.mechanism.roller_radius_mm, atol=1e-6)  # type: ignore[attr-defined]


@settings(max_examples=5, deadline=None)
@given(
    base=st.floats(30.0, 60.0),
    offset=st.floats(-10.0, 10.0),
    face_deg=st.floats(-20.0, 20.0),
    rise=st.floats(5.0, 25.0),
)
def test_adaptive_sampling_holds_on_random_flat_designs(
    base: float, offset: float, face_deg: float, rise: float
) -> None:
    from hypothesis import assume

    design = CamDesign(
        "random", FlatTranslating(base, offset, math.radians(face_deg)), _program(rise)
    )
    try:
        pts = profile_points(design, tolerance_mm=1e-4)
    except UndercutError:
        assume(False)
        return
    ref = analytic_curves(design)["CAM_PROFILE"]
    poly = np.column_stack([pts.profile.x_mm, pts.profile.y_mm])
    assert hausdorff_mm(poly, ref) <= 1e-4


def test_report_writer_only_writes_what_it_is_given(tmp_path: Path) -> None:
    """The report layer writes sampled points; a CSV needs the table the core computed."""
    from camtol.analysis.profile import profile_table
    from camtol.report.export import write_profile_points

    design = load_example("cw06-translating")
    pts = profile_points(design)
    with pytest.raises(ExportError, match="needs the table"):
        write_profile_points(design, pts, tmp_path / "p.csv")
    assert not (tmp_path / "p.csv").exists()
    write_profile_points(design, pts, tmp_path / "p.csv", table=profile_table(design, pts))
    write_profile(design, tmp_path / "q.csv")
    assert (tmp_path / "p.csv").read_text() == (tmp_path / "q.csv").read_text()
