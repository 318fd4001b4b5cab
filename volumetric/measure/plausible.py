"""Plausible sizes of a measurement CSV's numbers (formats.md section 2), one rule per
column, from the limits every entry point shares (:mod:`volumetric.plausible`), that every
reader applies (the offline commands and the service's uploads).

A number can be finite and still be nonsense: a reading of 1e9 µm (a metre) fits as a
21,654,072 µm RMS, a reading of 1e300 µm overflows the normal equations into NaN, a
temperature of 293 is kelvin. The limits refuse only a wrong unit, a wrong column or a
corrupt file, and say which unit the numbers look like where one explains them; what
real data could also look like (readings of 0.01 "µm" that are mm, a hall at 70 "°C"
that is °F) is warned about instead (:func:`measurement_warnings`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from volumetric.plausible.angles import ANGLE, ROTARY_POSITION, angle_cause, angle_warning
from volumetric.plausible.displacements import (
    DISPLACEMENT,
    displacement_cause,
    displacement_warning,
)
from volumetric.plausible.lengths import LINEAR_POSITION, TOOL_LENGTH, length_cause
from volumetric.plausible.limit import Limit
from volumetric.plausible.temperatures import TEMPERATURE, temperature_problem, temperature_warning
from volumetric.plausible.times import CAMPAIGN_TIME, campaign_time_warning

if TYPE_CHECKING:
    from volumetric.measure.readings import Measurements

__all__ = ["LIMITS", "Limit", "implausible", "measurement_warnings", "rotary_mismatch"]

DISPLACEMENT_UM = DISPLACEMENT.hi
ANGLE_URAD = ANGLE.hi
LIMITS: Mapping[str, Limit] = {
    **{c: LINEAR_POSITION for c in ("x_mm", "y_mm", "z_mm")},
    **{c: ROTARY_POSITION for c in ("a_deg", "b_deg", "c_deg")},
    "tool_mm": TOOL_LENGTH,
    "time_s": CAMPAIGN_TIME,
}
READING = {False: Limit(DISPLACEMENT.lo, DISPLACEMENT.hi, "µm", "a displacement reading"),
           True: Limit(ANGLE.lo, ANGLE.hi, "µrad", "an angle reading")}


def _cause(col: str, values: NDArray[np.float64], angle: bool) -> str | None:
    """The likely unit slip of a column's refused values, or None."""
    if col == "value":
        return angle_cause(values) if angle else displacement_cause(values)
    if col in ("x_mm", "y_mm", "z_mm", "tool_mm"):
        return length_cause(values[:1000].tolist())
    return None


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
    bound = np.where(is_angle, ANGLE_URAD, DISPLACEMENT_UM)  # symmetric limits
    checks.append(("value", np.abs(value) > bound, None))  # None: by the row's quantity
    first: tuple[int, str, str] | None = None
    for col, bad, fixed in checks:
        rows = np.flatnonzero(bad)
        if rows.size and (first is None or int(rows[0]) < first[0]):
            i = int(rows[0])
            cell = float(columns[col][i])
            angle = bool(is_angle[i])
            if col in temperature_columns:  # in the words of every entry point
                first = (i, col, f"{temperature_problem(cell)} ({rows.size} such rows in "
                                 "this block)")
                continue
            limit = fixed if fixed is not None else READING[angle]
            same = rows if fixed is not None else rows[is_angle[rows] == angle]
            cause = _cause(col, columns[col][same], angle)
            first = (i, col, f"{limit.text()} (got {cell:g}); "
                             f"{cause or 'check the unit and the column'} ({rows.size} "
                             "such rows in this block)")
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


def measurement_warnings(m: Measurements, name: str) -> list[str]:
    """What in plausible readings looks like a unit slip all the same (module docstring):
    displacements or angles too small to be µm or µrad, temperature columns hot enough
    to be °F, a campaign long enough to be milliseconds. One line each, naming ``name``."""
    out = [
        displacement_warning(m.value[~m.is_angle], f"{name}: displacement readings"),
        angle_warning(m.value[m.is_angle], f"{name}: angle readings"),
        campaign_time_warning(m.time_s, f"{name}: time_s"),
    ]
    out += [temperature_warning(m.temperatures[s], f"{name}: {c}")
            for s, c in m.temperature_columns.items()]
    return [w for w in out if w is not None]
