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
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from protocol.messages import Temperatures

__all__ = ["Reading", "TemperatureStore", "column_of"]

Source = Literal["sensor", "center"]


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


class TemperatureStore:
    """Latest reading per sensor (keyed by the sensor name of Telemetry / MQTT).

    Parameters
    ----------
    stale_after_s : float
        Age beyond which a reading is stale, s.
    """

    def __init__(self, stale_after_s: float = 60.0) -> None:
        if not stale_after_s > 0:
            raise ValueError(f"stale_after_s must be > 0, got {stale_after_s!r}")
        self.stale_after_s = float(stale_after_s)
        self._readings: dict[str, Reading] = {}
        self._values: dict[str, float] = {}
        self.messages = 0
        """Temperatures messages applied."""
        self.updated_s = float("-inf")
        """Machine time of the last change (a cycle can tell new values cheaply)."""

    def update(self, sensor: str, celsius: float, taken_s: float, source: Source) -> bool:
        """Store a reading; True if stored.

        Readings of one source replace each other in the order they come (the center sends
        a sensor's readings in order; a sender's clock that steps back must not freeze
        it). Between the two sources the newer reading wins, so the machine's own sensor
        read a moment ago is not overwritten by an older value forwarded by the center.
        """
        old = self._readings.get(sensor)
        if old is not None and old.source != source and old.taken_s > taken_s:
            return False
        self._readings[sensor] = Reading(float(celsius), float(taken_s), source)
        self._values[column_of(sensor)] = float(celsius)
        self.updated_s = max(self.updated_s, float(taken_s))
        return True

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
