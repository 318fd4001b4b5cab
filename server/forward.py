"""Forwarding temperatures to the machines: Temperatures messages, coalesced per machine.

:class:`TemperatureForwarder` gets every accepted reading that did not come from the
machine itself (MQTT, REST) through :meth:`~TemperatureForwarder.note` and sends the
machine a Temperatures message (protocol README section 3) over its live session:

* at once when the machine had no message in the last ``interval_s`` (the usual case: a
  sensor publishes every few seconds, so the first reading goes out without delay);
* otherwise at ``last sent + interval_s``, with every sensor noted meanwhile and, per
  sensor, the last value only. So a machine gets at most one message per ``interval_s``
  however fast its sensors publish, and no reading waits longer than ``interval_s``.

A machine without a session on this node is skipped (the readings stay on the board and
go out with :meth:`~TemperatureForwarder.resend` when it connects). Everything runs in the
event loop, synchronously: :meth:`MachineSession.send` only queues bytes, so a reading
reaches the socket in the same loop turn as the MQTT message that carried it.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Final

from protocol import TemperatureReading, Temperatures
from protocol.limits import MAX_LABEL_BYTES, MAX_SENSORS
from server.links.ednc.session import LinkClosed, MachineSession

log = logging.getLogger(__name__)

INTERVAL_S: Final = 0.02
"""At most one Temperatures per machine per 20 ms: five Siemens IPO cycles, far below any
thermal time constant, and it bounds what a flood of readings can cost a machine link."""

_MAX_AGE_MS: Final = 2**32 - 1


def sensor_name(column: str) -> str:
    """The wire name of a model column (``T_spindle_C`` → ``spindle``)."""
    if column.startswith("T_") and column.endswith("_C") and len(column) > 4:
        return column[2:-2]
    return column


@dataclass
class ForwardStats:
    """Counters for tests, benchmarks and the REST view."""

    messages: int = 0
    readings: int = 0
    no_session: int = 0
    unsendable: int = 0
    """Readings whose name does not fit the wire (over 16 bytes)."""
    coalesced: int = 0
    """Readings replaced by a newer one of the same sensor before their message left."""


@dataclass
class _Pending:
    readings: dict[str, tuple[float, float]] = field(default_factory=dict)
    """wire name → (°C, time taken, s since the epoch)."""
    last_sent: float = float("-inf")
    """Loop time of the last message."""
    timer: asyncio.TimerHandle | None = None


Sent = Callable[[str, Temperatures], None]
"""Observer: (machine, message) after each message is written."""


class TemperatureForwarder:
    """Sends Temperatures messages to the machines' sessions (module docstring).

    Parameters
    ----------
    sessions : mapping of machine name to MachineSession
        The live sessions of this node (``MachineServer.sessions``), read at each send.
    interval_s : float
        Least time between two messages to one machine, s.
    clock : callable
        Wall clock, s since the epoch (the messages' timestamp and the readings' age).
    """

    def __init__(self, sessions: Mapping[str, MachineSession], *,
                 interval_s: float = INTERVAL_S,
                 clock: Callable[[], float] = time.time) -> None:
        if not interval_s >= 0:
            raise ValueError(f"interval_s must be >= 0, got {interval_s!r}")
        self.sessions = sessions
        self.interval_s = float(interval_s)
        self.clock = clock
        self.stats = ForwardStats()
        self.observers: list[Sent] = []
        self._pending: dict[str, _Pending] = {}

    def note(self, machine: str, column: str, celsius: float, taken: float) -> None:
        """A new reading of ``machine``'s ``column`` (°C, taken at ``taken`` s since the
        epoch): send it now or with the next message (module docstring)."""
        name = sensor_name(column)
        if len(name.encode()) > MAX_LABEL_BYTES:
            self.stats.unsendable += 1
            return
        p = self._pending.get(machine)
        if p is None:
            p = self._pending[machine] = _Pending()
        if name in p.readings:
            self.stats.coalesced += 1
        p.readings[name] = (celsius, taken)
        if p.timer is not None:
            return  # a message is already due: it will carry this value
        loop = asyncio.get_running_loop()
        due = p.last_sent + self.interval_s
        if loop.time() >= due:
            self.flush(machine)
        else:
            p.timer = loop.call_at(due, self.flush, machine)

    def resend(self, machine: str, readings: Iterable[tuple[str, float, float]]) -> None:
        """Send ``readings`` ((column, °C, taken) each) to ``machine`` as soon as the
        interval allows, e.g. everything the board holds when the machine connects."""
        for column, celsius, taken in readings:
            self.note(machine, column, celsius, taken)

    def flush(self, machine: str) -> int:
        """Send ``machine``'s pending readings now; returns the messages written."""
        p = self._pending.get(machine)
        if p is None:
            return 0
        if p.timer is not None:
            p.timer.cancel()
            p.timer = None
        readings, p.readings = p.readings, {}
        if not readings:
            return 0
        session = self.sessions.get(machine)
        if session is None:
            self.stats.no_session += len(readings)
            del self._pending[machine]  # nothing to rate-limit: forget the machine
            return 0
        p.last_sent = asyncio.get_running_loop().time()
        now = self.clock()
        stamp = max(0, int(now * 1000))
        items = [TemperatureReading(name, celsius,
                                    min(_MAX_AGE_MS, max(0, round((now - taken) * 1000))))
                 for name, (celsius, taken) in readings.items()]
        sent = 0
        for k in range(0, len(items), MAX_SENSORS):  # more than 32 sensors: several
            msg = Temperatures(stamp, tuple(items[k:k + MAX_SENSORS]))
            try:
                session.send(msg)
            except LinkClosed as exc:
                log.debug("%s: temperatures not sent: %s", machine, exc)
                return sent
            sent += 1
            self.stats.messages += 1
            self.stats.readings += len(msg.readings)
            for observer in list(self.observers):
                observer(machine, msg)
        return sent

    def forget(self, machine: str) -> None:
        """Drop a machine's pending readings and timer (its session ended)."""
        p = self._pending.pop(machine, None)
        if p is not None and p.timer is not None:
            p.timer.cancel()

    def close(self) -> None:
        """Cancel every timer (shutdown)."""
        for name in list(self._pending):
            self.forget(name)
