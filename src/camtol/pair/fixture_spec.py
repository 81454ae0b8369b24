"""The ``[inspection]`` table of a design file, typed (THEORY §4, §8.3).

A conjugate design's file may carry the inputs of the fixture analysis::

    [inspection]
    tolerance_a_um = [-22, 22]      # radial tolerance of cam A (lower, upper) [µm]
    tolerance_b_um = [-22, 22]      # of cam B (default: as cam A) [µm]
    dl_a_um = 19                    # arm-length errors Δl_A, Δl_B [µm]
    dl_b_um = 19
    drr_c_um = 11                   # roller-radius errors Δr_rC, Δr_rD [µm]
    drr_d_um = 11
    deta_deg = 0.022                # arm-angle error Δη [deg]
    master_a_um = "18.5 + 3.5*sin(theta)"   # master cams' known errors:
    master_b_um = "17.5 + 4.5*cos(2*theta)" #   number, formula or CSV path
    df_mea_um = 22                  # measured Δf: number, formula or CSV path

The table is validated once, when the design is loaded, by a strict table of fields
(:mod:`camtol.config.fields`: a string is not a number, a boolean is not a length; every
length within ±10 mm, Δη within ±10°) and becomes a frozen :class:`FixtureSpec` on the design
(:attr:`camtol.design.cam_design.CamDesign.inspection`). Messages name the field as the user wrote
it (``inspection.tolerance_a_um``), its value and what is allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError
from camtol.inspection.error_functions import ErrorFunction
from camtol.inspection.units import MAX_ERROR_UM
from camtol.inspection.zone import ZoneSpec, ZoneTable

__all__ = ["FixtureErrors", "FixtureSpec", "fixture_spec"]


@dataclass(frozen=True)
class FixtureErrors:
    """The constant errors of the follower (THEORY §4.1).

    Attributes
    ----------
    dl_a_mm, dl_b_mm : float
        Arm-length errors Δl_A, Δl_B. [mm]
    drr_c_mm, drr_d_mm : float
        Roller-radius errors Δr_rC, Δr_rD. [mm]
    deta_rad : float
        Arm-angle error Δη (> 0: arms opened wider). [rad]
    """

    dl_a_mm: float = 0.0
    dl_b_mm: float = 0.0
    drr_c_mm: float = 0.0
    drr_d_mm: float = 0.0
    deta_rad: float = 0.0


@dataclass(frozen=True)
class FixtureSpec:
    """Inputs of a fixture analysis (THEORY §4, §8.3).

    Attributes
    ----------
    errors : FixtureErrors
        Constant errors of the follower.
    tolerance_a_um, tolerance_b_um : tuple of float
        Radial tolerances (lower, upper) of cams A and B. [µm]
    master_a, master_b : ErrorFunction
        Known radial errors of the master cams. [µm]
    df_mea : ErrorFunction or None
        Measured centre-distance variation; None when there is no record. [µm]
    table : tuple of (str, object)
        The ``[inspection]`` table as validated (relative CSV paths made absolute), for
        writing the design back; empty when built in Python.
    """

    errors: FixtureErrors
    tolerance_a_um: tuple[float, float]
    tolerance_b_um: tuple[float, float]
    master_a: ErrorFunction
    master_b: ErrorFunction
    df_mea: ErrorFunction | None = None
    table: tuple[tuple[str, Any], ...] = field(default=(), compare=False, repr=False)
    profile_zones: ZoneTable | None = None

    def __post_init__(self) -> None:
        for cam, (lo, hi) in (("a", self.tolerance_a_um), ("b", self.tolerance_b_um)):
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise DesignError(
                    f"inspection.tolerance_{cam}_um=[{lo:g}, {hi:g}] is not allowed; give"
                    " [lower, upper] with lower < upper"
                )
            if max(abs(lo), abs(hi)) > MAX_ERROR_UM:
                raise DesignError(
                    f"inspection.tolerance_{cam}_um=[{lo:g}, {hi:g}] is not allowed; give"
                    f" limits within ±{MAX_ERROR_UM:g} µm (check the unit)"
                )

    def band_um(self, cam: str) -> tuple[float, float]:
        """Return the radial tolerance band (lower, upper) of cam ``"A"`` or ``"B"``. [µm]

        Parameters
        ----------
        cam : {"A", "B"}
            The cam's letter (:attr:`camtol.design.cam_design.Cam.letter`).

        Returns
        -------
        (float, float)
            ``tolerance_a_um`` or ``tolerance_b_um``.
        """
        return self.tolerance_a_um if cam == "A" else self.tolerance_b_um

    def profile_zone(self, cam: str) -> ZoneSpec | None:
        """Return the CMM profile zone (ISO 1101) the table states for a cam, or None.

        The fixture's radial bands (``tolerance_a_um``) are not a CMM zone (issue 31).

        Parameters
        ----------
        cam : {"A", "B"}
            The cam's letter.
        """
        return None if self.profile_zones is None else self.profile_zones.profile_zone(cam)

    def to_mapping(self) -> dict[str, Any]:
        """Return the ``[inspection]`` table this spec was built from (empty if none).

        Returns
        -------
        dict
            Field name → value as validated (relative CSV paths made absolute).
        """
        return dict(self.table)


def fixture_spec(design: CamDesign) -> FixtureSpec | None:
    """Return the measuring fixture's inputs of a design (its ``[inspection]`` table), or None.

    Parameters
    ----------
    design : CamDesign
        Any design.

    Returns
    -------
    FixtureSpec or None
        The design's :attr:`~camtol.design.cam_design.CamDesign.inspection`, typed.

    Raises
    ------
    DesignError
        If the design carries an inspection table of another kind.
    """
    spec = design.inspection
    if spec is None or isinstance(spec, FixtureSpec):
        return spec
    if isinstance(spec, ZoneTable):  # a CMM zone only: no fixture inputs
        return None
    raise DesignError(
        f"design {design.name!r}: its [inspection] table is a {type(spec).__name__}, not the"
        " measuring fixture's inputs"
    )
