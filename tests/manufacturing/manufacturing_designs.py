"""Designs shared by the manufacturing tests."""

from __future__ import annotations

from camtol.config.design_file import design_from_mapping
from camtol.design.cam_design import CamDesign


def concave_roller_design() -> CamDesign:
    """Roller follower whose profile is concave (ρ ≈ −16.9 mm near θ = 230.6°)."""
    segs = [
        {"kind": "rise", "law": "cycloidal", "start_deg": 0, "end_deg": 60, "lift_mm": 20.0},
        {"kind": "dwell", "end_deg": 180},
        {"kind": "return", "law": "cycloidal", "end_deg": 240, "lift_mm": 20.0},
        {"kind": "dwell", "end_deg": 360},
    ]
    return design_from_mapping(
        {
            "name": "concave-roller",
            "follower": {
                "type": "roller_translating",
                "base_radius_mm": 20.0,
                "roller_radius_mm": 5.0,
                "offset_mm": 0.0,
            },  # fmt: skip
            "motion": {"segments": segs},
        }
    )


#: The same design as a TOML file.
CONCAVE_ROLLER_TOML = """
name = "concave-roller"

[follower]
type = "roller_translating"
base_radius_mm = 20.0
roller_radius_mm = 5.0
offset_mm = 0.0

[motion]
segments = [
  { kind = "rise", law = "cycloidal", start_deg = 0, end_deg = 60, lift_mm = 20.0 },
  { kind = "dwell", end_deg = 180 },
  { kind = "return", law = "cycloidal", end_deg = 240, lift_mm = 20.0 },
  { kind = "dwell", end_deg = 360 },
]
"""
