"""The last temperature of every machine's sensors, from MQTT or from Telemetry.

Fanuc-style machines publish their sensors on MQTT (the bridge in :mod:`server.mqtt`);
Siemens-style machines report them in Telemetry (:mod:`server.links.ednc`). Both land here, keyed
by machine and by the model's column name: the sensor ``spindle`` of a topic or of
Telemetry is the column ``T_spindle_C`` of a measurement CSV and of a thermal model term
(formats.md §2). The push scheduler listens for changes.

An intake (:class:`server.intake.TemperatureIntake`) may install a ``screen`` on the board:
every update, whatever its path (MQTT, REST, Telemetry), is checked by it first, and a
refused reading changes nothing (the last good one stays).

A reading is *stale* when it is older than ``stale_after_s`` or when its source went away
(the broker disconnected); a stale reading is kept, and still used, until a fresh one
replaces it: the last known temperature is a better input to a map than none.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Literal

Source = Literal["mqtt", "telemetry", "rest", "lag"]
_SENSOR = re.compile(r"^[A-Za-z0-9_]{1,64}$")
MAX_READINGS = 100_000
"""Bound on (machine, sensor) pairs kept: topics come from the network, names are free."""


def column_of(sensor: str) -> str:
    """The model / CSV column of a sensor: ``spindle`` → ``T_spindle_C`` (kept if already
    a column name)."""
    if sensor.startswith("T_") and sensor.endswith("_C") and len(sensor) > 4:
        return sensor
    return f"T_{sensor}_C"


def valid_sensor(sensor: str) -> bool:
    """Sensor names are letters, digits and underscores (they become column names)."""
    return bool(_SENSOR.match(sensor))


@dataclass(frozen=True, slots=True)
class Reading:
    """One sensor's last value.

    Attributes
    ----------
    celsius : float
        °C.
    time : float
        When it was measured, s since the Unix epoch (the sender's stamp, else receipt).
    received : float
        When it arrived, ``time.monotonic()`` s (for the staleness check).
    source : {"mqtt", "telemetry", "rest", "lag"}
        (``lag``: a lag state the center follows for a lagged thermal model,
        :mod:`volumetric.model.live`)
    stale : bool
    """

    celsius: float
    time: float
    received: float
    source: Source
    stale: bool = False


Listener = Callable[[str, str, float], None]
"""Called with (machine, column, °C) after every update."""

Screen = Callable[[str, str, float, Source, float], str | None]
"""Called with (machine, column, °C, source, time taken in s since the epoch) before a
reading is stored; returns why it is refused, or None to let it in."""


class TemperatureBoard:
    """Last readings per machine and column; used from the event loop only."""

    def __init__(self, stale_after_s: float = 60.0) -> None:
        if not stale_after_s > 0:
            raise ValueError(f"stale_after_s must be > 0, got {stale_after_s}")
        self.stale_after_s = stale_after_s
        self._readings: dict[str, dict[str, Reading]] = {}
        self._count = 0
        self._listeners: list[Listener] = []
        self.dropped = 0
        """Readings refused because :data:`MAX_READINGS` pairs are already kept."""
        self.screen: Screen | None = None
        """The intake's check, run before every update (see the module docstring)."""
        self.refused = 0
        """Readings the screen refused."""
        self.notes: dict[tuple[str, str], str] = {}
        """What a derived column stands for, by (machine, column): the intake's lag states
        (``T_lag1_C``: "T_t4_C through a 47 min lag"), for the dashboard."""

    def subscribe(self, listener: Listener) -> Callable[[], None]:
        self._listeners.append(listener)
        return lambda: self._listeners.remove(listener)

    def update(self, machine: str, sensor: str, celsius: float, *, source: Source,
               at: float | None = None) -> bool:
        """Store a reading of ``sensor`` (a name or a column) and tell the listeners.

        Returns False when it was dropped (too many distinct sensors kept) or the
        screen refused it.
        """
        column = column_of(sensor)
        taken = at if at is not None else time.time()
        if self.screen is not None and self.screen(machine, column, celsius, source,
                                                   taken) is not None:
            self.refused += 1
            return False
        per = self._readings.get(machine)
        if per is None or column not in per:
            if self._count >= MAX_READINGS:
                self.dropped += 1
                return False
            self._count += 1
            per = self._readings.setdefault(machine, {})
        now = time.monotonic()
        per[column] = Reading(celsius, taken, now, source)
        for listener in list(self._listeners):
            listener(machine, column, celsius)
        return True

    def reading(self, machine: str, column: str) -> Reading | None:
        """One column's reading, None when it has none (no copy: the cheap path)."""
        per = self._readings.get(machine)
        return None if per is None else per.get(column)

    def readings(self, machine: str) -> dict[str, Reading]:
        """The machine's readings by column (a copy)."""
        return dict(self._readings.get(machine, {}))

    def columns(self, machine: str, wanted: Iterable[str]) -> dict[str, float]:
        """°C of the ``wanted`` columns that have a reading (stale ones included)."""
        per = self._readings.get(machine, {})
        return {c: per[c].celsius for c in wanted if c in per}

    def forget(self, machine: str) -> int:
        """Drop every reading of ``machine`` (deleted or renamed: a new machine of the same
        name must not inherit its sensors). Returns how many went."""
        per = self._readings.pop(machine, {})
        self._count -= len(per)
        for column in per:
            self.notes.pop((machine, column), None)
        return len(per)

    def mark_stale(self, *, source: Source | None = None) -> int:
        """Mark readings stale: all of ``source`` (its feed went away), or, without
        ``source``, those older than ``stale_after_s``. Returns how many changed."""
        limit = time.monotonic() - self.stale_after_s
        changed = 0
        for per in self._readings.values():
            for column, r in per.items():
                if r.stale:
                    continue
                if (source is not None and r.source == source) or (
                        source is None and r.received < limit):
                    per[column] = replace(r, stale=True)
                    changed += 1
        return changed
