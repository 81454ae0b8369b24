"""One CMM inspection of a cam, from its inputs (THEORY §2, §3, §5; docs/cmm-inspection.md).

:class:`CmmInputs` gathers what a scan is judged with besides the design: the point file
and how to read it (cam, stylus radius, column names), the registration datum, the
profile tolerance and the deviation it bounds (Δn or Δr), and the follower-motion error's
grid, smoothing and spec. :func:`run_cmm` reads the scan, registers it, computes the
deviations and the verdict and the follower's motion error, and returns the
:class:`CmmRun`. ``camtol inspect`` is this one call, and so is the re-run of a stored CMM
record (``camtol records rerun``): the same inputs give the same run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camtol.design.cam_design import CamDesign
from camtol.exceptions import GeometryError, InputFileError
from camtol.inspection.cmm import CamLabel, Scan, header_stylus_radius_mm, read_scan
from camtol.inspection.deviations import (
    CamProfile,
    CmmInspection,
    ToleranceKind,
    cam_profile,
    inspect_scan,
)
from camtol.inspection.functional import (
    DEFAULT_HARMONICS,
    FunctionalDeviation,
    functional_deviation,
)
from camtol.inspection.registration import Datum

__all__ = ["CmmInputs", "CmmRun", "datum_from_mapping", "datum_to_mapping", "run_cmm"]


@dataclass(frozen=True)
class CmmInputs:
    """What a CMM inspection is judged with, besides the design.

    Field names follow the options of ``camtol inspect``.

    Attributes
    ----------
    points_path : str
        The CMM point file (``--points``).
    cam : {"A", "B"}
        Which cam of a conjugate pair the scan is (a single cam is ``"A"``).
    stylus_radius_mm : float
        Stylus-ball radius: the points are ball centres (0: surface points). [mm]
    aliases : mapping of str to str, optional
        Column names of the file mapped onto x_mm, y_mm, ... (``--columns``).
    datum : Datum
        Registration (``--datum``, ``--datum-angle``, ``--datum-point``, ``--loss``).
    tolerance_um : (float, float), optional
        An explicit profile zone [lower, upper] (default: the design's ISO 1101 zone,
        :func:`~camtol.inspection.deviations.design_zone`). [µm]
    tolerance_kind : {"normal", "radial"}, optional
        Whether the zone bounds Δn (default, ISO 1101) or Δr (a radial band, not ISO).
    harmonics : int
        Fourier cut-off of the smoothing of Δn for the follower error.
    step_deg : float
        Cam-angle grid of the follower error. [deg]
    spec : float, optional
        Motion spec on max |ΔS| measured, in the unit of S (mm for a lift, rad for a
        swing). [mm or rad]
    decision : {"simple", "guard-band"}
        ISO 14253-1 decision rule of the profile verdict.
    u_cmm_um : float, optional
        The CMM's expanded uncertainty U (needed by ``guard-band``). [µm]
    """

    points_path: str
    cam: CamLabel = "A"
    stylus_radius_mm: float = 0.0
    aliases: Mapping[str, str] | None = None
    datum: Datum = field(default_factory=Datum)
    tolerance_um: tuple[float, float] | None = None
    tolerance_kind: ToleranceKind | None = None
    harmonics: int = DEFAULT_HARMONICS
    step_deg: float = 0.1
    spec: float | None = None
    decision: str = "simple"
    u_cmm_um: float | None = None


@dataclass(frozen=True)
class CmmRun:
    """A CMM inspection with what it was judged with.

    Attributes
    ----------
    profile : CamProfile
        The inspected cam with its tabulated nominal profile.
    inspection : CmmInspection
        Registration, deviations of every point, form and the profile verdict.
    functional : FunctionalDeviation or None
        The follower's motion error on the measured cam; None when it could not be
        computed (``functional_error`` says why).
    functional_error : str or None
        Why the follower error was not computed (the contact engine's message).
    """

    profile: CamProfile
    inspection: CmmInspection
    functional: FunctionalDeviation | None
    functional_error: str | None = None

    @property
    def verdict(self) -> str:
        """``pass`` when the profile and (with a spec) the motion pass, else ``fail``."""
        motion_ok = self.functional is None or self.functional.passed is not False
        return "pass" if self.inspection.passed and motion_ok else "fail"

    @property
    def max_abs_ds_um(self) -> float | None:
        """Max |ΔS| of a translating follower's measured motion (None for a swing). [µm]"""
        func = self.functional
        if func is None or func.unit != "mm":
            return None
        return func.max_abs_measured * 1e3

    @property
    def max_abs_ds_deg(self) -> float | None:
        """Max |ΔS| of an oscillating follower's measured motion (None for a lift). [deg]"""
        func = self.functional
        if func is None or func.unit == "mm":
            return None
        return float(np.degrees(func.max_abs_measured))

    @property
    def motion_unit(self) -> str | None:
        """Unit of the follower error: ``um`` (a lift) or ``deg`` (a swing)."""
        func = self.functional
        if func is None:
            return None
        return "um" if func.unit == "mm" else "deg"


def run_cmm(design: CamDesign, inputs: CmmInputs, *, profile: CamProfile | None = None) -> CmmRun:
    """Read, register and judge a CMM scan, and compute the follower's motion error.

    Parameters
    ----------
    design : CamDesign
        The design (for a conjugate pair, the pair).
    inputs : CmmInputs
        The scan and everything it is judged with.
    profile : CamProfile, optional
        Cam ``inputs.cam`` of the design, when already built (:func:`cam_profile`).

    Returns
    -------
    CmmRun
        The inspection; ``functional`` None (with the reason) when the contact engine
        cannot follow the measured cam.

    Raises
    ------
    InputFileError
        A scan that cannot be read, does not go round the cam or does not match it.
    DesignError
        No profile tolerance, bad harmonics, spec or datum.
    """
    prof = cam_profile(design, inputs.cam) if profile is None else profile
    scan = read_scan(
        inputs.points_path,
        cam=inputs.cam,
        stylus_radius_mm=inputs.stylus_radius_mm,
        aliases=None if inputs.aliases is None else dict(inputs.aliases),
    )
    try:
        insp = _inspect(design, scan, inputs, prof)
    except InputFileError as exc:
        header = header_stylus_radius_mm(inputs.points_path)
        if header is None or header == inputs.stylus_radius_mm:
            raise
        raise InputFileError(
            f"{exc}; the header says stylus {header:g} mm: give --stylus-radius-mm {header:g}"
        ) from None
    try:
        func = functional_deviation(
            prof, insp, step_deg=inputs.step_deg, harmonics=inputs.harmonics, spec=inputs.spec
        )
    except GeometryError as exc:
        return CmmRun(prof, insp, None, str(exc))
    return CmmRun(prof, insp, func)


def _inspect(design: CamDesign, scan: Scan, inputs: CmmInputs, prof: CamProfile) -> CmmInspection:
    """Run the profile inspection of :func:`run_cmm`."""
    return inspect_scan(
        design,
        scan,
        cam=inputs.cam,
        datum=inputs.datum,
        tolerance_um=inputs.tolerance_um,
        tolerance_kind=inputs.tolerance_kind,
        profile=prof,
        decision=inputs.decision,
        u_cmm_um=inputs.u_cmm_um,
    )


def datum_to_mapping(datum: Datum) -> dict[str, Any]:
    """Return a datum as JSON-ready values (the fields a command line sets).

    Parameters
    ----------
    datum : Datum
        The registration datum.

    Returns
    -------
    dict
        ``mode``, ``centre_mm``, ``angle_deg``, ``point_mm``, ``point_angle_deg`` and
        ``loss`` (lists for the coordinate pairs, None when not given).
    """
    return {
        "mode": datum.mode,
        "centre_mm": None if datum.centre_mm is None else list(datum.centre_mm),
        "angle_deg": datum.angle_deg,
        "point_mm": None if datum.point_mm is None else list(datum.point_mm),
        "point_angle_deg": datum.point_angle_deg,
        "loss": datum.loss,
        "keyway_deg": datum.keyway_deg,
    }


def datum_from_mapping(data: Mapping[str, Any]) -> Datum:
    """Rebuild a datum written by :func:`datum_to_mapping`.

    Parameters
    ----------
    data : mapping
        ``mode``, ``centre_mm``, ``angle_deg``, ``point_mm``, ``point_angle_deg``,
        ``loss``.

    Returns
    -------
    Datum
    """
    centre, point = data.get("centre_mm"), data.get("point_mm")
    return Datum(
        mode=data.get("mode", "fit"),
        centre_mm=None if centre is None else (float(centre[0]), float(centre[1])),
        angle_deg=data.get("angle_deg"),
        point_mm=None if point is None else (float(point[0]), float(point[1])),
        point_angle_deg=data.get("point_angle_deg"),
        loss=data.get("loss", "soft_l1"),
        keyway_deg=data.get("keyway_deg"),
    )
