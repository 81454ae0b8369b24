"""ISO 286-1 standard tolerance grades IT01..IT18 and accuracy grades.

The data are ISO 286-1:2010, *Geometrical product specifications (GPS) - ISO code
system for tolerances on linear sizes - Part 1*, Table 1 ("Values of standard
tolerance grades for nominal sizes up to 3150 mm", grades IT1..IT18) together with
the grades IT01 and IT0, which the 2010 edition tabulates separately (Annex A) and
only for nominal sizes up to 500 mm. See THEORY §7 (the IT5..IT12 rows up to 500 mm,
which the tests check against this table exactly) and THEORY §3.6 (how the papers
use the grades: full IT value as the deviation, angles in degrees read "as if
millimetres", and the accuracy grade of an output).

Notes on the standard that this module enforces:

- a nominal size range is "over a, up to and including b" mm, so a size exactly on a
  boundary belongs to the lower range (3 mm is in 0-3, not 3-6);
- the grades IT14..IT18 are not used for nominal sizes up to and including 1 mm
  (footnote to Table 1): asking for them raises :class:`ToleranceGradeError`;
- IT01 and IT0 are not defined over 500 mm: asking for them raises too;
- the standard prints IT1..IT11 in micrometres and IT12..IT18 in millimetres; this
  module stores every value in micrometres (an exact decimal shift, e.g. IT14 for
  180-250 mm is 1.15 mm = 1150 µm);
- IT1..IT5 over 500 mm are marked in the standard as "included for experimental use";
  they are returned like any other value.

The angle convention (:func:`angle_tolerance_deg`, :func:`grade_of_angle_deviation`)
is **not** defined by ISO 286: it is the habit of the papers camtol reproduces (THEORY
§0 and §3.6), which apply the table to the number of degrees as if it were millimetres
and read the micrometre value as thousandths of a degree.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from dataclasses import dataclass
from typing import Final

from camtol.exceptions import ToleranceGradeError

__all__ = [
    "GRADES",
    "SIZE_RANGES_MM",
    "GradeBracket",
    "ToleranceGradeError",
    "angle_tolerance_deg",
    "grade_of_angle_deviation",
    "grade_of_deviation",
    "parse_grade",
    "tolerance_mm",
    "tolerance_um",
]

GRADES: Final[tuple[str, ...]] = (
    "IT01",
    "IT0",
    *(f"IT{k}" for k in range(1, 19)),
)
"""All standard tolerance grades, finest first: ``("IT01", "IT0", ..., "IT18")``."""

_GRADE_INDEX: Final[dict[str, int]] = {g: i for i, g in enumerate(GRADES)}

_MAX_NOMINAL_MM: Final[float] = 3150.0
"""Largest nominal size covered by ISO 286-1:2010 Table 1."""

_FINE_GRADES_MAX_MM: Final[float] = 500.0
"""IT01 and IT0 are tabulated only up to and including this nominal size."""

_COARSE_GRADES_MIN_MM: Final[float] = 1.0
"""IT14..IT18 are not used for nominal sizes up to and including this size."""

_FINE_GRADES: Final[frozenset[str]] = frozenset({"IT01", "IT0"})
_COARSE_GRADES: Final[frozenset[str]] = frozenset(f"IT{k}" for k in range(14, 19))

# ISO 286-1:2010 Table 1 (IT1..IT18) and Annex A (IT01, IT0), values in micrometres.
# Each row: (over_mm, up_to_and_including_mm, (IT01, IT0, IT1, ..., IT18)).
# None marks a value the standard does not define (IT01 and IT0 over 500 mm).
# fmt: off
_TABLE_1: Final[tuple[tuple[int, int, tuple[float | None, ...]], ...]] = (
    # over to     IT01  IT0   IT1  IT2  IT3  IT4  IT5  IT6  IT7  IT8  IT9  IT10  IT11  IT12  IT13  IT14  IT15  IT16   IT17   IT18  # noqa: E501
    (0,    3,    (0.3,  0.5,  0.8, 1.2, 2,   3,   4,   6,   10,  14,  25,  40,   60,   100,  140,  250,  400,  600,   1000,  1400)),  # noqa: E501
    (3,    6,    (0.4,  0.6,  1,   1.5, 2.5, 4,   5,   8,   12,  18,  30,  48,   75,   120,  180,  300,  480,  750,   1200,  1800)),  # noqa: E501
    (6,    10,   (0.4,  0.6,  1,   1.5, 2.5, 4,   6,   9,   15,  22,  36,  58,   90,   150,  220,  360,  580,  900,   1500,  2200)),  # noqa: E501
    (10,   18,   (0.5,  0.8,  1.2, 2,   3,   5,   8,   11,  18,  27,  43,  70,   110,  180,  270,  430,  700,  1100,  1800,  2700)),  # noqa: E501
    (18,   30,   (0.6,  1,    1.5, 2.5, 4,   6,   9,   13,  21,  33,  52,  84,   130,  210,  330,  520,  840,  1300,  2100,  3300)),  # noqa: E501
    (30,   50,   (0.6,  1,    1.5, 2.5, 4,   7,   11,  16,  25,  39,  62,  100,  160,  250,  390,  620,  1000, 1600,  2500,  3900)),  # noqa: E501
    (50,   80,   (0.8,  1.2,  2,   3,   5,   8,   13,  19,  30,  46,  74,  120,  190,  300,  460,  740,  1200, 1900,  3000,  4600)),  # noqa: E501
    (80,   120,  (1,    1.5,  2.5, 4,   6,   10,  15,  22,  35,  54,  87,  140,  220,  350,  540,  870,  1400, 2200,  3500,  5400)),  # noqa: E501
    (120,  180,  (1.2,  2,    3.5, 5,   8,   12,  18,  25,  40,  63,  100, 160,  250,  400,  630,  1000, 1600, 2500,  4000,  6300)),  # noqa: E501
    (180,  250,  (2,    3,    4.5, 7,   10,  14,  20,  29,  46,  72,  115, 185,  290,  460,  720,  1150, 1850, 2900,  4600,  7200)),  # noqa: E501
    (250,  315,  (2.5,  4,    6,   8,   12,  16,  23,  32,  52,  81,  130, 210,  320,  520,  810,  1300, 2100, 3200,  5200,  8100)),  # noqa: E501
    (315,  400,  (3,    5,    7,   9,   13,  18,  25,  36,  57,  89,  140, 230,  360,  570,  890,  1400, 2300, 3600,  5700,  8900)),  # noqa: E501
    (400,  500,  (4,    6,    8,   10,  15,  20,  27,  40,  63,  97,  155, 250,  400,  630,  970,  1550, 2500, 4000,  6300,  9700)),  # noqa: E501
    (500,  630,  (None, None, 9,   11,  16,  22,  32,  44,  70,  110, 175, 280,  440,  700,  1100, 1750, 2800, 4400,  7000,  11000)),  # noqa: E501
    (630,  800,  (None, None, 10,  13,  18,  25,  36,  50,  80,  125, 200, 320,  500,  800,  1250, 2000, 3200, 5000,  8000,  12500)),  # noqa: E501
    (800,  1000, (None, None, 11,  15,  21,  28,  40,  56,  90,  140, 230, 360,  560,  900,  1400, 2300, 3600, 5600,  9000,  14000)),  # noqa: E501
    (1000, 1250, (None, None, 13,  18,  24,  33,  47,  66,  105, 165, 260, 420,  660,  1050, 1650, 2600, 4200, 6600,  10500, 16500)),  # noqa: E501
    (1250, 1600, (None, None, 15,  21,  29,  39,  55,  78,  125, 195, 310, 500,  780,  1250, 1950, 3100, 5000, 7800,  12500, 19500)),  # noqa: E501
    (1600, 2000, (None, None, 18,  25,  35,  46,  65,  92,  150, 230, 370, 600,  920,  1500, 2300, 3700, 6000, 9200,  15000, 23000)),  # noqa: E501
    (2000, 2500, (None, None, 22,  30,  41,  55,  78,  110, 175, 280, 440, 700,  1100, 1750, 2800, 4400, 7000, 11000, 17500, 28000)),  # noqa: E501
    (2500, 3150, (None, None, 26,  36,  50,  68,  96,  135, 210, 330, 540, 860,  1350, 2100, 3300, 5400, 8600, 13500, 21000, 33000)),  # noqa: E501
)
# fmt: on

SIZE_RANGES_MM: Final[tuple[tuple[float, float], ...]] = tuple(
    (float(lo), float(hi)) for lo, hi, _ in _TABLE_1
)
"""Nominal size ranges of Table 1 as ``(over, up_to_and_including)`` pairs in mm."""

_UPPER_LIMITS_MM: Final[tuple[float, ...]] = tuple(hi for _, hi in SIZE_RANGES_MM)
#: A size within this fraction above a range limit is that limit, and a deviation within
#: it of a table value is that value (:func:`grade_of_deviation`); camtol's one rule for
#: rounding noise against a limit (the pressure-angle limit too). Sizes reach the table
#: with rounding noise: a cam's computed maximum radius of 50 mm comes out as
#: 50.000000000000007, a lift of 6° as 6.000000000000001 after degrees → radians →
#: degrees. Noise must not move a size into the next range ("over 30 up to and including
#: 50" is the drawing's 50 mm); a part in 10^12 is far above it and far below anything a
#: drawing gives (50 fm at 50 mm).
ROUNDING_RTOL: Final[float] = 1e-12


def _table_size(size: float) -> float:
    """``size`` as it meets the range limits: moved down by :data:`ROUNDING_RTOL` of itself."""
    return size / (1.0 + ROUNDING_RTOL)


# Display units of a bracket and the divisor from the table's micrometres to them.
_UNIT_DIVISOR: Final[dict[str, float]] = {"µm": 1.0, "°": 1000.0}


def _allowed_grades_text() -> str:
    return ", ".join(GRADES)


def parse_grade(text: str) -> str:
    """Normalise a tolerance-grade name to its canonical form.

    Parameters
    ----------
    text : str
        A grade such as ``"IT6"``, ``"it6"``, ``" IT 6 "`` or ``"IT01"``. Case and
        whitespace are ignored; the ``IT`` prefix is required, and the number must be
        written as in the standard (``"IT06"`` and a bare ``"6"`` are rejected).

    Returns
    -------
    str
        The canonical grade name, one of :data:`GRADES` (e.g. ``"IT6"``).

    Raises
    ------
    ToleranceGradeError
        If ``text`` is not a string naming one of IT01, IT0, IT1, ..., IT18; the
        message repeats the value and lists the allowed grades.
    """
    if not isinstance(text, str):
        raise ToleranceGradeError(
            f"tolerance grade must be a string such as 'IT6', got {text!r}; "
            f"allowed grades: {_allowed_grades_text()}"
        )
    canonical = "".join(text.split()).upper()
    if canonical not in _GRADE_INDEX:
        raise ToleranceGradeError(
            f"unknown ISO 286 tolerance grade {text!r}; "
            f"allowed grades: {_allowed_grades_text()} (case-insensitive, e.g. 'IT6')"
        )
    return canonical


def _what(size: object, angle: bool) -> str:
    """Name a size (or an angle used as a size) for error messages."""
    if angle:
        return f"angle {size!r}° (its number of degrees read as mm)"
    return f"nominal size {size!r} mm"


def _row_index(size: float, angle: bool) -> int:
    """Return the Table 1 row for ``size``; ``angle`` words the error messages."""
    if isinstance(size, bool) or not isinstance(size, (int, float)):
        raise ToleranceGradeError(f"{_what(size, angle)}: must be a real number")
    if not (math.isfinite(size) and 0.0 < size and _table_size(size) <= _MAX_NOMINAL_MM):
        raise ToleranceGradeError(
            f"{_what(size, angle)} is outside ISO 286-1 Table 1: it must be greater "
            f"than 0 and at most {_MAX_NOMINAL_MM:g} mm"
        )
    # "over a up to and including b": the first range whose upper limit is >= size.
    return bisect_left(_UPPER_LIMITS_MM, _table_size(size))


def _undefined_reason(grade: str, size: float) -> str | None:
    """Say why ``grade`` is not defined at ``size`` (already in range), else None."""
    size = _table_size(size)
    if grade in _FINE_GRADES and size > _FINE_GRADES_MAX_MM:
        return (
            f"IT01 and IT0 are tabulated only for nominal sizes up to "
            f"{_FINE_GRADES_MAX_MM:g} mm; use IT1..IT18"
        )
    if grade in _COARSE_GRADES and size <= _COARSE_GRADES_MIN_MM:
        return (
            f"IT14..IT18 are not used for nominal sizes up to and including "
            f"{_COARSE_GRADES_MIN_MM:g} mm; use IT01..IT13"
        )
    return None


def _value_um(grade: str, size: float, angle: bool) -> float:
    """Table value (µm) of ``grade`` at ``size``; ``angle`` words the errors."""
    canonical = parse_grade(grade)
    row = _row_index(size, angle)
    reason = _undefined_reason(canonical, size)
    value = _TABLE_1[row][2][_GRADE_INDEX[canonical]]
    if reason is not None or value is None:
        raise ToleranceGradeError(
            f"grade {canonical} is not defined by ISO 286-1 for {_what(size, angle)}: {reason}"
        )
    return float(value)


def _defined_values_um(size: float, angle: bool) -> list[tuple[str, float]]:
    """All grades defined at ``size`` with their table values (µm), finest first."""
    row = _row_index(size, angle)
    values = _TABLE_1[row][2]
    out: list[tuple[str, float]] = []
    for grade, value in zip(GRADES, values, strict=True):
        if value is not None and _undefined_reason(grade, size) is None:
            out.append((grade, float(value)))
    return out


def tolerance_um(grade: str, nominal_mm: float) -> float:
    """Return the standard tolerance (IT value) in µm, ISO 286-1:2010 Table 1.

    Parameters
    ----------
    grade : str
        Tolerance grade, parsed by :func:`parse_grade` (``"IT6"``, ``"it6"``, ...).
    nominal_mm : float
        Nominal size in mm, ``0 < nominal_mm <= 3150``. Ranges are "over a, up to
        and including b": a size on a range boundary takes the lower range, and so
        does a size within :data:`ROUNDING_RTOL` (a part in 10^12) above it, which is
        rounding noise (a computed 50.000000000000007 is the drawing's 50).

    Returns
    -------
    float
        The IT value in µm.

    Raises
    ------
    ToleranceGradeError
        For an unknown grade, a size outside (0, 3150] mm, IT01/IT0 over 500 mm or
        IT14..IT18 at 1 mm and below.
    """
    return _value_um(grade, nominal_mm, angle=False)


def tolerance_mm(grade: str, nominal_mm: float) -> float:
    """Return the standard tolerance (IT value) in mm, ISO 286-1:2010 Table 1.

    Parameters
    ----------
    grade : str
        Tolerance grade, parsed by :func:`parse_grade`.
    nominal_mm : float
        Nominal size in mm, ``0 < nominal_mm <= 3150``.

    Returns
    -------
    float
        The IT value in mm (:func:`tolerance_um` divided by 1000).

    Raises
    ------
    ToleranceGradeError
        As :func:`tolerance_um`.
    """
    return tolerance_um(grade, nominal_mm) / 1000.0


def angle_tolerance_deg(grade: str, angle_deg: float) -> float:
    """Angular tolerance in degrees by the papers' convention (THEORY §0, §3.6).

    ISO 286 does not define tolerances on angles. The papers camtol reproduces apply
    the IT table to the number of degrees as if it were a size in mm and read the
    micrometre value as thousandths of a degree: 15° at IT6 gives 11 -> 0.011°, and
    100° at IT6 gives 22 -> 0.022°. The sign of the angle is ignored.

    Parameters
    ----------
    grade : str
        Tolerance grade, parsed by :func:`parse_grade`.
    angle_deg : float
        The angle in degrees; ``0 < abs(angle_deg) <= 3150``.

    Returns
    -------
    float
        The tolerance in degrees.

    Raises
    ------
    ToleranceGradeError
        For an unknown grade or an angle outside the table, as :func:`tolerance_um`.
    """
    return _value_um(grade, _abs_angle(angle_deg), angle=True) / 1000.0


def _abs_angle(value: float) -> float:
    """Return ``abs(value)`` after checking it against the table's range."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ToleranceGradeError(f"{_what(value, True)}: must be a real number")
    size = abs(float(value))
    if not (math.isfinite(size) and 0.0 < size and _table_size(size) <= _MAX_NOMINAL_MM):
        raise ToleranceGradeError(
            f"{_what(value, True)} is outside ISO 286-1 Table 1: its magnitude must "
            f"be greater than 0 and at most {_MAX_NOMINAL_MM:g}"
        )
    return size


@dataclass(frozen=True)
class GradeBracket:
    """The standard tolerance grades that bracket a deviation (THEORY §3.6).

    Attributes
    ----------
    lower : str or None
        The coarsest grade whose value does not exceed the deviation (the deviation
        "reaches" this grade), or None if the deviation is finer than every grade
        defined at that size.
    upper : str or None
        The finest grade whose value is not less than the deviation (the deviation
        "meets" this grade), or None if it is coarser than every defined grade.
    lower_um : float or None
        The table value of ``lower`` in µm (for an angle bracket: the table value
        read as thousandths of a degree, e.g. 27 for 0.027°).
    upper_um : float or None
        The table value of ``upper``, in the same sense as ``lower_um``.
    unit : str
        Display unit of :meth:`describe`: ``"µm"`` for sizes, ``"°"`` for angles.
    """

    lower: str | None
    upper: str | None
    lower_um: float | None
    upper_um: float | None
    unit: str = "µm"

    def __post_init__(self) -> None:
        """Check the unit and that each grade comes with its value."""
        if self.unit not in _UNIT_DIVISOR:
            raise ValueError(f"unit must be one of {sorted(_UNIT_DIVISOR)}, got {self.unit!r}")
        if (self.lower is None) != (self.lower_um is None) or (self.upper is None) != (
            self.upper_um is None
        ):
            raise ValueError("a grade and its value must be given together")
        if self.lower is None and self.upper is None:
            raise ValueError("at least one of lower and upper must be a grade")

    @property
    def lower_value(self) -> float | None:
        """Value of ``lower`` in the display unit (µm, or degrees for angles)."""
        if self.lower_um is None:
            return None
        return self.lower_um / _UNIT_DIVISOR[self.unit]

    @property
    def upper_value(self) -> float | None:
        """Value of ``upper`` in the display unit (µm, or degrees for angles)."""
        if self.upper_um is None:
            return None
        return self.upper_um / _UNIT_DIVISOR[self.unit]

    def _fmt(self, grade: str, value: float) -> str:
        if self.unit == "µm":
            return f"{grade} ({value:g} µm)"
        return f"{grade} ({value:g}{self.unit})"

    def describe(self) -> str:
        """Describe the bracket in words.

        Returns
        -------
        str
            ``"between IT7 (21 µm) and IT8 (33 µm)"``, ``"IT7 (21 µm)"`` for an exact
            hit, ``"finer than IT01 (0.3 µm)"`` or ``"coarser than IT18 (...)"``;
            angle brackets give degrees, e.g. ``"between IT8 (0.027°) and IT9
            (0.043°)"``.
        """
        lo, hi = self.lower_value, self.upper_value
        if self.lower is None or lo is None:
            assert self.upper is not None and hi is not None
            return f"finer than {self._fmt(self.upper, hi)}"
        if self.upper is None or hi is None:
            return f"coarser than {self._fmt(self.lower, lo)}"
        if self.lower == self.upper:
            return self._fmt(self.lower, lo)
        return f"between {self._fmt(self.lower, lo)} and {self._fmt(self.upper, hi)}"


def _bracket(deviation: float, size: float, unit: str) -> GradeBracket:
    """Bracket ``abs(deviation)`` (in ``unit``) among the grades defined at ``size``."""
    if isinstance(deviation, bool) or not isinstance(deviation, (int, float)):
        raise ValueError(f"deviation must be a real number, got {deviation!r}")
    if math.isnan(deviation):
        raise ValueError(f"deviation must not be NaN, got {deviation!r}")
    dev = abs(float(deviation))
    divisor = _UNIT_DIVISOR[unit]
    # Compare in the display unit, so that e.g. 0.027° equals IT8 at 15° exactly.
    angle = unit != "µm"
    graded = [(g, v, v / divisor) for g, v in _defined_values_um(size, angle)]
    # A deviation equal to a table value up to rounding noise is that value: 13 µm
    # through mm comes back as 13.000000000000002 and is IT6, not "between IT6 and IT7".
    dev = next((val for _, _, val in graded if abs(dev - val) <= ROUNDING_RTOL * val), dev)
    first_g, first_um, first_val = graded[0]
    if dev < first_val:
        return GradeBracket(None, first_g, None, first_um, unit)
    lower = max((item for item in graded if item[2] <= dev), key=lambda it: it[2])
    uppers = [item for item in graded if item[2] >= dev]
    if not uppers:
        return GradeBracket(lower[0], None, lower[1], None, unit)
    upper = uppers[0]
    return GradeBracket(lower[0], upper[0], lower[1], upper[1], unit)


def grade_of_deviation(deviation_um: float, nominal_mm: float) -> GradeBracket:
    """Accuracy grade of a deviation on a size (THEORY §3.6).

    Compares ``abs(deviation_um)`` with the IT values of ``nominal_mm`` (for the
    output of a cam mechanism: max|ΔS| against the follower's total travel). For a
    22 mm travel, 25.57 µm lies between IT7 (21 µm) and IT8 (33 µm). Only the grades
    the standard defines at that size take part (no IT01/IT0 over 500 mm, no
    IT14..IT18 at 1 mm and below).

    Parameters
    ----------
    deviation_um : float
        The deviation in µm; its sign is ignored.
    nominal_mm : float
        The nominal size in mm, ``0 < nominal_mm <= 3150``.

    Returns
    -------
    GradeBracket
        The bracketing grades; ``lower == upper`` when the deviation equals a grade
        value, exactly or within :data:`ROUNDING_RTOL` (a part in 10^12) of it.

    Raises
    ------
    ToleranceGradeError
        If the nominal size is outside (0, 3150] mm.
    ValueError
        If the deviation is NaN.
    """
    return _bracket(deviation_um, nominal_mm, "µm")


def grade_of_angle_deviation(deviation_deg: float, angle_deg: float) -> GradeBracket:
    """Accuracy grade of an angular deviation, by the papers' angle convention.

    ISO 286 does not define this (THEORY §0, §3.6): the IT table is applied to the
    number of degrees of ``angle_deg`` as if millimetres, each value read as
    thousandths of a degree. For a 15° swing IT8 is 0.027° and IT9 0.043°, so a
    deviation of 0.03° is "between IT8 (0.027°) and IT9 (0.043°)".

    Parameters
    ----------
    deviation_deg : float
        The angular deviation in degrees; its sign is ignored.
    angle_deg : float
        The reference angle (e.g. the follower's total swing) in degrees; its sign is
        ignored and ``0 < abs(angle_deg) <= 3150``.

    Returns
    -------
    GradeBracket
        The bracketing grades with ``unit == "°"``; ``lower_um``/``upper_um`` hold
        the table values (thousandths of a degree), :meth:`GradeBracket.describe`
        states degrees.

    Raises
    ------
    ToleranceGradeError
        If the angle is zero or exceeds 3150°.
    ValueError
        If the deviation is NaN.
    """
    return _bracket(deviation_deg, _abs_angle(angle_deg), "°")
