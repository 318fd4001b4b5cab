"""The latest temperatures a machine endpoint has, with their age.

Two sources fill it: the machine's own sensors where its controller reads them (a
Siemens-style NC with its sensors on the PLC: :class:`~machine_sim.runtime.MachineRuntime`
stores them), and the center's Temperatures messages (protocol README section 3, stored
by :mod:`machine_sim.link`) for sensors the machine cannot read itself (a Fanuc-style
machine whose sensors publish to MQTT). The endpoint's cycle reads :meth:`values` every
cycle; nothing here blocks or allocates much, since a PLC cycle is milliseconds.

Times are the machine's own clock (s, the controller time of ``step``); a forwarded
reading's time is its arrival minus its ``age_ms``, so no clock shared with the center
is needed. A reading older than ``stale_after_s`` is *stale*: it is still returned (the
last known temperature is a better input than none) and flagged by :meth:`stale`.

The machine screens every reading as the center's intake does (``server/intake.py``,
the same rules and reason names), since a reading may come from its own sensor without
passing the center, and refuses it, keeping the last good value, when

* ``not_finite``: it is NaN or infinite;
* ``out_of_range``: it is outside ``plausible_C`` (-20..100 °C by default);
* ``unknown_sensor``: ``sensors`` names the machine's sensors and this is none of them;
* ``too_fast``: it moved from the sensor's last good reading by more than
  ``max_rate_K_per_s`` times the time between them plus ``jump_allowance_K``.

Each refusal is counted by reason (:attr:`TemperatureStore.refused`), kept among the
recent ones (:attr:`TemperatureStore.refusals`) and logged (at most once per sensor and
reason every ``log_every_s``).
"""

from __future__ import annotations

import logging
import math
from collections import Counter, deque
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final, Literal

from protocol.messages import Temperatures
from volumetric.plausible.temperatures import TEMPERATURE

__all__ = ["JUMP_ALLOWANCE_K", "MAX_RATE_K_PER_S", "PLAUSIBLE_C", "Reading", "Refusal",
           "TemperatureStore", "column_of"]

Source = Literal["sensor", "center"]
Reason = Literal["not_finite", "out_of_range", "unknown_sensor", "too_fast"]
log = logging.getLogger(__name__)

PLAUSIBLE_C: Final = (TEMPERATURE.lo, TEMPERATURE.hi)
"""A machine tool's temperatures in a shop; outside is a sensor or unit fault: the one
range every entry point of the center uses (:mod:`volumetric.plausible.temperatures`),
so a reading the center takes is one the machine takes."""
MAX_RATE_K_PER_S: Final = 1.0
"""A structure warms by hundredths of a kelvin per second, a spindle bearing by a tenth
at most: 1 K/s is a fault."""
JUMP_ALLOWANCE_K: Final = 10.0
"""Allowed on top of the rate (noise, a heater switched on, a sensor read again after a
pause); a unit mix-up or a broken sensor jumps further."""


def column_of(sensor: str) -> str:
    """The model column of a sensor name (``spindle`` → ``T_spindle_C``), as thermal
    terms name their sensor; a column name is kept."""
    if sensor.startswith("T_") and sensor.endswith("_C") and len(sensor) > 4:
        return sensor
    return f"T_{sensor}_C"


@dataclass(frozen=True, slots=True)
class Reading:
    """One sensor's latest value.

    Attributes
    ----------
    celsius : float
        °C.
    taken_s : float
        When it was read, machine time, s.
    source : {"sensor", "center"}
        Read by the machine itself, or forwarded by the center.
    """

    celsius: float
    taken_s: float
    source: Source


@dataclass(frozen=True, slots=True)
class Refusal:
    """A reading the store refused (module docstring)."""

    sensor: str
    celsius: float
    taken_s: float
    source: Source
    reason: Reason
    text: str


