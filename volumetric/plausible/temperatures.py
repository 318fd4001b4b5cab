"""Temperatures, °C: one range for every way in (CSV columns, ``--temperature``, REST,
MQTT, Telemetry, the machine's own screen).

-20..100 °C holds every machine tool in a shop: an unheated hall in winter, a spindle
bearing near its limit, coolant. Outside it a reading is a faulty sensor or a unit slip,
and the machines' own screens (protocol/README.md section 6, ``machine_sim``) refuse it
too: a model fitted on, or a map built for, such a temperature would never be applied.

The slips a plant engineer makes, and how they show:

* kelvin: 293 for 20 °C, refused (outside the range), named as kelvin;
* m°C (a PLC's integer): 21 500 for 21.5 °C, refused, named;
* °F: 68-95 for 20-35 °C of a hall, *inside* the range: a single value of 50 °C or more
  is warned about (a spindle can be that hot, a room cannot), a CSV column whose every
  reading is that hot too.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .limit import Implausible, Limit, Slip, likely_unit, looks_like

__all__ = ["HOT_C", "TEMPERATURE", "check_temperature", "temperature_problem",
           "temperature_warning"]

TEMPERATURE = Limit(-20.0, 100.0, "°C", "a temperature")
HOT_C = 50.0
"""At or above: hot for a machine tool; warned about as a possible °F."""
_SHOP_C = (-20.0, 45.0)
"""Where a shop's temperatures lie, to judge which slip explains a number."""
_SLIPS = (
    Slip("kelvin", 1.0, -273.15, "subtract 273.15"),
    Slip("°F", 5.0 / 9.0, -32.0 * 5.0 / 9.0, "°C = (°F - 32) / 1.8"),
    Slip("m°C (thousandths of a degree)", 1e-3, 0.0, "divide by 1000", at_least=1000.0),
)


def temperature_problem(value: float, where: str = "") -> str | None:
    """Why ``value`` (°C) cannot be a temperature, naming the likely unit; None if it can.

    ``where`` (e.g. ``"--temperature T_spindle_C"``) starts the message when given.
    """
    if TEMPERATURE.holds(value):
        return None
    if not np.isfinite(value):
        return f"{where + ': ' if where else ''}{value!r} is not a finite temperature"
    cause = (looks_like(likely_unit([value], _SLIPS, _SHOP_C), "°C")
             if value > TEMPERATURE.hi else None)
    return (f"{where + ': ' if where else ''}{value:g} °C is outside {TEMPERATURE.lo:g}.."
            f"{TEMPERATURE.hi:g} °C, a machine tool's temperatures"
            + (f"; {cause}" if cause else ""))


def check_temperature(value: float, where: str = "") -> float:
    """``value`` when it is a plausible temperature, else :class:`Implausible`."""
    problem = temperature_problem(value, where)
    if problem is not None:
        raise Implausible(problem)
    return value


def temperature_warning(values: ArrayLike, where: str) -> str | None:
    """A warning when every value is at least :data:`HOT_C` (°F written as °C), or None.

    Parameters
    ----------
    values : array_like of float, shape (N,)
        Plausible temperatures (already checked), °C.
    where : str
        What holds them, for the message (a column, an option).
    """
    v = np.asarray(values, dtype=np.float64).ravel()
    if v.size == 0 or float(np.min(v)) < HOT_C:
        return None
    lo, hi = float(np.min(v)), float(np.max(v))
    shown = f"{lo:g} °C" if lo == hi else f"{lo:g}..{hi:g} °C"
    f_lo, f_hi = ((x - 32.0) / 1.8 for x in (lo, hi))
    as_c = f"{f_lo:.1f} °C" if lo == hi else f"{f_lo:.1f}..{f_hi:.1f} °C"
    return (f"{where}: {shown} is hot for a machine tool (a spindle can be, a hall "
            f"cannot); if this is °F, it is {as_c}: temperatures are °C")
