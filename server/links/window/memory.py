"""What the center needs of a controller's memory: read and write bytes of a window.

One small interface per link (python-can's ``BusABC`` is the model): a link module
(:mod:`server.links.modbus`, :mod:`server.links.opcua`) translates byte reads
and writes of the window (protocol/README.md §13) into its protocol's requests, and the
session (:mod:`server.links.window.session`) does the rest the same way for every link.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from server.links.state import LinkCondition, LinkStateName

__all__ = ["LinkError", "MemoryClient"]


class LinkError(Exception):
    """The controller cannot be reached, or refused a request (text says which).

    ``state`` and ``reason`` classify it for the operator (:mod:`server.links.state`):
    where it is raised is where it is known what happened, so the classification is
    given there, never guessed from the text later. ``transient``: worth asking again in
    the same session (a busy controller).
    """

    def __init__(self, text: str, *, state: LinkStateName = "failed",
                 reason: str = "link_error", transient: bool = False) -> None:
        super().__init__(text)
        self.state: LinkStateName = state
        self.reason = reason
        self.transient = transient

    @property
    def condition(self) -> LinkCondition:
        return LinkCondition(self.state, self.reason, str(self))


class MemoryClient(Protocol):
    """A connection to one controller's memory window (offsets in bytes, even)."""

    block: int
    """Largest write in one request, bytes (246 for Modbus: 123 registers)."""

    @property
    def address(self) -> str:
        """Where the controller is, for logs and the dashboard (``host:port``)."""
        ...

    async def connect(self) -> None:
        """Open the connection (and log in); raises :class:`LinkError`."""
        ...

    async def read(self, offset: int, size: int) -> bytes:
        """``size`` bytes of the window from ``offset``; raises :class:`LinkError`."""
        ...

    async def write(self, offset: int, data: bytes) -> None:
        """Write ``data`` (at most :attr:`block` bytes) at ``offset``; raises
        :class:`LinkError`."""
        ...

    async def write_many(self, writes: Sequence[tuple[int, bytes]], *,
                         read: tuple[int, int] | None = None) -> bytes:
        """Write each ``(offset, data)`` (each at most :attr:`block` bytes) and, with
        ``read`` = ``(offset, size)``, read that span in the same exchange (asked before
        the writes); returns the bytes read (empty without ``read``) when every request
        is done. The link may send them all without waiting for each answer and the
        controller may take them in any order, so only requests whose order changes
        nothing belong in one call (§13.2 steps 0-4); raises :class:`LinkError`."""
        ...

    async def close(self) -> None:
        """Close the connection (never raises)."""
        ...
