"""Display units of an analysis: the one place that turns internal units into shown ones.

:func:`camtol.analysis.result.analyze` returns every result in internal units (THEORY §0: mm,
rad, per radian of cam angle; :attr:`camtol.analysis.result.Quantity.unit`). Tables, files,
plots and the HTML report show

* the output errors ΔS of a translating follower in µm, of an oscillating one in
  degrees; their derivatives ΔV, ΔA per radian of cam angle, or per second (s²) when the
  design gives a cam speed ω (THEORY §3: d/dt = ω d/dθ);
* angles (pressure, shift angle; the oscillating radial factor's numerator) in degrees;
* lengths (radii, contact on the face) in mm, as computed.

:func:`display_unit` gives the unit and factor of one quantity; :func:`display_analysis`
the whole analysis as shown (quantities, lazily converted curves, extremes, travel).
Curves are converted when read (:meth:`camtol.analysis.result.Curves.scaled`), so a fine grid
holds no second copy of them (docs/performance.md, "Nothing kept twice").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from camtol.analysis.extremes import Extreme, scaled_extremes
from camtol.jet import FloatArray

if TYPE_CHECKING:  # pragma: no cover
    from camtol.analysis.result import Analysis, Quantity
    from camtol.design.cam_design import CamDesign
    from camtol.iso286 import GradeBracket

__all__ = [
    "ACCURACY_NOT_ASSESSED",
    "AnalysisDisplay",
    "DisplayCurves",
    "DisplayUnit",
    "DisplayUnits",
    "accuracy_words",
    "analysis_notes",
    "display_analysis",
    "display_curves",
    "display_extremes",
    "display_unit",
    "output_error_unit",
]

#: Degrees per radian. [deg/rad]
_DEG = 180.0 / math.pi

#: What every report says of the output accuracy of a design that tolerances nothing
#: (:attr:`camtol.analysis.result.Analysis.accuracy` is None: its ΔS is zero by construction).
ACCURACY_NOT_ASSESSED = "not assessed: the design gives no tolerances"


def accuracy_words(accuracy: GradeBracket | None) -> str:
    """Return the output accuracy in words, e.g. ``between IT7 (21 µm) and IT8 (33 µm)``.

    Parameters
    ----------
    accuracy : iso286.GradeBracket or None
        :attr:`camtol.analysis.result.Analysis.accuracy` (None: nothing toleranced).

    Returns
    -------
    str
        The bracket's description, or :data:`ACCURACY_NOT_ASSESSED`.
    """
    return ACCURACY_NOT_ASSESSED if accuracy is None else accuracy.describe()


@dataclass(frozen=True)
class DisplayUnit:
    """How one quantity is shown.

    Attributes
    ----------
    unit : str
        ASCII display unit, e.g. ``um``, ``deg``, ``um/s2``, ``deg/mm``, ``-``.
    factor : float
        Display value = internal value × factor. [display unit per internal unit]
    """

    unit: str
    factor: float


def output_error_unit(internal_unit: str) -> DisplayUnit:
    """How an error of the follower's output is shown: µm for mm, degrees for rad.

    Parameters
    ----------
    internal_unit : {"mm", "rad"}
        Internal unit of the output (:attr:`camtol.mechanisms.base.Mechanism.output_unit`).

    Returns
    -------
    DisplayUnit
        (``um``, 1e3) for a translating follower, (``deg``, 180/π) for an oscillating one.
    """
    return DisplayUnit("um", 1e3) if internal_unit == "mm" else DisplayUnit("deg", _DEG)


@dataclass(frozen=True)
class DisplayUnits:
    """Display units of the output errors ΔS, ΔV, ΔA and the factors from internal units.

    Attributes
    ----------
    lift, velocity, acceleration : str
        Unit keys of ΔS, ΔV, ΔA: ``um``, ``um/rad`` or ``um/s``, ``um/rad2`` or
        ``um/s2`` for a translating follower; ``deg...`` for an oscillating one.
    lift_scale, velocity_scale, acceleration_scale : float
        Factors from the internal unit (mm or rad, per rad^k of cam angle) to those
        units; with a cam speed ω they include ω and ω².
    """

    lift: str
    velocity: str
    acceleration: str
    lift_scale: float
    velocity_scale: float
    acceleration_scale: float

    @classmethod
    def of(cls, design: CamDesign) -> DisplayUnits:
        """Return the display units of a design's output errors.

        Parameters
        ----------
        design : CamDesign
            The design (its follower's output and its cam speed).

        Returns
        -------
        DisplayUnits
            µm or ° for ΔS; per rad, or per s when the design gives a speed.
        """
        shown = output_error_unit(design.mechanism.output_unit)
        unit, scale = shown.unit, shown.factor
        omega = design.omega_rad_s
        if omega is None:
            return cls(unit, f"{unit}/rad", f"{unit}/rad2", scale, scale, scale)
        return cls(unit, f"{unit}/s", f"{unit}/s2", scale, scale * omega, scale * omega**2)

    def order(self, k: int) -> DisplayUnit:
        """Display unit of the k-th derivative of the output error.

        Parameters
        ----------
        k : int
            0 for ΔS, 1 for ΔV, 2 for ΔA.

        Returns
        -------
        DisplayUnit
            Its unit and factor.
        """
        units = (self.lift, self.velocity, self.acceleration)
        scales = (self.lift_scale, self.velocity_scale, self.acceleration_scale)
        return DisplayUnit(units[k], scales[k])


def display_unit(quantity: Quantity, design: CamDesign) -> DisplayUnit:
    """Display unit and factor of a quantity of :func:`camtol.analysis.result.analyze`.

    Parameters
    ----------
    quantity : Quantity
        The quantity, with its internal unit (its key says whether it is an output error
        ``dS_*``, ``dV_*``, ``dA_*``).
    design : CamDesign
        The analysed design (its follower's output and its cam speed).

    Returns
    -------
    DisplayUnit
        µm or ° (per rad or per s) for output errors, ° for angles, the internal unit
        (factor 1) for lengths and dimensionless factors.
    """
    key, unit = quantity.key, quantity.unit
    if key[:3] in ("dS_", "dV_", "dA_"):
        return DisplayUnits.of(design).order("SVA".index(key[1]))
    if unit == "rad" or unit.startswith("rad/"):
        return DisplayUnit("deg" + unit[3:], _DEG)
    return DisplayUnit(unit, 1.0)


class DisplayCurves(Mapping[str, FloatArray]):
    """Every curve of an analysis in its display unit, converted when read.

    Keys are those of :attr:`camtol.analysis.result.Analysis.curves`; each look-up returns a
    new array (or the analysis' own one when the factor is 1: do not modify it).
    """

    def __init__(self, analysis: Analysis) -> None:
        self._analysis = analysis

    def unit(self, key: str) -> DisplayUnit:
        """Display unit and factor of one curve.

        Parameters
        ----------
        key : str
            Curve key, e.g. ``"dV_phi"``.

        Returns
        -------
        DisplayUnit
            Its display unit and the factor from the internal unit.
        """
        from camtol.analysis.result import Quantity

        a = self._analysis
        return display_unit(Quantity(key, key, a.curves.unit(key)), a.design)

    def __getitem__(self, key: str) -> FloatArray:
        return self._analysis.curves.scaled(key, self.unit(key).factor)

    def __iter__(self) -> Iterator[str]:
        return iter(self._analysis.curves)

    def __len__(self) -> int:
        return len(self._analysis.curves)


def display_curves(analysis: Analysis) -> DisplayCurves:
    """Return the curves of an analysis in display units (a mapping converted when read).

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyze`.

    Returns
    -------
    DisplayCurves
        ``{key: curve}`` in the units of :func:`display_unit`.
    """
    return DisplayCurves(analysis)


def display_extremes(analysis: Analysis) -> dict[str, tuple[Extreme, Extreme]]:
    """Return the extremes of an analysis in display units.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyze`.

    Returns
    -------
    dict of str to (Extreme, Extreme)
        ``{key: (max, min)}`` for every quantity, values in the units of
        :func:`display_unit` (max and min swapped should a factor be negative).

    Raises
    ------
    DesignError
        A finite internal extreme overflows in its display unit (a dimension or tolerance
        far outside a plausible range), naming the quantity and where.
    """
    return {
        q.key: scaled_extremes(
            analysis.extremes[q.key], display_unit(q, analysis.design).factor, q.label
        )
        for q in analysis.quantities
    }


@dataclass(frozen=True)
class AnalysisDisplay:
    """An analysis as tables, files and plots show it (see :func:`display_analysis`).

    Attributes
    ----------
    quantities : tuple of Quantity
        The analysis' quantities with their display units.
    curves : DisplayCurves
        Every curve in its display unit (converted when read).
    extremes : dict of str to (Extreme, Extreme)
        (max, min) of every quantity in its display unit.
    error_unit : str
        Display unit of ΔS: ``um`` (translating follower) or ``deg`` (oscillating).
    travel : float
        Total follower travel. [:attr:`travel_unit`]
    travel_unit : str
        ``mm`` or ``deg`` (oscillating follower).
    """

    quantities: tuple[Quantity, ...]
    curves: DisplayCurves
    extremes: dict[str, tuple[Extreme, Extreme]]
    error_unit: str
    travel: float
    travel_unit: str


def display_analysis(analysis: Analysis) -> AnalysisDisplay:
    """Return an analysis in display units: quantities, curves, extremes and travel.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyze`.

    Returns
    -------
    AnalysisDisplay
        The converted view (curves stay lazy; extremes are converted now).

    Raises
    ------
    DesignError
        An extreme overflows in its display unit (:func:`display_extremes`).
    """
    design = analysis.design
    quantities = tuple(
        dataclasses.replace(q, unit=display_unit(q, design).unit) for q in analysis.quantities
    )
    if analysis.travel_unit == "rad":
        travel, travel_unit = math.degrees(analysis.travel), "deg"
    else:
        travel, travel_unit = analysis.travel, analysis.travel_unit
    return AnalysisDisplay(
        quantities,
        display_curves(analysis),
        display_extremes(analysis),
        DisplayUnits.of(design).lift,
        travel,
        travel_unit,
    )


def analysis_notes(analysis: Analysis) -> tuple[str, ...]:
    """Return what the user must know to trust the numbers, in words and display units.

    Parameters
    ----------
    analysis : Analysis
        Result of :func:`camtol.analysis.result.analyze`.

    Returns
    -------
    tuple of str
        For a lift table (:attr:`camtol.analysis.result.Analysis.lift_table`): that V, A, J come
        from a spline through it, and how much its rounding can change A (lengths in mm,
        an oscillating follower's angles in degrees); then :attr:`Analysis.notes`.
    """
    lt = analysis.lift_table
    if lt is None:
        return analysis.notes
    unit, scale = ("°", _DEG) if lt.unit == "rad" else (" mm", 1.0)
    notes = [
        f"the motion is a lift table every {lt.step_deg:g}°: V, A and J are the derivatives"
        " of a periodic cubic spline through it and depend on the table's precision"
        " (THEORY §1, §6.1); J jumps at every tabulated angle"
    ]
    bound = lt.acceleration_noise_bound
    if bound is not None and lt.resolution is not None:
        notes.append(
            f"the table is rounded to {lt.resolution * scale:g}{unit}: rounding alone can"
            f" change the spline's A by up to 6Q/Δθ² = {bound * scale:.4g}{unit}/rad²"
            " (alternating ±Q/2; 3× the second-difference bound 2Q/Δθ² of [CDH] eq. 10.4),"
            f" against max |A| = {lt.max_abs_acceleration * scale:.4g}{unit}/rad²"
            + (
                ""
                if lt.derivatives_reliable
                else "; ΔV and ΔA are NOT reliable at this precision: tabulate with more decimals"
            )
        )
    return (*notes, *analysis.notes)
