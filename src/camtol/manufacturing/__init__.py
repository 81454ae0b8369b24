"""Manufacturing: table precision, cutting simulation, derivatives of measured lifts, G-code.

THEORY §6 ([Pop], [CDH]): how precise the lift table given to the machine must be
(:mod:`~camtol.manufacturing.precision`), how fine the angular cutting step
(:mod:`~camtol.manufacturing.cutting`, with the contact engine of THEORY §5), how far to
trust V, A, J derived from a measured lift (:mod:`~camtol.manufacturing.derivatives`), and
the program the machine runs (:mod:`~camtol.manufacturing.gcode`).
"""

from __future__ import annotations

from camtol.manufacturing.precision import PrecisionRow, PrecisionStudy, table_precision

__all__ = ["PrecisionRow", "PrecisionStudy", "table_precision"]
