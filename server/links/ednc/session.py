"""One machine connection: a thin asyncio adapter over the sans-I/O :class:`protocol.Connection`.

It owns the stream and the codec and nothing else: :meth:`MachineSession.receive` reads
until the codec yields a message, :meth:`send` writes one frame, :meth:`push_map` sends a
map and waits for the machine's verdict, :meth:`abort` ends the session with an Error.
What the messages mean (handshake, telemetry, heartbeats) is the server's business
(:mod:`server.links.ednc.server`).

Bounds, so that one peer cannot hurt the others: a read takes at most ``READ_BYTES`` and
the codec holds at most one incomplete frame (8220 bytes, protocol README §2); a peer that
stops reading is dropped once ``MAX_WRITE_BUFFER`` bytes wait for it.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import logging
from dataclasses import dataclass
from typing import Final

from protocol import (
    CONNECTION_CLOSED,
    NEED_DATA,
    Connection,
    ErrorCode,
    Hello,
    LocalProtocolError,
    MapAck,
    MapReject,
    MapRejectReason,
    Message,
    Role,
    split_into_chunks,
)

log = logging.getLogger(__name__)

READ_BYTES: Final = 65536
"""Largest single read: eight whole MapChunk frames' worth, small enough per connection."""

MAX_WRITE_BUFFER: Final = 32 * 1024 * 1024
"""A peer with this much unread (two largest maps) is not reading: drop it."""

DRAIN_EVERY: Final = 256 * 1024
"""While sending a map, wait for the socket after this many bytes (flow control)."""


class LinkClosed(Exception):
    """The session is over (the peer closed, or we aborted it); the text says why."""


@dataclass(frozen=True, slots=True)
class Verdict:
    """The machine's answer to one map push.

    Attributes
    ----------
    version : int
    applied : bool
        MapAck (True) or MapReject (False).
    reason : MapRejectReason or None
    text : str
        The machine's text with a MapReject.
    latency_s : float
        From writing MapBegin to receiving the answer, s.
    """

    version: int
    applied: bool
    reason: MapRejectReason | None
    text: str
    latency_s: float


def peer_ip(writer: asyncio.StreamWriter | asyncio.BaseTransport) -> str:
    """The peer's IP address in canonical form (IPv4-mapped IPv6 as plain IPv4)."""
    peer = writer.get_extra_info("peername")
    host = str(peer[0]) if isinstance(peer, tuple) and peer else "unknown"
    try:
        addr = ipaddress.ip_address(host.split("%")[0])
    except ValueError:
        return host
    if isinstance(addr, ipaddress.IPv6Address) and addr.ipv4_mapped is not None:
        return str(addr.ipv4_mapped)
    return str(addr)


