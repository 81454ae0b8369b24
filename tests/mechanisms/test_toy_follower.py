"""A new follower type added in one file works everywhere (issue 8 acceptance).

The toy is a centred translating roller follower described by its *prime* radius
r_p = r_b + r_f (instead of the base radius). It is declared here and nowhere else: its
parameters, synthesis, sensitivities, contact element and drawing come from the class, and
the design-file schema, ``analyze``, ``verify``, the profile export, the cam drawing and
``dump_design`` take everything from it.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

from camtol.analysis.profile import profile_points
from camtol.analysis.result import analyze
from camtol.cli.app import main
from camtol.config.design_file import design_from_mapping, dump_design, load_design
from camtol.jet import FloatArray, JetLike
from camtol.mechanisms.base import (
    FOLLOWER_TYPES,
    ContactGeometry,
    ErrorSource,
    OutputKind,
    register_follower,
)
from camtol.mechanisms.elements import RollerGuide
from camtol.mechanisms.roller_common import RollerMechanism
from camtol.mechanisms.roller_translating import RollerTranslating
from camtol.mechanisms.spec import Parameter, length
from camtol.verify import verify

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib


@dataclass(frozen=True)
class ToyCentredRoller(RollerMechanism):
    """Centred translating roller given by prime radius r_p and roller radius r_f. [mm]"""

    prime_radius_mm: float
    roller_radius_mm: float

    kind: ClassVar[str] = "toy_centred_roller"
    output: ClassVar[OutputKind] = "translating"
    title: ClassVar[str] = "toy centred roller"
    radial_factor_label: ClassVar[str] = "ΔS_r/Δr = cos λ / cos φ"
    sources: ClassVar[tuple[ErrorSource, ...]] = (
        ErrorSource("r", "radial profile error Δr", "mm"),
        ErrorSource("n", "normal profile error Δn", "mm"),
        ErrorSource("rf", "roller-radius error Δr_f", "mm", "roller_radius_mm"),
    )
    parameters: ClassVar[tuple[Parameter, ...]] = (
        length("prime_radius_mm", "prime radius r_p = r_b + r_f"),
        length("roller_radius_mm", "roller radius r_f"),
    )

    @property
    def _same(self) -> RollerTranslating:
        # the same geometry as the built-in roller, reused rather than re-derived
        return RollerTranslating(
            self.prime_radius_mm - self.roller_radius_mm, self.roller_radius_mm
        )

    def contact(self, theta: JetLike, lift: JetLike, velocity: JetLike) -> ContactGeometry:
        """Contact geometry (THEORY §2.3 with e = 0)."""
        return self._same.contact(theta, lift, velocity)

    def sensitivities(self, geometry: ContactGeometry, theta: JetLike) -> dict[str, JetLike]:
        """ΔS_r, ΔS_n, ΔS_rf (THEORY §3.3); the path of the roller centre does not move."""
        out = self._same.sensitivities(geometry, theta)
        return {k: out[k] for k in ("r", "n", "rf")}

    def curvature_radius(
        self,
        theta_rad: FloatArray,
        lift: FloatArray,
        velocity: FloatArray,
        acceleration: FloatArray,
    ) -> FloatArray:
        """Signed profile radius of curvature. [mm]"""
        return self._same.curvature_radius(theta_rad, lift, velocity, acceleration)

    def nominal_size(self, key: str, max_radius_mm: float) -> float:
        """IT nominal sizes."""
        return {"r": max_radius_mm, "n": max_radius_mm, "rf": self.roller_radius_mm}[key]

    def summary(self) -> list[tuple[str, str]]:
        """Parameters with units."""
        return [("follower", self.title), ("prime radius r_p", f"{self.prime_radius_mm:g} mm")]

    def contact_element(self) -> RollerGuide:
        """The roller on the line of motion through O2; S = 0 at r_p."""
        return RollerGuide("line", self.roller_radius_mm, zero=self.prime_radius_mm)


TOML = """
name = "toy"
[follower]
type = "toy_centred_roller"
prime_radius_mm = 55.0
roller_radius_mm = 10.0
[motion]
segments = [
  { kind = "rise", law = "cycloidal", start_deg = 0, end_deg = 120, lift_mm = 12.0 },
  { kind = "dwell", start_deg = 120, end_deg = 180 },
  { kind = "return", law = "cycloidal", start_deg = 180, end_deg = 300, lift_mm = 12.0 },
  { kind = "dwell", start_deg = 300, end_deg = 360 },
]
[tolerances]
r = "IT6"
rf_um = 8.0
phase_deg = 0.01
"""


@pytest.fixture
def toy(tmp_path: Path) -> Iterator[Path]:
    register_follower(ToyCentredRoller)
    path = tmp_path / "toy.toml"
    path.write_text(TOML, encoding="utf-8")
    try:
        yield path
    finally:
        FOLLOWER_TYPES.pop(ToyCentredRoller.kind, None)


def test_the_design_file_schema_knows_it(toy: Path) -> None:
    design = load_design(toy)
    assert isinstance(design.mechanism, ToyCentredRoller)
    assert design_from_mapping(tomllib.loads(dump_design(design))) == design
    bad = TOML.replace("prime_radius_mm = 55.0", 'prime_radius_mm = "55"')
    with pytest.raises(Exception, match=r"follower.prime_radius_mm='55'"):
        design_from_mapping(tomllib.loads(bad))


def test_analyze_matches_the_builtin_roller(toy: Path) -> None:
    design = load_design(toy)
    a = analyze(design, step_deg=1.0)
    builtin = TOML.replace('type = "toy_centred_roller"', 'type = "roller_translating"')
    builtin = builtin.replace("prime_radius_mm = 55.0", "base_radius_mm = 45.0")
    b = analyze(design_from_mapping(tomllib.loads(builtin)), step_deg=1.0)
    for key in ("pressure_angle", "dS_r", "dS_rf", "dS_phase", "dS_worst"):
        np.testing.assert_allclose(a.curves[key], b.curves[key], rtol=1e-12, atol=1e-12)
    assert math.isclose(a.max_radius_mm, b.max_radius_mm, rel_tol=1e-12)


def test_verify_checks_it_exactly(toy: Path) -> None:
    v = verify(load_design(toy), step_deg=1.0)
    assert v.ok
    assert v.roundtrip_max_error < 1e-9
    assert set(v.linearisation) == {"r", "rf", "phase"}
    assert v.polyline is not None and v.polyline.ok


def test_export_and_cli(toy: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pts = profile_points(load_design(toy)).profile
    radius = np.hypot(pts.x_mm, pts.y_mm)
    assert radius.min() == pytest.approx(45.0, abs=1e-6)  # base circle r_p − r_f
    assert radius.max() == pytest.approx(57.0, abs=1e-6)
    out = tmp_path / "toy.csv"
    assert main(["profile", str(toy), "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8").count("\n") > 100
    assert main(["analyze", str(toy)]) == 0
    assert "toy centred roller" in capsys.readouterr().out
    assert main(["verify", str(toy), "--step", "1"]) == 0
