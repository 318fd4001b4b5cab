"""Thermal terms as a Siemens NC's own temperature compensation setting data.

The NC corrects each axis by (Sinumerik 840D, function "temperature compensation")

    ΔK = SD43900 + SD43910 · (P - SD43920)

with SD43900 ``$SA_TEMP_COMP_ABS_VALUE`` (mm, MD32750 bit 0), SD43910
``$SA_TEMP_COMP_SLOPE`` (the gradient tan β, mm per mm) and SD43920
``$SA_TEMP_COMP_REF_POSITION`` (P0, mm; both MD32750 bit 1), P the axis's machine
coordinate. That is exactly what a model's thermal terms (:class:`ThermalTerm`) are at a
given temperature: a drift ``k·(T - T_ref)`` µm is an offset, an expansion
``α·(T - T_ref)·(q - q_min)`` µm(with α in µm/(m·K), q in mm, hence 1e-3) is a slope
about ``q_min``. The correction cancels the error: ΔK = -ΔE / 1000 mm.

Several terms on one axis add up: their offsets add, and slopes about different reference
positions are one slope about the first term's reference plus a constant folded into
the offset (``s1 (q - r1) + s2 (q - r2) = (s1 + s2)(q - r1) + s2 (r1 - r2)``).

The PLC writes these when temperatures change (every few seconds), not per cycle: the NC
evaluates the slope at the axis's own position each interpolation cycle, so a
position-dependent thermal correction carries no lookup latency at all, and MD32760 limits
how fast the applied value may follow a new setting.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence

from protocol.mapformat import THERMAL_DRIFT, ThermalRecord
from volumetric.compensate.tempcomp import ActingTerm, AxisTempComp, cancelling_setting_data
from volumetric.model.model import ThermalTerm

from .chaineval import sensor_key

__all__ = ["TempCompData", "record_setting_data", "temp_comp_data"]


TempCompData = AxisTempComp
"""One axis's setting data: the numeric core's type (the center computes the same data for
a native SINUMERIK), by the name the simulated NC has used for it."""


def _setting_data(names: Sequence[str], acting: Iterable[ActingTerm]) -> dict[str, TempCompData]:
    """Offset, slope and reference per axis that cancel ``acting``: the center's one rule
    (:func:`~volumetric.compensate.tempcomp.cancelling_setting_data`) for the model's
    terms and the map's records alike."""
    return {n: TempCompData(*v) for n, v in cancelling_setting_data(names, acting).items()}


def temp_comp_data(terms: Iterable[ThermalTerm], temperatures: Mapping[str, float],
                   axes: Sequence[str]) -> dict[str, TempCompData]:
    """The setting data of each axis that cancel ``terms`` at ``temperatures``.

    Parameters
    ----------
    terms : iterable of ThermalTerm
        Drift (µm/K) and expansion (µm/(m·K)) terms, each on one linear axis.
    temperatures : mapping of column to float
        °C by the terms' sensor columns (``T_spindle_C``).
    axes : sequence of str
        The NC's axes (any case).

    Returns
    -------
    dict of str to TempCompData
        By upper-case axis name, for every axis of ``axes`` (zero where no term acts).

    Raises
    ------
    ValueError
        A term's axis is not one of ``axes``, or its sensor has no temperature.
    """
    names = [a.upper() for a in axes]
    acting: list[ActingTerm] = []
    for t in terms:
        axis = t.axis.upper()
        if axis not in names:
            raise ValueError(f"{t.kind} term on axis {t.axis!r}, which the NC does not have "
                             f"({' '.join(names)})")
        if t.sensor not in temperatures:
            raise ValueError(f"{t.kind} term of axis {t.axis} needs {t.sensor}; have "
                             f"{sorted(temperatures)}")
        acting.append(ActingTerm(axis, t.kind == "thermal_drift", t.coefficient,
                                 float(temperatures[t.sensor]) - t.t_ref_C, t.q_min))
    return _setting_data(names, acting)


def record_setting_data(records: Iterable[ThermalRecord], temperatures: Mapping[str, float],
                        axes: Sequence[str]) -> dict[str, TempCompData]:
    """The setting data of each axis that cancel a map's thermal records at ``temperatures``.

    The machine side of :func:`temp_comp_data`: from the records a map carries (protocol
    README section 6), as the machine's cycle evaluates them (:mod:`machine_sim.chaineval`):
    a sensor without a (finite) temperature counts as at its reference, a record on an
    axis the NC does not have is left to the cycle.

    Parameters
    ----------
    records : iterable of ThermalRecord
        Drift (µm/K) and expansion (µm/(m·K) about ``q_min``) records.
    temperatures : mapping of str to float
        °C by sensor label or column (``spindle`` or ``T_spindle_C``).
    axes : sequence of str
        The NC's axes.

    Returns
    -------
    dict of str to TempCompData
        By upper-case axis name, for every axis of ``axes`` (zero where no record acts).
    """
    temps = {sensor_key(k): float(v) for k, v in temperatures.items()}
    names = [a.upper() for a in axes]
    acting: list[ActingTerm] = []
    for rec in records:
        axis = rec.axis.upper()
        t = temps.get(sensor_key(rec.sensor))
        if axis not in names or t is None or not math.isfinite(t):
            continue
        acting.append(ActingTerm(axis, rec.kind == THERMAL_DRIFT, rec.coefficient,
                                 t - rec.t_ref_C, rec.q_min))
    return _setting_data(names, acting)
