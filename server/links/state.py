"""What a machine's link is doing now, and why: its state, a stable reason, a text.

A plant engineer who mistypes a byte order, a machine name or a password must see why
within seconds (the API's status, the dashboard's row, the metric
``ednc_machine_link_state`` and an event), without the center flooding the event log:
the first failure of each reason is an event at once, a repeat of the same reason at most
once per :data:`REPEAT_S` per machine (:class:`Throttle`).

States, in the order a link goes through them:

========== ===============================================================================
state      meaning
========== ===============================================================================
connecting the center is trying (no failure yet, or the backoff before the next try)
connected  a session is open and the PLC program answers
plc_stopped the controller answers, its PLC program does not (heartbeat still)
refused    the controller answers but refuses: another machine's window, no EDNC program
           (magic), another layout, the wrong byte order, a Modbus exception, a login
unreachable nothing answers: connection refused, no route, time-out
failed     a session opened and a request failed in it (a lost connection, a write refused)
offline    no session and nothing tried (an EDNC machine not connected)
========== ===============================================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final, Literal

__all__ = ["REPEAT_S", "STATES", "LinkCondition", "LinkStateName", "Throttle"]

LinkStateName = Literal["connected", "connecting", "plc_stopped", "refused", "unreachable",
                        "failed", "offline"]

STATES: Final[tuple[LinkStateName, ...]] = (
    "connected", "connecting", "plc_stopped", "refused", "unreachable", "failed", "offline")

REPEAT_S: Final = 60.0
"""A reason already reported for a machine is reported again at most this often, s."""


@dataclass(frozen=True, slots=True)
class LinkCondition:
    """A link's state with its reason.

    Attributes
    ----------
    state : LinkStateName
    reason : str
        Stable label (metrics, tests): ``identity_name``, ``magic``, ``byte_order``,
        ``layout``, ``formats``, ``no_answer``, ``connect``, ``exception_02``,
        ``heartbeat``, ...; empty when there is nothing to explain.
    text : str
        For the operator: what was seen, where.
    """

    state: LinkStateName
    reason: str = ""
    text: str = ""

    @property
    def summary(self) -> str:
        """One line: ``refused (byte_order): ...``."""
        head = self.state.replace("_", " ")
        if self.reason:
            head = f"{head} ({self.reason})"
        return f"{head}: {self.text}" if self.text else head


@dataclass
class Throttle:
    """First report of each (machine, reason) at once, repeats at most every ``repeat_s``.

    Attributes
    ----------
    repeat_s : float
        Least time between two reports of the same reason for one machine, s.
    """

    repeat_s: float = REPEAT_S
    _last: dict[tuple[str, str], float] = field(default_factory=dict)
    suppressed: int = 0
    """Reports held back (for tests and logs)."""

    def allow(self, machine: str, reason: str, now: float) -> bool:
        """Whether to report ``reason`` for ``machine`` at ``now`` (a monotonic time, s);
        an allowed report is remembered."""
        key = (machine, reason)
        last = self._last.get(key)
        if last is not None and now - last < self.repeat_s:
            self.suppressed += 1
            return False
        self._last[key] = now
        return True

    def forget(self, machine: str) -> None:
        """The machine's link was healthy again: its next failure is news at once."""
        for key in [k for k in self._last if k[0] == machine]:
            del self._last[key]
