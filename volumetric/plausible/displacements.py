"""Displacements (tool-tip errors, straightness, a reading's ``value``), µm.

A machine tool's geometric errors are µm to a few hundred µm; 10 mm is a crash, not an
error. The slips:

* nm: 10 µm written as 10 000, larger ones refused and named;
* mm (or m): 10 µm written as 0.01, inside the range: a set of readings whose largest is
  below :data:`TINY_UM` is warned about (no machine tool is that good over its travel).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .limit import Limit, Slip, likely_unit, looks_like

__all__ = ["DISPLACEMENT", "TINY_UM", "displacement_cause", "displacement_warning"]

DISPLACEMENT = Limit(-10_000.0, 10_000.0, "µm", "a displacement")
TINY_UM = 0.05
"""Largest |displacement| of a whole campaign below which it looks like mm, not µm."""
_TYPICAL_UM = (-2000.0, 2000.0)
_TOO_LARGE = (Slip("nm", 1e-3, fix="divide by 1000"),)


def displacement_cause(values: ArrayLike) -> str | None:
    """The likely unit of displacements too large for µm, or None."""
    v = np.asarray(values, dtype=np.float64).ravel()
    return looks_like(likely_unit(v[np.isfinite(v)][:1000], _TOO_LARGE, _TYPICAL_UM), "µm",
                      "they look")


def displacement_warning(values: ArrayLike, where: str) -> str | None:
    """A warning when the largest |value| is below :data:`TINY_UM` but not 0, or None.

    Parameters
    ----------
    values : array_like of float, shape (N,)
        The readings, µm (checked already).
    where : str
        What holds them, for the message.
    """
    v = np.abs(np.asarray(values, dtype=np.float64).ravel())
    if v.size < 2:
        return None
    worst = float(np.max(v))
    if not 0.0 < worst < TINY_UM:
        return None
    unit = "m (multiply by 1e6)" if worst < TINY_UM * 1e-3 else "mm (multiply by 1000)"
    return (f"{where}: the largest |value| is {worst:.3g} µm, smaller than any machine "
            f"tool's errors: the values look like {unit}; displacements are µm")
