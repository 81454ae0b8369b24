"""The independent error sources of a conjugate pair, and which cam each one moves.

A pair's ``[tolerances]`` name its sources per cam (``r_a``, ``r_b``), per roller
(``rf_c``, ``rf_d``), per arm (``l_a``, ``l_b``), the arm angle ``eta`` and the machine's
centre distance ``f``; ``r``, ``n``, ``rf``, ``l`` give one tolerance to both cams' own
sources, which are made independently (:meth:`~camtol.mechanisms.conjugate.ConjugatePair
.cam_source_keys`). :func:`pair_sources` lists the sources as independent random
variables: a per-cam source moves one cam, the centre distance and a design-level source
(the shaft's phase) move both. Each resolves its tolerance as the cam it moves does (the
IT nominal size of that cam's own source).
"""

from __future__ import annotations

from dataclasses import dataclass

from camtol.analysis.result import max_radius_mm
from camtol.design.cam_design import CamDesign, ResolvedTolerance
from camtol.design.sources import DESIGN_SOURCES
from camtol.pair.kinematics import require_pair

__all__ = ["PairSource", "pair_sources"]


@dataclass(frozen=True)
class PairSource:
    """One independent error source of a conjugate pair.

    Attributes
    ----------
    key : str
        The pair's own key (``r_a``, ``rf_d``, ``eta``, ``f``, ``phase``, ...).
    design_key : str
        The ``[tolerances]`` key that gives its tolerance (``r`` for both ``r_a`` and
        ``r_b`` when one tolerance covers both cams).
    cams : tuple of (str, str)
        (cam letter, that cam's own source key) of every cam it moves.
    tolerance : ResolvedTolerance
        Its deviation in internal units (under the cam's source key). [mm or rad]
    """

    key: str
    design_key: str
    cams: tuple[tuple[str, str], ...]
    tolerance: ResolvedTolerance


def pair_sources(design: CamDesign) -> tuple[PairSource, ...]:
    """List a pair's toleranced sources as independent variables, in the design's order.

    Parameters
    ----------
    design : CamDesign
        A conjugate design.

    Returns
    -------
    tuple of PairSource

    Raises
    ------
    DesignError
        Not a conjugate design, or a tolerance that cannot be resolved (e.g. a grade on η).
    """
    pair = require_pair(design, "a pair's tolerance analysis needs")
    cams = design.cams()
    resolved = {
        cam.letter: {t.key: t for t in cam.design.resolve_tolerances(max_radius_mm(cam.design))}
        for cam in cams
    }
    out: list[PairSource] = []
    for t in design.tolerances:
        moved = []
        for cam in cams:
            own = t.key if t.key in DESIGN_SOURCES else pair.cam_source_keys(cam.label).get(t.key)
            if own is not None:
                moved.append((cam.letter, cam.label, own))
        shared = t.key in DESIGN_SOURCES or t.key in pair.SHARED_KEYS
        if shared:
            letter, _, own = moved[0]
            tol = resolved[letter][own]
            out.append(PairSource(t.key, t.key, tuple((m[0], m[2]) for m in moved), tol))
            continue
        for letter, label, own in moved:
            key = pair.per_cam_key(label, own)
            out.append(PairSource(key, t.key, ((letter, own),), resolved[letter][own]))
    return tuple(out)
