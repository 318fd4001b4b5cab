"""A Siemens-style controller: temperature compensation data driven by a PLC lookup.

The NC's temperature compensation per axis (Sinumerik 840D's, simplified):

* MD32750 ``TEMP_COMP_TYPE``: bit 0 enables the position-independent offset SD43900,
  bit 1 the position-dependent part SD43910/SD43920. Default here: 1.
* SD43900 ``TEMP_COMP_ABS_VALUE``: the offset, mm.
* SD43910 ``TEMP_COMP_SLOPE`` and SD43920 ``TEMP_COMP_REF_POSITION``: the position-
  dependent part ``slope · (position - reference)`` (slope in mm/mm, reference in mm).
* MD32760 ``COMP_ADD_VELO_FACTOR``: the applied compensation changes by at most
  ``MD32760 · MD32000 · ipo_s / 60`` mm per interpolation cycle (MD32000
  ``MAX_AX_VELO``, mm/min). Default 0.01 of 10 m/min: 6.7 µm per 4 ms cycle.

Writing SD43900 while MD32750 bit 0 is off is refused with alarm ``SD43900_DISABLED``
(:class:`SiemensAlarm`), as the real control does; SD43910/SD43920 likewise need bit 1.

The PLC part (every ``plc_every`` interpolation cycles) looks the map up at the current
machine coordinates (:mod:`machine_sim.controller`) and writes the result to SD43900; the
NC part runs every interpolation cycle (:meth:`SiemensNC.ipo_cycle`). The machine takes
grid maps and tables maps (Hello: float32 mm and tables); a tables map is evaluated
through the chain every PLC cycle (:mod:`machine_sim.chaineval`).

Thermal terms a map carries (tables, or a grid of format version 3) go in as the NC's own
temperature compensation where the NC can express them (:meth:`SiemensNC.sync_thermal`,
every PLC cycle in which the map or the temperatures changed): per axis the records at the
latest temperatures are an offset and a slope about a reference position
(:func:`~machine_sim.siemens_thermal.record_setting_data`); where MD32750 bit 1 is on the
slope goes to SD43910 and the reference to SD43920, and the NC evaluates it at the axis's
position every IPO cycle, without the PLC's latency. The PLC's SD43900 then carries the
rest: the map's whole correction at the position it read (geometry, the thermal offset,
whatever of the thermal part is not linear in the axis's own position, e.g. through the
chain of a 5-axis machine) minus the NC's slope term there, so the applied total is the
map's. With bit 1 off the PLC carries all of it, as before. MD32760 limits how fast the
applied total follows, thermal steps included.

Temperatures (:attr:`SiemensNC.temperatures`) pass the machine's screen
(:mod:`machine_sim.temperatures`: not a number, outside -20..100 °C, a jump faster than
``SiemensConfig.max_temp_rate_K_per_s``: refused, the last good value kept). When a
sensor the map's records use sends nothing for longer than ``SiemensConfig.stale_after_s``
it is listed in :attr:`SiemensNC.thermal_stale`; the thermal part stays at the value of
its last good readings (no extrapolation, never dropped to zero), reached from wherever
the applied value was at MD32760's rate.

Without records in the map, thermal terms can still be written by hand
(:meth:`SiemensNC.write_temp_comp`, data from :func:`~machine_sim.siemens_thermal.
temp_comp_data`): the slope in SD43910/SD43920 where MD32750 bit 1 is on, else evaluated by
the PLC; the offset added to the PLC's SD43900 writes. A map with records replaces them.
Bit 2 (compensation in tool direction, SD42960) is not simulated.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from protocol.codes import MapEncoding
from protocol.mapformat import ThermalRecord

from .chaineval import sensor_key
from .controller import Compensator
from .lookup import ActiveMap, GridMap, TablesMap
from .mapstore import MapStore
from .siemens_thermal import TempCompData, record_setting_data
from .temperatures import JUMP_ALLOWANCE_K, MAX_RATE_K_PER_S, PLAUSIBLE_C, TemperatureStore

__all__ = [
    "MD_MAX_AX_VELO",
    "MD_TEMP_COMP_TYPE",
    "MD_VELO_FACTOR",
    "SD_ABS_VALUE",
    "SD_REF_POSITION",
    "SD_SLOPE",
    "SiemensAlarm",
    "SiemensConfig",
    "SiemensNC",
]

F64 = NDArray[np.float64]
MD_MAX_AX_VELO = 32000
MD_TEMP_COMP_TYPE = 32750
MD_VELO_FACTOR = 32760
SD_ABS_VALUE = 43900
SD_SLOPE = 43910
SD_REF_POSITION = 43920
_MACHINE_DATA = (MD_MAX_AX_VELO, MD_TEMP_COMP_TYPE, MD_VELO_FACTOR)
_SETTING_DATA = (SD_ABS_VALUE, SD_SLOPE, SD_REF_POSITION)


class SiemensAlarm(RuntimeError):
    """The NC refused a write; ``code`` names the alarm."""

    def __init__(self, code: str, text: str) -> None:
        super().__init__(f"{code}: {text}")
        self.code = code


@dataclass(frozen=True)
class SiemensConfig:
    """Cycle times and initial machine data.

    Attributes
    ----------
    ipo_s : float
        Interpolation cycle, s (4 ms default).
    plc_every : int
        The PLC lookup runs every this many interpolation cycles.
    limit_mm : float
        Largest |SD43900| accepted, mm.
    max_ax_velo_mm_min, velo_factor : float
        Initial MD32000 and MD32760.
    temp_comp_type : int
        Initial MD32750 of every axis: 3 (offset and slope) by default, a machine whose
        temperature compensation is commissioned.
    expiry_ramp_s : float
    stale_after_s : float
        A temperature older than this is stale, s (machine time).
    plausible_C : (float, float)
        Temperatures outside are refused, °C.
    max_temp_rate_K_per_s, temp_jump_allowance_K : float
        A temperature further from its sensor's last good one than the rate times the
        time between them plus the allowance is refused.
    """

    ipo_s: float = 0.004
    plc_every: int = 2
    limit_mm: float = 0.5
    max_ax_velo_mm_min: float = 10000.0
    velo_factor: float = 0.01
    temp_comp_type: int = 3
    expiry_ramp_s: float = 2.0
    stale_after_s: float = 60.0
    plausible_C: tuple[float, float] = PLAUSIBLE_C
    max_temp_rate_K_per_s: float = MAX_RATE_K_PER_S
    temp_jump_allowance_K: float = JUMP_ALLOWANCE_K

    def __post_init__(self) -> None:
        if not (self.ipo_s > 0 and self.plc_every >= 1 and self.limit_mm > 0):
            raise ValueError("ipo_s and limit_mm must be > 0, plc_every >= 1")
        if not 0 <= self.temp_comp_type <= 7:
            raise ValueError(f"temp_comp_type (MD32750) must be 0..7, got "
                             f"{self.temp_comp_type!r}")


class SiemensNC(Compensator):
    """A Siemens-style machine's NC and PLC compensation.

    Parameters
    ----------
    machine : str
    axes : sequence of str
    config : SiemensConfig
    """

    def __init__(self, machine: str, axes: Sequence[str], config: SiemensConfig | None = None
                 ) -> None:
        self.config = c = config or SiemensConfig()
        # the NC's PLC evaluates tables maps itself (chain, tables, solve), float32 mm
        store = MapStore(machine, axes, accepted=MapEncoding.FLOAT32_MM | MapEncoding.TABLES,
                         limit_mm=c.limit_mm)
        super().__init__(axes, store, expiry_ramp_s=c.expiry_ramp_s)
        self.temperatures = TemperatureStore(
            c.stale_after_s, plausible_C=c.plausible_C,
            max_rate_K_per_s=c.max_temp_rate_K_per_s, jump_allowance_K=c.temp_jump_allowance_K)
        n = len(self.axes)
        self.md: dict[int, F64] = {
            MD_MAX_AX_VELO: np.full(n, c.max_ax_velo_mm_min),
            MD_TEMP_COMP_TYPE: np.full(n, float(c.temp_comp_type)),
            MD_VELO_FACTOR: np.full(n, c.velo_factor),
        }
        self.sd: dict[int, F64] = {k: np.zeros(n) for k in _SETTING_DATA}
        self.applied = np.zeros(n)
        self._last_desired = np.zeros(n)
        # thermal part (write_temp_comp): an offset the PLC adds to its SD43900 writes, and
        # the slope the NC cannot take (MD32750 bit 1 off), which the PLC then evaluates
        self.thermal_offset_mm = np.zeros(n)
        self._plc_slope = np.zeros(n)
        self._plc_ref_mm = np.zeros(n)
        self._hand: dict[str, TempCompData] = {}  # write_temp_comp's, for bit-1 axes
        # the map's thermal records as setting data (sync_thermal): what they are at the
        # latest temperatures, and the slope the NC itself applies (bit-1 axes)
        self.map_thermal: dict[str, TempCompData] = {}
        self._native_slope = np.zeros(n)
        self._native_ref_mm = np.zeros(n)
        self._synced: tuple[object, ...] | None = None
        self.cycles = 0
        self.alarms: list[str] = []

    def _axis(self, axis: str) -> int:
        key = axis.upper()
        if key not in self.axes:
            raise ValueError(f"no axis {axis!r} on this NC ({' '.join(self.axes)})")
        return self.axes.index(key)

    def write_md(self, number: int, axis: str, value: float) -> None:
        """Set machine data ``number`` of one axis."""
        if number not in _MACHINE_DATA:
            raise ValueError(f"MD{number} is not simulated (known: {_MACHINE_DATA})")
        self.md[number][self._axis(axis)] = float(value)

    def read_md(self, number: int, axis: str) -> float:
        return float(self.md[number][self._axis(axis)])

    def write_sd(self, number: int, axis: str, value: float) -> None:
        """Set setting data ``number`` of one axis; raises :class:`SiemensAlarm` when
        MD32750 does not enable it or the value is out of range."""
        if number not in _SETTING_DATA:
            raise ValueError(f"SD{number} is not simulated (known: {_SETTING_DATA})")
        j = self._axis(axis)
        comp_type = int(self.md[MD_TEMP_COMP_TYPE][j])
        if number == SD_ABS_VALUE and not comp_type & 1:
            raise SiemensAlarm("SD43900_DISABLED", f"axis {self.axes[j]}: SD43900 write "
                               f"refused, MD32750 = {comp_type} has bit 0 off")
        if number in (SD_SLOPE, SD_REF_POSITION) and not comp_type & 2:
            raise SiemensAlarm(f"SD{number}_DISABLED", f"axis {self.axes[j]}: SD{number} "
                               f"write refused, MD32750 = {comp_type} has bit 1 off")
        v = float(value)
        if not np.isfinite(v) or (number == SD_ABS_VALUE and abs(v) > self.config.limit_mm):
            raise SiemensAlarm("SD43900_RANGE", f"axis {self.axes[j]}: SD{number} = {v!r} "
                               f"is outside ±{self.config.limit_mm} mm")
        self.sd[number][j] = v

    def read_sd(self, number: int, axis: str) -> float:
        return float(self.sd[number][self._axis(axis)])

    def applied_mm(self) -> F64:
        return self.applied

    def max_step_mm(self) -> F64:
        """Largest change of the applied compensation per IPO cycle, per axis, mm."""
        out: F64 = (self.md[MD_VELO_FACTOR] * self.md[MD_MAX_AX_VELO] / 60.0
                    * self.config.ipo_s)
        return out

    @property
    def state(self) -> str:
        """Telemetry label: ``alarm``, ``releasing``, ``ramping``, ``compensating``, ``idle``."""
        if self.alarms:
            return "alarm"
        if self.releasing:
            return "releasing"
        if np.any(np.abs(self.applied - self._last_desired) > 1e-12):
            return "ramping"
        return "compensating" if self.store.active is not None else "idle"

    def _desired(self) -> F64:
        comp_type = self.md[MD_TEMP_COMP_TYPE].astype(np.int64)
        out: F64 = np.where(comp_type & 1, self.sd[SD_ABS_VALUE], 0.0)
        return out

    def ipo_cycle(self, now_s: float, positions: Mapping[str, float] | F64,
                  directions: Mapping[str, int] | NDArray[np.integer] | None = None) -> F64:
        """One interpolation cycle (with the PLC lookup every ``plc_every``); returns the
        compensation applied per axis, mm."""
        pos = self._vector(positions, float)
        if self.cycles % self.config.plc_every == 0:
            wanted = self.wanted_mm(now_s, pos, directions)
            if self.sync_thermal():  # the map's records: the NC adds its slope term itself
                wanted = wanted - self._native_slope * (pos - self._native_ref_mm)
            else:
                wanted = (wanted + self.thermal_offset_mm
                          + self._plc_slope * (pos - self._plc_ref_mm))
            # the final clamp to the channel's range, after the reversal (§6: the applied
            # correction never exceeds the limit)
            lim = self.config.limit_mm
            wanted = np.clip(wanted, -lim, lim)
            for j, axis in enumerate(self.axes):
                if wanted[j] == self.sd[SD_ABS_VALUE][j]:
                    continue
                try:
                    self.write_sd(SD_ABS_VALUE, axis, float(wanted[j]))
                except SiemensAlarm as exc:
                    if str(exc) not in self.alarms:
                        self.alarms.append(str(exc))
        comp_type = self.md[MD_TEMP_COMP_TYPE].astype(np.int64)
        desired = self._desired() + np.where(
            comp_type & 2, self.sd[SD_SLOPE] * (pos - self.sd[SD_REF_POSITION]), 0.0)
        step = self.max_step_mm()
        self._last_desired = desired
        self.applied = self.applied + np.clip(desired - self.applied, -step, step)
        self.cycles += 1
        return self.applied

    def write_temp_comp(self, data: Mapping[str, TempCompData]) -> None:
        """Write thermal setting data per axis (:func:`~machine_sim.siemens_thermal.
        temp_comp_data`): the slope to SD43910/SD43920 where MD32750 bit 1 enables them,
        else to the PLC, which then adds it to its SD43900 writes at the position it reads
        (a cycle late, as any PLC value); the offset joins the PLC's SD43900 writes.

        Raises
        ------
        SiemensAlarm
            An offset while MD32750 bit 0 is off (nothing is then changed for that axis).
        """
        for axis, d in data.items():
            j = self._axis(axis)
            comp_type = int(self.md[MD_TEMP_COMP_TYPE][j])
            if d.offset_mm != 0.0 and not comp_type & 1:
                raise SiemensAlarm("SD43900_DISABLED", f"axis {self.axes[j]}: thermal offset "
                                   f"refused, MD32750 = {comp_type} has bit 0 off")
            if comp_type & 2:
                self.write_sd(SD_SLOPE, axis, d.slope)
                self.write_sd(SD_REF_POSITION, axis, d.ref_mm)
                self._plc_slope[j], self._plc_ref_mm[j] = 0.0, 0.0
            else:
                self._plc_slope[j], self._plc_ref_mm[j] = d.slope, d.ref_mm
            self.thermal_offset_mm[j] = d.offset_mm
            self._hand[self.axes[j]] = d
        self._synced = None  # a map with records writes its own again

    @staticmethod
    def _records(m: ActiveMap | None) -> tuple[ThermalRecord, ...]:
        if isinstance(m, TablesMap):
            return m.payload.thermal
        if isinstance(m, GridMap):
            return m.thermal
        return ()  # none, or a kind this NC does not take

    def sync_thermal(self) -> bool:
        """Write the active map's thermal records at the latest temperatures as setting
        data (module docstring) if the map, the temperatures or MD32750 changed since the
        last call; True while the map carries records (the PLC then subtracts the NC's
        own slope term from its SD43900 writes), False without (the setting data written
        by :meth:`write_temp_comp`, if any, are back in SD43910/SD43920)."""
        m = self.store.active
        records = self._records(m)
        comp_type = self.md[MD_TEMP_COMP_TYPE].astype(np.int64)
        key = (id(m), self.store.version, self.temperatures.updated_s,
               tuple(comp_type.tolist()))
        if key == self._synced:
            return bool(records)
        self._synced = key
        if records:
            self.map_thermal = record_setting_data(records, self.temperatures.values(),
                                                   self.axes)
            source = self.map_thermal
        elif self.map_thermal:  # the records are gone: back to the hand-written data
            self.map_thermal = {}
            source = self._hand
        else:  # nothing of ours in SD43910/SD43920
            self._native_slope[:] = 0.0
            return False
        self._native_slope[:] = 0.0
        self._native_ref_mm[:] = 0.0
        for j, axis in enumerate(self.axes):
            if not comp_type[j] & 2:
                continue
            d = source.get(axis, TempCompData())
            self.sd[SD_SLOPE][j] = d.slope  # checked data: finite, bit 1 on
            self.sd[SD_REF_POSITION][j] = d.ref_mm
            if records:
                self._native_slope[j], self._native_ref_mm[j] = d.slope, d.ref_mm
        return bool(records)

    @property
    def thermal_stale(self) -> frozenset[str]:
        """Sensors of the active map's thermal records whose latest reading is older than
        ``stale_after_s`` (the thermal part holds their last good value), by sensor name
        as the store keys them."""
        used = {sensor_key(r.sensor) for r in self._records(self.store.active)}
        return frozenset(s for s in self.temperatures.stale(self.now_s)
                         if sensor_key(s) in used)

    def reset_alarms(self) -> None:
        """Operator reset."""
        self.alarms.clear()
