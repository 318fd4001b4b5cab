"""A model's thermal terms as a SINUMERIK's own temperature compensation setting data.

The NC corrects each axis by (function manual K3, "temperature compensation")

    ΔK = SD43900 + SD43910 · (P - SD43920)

SD43900 ``$SA_TEMP_COMP_ABS_VALUE`` the position-independent offset (mm, MD32750 bit 0),
SD43910 ``$SA_TEMP_COMP_SLOPE`` the gradient tan β (mm per mm) and SD43920
``$SA_TEMP_COMP_REF_POSITION`` its reference position P0 (mm; both MD32750 bit 1), P the
axis's machine position. At given temperatures a model's thermal terms
(:class:`~volumetric.model.model.ThermalTerm`) are exactly that: a drift
``k · (T - T_ref)`` µm is an offset, an expansion ``α · (T - T_ref) · (q - q_min)`` µm
(α in µm/(m·K), q in mm, hence 1e-3) a slope about ``q_min``. The setting data cancel
the error: ΔK = -error / 1000 mm.

Several terms on one axis add up: offsets add, and slopes about different references are
one slope about the first term's reference plus a constant folded into the offset,
``s1 (q - r1) + s2 (q - r2) = (s1 + s2) (q - r1) + s2 (r1 - r2)``.

Limits (:class:`TempCompLimits`): the NC refuses an offset beyond what the machine
allows (the plant's value; 0.5 mm in the simulated NC) and K3 says MD32760
``COMP_ADD_VELO_FACTOR`` "also limits the maximum gradient of the error line (tan β)".
A value beyond its limit is clamped to it and the axis says so (:attr:`AxisTempComp.
clamped`), so the center never writes what the NC would refuse and still corrects as
much as it may. A term whose sensor has no temperature leaves its axis out (the caller
keeps what the NC holds: no correction is better dropped to zero than held).

Dynamic (lagged) thermal terms are not carried here: their states are the center's, not
a temperature the NC can be given once.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

from volumetric.model.model import ThermalTerm

__all__ = ["ActingTerm", "AxisTempComp", "TempCompLimits", "TempCompResult",
           "cancelling_setting_data", "temp_comp_setting_data"]


@dataclass(frozen=True)
class TempCompLimits:
    """What the NC accepts per axis.

    Attributes
    ----------
    max_offset_mm : float
        Largest |SD43900|, mm (the machine's; the simulated NC's 0.5 mm by default).
    max_slope : float
        Largest |SD43910|, mm/mm: MD32760 ``COMP_ADD_VELO_FACTOR`` (K3: it also limits
        tan β; 0.01 by default, the simulated NC's).
    """

    max_offset_mm: float = 0.5
    max_slope: float = 0.01

    def __post_init__(self) -> None:
        if not (self.max_offset_mm > 0 and self.max_slope > 0):
            raise ValueError(f"limits must be > 0: offset {self.max_offset_mm!r} mm, "
                             f"slope {self.max_slope!r}")


@dataclass(frozen=True)
class AxisTempComp:
    """One axis's SD43900/43910/43920: what the center writes to a native SINUMERIK
    (:mod:`server.links.sinumerik_sd`) and what the simulated NC holds and applies
    (:mod:`machine_sim.siemens_thermal`).

    Attributes
    ----------
    offset_mm : float
        SD43900, mm.
    slope : float
        SD43910, mm per mm of travel.
    ref_mm : float
        SD43920, mm.
    clamped : tuple of str
        ``"offset"`` and/or ``"slope"`` when the model asked for more than the limits.
    """

    offset_mm: float = 0.0
    slope: float = 0.0
    ref_mm: float = 0.0
    clamped: tuple[str, ...] = ()

    def correction_mm(self, position_mm: float) -> float:
        """What the NC adds at an axis position, mm (module docstring)."""
        return self.offset_mm + self.slope * (position_mm - self.ref_mm)

    @property
    def needs_slope(self) -> bool:
        """Whether SD43910/SD43920 (MD32750 bit 1) are needed."""
        return self.slope != 0.0


@dataclass(frozen=True)
class TempCompResult:
    """Setting data per axis and the axes left out.

    Attributes
    ----------
    axes : dict of str to AxisTempComp
        By upper-case axis name: every axis of the machine that has all its
        temperatures (zeros where no term acts).
    waiting : dict of str to tuple of str
        Axes left out, with the sensor columns they lack.
    """

    axes: dict[str, AxisTempComp] = field(default_factory=dict)
    waiting: dict[str, tuple[str, ...]] = field(default_factory=dict)


def _clamp(value: float, limit: float) -> tuple[float, bool]:
    if abs(value) <= limit:
        return value, False
    return math.copysign(limit, value), True


class ActingTerm(NamedTuple):
    """One drift or expansion at its temperature, whatever it was read from (a model's
    term, a map's thermal record).

    Attributes
    ----------
    axis : str
        Upper-case axis name.
    drift : bool
        True: a drift (µm/K); False: an expansion (µm/(m·K)) about ``q_min``.
    coefficient : float
    dt_K : float
        Temperature minus the term's reference, K.
    q_min : float
        Expansion reference position, mm.
    """

    axis: str
    drift: bool
    coefficient: float
    dt_K: float
    q_min: float = 0.0


def cancelling_setting_data(axes: Sequence[str], acting: Iterable[ActingTerm]
                            ) -> dict[str, tuple[float, float, float]]:
    """(SD43900 mm, SD43910 mm/mm, SD43920 mm) per axis that cancel ``acting`` (module
    docstring: offsets add, slopes about other references fold into the first), by
    upper-case axis, zeros where nothing acts; no limits applied. The one rule for every
    source of thermal terms."""
    names = [a.upper() for a in axes]
    offset = dict.fromkeys(names, 0.0)
    slope = dict.fromkeys(names, 0.0)
    ref: dict[str, float | None] = dict.fromkeys(names, None)
    for a in acting:
        if a.drift:
            offset[a.axis] -= a.coefficient * a.dt_K * 1e-3  # µm -> mm, cancelling the error
            continue
        s = -a.coefficient * a.dt_K * 1e-6  # µm/(m·K) · K -> mm/mm, cancelling the error
        r = ref[a.axis]
        if r is None:
            ref[a.axis] = r = a.q_min
        slope[a.axis] += s
        offset[a.axis] += s * (r - a.q_min)  # a slope about another reference (docstring)
    return {n: (offset[n], slope[n], ref[n] or 0.0) for n in names}


def temp_comp_setting_data(terms: Iterable[object], temperatures: Mapping[str, float],
                           axes: Sequence[str], limits: TempCompLimits | None = None
                           ) -> TempCompResult:
    """The setting data per axis that cancel the thermal terms at ``temperatures``.

    Parameters
    ----------
    terms : iterable
        A model's terms; only :class:`~volumetric.model.model.ThermalTerm` (drift in
        µm/K, expansion in µm/(m·K) about ``q_min`` mm) are used.
    temperatures : mapping of str to float
        °C by the terms' sensor columns (``T_spindle_C``); a missing or non-finite value
        leaves the axes of its terms out.
    axes : sequence of str
        The NC's machine axes (any case).
    limits : TempCompLimits, optional

    Returns
    -------
    TempCompResult

    Raises
    ------
    ValueError
        A thermal term on an axis the NC does not have.
    """
    lim = limits or TempCompLimits()
    names = [a.upper() for a in axes]
    acting: list[ActingTerm] = []
    missing: dict[str, list[str]] = {}
    for t in terms:
        if not isinstance(t, ThermalTerm):
            continue
        axis = t.axis.upper()
        if axis not in names:
            raise ValueError(f"{t.kind} term on axis {t.axis!r}, which the NC does not have "
                             f"({' '.join(names)})")
        celsius = temperatures.get(t.sensor)
        if celsius is None or not math.isfinite(celsius):
            missing.setdefault(axis, []).append(t.sensor)
            continue
        acting.append(ActingTerm(axis, t.kind == "thermal_drift", t.coefficient,
                                 float(celsius) - t.t_ref_C, t.q_min))
    out: dict[str, AxisTempComp] = {}
    for a, (offset, slope, ref) in cancelling_setting_data(names, acting).items():
        if a in missing:
            continue
        o, o_cut = _clamp(offset, lim.max_offset_mm)
        s, s_cut = _clamp(slope, lim.max_slope)
        cut = tuple(n for n, c in (("offset", o_cut), ("slope", s_cut)) if c)
        out[a] = AxisTempComp(o, s, ref, cut)
    return TempCompResult(out, {a: tuple(dict.fromkeys(v)) for a, v in missing.items()})
