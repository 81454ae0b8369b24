"""What a cam *is*: motion program, follower mechanism, tolerances, design-level sources.

The motion program (laws, segments, lift tables), the design that pairs
it with a follower mechanism, its tolerances and its design-level error sources.

The lowest layer above the follower mechanisms (docs/architecture.md): nothing here knows
about the engines, inspection, files or the command line.
"""

from __future__ import annotations

from camtol.design.cam_design import (
    IT_CONVENTIONS,
    Cam,
    CamDesign,
    ResolvedTolerance,
    ToleranceSpec,
)
from camtol.design.motion import (
    MOTION_LAWS,
    LiftTable,
    MotionProgram,
    MotionState,
    Segment,
    SegmentProgram,
)
from camtol.design.sources import (
    AngularPhase,
    DesignSource,
    design_source,
    register_design_source,
)

__all__ = [
    "AngularPhase",
    "Cam",
    "CamDesign",
    "DesignSource",
    "IT_CONVENTIONS",
    "LiftTable",
    "MOTION_LAWS",
    "MotionProgram",
    "MotionState",
    "ResolvedTolerance",
    "Segment",
    "SegmentProgram",
    "ToleranceSpec",
    "design_source",
    "register_design_source",
]
