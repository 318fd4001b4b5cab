"""What the center needs of a controller's memory: read and write bytes of a window.

One small interface per link (python-can's ``BusABC`` is the model): a link module
(:mod:`server.links.modbus`, :mod:`server.links.opcua`) translates byte reads
and writes of the window (protocol/README.md §13) into its protocol's requests, and the
session (:mod:`server.links.window.session`) does the rest the same way for every link.
"""

from __future__ import annotations

from typing import Protocol

__all__ = ["LinkError", "MemoryClient"]


class LinkError(Exception):
    """The controller cannot be reached, or refused a request (text says which)."""


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

    async def close(self) -> None:
        """Close the connection (never raises)."""
        ...
