"""The Modbus/TCP link: the center as client of a Fanuc PMC's Modbus/TCP Server function.

Only what that server answers is used: 03h Read Holding Registers (at most 125 per
request) and 10h Write Multiple Registers (at most 123). A window byte offset is a
register offset (two bytes a register), placed in PMC memory in the link's byte order.

**Pipelined requests.** Modbus/TCP carries a transaction id in every frame so that a
client may send several requests before the first answer (Messaging on TCP/IP
Implementation Guide V1.0b, §3.1.3 and §4.2); a server answers them in turn. A push's
status read, payload blocks and header (§13.2 steps 0-4, whose order changes nothing the
PLC uses) go out together in one :meth:`ModbusMemory.write_many` and their answers come
back together; the switch word (step 5) goes alone once all of them are answered (the
session's order: :mod:`server.links.window.session`). Three round trips a push instead
of nine, which is most of what a push costs the center: each request sent and answered
costs about 0.1 ms of system time on this 2-core machine, more than its Python. A server
that answers only the first (or none) of several requests in one segment (pymodbus' own
server) is told apart by its time-out: the center connects again and goes on one
request at a time, and the link setting ``pipeline: false`` asks for that from the
start.

The frames are :mod:`protocol.mbap`'s (sans-I/O); the connection is an asyncio protocol
of its own, since pymodbus' client waits for each answer before the next request.

A busy answer (exception 05 or 06) is asked again a few times within the session, and a
request not answered on a connection that answered before is asked once more; any other
exception response, a second time-out, a garbled answer or a lost connection is a
:class:`LinkError` naming it, with its state and reason (:mod:`server.links.state`).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Sequence
from dataclasses import dataclass, field

from protocol.ctrlmem import ByteOrder
from protocol.mbap import (
    MAX_READ_REGISTERS,
    MAX_WRITE_REGISTERS,
    MbapError,
    ModbusException,
    frame,
    read_answer,
    read_request,
    take_frame,
    write_answer,
    write_request,
)
from server.links.window.memory import LinkError
from server.schemas.link import ModbusLink

__all__ = ["BUSY_CODES", "BUSY_RETRIES", "MAX_READ_REGISTERS", "MAX_WRITE_REGISTERS",
           "ModbusMemory", "memory_for_link"]

log = logging.getLogger(__name__)

_EXCEPTIONS = {1: "illegal function", 2: "illegal data address", 3: "illegal data value",
               4: "server device failure", 5: "acknowledge (busy with a long request)",
               6: "server device busy", 10: "gateway path unavailable",
               11: "gateway target failed to respond"}

BUSY_RETRIES = 10
"""Busy answers to one request before the session ends (0.3^11: a controller answering
busy to 30 % of requests ends a session once in half a million requests)."""
BUSY_PAUSE_S = 0.02
BUSY_PAUSE_CAP_S = 0.25
"""Pause before asking again: 20 ms growing by half each time, at most 250 ms (1.4 s
over all the retries of one request)."""

BUSY_CODES = frozenset({5, 6})
"""Exception answers that mean "ask again later" (Modbus application protocol v1.1b3
§7): 05 acknowledge, 06 server device busy."""


def _swapped(data: bytes) -> bytes:
    """``data`` with each pair of bytes swapped (a register's two bytes)."""
    out = bytearray(len(data))
    out[0::2] = data[1::2]
    out[1::2] = data[0::2]
    return bytes(out)


@dataclass(slots=True)
class _Ask:
    """One request of an exchange and what became of it."""

    what: str
    """``read`` or ``write``."""
    first: int
    count: int
    pdu: bytes
    answer: bytes | None = None
    tid: int = 0
    busy: int = 0
    timed_out: bool = False
    reply: tuple[int, bytes] | None = field(default=None, repr=False)
    """The answer's unit id and PDU, as the last round heard it (None: none came)."""
    lost: str | None = field(default=None, repr=False)
    """Why the connection went before the answer came (None: it did not)."""

    @property
    def span(self) -> str:
        return f"{self.what} of registers {self.first}..{self.first + self.count - 1}"


class _Round:
    """The requests sent together in one round, awaited as one: ``done`` is set by the
    last answer (or the lost connection), or by the time-out, which runs from the last
    answer heard. One future and one timer a round, whatever its requests: a future per
    request, each woken by its answer, cost the event loop a callback per request, and
    a fleet's re-push is mostly such rounds (issue 30)."""

    __slots__ = ("_loop", "_timer", "done", "last", "left", "timeout_s")

    def __init__(self, loop: asyncio.AbstractEventLoop, count: int, timeout_s: float) -> None:
        self._loop = loop
        self.left = count
        self.timeout_s = timeout_s
        self.last = loop.time()
        """When the round last heard something (sent, an answer), loop time, s."""
        self.done: asyncio.Future[None] = loop.create_future()
        self._timer = loop.call_at(self.last + timeout_s, self._check)

    def heard(self, ask: _Ask, reply: tuple[int, bytes]) -> None:
        ask.reply = reply
        self.left -= 1
        self.last = self._loop.time()
        if self.left == 0:
            self.end()

    def lost(self, ask: _Ask, why: str) -> None:
        ask.lost = why
        self.end()

    def _check(self) -> None:
        due = self.last + self.timeout_s
        if self._loop.time() >= due:
            self.end()  # nothing within the time-out of the last answer: given up
        else:
            self._timer = self._loop.call_at(due, self._check)

    def end(self) -> None:
        self._timer.cancel()
        if not self.done.done():
            self.done.set_result(None)


class _Wire(asyncio.Protocol):
    """The TCP connection: frames out, each answer given to the request with its
    transaction id (a late answer to a request given up on is skipped)."""

    def __init__(self) -> None:
        self.transport: asyncio.Transport | None = None
        self.buffer = bytearray()
        self.waiting: dict[int, tuple[_Ask, _Round]] = {}
        self.lost: str | None = None
        """Why the connection is gone (None while it is up)."""

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport

    def data_received(self, data: bytes) -> None:
        self.buffer += data
        try:
            while (got := take_frame(self.buffer)) is not None:
                tid, unit, pdu = got
                waiting = self.waiting.pop(tid, None)
                if waiting is not None:
                    waiting[1].heard(waiting[0], (unit, pdu))
        except MbapError as exc:
            self._lose(f"garbled answer ({exc})")
            if self.transport is not None:
                self.transport.abort()

    def connection_lost(self, exc: Exception | None) -> None:
        self._lose(f"connection lost ({exc})" if exc else "connection closed by the server")

    def _lose(self, why: str) -> None:
        if self.lost is None:
            self.lost = why
        for ask, round_ in self.waiting.values():
            round_.lost(ask, self.lost)
        self.waiting.clear()


class ModbusMemory:
    """A controller window behind a Modbus/TCP server (a ``MemoryClient``).

    Parameters
    ----------
    host, port : str, int
    unit_id : int
    register : int
        First holding register of the window.
    byte_order : {"little", "big"}
    timeout_s : float
        Per request (in an exchange of several: since the last answer).
    block : int
        Largest write, bytes (even, at most 246).
    pipeline : bool
        Send the requests of one exchange without waiting for each answer (module
        docstring); False: one at a time.
    """

    block: int
    """Largest write, bytes: 246 (123 registers, the Modbus limit) unless the link's
    ``block_registers`` says the controller or its gateway takes fewer."""

    def __init__(self, host: str, port: int = 502, *, unit_id: int = 1, register: int = 0,
                 byte_order: ByteOrder = "little", timeout_s: float = 2.0,
                 block: int = 2 * MAX_WRITE_REGISTERS, pipeline: bool = True) -> None:
        if not 2 <= block <= 2 * MAX_WRITE_REGISTERS or block % 2:
            raise LinkError(f"block {block}: 2..{2 * MAX_WRITE_REGISTERS} bytes, even (a "
                            f"write takes at most {MAX_WRITE_REGISTERS} registers)",
                            state="refused", reason="settings")
        self.block = block
        self.host = host
        self.port = port
        self.unit_id = unit_id
        self.register = register
        self.byte_order: ByteOrder = byte_order
        self.timeout_s = timeout_s
        self.pipeline = pipeline
        """Several requests in flight at once (turned off when the server proves it
        answers only the first of them)."""
        self._wire: _Wire | None = None
        self._lock = asyncio.Lock()
        self._tid = 0
        self.requests = 0
        """Requests answered (each answer counts, a busy one too)."""
        self.busy_retries = 0
        """Requests asked again after a busy answer (05, 06)."""
        self.busy_note = ""
        """The last busy answer, for the operator."""
        self.no_answer_retries = 0
        """Requests asked again after a time-out on a connection that answered before."""
        self._answered = False
        """This connection answered a request (a time-out then is asked once more)."""

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    async def connect(self) -> None:
        await self.close()
        loop = asyncio.get_running_loop()
        self._answered = False
        try:
            async with asyncio.timeout(self.timeout_s):
                _transport, wire = await loop.create_connection(_Wire, self.host, self.port)
        except TimeoutError:
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect (no answer within "
                            f"{self.timeout_s:g} s)", state="unreachable",
                            reason="connect") from None
        except OSError as exc:
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect: {exc}",
                            state="unreachable", reason="connect") from None
        self._wire = wire

    def _live(self) -> _Wire:
        wire = self._wire
        if wire is None or wire.lost is not None or wire.transport is None:
            why = "not connected" if wire is None else (wire.lost or "not connected")
            raise LinkError(f"Modbus/TCP {self.address}: {why}", state="unreachable",
                            reason="connection_lost")
        return wire

    def _register(self, offset: int, size: int) -> int:
        if offset % 2 or size % 2 or size <= 0:
            raise LinkError(f"window offset {offset} and size {size} must be even and > 0")
        return self.register + offset // 2

    def _wire_bytes(self, data: bytes) -> bytes:
        """Window bytes as register values on the wire (most significant byte first)."""
        return data if self.byte_order == "big" else _swapped(data)

    # -- an exchange: requests sent, answers awaited, busy and late ones asked again
    async def _exchange(self, asks: Sequence[_Ask]) -> None:
        """Every request of ``asks`` answered (``answer`` set), or a :class:`LinkError`.

        A round sends what is still unanswered (all at once when pipelining, else one
        at a time) and waits for the answers. Then, request by request: a busy answer
        (05, 06: "ask again later") is asked again in the next round after a growing
        pause, at most :data:`BUSY_RETRIES` times; a request not answered within the
        time-out on a connection that answered before is asked once more (a controller
        late for a moment, as on a loaded network, does not end the session; a second
        time-out does). Asking again is harmless: a read reads again and a write writes
        the same registers again (§13.2: nothing before the switch word changes what the
        PLC uses, and a switch word it handled already is no new one)."""
        async with self._lock:
            todo = list(asks)
            while todo:
                again: list[_Ask] = []
                for group in [todo] if self.pipeline else [[a] for a in todo]:
                    await self._round(self._live(), group)
                    pipelined = self.pipeline
                    again += self._judge(group)
                    if pipelined and not self.pipeline:
                        # what the server left unread of the stream may still be in its
                        # buffer, ahead of anything asked again: a new connection
                        answered = self._answered
                        await self.connect()
                        self._answered = answered
                todo = again
                pause = max((a.busy for a in todo), default=0)
                if pause:
                    await asyncio.sleep(min(BUSY_PAUSE_CAP_S, BUSY_PAUSE_S * 1.5 ** (pause - 1)))

    async def _round(self, wire: _Wire, asks: Sequence[_Ask]) -> None:
        """Send ``asks`` together and wait for their answers (:class:`_Round`)."""
        round_ = _Round(asyncio.get_running_loop(), len(asks), self.timeout_s)
        frames = []
        for ask in asks:
            ask.reply = ask.lost = None
            self._tid = ask.tid = self._tid % 0xFFFF + 1
            wire.waiting[ask.tid] = (ask, round_)
            frames.append(frame(ask.tid, self.unit_id, ask.pdu))
        assert wire.transport is not None
        try:
            wire.transport.write(b"".join(frames))
            await round_.done
        finally:
            round_.end()
            for ask in asks:  # given up on: its answer, if it comes, is skipped
                if ask.reply is None:
                    wire.waiting.pop(ask.tid, None)

    def _judge(self, asks: Sequence[_Ask]) -> list[_Ask]:
        """The requests of a round still to ask (busy or late), or the LinkError that
        ends the exchange; every answer is read."""
        again: list[_Ask] = []
        lost = next((a for a in asks if a.lost is not None), None)
        if lost is not None:
            raise LinkError(f"Modbus/TCP {self.address}: {lost.span} failed: {lost.lost}",
                            state="unreachable", reason="connection_lost")
        late = [a for a in asks if a.reply is None]
        given_up = {id(a) for a in late}
        if late and self.pipeline and len(asks) > 1 and (len(late) < len(asks)
                                                         or self._answered):
            # some of a round answered and not the rest, or none of it on a connection
            # that answered single requests: a server that takes one request of a TCP
            # segment (pymodbus' answers none of them); one at a time from now on
            self.pipeline = False
            log.warning("Modbus/TCP %s answered %d of %d requests sent together: one "
                        "request at a time from now on", self.address,
                        len(asks) - len(late), len(asks))
        failure: LinkError | None = None
        for ask in asks:
            if id(ask) in given_up:
                if self._answered and not ask.timed_out:
                    ask.timed_out = True
                    self.no_answer_retries += 1
                    again.append(ask)
                    continue
                failure = failure or LinkError(
                    f"Modbus/TCP {self.address}: {ask.span}: no answer within "
                    f"{self.timeout_s:g} s", state="unreachable", reason="no_answer")
                continue
            assert ask.reply is not None
            unit, pdu = ask.reply
            self.requests += 1
            try:
                if unit != self.unit_id:
                    raise MbapError(f"answer from unit id {unit}, not {self.unit_id}")
                if ask.what == "read":
                    ask.answer = read_answer(pdu, ask.count)
                else:
                    write_answer(pdu, ask.first, ask.count)
                    ask.answer = b""
                self._answered = True
            except ModbusException as exc:
                code = exc.code
                text = (f"Modbus/TCP {self.address}: {ask.span}: exception {code:02d} "
                        f"({_EXCEPTIONS.get(code, '?')}, unit id {self.unit_id})")
                if code in BUSY_CODES and ask.busy < BUSY_RETRIES:
                    ask.busy += 1
                    self.busy_retries += 1
                    self.busy_note = text
                    again.append(ask)
                    continue
                failure = failure or LinkError(
                    text, state="failed" if code in BUSY_CODES or code == 4 else "refused",
                    reason=f"exception_{code:02d}", transient=code in BUSY_CODES)
            except MbapError as exc:
                failure = failure or LinkError(
                    f"Modbus/TCP {self.address}: {ask.span}: {exc}", state="refused",
                    reason="answer")
        if failure is not None:
            raise failure
        return again

    # -- the MemoryClient
    def _reads(self, offset: int, size: int) -> list[_Ask]:
        first = self._register(offset, size)
        count = size // 2
        return [_Ask("read", first + k, min(MAX_READ_REGISTERS, count - k),
                     read_request(first + k, min(MAX_READ_REGISTERS, count - k)))
                for k in range(0, count, MAX_READ_REGISTERS)]

    def _bytes_read(self, asks: Sequence[_Ask]) -> bytes:
        return self._wire_bytes(b"".join(a.answer or b"" for a in asks if a.what == "read"))

    async def read(self, offset: int, size: int) -> bytes:
        asks = self._reads(offset, size)
        await self._exchange(asks)
        return self._bytes_read(asks)  # the swap is its own inverse

    async def write(self, offset: int, data: bytes) -> None:
        await self.write_many([(offset, data)])

    async def write_many(self, writes: Sequence[tuple[int, bytes]], *,
                         read: tuple[int, int] | None = None) -> bytes:
        """Write each ``(offset, data)``, and read ``read`` = ``(offset, size)`` first in
        the same exchange; pipelined, so the server may take them in any order: only
        requests whose order changes nothing belong in one call."""
        asks = self._reads(*read) if read is not None else []
        for offset, data in writes:
            first = self._register(offset, len(data))
            if len(data) > self.block:
                raise LinkError(f"a write of {len(data)} bytes exceeds {self.block} (123 "
                                "registers, the Modbus limit)")
            asks.append(_Ask("write", first, len(data) // 2,
                             write_request(first, self._wire_bytes(data))))
        await self._exchange(asks)
        return self._bytes_read(asks)

    async def close(self) -> None:
        wire, self._wire = self._wire, None
        if wire is not None and wire.transport is not None:
            wire.transport.close()
            wire._lose("closed by the center")


def memory_for_link(spec: ModbusLink, ip: str) -> ModbusMemory:
    """The memory client of a registration's ``modbus`` link (the registry's entry,
    :data:`server.links.BACKENDS`): its host, or the machine's ``ip`` when it names none;
    several controllers behind one gateway differ by ``unit_id``."""
    return ModbusMemory(spec.host or ip, spec.port, unit_id=spec.unit_id,
                        register=spec.start_register, byte_order=spec.byte_order,
                        block=2 * spec.block_registers, pipeline=spec.pipeline)
