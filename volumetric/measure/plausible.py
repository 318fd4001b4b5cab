"""Plausible sizes of a measurement CSV's numbers (formats.md section 2), one rule per
quantity, that every reader applies (the offline commands and the service's uploads).

A number can be finite and still be nonsense: a reading of 1e9 µm (a metre) fits as a
21,654,072 µm RMS, a reading of 1e300 µm overflows the normal equations into NaN. The
limits are far beyond any machine tool's errors yet far below what breaks the arithmetic,
so they refuse only a wrong unit, a wrong column or a corrupt file:

=============== ================================ =========================================
quantity        limit                            why
=============== ================================ =========================================
displacement    abs(value) <= 10 000 µm          a tool-tip error of 10 mm is a crash, not
                                                 a geometric error
angle           abs(value) <= 100 000 µrad       0.1 rad (5.7°) of tilt
x_mm y_mm z_mm  abs <= 100 000 mm                100 m, beyond the largest gantry
a/b/c_deg       abs <= 36 000°                   a hundred turns of a rotary table
tool_mm         0 <= tool_mm <= 10 000 mm        a length from the gauge line, as in the
                                                 machine description
time_s          abs <= 3.2e9 s                   a century of campaign
T_<sensor>_C    -100 °C <= T <= 300 °C           any shop floor, spindle or coolant
=============== ================================ =========================================
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["LIMITS", "Limit", "implausible", "rotary_mismatch"]


@dataclass(frozen=True)
class Limit:
    """The accepted closed range of a column, and its unit for the message."""

    lo: float
    hi: float
    unit: str
    what: str

    def text(self) -> str:
        return f"{self.what} must lie within [{self.lo:g}, {self.hi:g}] {self.unit}"


DISPLACEMENT_UM = 10_000.0
ANGLE_URAD = 100_000.0
LIMITS: Mapping[str, Limit] = {
    **{c: Limit(-100_000.0, 100_000.0, "mm", "a linear position") for c in
       ("x_mm", "y_mm", "z_mm")},
    **{c: Limit(-36_000.0, 36_000.0, "°", "a rotary position") for c in
       ("a_deg", "b_deg", "c_deg")},
    "tool_mm": Limit(0.0, 10_000.0, "mm", "a tool length"),
    "time_s": Limit(-3.2e9, 3.2e9, "s", "a campaign time"),
}
TEMPERATURE = Limit(-100.0, 300.0, "°C", "a temperature")
READING = {False: Limit(-DISPLACEMENT_UM, DISPLACEMENT_UM, "µm", "a displacement reading"),
           True: Limit(-ANGLE_URAD, ANGLE_URAD, "µrad", "an angle reading")}


def implausible(columns: Mapping[str, NDArray[np.float64]], is_angle: NDArray[np.bool_],
                temperature_columns: list[str],
                line_of: Callable[[int], int]) -> tuple[int, str, str] | None:
    """The first implausible number of a block: (line, column, message), or None.

    Parameters
    ----------
    columns : mapping of column name to ndarray of float64, shape (N,)
        The block's numeric columns (finite already).
    is_angle : ndarray of bool, shape (N,)
        Which rows are angle readings (µrad) rather than displacements (µm).
    temperature_columns : list of str
        The ``T_<sensor>_C`` columns of the header.
    line_of : callable
        Row index to its line in the file.
    """
    checks: list[tuple[str, NDArray[np.bool_], Limit | None]] = []
    for col, limit in LIMITS.items():
        if col in columns:
            v = columns[col]
            checks.append((col, (v < limit.lo) | (v > limit.hi), limit))
    for col in temperature_columns:
        v = columns[col]
        checks.append((col, (v < TEMPERATURE.lo) | (v > TEMPERATURE.hi), TEMPERATURE))
    value = columns["value"]
    bound = np.where(is_angle, ANGLE_URAD, DISPLACEMENT_UM)
    checks.append(("value", np.abs(value) > bound, None))  # None: by the row's quantity
    first: tuple[int, str, str] | None = None
    for col, bad, fixed in checks:
        rows = np.flatnonzero(bad)
        if rows.size and (first is None or int(rows[0]) < first[0]):
            i = int(rows[0])
            cell = float(columns[col][i])
            limit = fixed if fixed is not None else READING[bool(is_angle[i])]
            first = (i, col, f"{limit.text()} (got {cell:g}); check the unit and the "
                             f"column ({rows.size} such rows in this block)")
    if first is None:
        return None
    i, col, message = first
    return line_of(i), col, message


def rotary_mismatch(has_rotary: tuple[bool, bool, bool], rotary_q: NDArray[np.float64],
                    rotary_axes: set[str]) -> str | None:
    """Why readings cannot be of a machine with these rotary axes, or None.

    A machine with a rotary axis needs that axis's column (a three-axis campaign fitted
    against a five-axis description reads as every table at 0°); a rotary column that
    moves an axis the machine lacks is another machine's file.

    Parameters
    ----------
    has_rotary : tuple of 3 bool
        Whether the readings have ``a_deg``, ``b_deg``, ``c_deg``.
    rotary_q : ndarray of float64, shape (N, 3)
        Those columns (0 where absent).
    rotary_axes : set of str
        The machine's rotary axes among ``A``, ``B``, ``C``.
    """
    for j, axis in enumerate("ABC"):
        column = f"{axis.lower()}_deg"
        if axis in rotary_axes and not has_rotary[j]:
            return (f"no {column} column, but the machine has rotary axis {axis}: these "
                    "readings are not of this machine (a campaign without its rotary axes), "
                    "or the description is another machine's")
        if axis not in rotary_axes and has_rotary[j] and bool(np.any(rotary_q[:, j] != 0)):
            return (f"column {column} moves axis {axis}, which the machine does not have; "
                    "check the description's chain")
    return None