class TemperatureStore:
    """Latest good reading per sensor (keyed by the sensor name of Telemetry / MQTT).

    Parameters
    ----------
    stale_after_s : float
        Age beyond which a reading is stale, s.
    plausible_C : (float, float)
        Readings outside are refused, °C.
    max_rate_K_per_s, jump_allowance_K : float
        A reading further from the sensor's last good one than ``max_rate_K_per_s`` times
        the time between them plus ``jump_allowance_K`` is refused.
    sensors : iterable of str, optional
        The machine's sensors (names or ``T_<name>_C`` columns); others are refused. None
        (default): any sensor.
    log_every_s : float
        A sensor's refusals for one reason are logged at most this often (machine time).
    """

    def __init__(self, stale_after_s: float = 60.0, *,
                 plausible_C: tuple[float, float] = PLAUSIBLE_C,
                 max_rate_K_per_s: float = MAX_RATE_K_PER_S,
                 jump_allowance_K: float = JUMP_ALLOWANCE_K,
                 sensors: Iterable[str] | None = None, log_every_s: float = 600.0) -> None:
        if not stale_after_s > 0:
            raise ValueError(f"stale_after_s must be > 0, got {stale_after_s!r}")
        lo, hi = (float(v) for v in plausible_C)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"plausible_C must be a finite (low, high), got {plausible_C!r}")
        if not (max_rate_K_per_s > 0 and jump_allowance_K >= 0):
            raise ValueError(f"max_rate_K_per_s must be > 0 and jump_allowance_K >= 0, got "
                             f"{max_rate_K_per_s!r} and {jump_allowance_K!r}")
        self.stale_after_s = float(stale_after_s)
        self.plausible_C = (lo, hi)
        self.max_rate_K_per_s = float(max_rate_K_per_s)
        self.jump_allowance_K = float(jump_allowance_K)
        self.sensors = None if sensors is None else frozenset(column_of(s) for s in sensors)
        self.log_every_s = float(log_every_s)
        self.refused: Counter[str] = Counter()
        """Refused readings by reason."""
        self.refusals: deque[Refusal] = deque(maxlen=100)
        """The latest refusals, oldest first."""
        self._logged: dict[tuple[str, str], float] = {}
        self._readings: dict[str, Reading] = {}
        self._values: dict[str, float] = {}
        self.messages = 0
        """Temperatures messages applied."""
        self.updated_s = float("-inf")
        """Machine time of the last change (a cycle can tell new values cheaply): the
        newest reading's time, and at least one step up on every stored reading, so a
        reading dated before the newest (a forwarded one, by its age) is still a change."""

    def update(self, sensor: str, celsius: float, taken_s: float, source: Source) -> bool:
        """Store a reading; True if stored.

        Readings of one source replace each other in the order they come (the center sends
        a sensor's readings in order; a sender's clock that steps back must not freeze
        it). Between the two sources the newer reading wins, so the machine's own sensor
        read a moment ago is not overwritten by an older value forwarded by the center.
        A reading the screen refuses (module docstring) is not stored: False, counted in
        :attr:`refused`.
        """
        old = self._readings.get(sensor)
        if old is not None and old.source != source and old.taken_s > taken_s:
            return False
        why = self._screen(sensor, celsius, taken_s, old)
        if why is not None:
            self._refuse(Refusal(sensor, float(celsius), float(taken_s), source, *why))
            return False
        self._readings[sensor] = Reading(float(celsius), float(taken_s), source)
        self._values[column_of(sensor)] = float(celsius)
        self.updated_s = max(math.nextafter(self.updated_s, math.inf), float(taken_s))
        return True

    def _screen(self, sensor: str, celsius: float, taken_s: float, last: Reading | None
                ) -> tuple[Reason, str] | None:
        """Why a reading is refused, or None (module docstring)."""
        t = float(celsius)
        if not math.isfinite(t):
            return "not_finite", f"{sensor}: {t!r} °C is not a number"
        lo, hi = self.plausible_C
        if not lo <= t <= hi:
            return "out_of_range", f"{sensor}: {t:g} °C is outside {lo:g}..{hi:g} °C"
        if self.sensors is not None and column_of(sensor) not in self.sensors:
            return "unknown_sensor", (f"{sensor} is not a sensor of this machine (have "
                                      f"{', '.join(sorted(self.sensors))})")
        if last is not None:
            gap = max(float(taken_s) - last.taken_s, 0.0)
            allowed = self.max_rate_K_per_s * gap + self.jump_allowance_K
            if abs(t - last.celsius) > allowed:
                return "too_fast", (f"{sensor}: {t:g} °C is {abs(t - last.celsius):.2f} K from "
                                    f"the last good {last.celsius:g} °C {gap:.1f} s earlier "
                                    f"(allowed {allowed:.2f} K)")
        return None

    def _refuse(self, r: Refusal) -> None:
        self.refused[r.reason] += 1
        self.refusals.append(r)
        key = (r.sensor, r.reason)
        if r.taken_s - self._logged.get(key, -math.inf) >= self.log_every_s:
            self._logged[key] = r.taken_s
            log.warning("temperature refused (%s, kept the last good one): %s", r.reason,
                        r.text)

    def apply(self, msg: Temperatures, now_s: float) -> int:
        """Store the readings of a Temperatures message received at ``now_s`` (machine
        time); returns how many were newer than what the store had."""
        self.messages += 1
        stored = 0
        for r in msg.readings:
            stored += self.update(r.name, r.celsius, now_s - r.age_ms / 1000.0, "center")
        return stored

    def values(self, now_s: float | None = None) -> dict[str, float]:
        """°C by model column (``T_spindle_C``) of every sensor, stale ones included.

        ``now_s`` is accepted so that a caller states the cycle it evaluates; the values
        do not depend on it (no extrapolation: a temperature is held until the next one).
        """
        return dict(self._values)

    def readings(self) -> dict[str, Reading]:
        """Every reading by sensor name (a copy)."""
        return dict(self._readings)

    def age_s(self, sensor: str, now_s: float) -> float | None:
        """Age of a sensor's reading at ``now_s``, s; None when it has none."""
        r = self._readings.get(sensor)
        return None if r is None else now_s - r.taken_s

    def stale(self, now_s: float) -> frozenset[str]:
        """Sensors whose reading is older than ``stale_after_s`` at ``now_s``."""
        limit = now_s - self.stale_after_s
        return frozenset(s for s, r in self._readings.items() if r.taken_s < limit)
