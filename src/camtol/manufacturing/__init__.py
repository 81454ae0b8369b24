"""Manufacturing: table precision, cutting simulation, derivatives of measured lifts, G-code.

THEORY §6 ([Pop], [CDH]): how precise the lift table given to the machine must be
(:mod:`~camtol.manufacturing.precision`), how fine the angular cutting step
(:mod:`~camtol.manufacturing.cutting`, with the contact engine of THEORY §5), how far to
trust V, A, J derived from a measured lift (:mod:`~camtol.manufacturing.derivatives`), and
the program the machine runs (:mod:`~camtol.manufacturing.gcode`).
"""

from __future__ import annotations

from camtol.manufacturing.cutting import (
    CutCam,
    CutResult,
    coarsest_cut_step,
    cut_cam,
    simulate_cut,
)
from camtol.manufacturing.derivatives import DerivedMotion, derive_lift
from camtol.manufacturing.gcode import (
    GcodePath,
    GcodeProgram,
    path_deviation,
    read_gcode,
    write_gcode,
)
from camtol.manufacturing.precision import PrecisionRow, PrecisionStudy, table_precision
from camtol.manufacturing.toolpath import PathSample, profile_path

__all__ = [
    "CutCam",
    "CutResult",
    "DerivedMotion",
    "GcodePath",
    "GcodeProgram",
    "PathSample",
    "PrecisionRow",
    "PrecisionStudy",
    "coarsest_cut_step",
    "cut_cam",
    "derive_lift",
    "path_deviation",
    "profile_path",
    "read_gcode",
    "simulate_cut",
    "table_precision",
    "write_gcode",
]
