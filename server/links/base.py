"""The one interface the center's scheduler and intake use to reach a machine.

python-can's ``BusABC`` is the model: whatever the link (a machine running the EDNC
client, a PMC behind Modbus/TCP, a SINUMERIK behind OPC UA), the push scheduler
(:mod:`server.push`) and the temperature forwarder (:mod:`server.forward`) see a
:class:`Link`: what the machine declared (``hello``), a map push that returns the
machine's verdict, a message sent (temperatures), an end. Each link module holds only
the translation to its protocol:

* :class:`server.links.ednc.session.MachineSession`: the machine connects (§1-12);
* :class:`server.links.window.session.ControllerSession`: the center connects to the
  controller's own server and writes its memory window (§13), through a memory backend
  chosen by the link's name (:mod:`server.links`'s registry).
"""

from __future__ import annotations

from typing import Protocol

from protocol import ErrorCode, Hello, Message
from server.links.ednc.session import LinkClosed, Verdict

__all__ = ["Link", "LinkClosed", "Verdict"]


class Link(Protocol):
    """A session with one machine, whichever way it is reached."""

    hello: Hello | None
    """What the machine declared (its name, map formats, chain); None before it did."""
    address: str
    """Where the machine (or its controller) is, ``host:port``."""
    closed_because: str | None
    """Why the session ended; None while it is open."""

    @property
    def name(self) -> str:
        """The machine's name."""
        ...

    @property
    def reported_version(self) -> int | None:
        """The map version the machine reported applied when the session opened (a PLC's
        status says it), None when the link does not say it at login: the scheduler does
        not send a map the machine has (protocol/README.md §13.2 step 0)."""
        ...

    async def push_map(self, version: int, payload: bytes, timeout_s: float) -> Verdict:
        """Send map ``version`` and wait for the machine's verdict.

        Raises
        ------
        TimeoutError
            No verdict within ``timeout_s``.
        LinkClosed
            The link failed or the session ended (a transport failure, not a verdict).
        """
        ...

    def send(self, msg: Message) -> None:
        """Send a message (Temperatures); raises :class:`LinkClosed` after the end."""
        ...

    def abort(self, code: ErrorCode | None, text: str) -> None:
        """End the session (never raises)."""
        ...

    async def wait_closed(self) -> None:
        """Return when the session has ended."""
        ...
