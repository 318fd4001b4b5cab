"""Angles: angular errors and angle readings (µrad), and rotary positions (degrees).

Angular errors of a machine tool are µrad to a few hundred µrad; 0.1 rad (5.7°) of tilt
is a broken machine. The slips:

* nrad: refused above 100 000, named;
* degrees or rad for µrad: 20 µrad is 0.0011° or 2e-5 rad, inside the range: a set of
  angle readings whose largest is below :data:`TINY_URAD` is warned about;
* arcsec for µrad (1" = 4.848 µrad): the size alone cannot tell, so a column or option
  that *names* arcsec (``EAX_arcsec``) is refused with the factor
  (:mod:`volumetric.plausible.columns`);
* radians for degrees in a rotary position or travel: a rotary axis whose whole travel
  lies within ±2π (6.3°) is warned about.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .limit import Limit, Slip, likely_unit, looks_like

__all__ = ["ANGLE", "ARCSEC_URAD", "ROTARY_POSITION", "TINY_URAD", "angle_cause",
           "angle_warning", "rotary_travel_warning"]

ANGLE = Limit(-100_000.0, 100_000.0, "µrad", "an angle")
ROTARY_POSITION = Limit(-36_000.0, 36_000.0, "°", "a rotary position")
"""A hundred turns of a rotary table either way."""
ARCSEC_URAD = math.pi / 180.0 / 3600.0 * 1e6
"""µrad per arcsecond (4.848)."""
TINY_URAD = 0.05
_TYPICAL_URAD = (-5000.0, 5000.0)
_TOO_LARGE = (Slip("nrad", 1e-3, fix="divide by 1000"),)


def angle_cause(values: ArrayLike) -> str | None:
    """The likely unit of angles too large for µrad, or None."""
    v = np.asarray(values, dtype=np.float64).ravel()
    return looks_like(likely_unit(v[np.isfinite(v)][:1000], _TOO_LARGE, _TYPICAL_URAD),
                      "µrad", "they look")


def angle_warning(values: ArrayLike, where: str) -> str | None:
    """A warning when the largest |angle| is below :data:`TINY_URAD` but not 0."""
    v = np.abs(np.asarray(values, dtype=np.float64).ravel())
    if v.size < 2:
        return None
    worst = float(np.max(v))
    if not 0.0 < worst < TINY_URAD:
        return None
    return (f"{where}: the largest |angle| is {worst:.3g} µrad, smaller than any machine "
            f"tool's errors: the values look like degrees (x 17453) or radians (x 1e6); "
            f"angles are µrad")


def rotary_travel_warning(key: str, lo: float, hi: float) -> str | None:
    """A warning when a rotary travel lies within ±2π and spans more than 1: radians."""
    if max(abs(lo), abs(hi)) <= 2 * math.pi + 1e-3 and hi - lo >= 1.0:
        return (f"travel_mm.{key}: [{lo:g}, {hi:g}] turns less than 6.3°: it looks like "
                f"radians; rotary travels are degrees ([{math.degrees(lo):.4g}, "
                f"{math.degrees(hi):.4g}])")
    return None