class MachineSession:
    """The center's end of one TCP connection from a machine."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader = reader
        self.writer = writer
        self.conn = Connection(Role.CENTER)
        self.ip = peer_ip(writer)
        peer = writer.get_extra_info("peername")
        port = peer[1] if isinstance(peer, tuple) and len(peer) > 1 else 0
        self.address = f"{self.ip}:{port}"
        self.hello: Hello | None = None
        self.secret_digest = b""
        """What the session logged in with (``admission.digest``), to tell a changed secret."""
        self._loop = asyncio.get_running_loop()
        self.last_heard = self._loop.time()
        self.closed_because: str | None = None
        self._verdict: tuple[int, float, asyncio.Future[Verdict]] | None = None

    @property
    def name(self) -> str:
        """The machine's name from Hello (the peer address before it)."""
        return self.hello.name if self.hello is not None else self.address

    @property
    def reported_version(self) -> int | None:
        """None: a machine says what it applied in its Telemetry, not at login."""
        return None

    # -- receiving
    async def receive(self) -> Message:
        """The next message from the machine.

        Raises
        ------
        RemoteProtocolError
            A bad frame or a message out of turn (the codec's text says which).
        LinkClosed
            The machine closed the connection, or :meth:`abort` did.
        """
        while True:
            event = self.conn.next_event()
            if event is NEED_DATA:
                if self.closed_because is not None:
                    raise LinkClosed(self.closed_because)
                data = await self.reader.read(READ_BYTES)
                self.conn.receive_data(data)
                continue
            if event is CONNECTION_CLOSED:
                raise LinkClosed(self.closed_because or "the machine closed the connection")
            self.last_heard = self._loop.time()
            return event

    def resolve(self, msg: MapAck | MapReject) -> None:
        """Hand the machine's answer to the waiting :meth:`push_map`."""
        pending = self._verdict
        if pending is None or pending[0] != msg.version:
            log.warning("%s: %s for version %d that is not being pushed", self.name,
                        type(msg).__name__, msg.version)
            return
        version, t0, future = pending
        latency = self._loop.time() - t0
        if not future.done():
            if isinstance(msg, MapAck):
                future.set_result(Verdict(version, True, None, "", latency))
            else:
                future.set_result(Verdict(version, False, msg.reason, msg.text, latency))

    # -- sending
    def send(self, msg: Message) -> None:
        """Write one frame (never blocks; see :data:`MAX_WRITE_BUFFER`).

        Raises
        ------
        LinkClosed
            The session is over, or the peer has stopped reading (then it is aborted).
        """
        if self.closed_because is not None or self.writer.is_closing():
            raise LinkClosed(self.closed_because or "the connection is closed")
        try:
            data = self.conn.send(msg)
        except LocalProtocolError as exc:  # e.g. the session closed meanwhile
            raise LinkClosed(f"cannot send {type(msg).__name__}: {exc}") from None
        self.writer.write(data)
        if self.writer.transport.get_write_buffer_size() > MAX_WRITE_BUFFER:
            self.abort(ErrorCode.TIMEOUT, "the machine does not read what it is sent")
            raise LinkClosed(self.closed_because or "peer not reading")

    async def push_map(self, version: int, payload: bytes, timeout_s: float) -> Verdict:
        """Send map ``version`` (MapBegin, MapChunk..., MapEnd) and wait for its answer.

        Raises
        ------
        TimeoutError
            No MapAck or MapReject within ``timeout_s`` (sending included).
        LinkClosed
            The session ended before the answer.
        """
        if self._verdict is not None:
            raise RuntimeError(f"{self.name}: a map push is already in progress")
        future: asyncio.Future[Verdict] = self._loop.create_future()
        self._verdict = (version, self._loop.time(), future)
        try:
            async with asyncio.timeout(timeout_s):
                unsent = 0
                for msg in split_into_chunks(payload, version):
                    self.send(msg)
                    unsent += 8 + len(getattr(msg, "data", b""))
                    if unsent >= DRAIN_EVERY:
                        await self.writer.drain()
                        unsent = 0
                await self.writer.drain()
                return await future
        except TimeoutError:  # an OSError too: let it through as itself
            raise
        except (ConnectionError, OSError) as exc:
            raise LinkClosed(f"connection lost while pushing: {exc!r}") from None
        finally:
            self._verdict = None
            if future.done() and not future.cancelled():
                future.exception()  # retrieved: an abort during sending set it unread

    def abort(self, code: ErrorCode | None, text: str) -> None:
        """End the session: an Error with ``code`` (unless None or already closed), then
        close the socket. The receive loop then ends with :class:`LinkClosed`."""
        if self.closed_because is None:
            self.closed_because = text
        if code is not None and not self.writer.is_closing():
            with contextlib.suppress(LocalProtocolError):
                self.writer.write(self.conn.send_error(code, text))
        if self._verdict is not None and not self._verdict[2].done():
            self._verdict[2].set_exception(LinkClosed(text))
        self.writer.close()

    async def wait_closed(self) -> None:
        """Close (if not yet) and wait for the socket to be released."""
        if not self.writer.is_closing():
            self.writer.close()
        with contextlib.suppress(OSError, ConnectionError):
            await self.writer.wait_closed()
