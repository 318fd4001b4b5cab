"""The center's session with a controller reached through its own server.

:class:`ControllerSession` stands where a :class:`~server.links.ednc.session.MachineSession`
stands for a machine that runs the EDNC client: the push scheduler, the temperature
forwarder and the registry use it the same way (``hello.map_formats``, ``push_map``,
``send(Temperatures)``, ``abort``). Underneath, every link is the same: bytes read and
written in the controller's memory window (protocol/README.md §13) through a
:class:`~server.links.window.memory.MemoryClient` (Modbus/TCP, OPC UA).

* :meth:`open` reads the PLC program's identity (its machine name must be this machine's)
  and status (the last switch it handled, so a restarted center resumes the sequence and
  learns the verdict it missed);
* :meth:`run` polls the status every ``poll_s``: the heartbeat must move (else the PLC
  program is not running and the session ends), the ack of a pending push resolves it,
  and positions, corrections and the applied version become the machine's telemetry;
* :meth:`push_map` writes the map into the buffer that is not active (header cleared
  first, payload, header, switch word last) and waits for the PLC's verdict;
* :meth:`send` takes a Temperatures message and writes the map's sensor slots.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import struct
import time
from collections.abc import Callable, Sequence
from typing import Any, Final

from protocol import Controller, ErrorCode, Hello, MapEncoding, MapRejectReason, Message
from protocol.ctrlmem import (
    IDENTITY_SIZE,
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    AckCode,
    ControllerMemoryError,
    Identity,
    Layout,
    Status,
    decode_buffer_header,
    decode_identity,
    decode_status,
    next_sequence,
    plan_map_write,
    plan_temperatures,
    sensor_slots,
    unpack_switch,
)
from protocol.mapformat import MapFormatError
from protocol.maptables import decode_payload
from protocol.messages import Temperatures
from server.links.ednc.session import LinkClosed, Verdict
from server.temperatures import column_of

from .memory import LinkError, MemoryClient

__all__ = ["ControllerSession", "LinkAck"]

log = logging.getLogger(__name__)

DEAD_AFTER_S: Final = 3.0
"""A PLC heartbeat that has not moved for this long ends the session (the PLC program
stopped, or the controller's server answers from memory no program reads)."""

_STATES: Final = {0: "idle", 1: "compensating"}


class LinkAck:
    """The PLC's verdict read from the status (also one a previous center missed)."""

    __slots__ = ("applied", "code", "seq", "version")

    def __init__(self, seq: int, code: int, version: int) -> None:
        self.seq = seq
        self.code = code
        self.version = version
        self.applied = code == AckCode.APPLIED


def reason_of(code: int) -> tuple[MapRejectReason, str]:
    """A MapReject reason and text for an ack code (memory codes map to the nearest)."""
    if code == AckCode.BAD_HEADER:
        return MapRejectReason.CHECKSUM_MISMATCH, "buffer header magic or CRC wrong"
    if code == AckCode.BAD_BUFFER:
        return MapRejectReason.DECODE_ERROR, "switch named no buffer"
    try:
        reason = MapRejectReason(code)
    except ValueError:
        return MapRejectReason.APPLY_FAILED, f"PLC ack code {code}"
    return reason, reason.name.lower().replace("_", " ")


class ControllerSession:
    """One controller's window, used like a machine's EDNC session.

    Parameters
    ----------
    name, ip : str
        The machine as registered.
    controller : Controller
    axes : sequence of str
        The machine's axes in controller order (names of the telemetry's positions).
    memory : MemoryClient
    link : str
        ``modbus`` or ``opcua`` (for the telemetry, the dashboard and the metrics).
    chain : str
        The machine's chain (``w X Y b Z t``), as its Hello would carry it.
    poll_s : float
        Status reads, s.
    """

    def __init__(self, name: str, ip: str, controller: Controller, axes: Sequence[str],
                 memory: MemoryClient, *, link: str, chain: str, poll_s: float = 0.1,
                 on_telemetry: Callable[[dict[str, Any]], None] | None = None,
                 dead_after_s: float = DEAD_AFTER_S) -> None:
        self._name = name
        self.ip = ip
        self.controller = controller
        self.axes = tuple(axes)
        self.chain = chain
        self.memory = memory
        self.link = link
        self.poll_s = poll_s
        self.on_telemetry = on_telemetry
        self.dead_after_s = dead_after_s
        self.address = memory.address
        self.hello: Hello | None = None
        self.identity: Identity | None = None
        self.layout: Layout | None = None
        self.status: Status | None = None
        self.missed: LinkAck | None = None
        """The verdict of a switch this session did not write (a previous center's)."""
        self.closed_because: str | None = None
        self.secret_digest = b""
        self.last_heard = asyncio.get_running_loop().time()
        self._seq = 0
        self._pending: tuple[int, int, float, asyncio.Future[Verdict]] | None = None
        self._slots: dict[str, int] = {}
        self._temps: dict[str, float] = {}
        self._temp_seq = 0
        self._temp_dirty = asyncio.Event()
        self._closed = asyncio.Event()
        self._beat: tuple[int, float] | None = None
        self.temperature_writes = 0

    @property
    def name(self) -> str:
        return self._name

    # -- opening
    async def open(self) -> None:
        """Connect, check the identity, read the status (raises :class:`LinkError`)."""
        await self.memory.connect()
        try:
            ident = decode_identity(await self.memory.read(0, IDENTITY_SIZE))
        except ControllerMemoryError as exc:
            raise LinkError(str(exc)) from None
        if ident.name != self._name:
            raise LinkError(f"the window at {self.address} declares machine "
                            f"{ident.name!r}, not {self._name!r}")
        formats = ident.formats
        if not formats & (MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM):
            raise LinkError(f"the PLC program declares no map format it evaluates "
                            f"({int(formats)})")
        self.identity, self.layout = ident, Layout(ident.capacity)
        self.hello = Hello(name=self._name, ip=self.ip, controller=self.controller,
                           map_formats=formats, software_version=f"plc/{self.link}",
                           chain=self.chain)
        st = await self._read_status()
        (word,) = struct.unpack("<H", await self.memory.read(SWITCH_AT, 2))
        written, buffer = unpack_switch(word)
        self._seq = max(written, st.ack_seq)
        if written and st.ack_seq == written and buffer in (1, 2):
            # the verdict on the last switch, whoever wrote it: the buffer's header says
            # which map version it was about (the status has only the applied one)
            at = self.layout.buffer_at(buffer)
            header = decode_buffer_header(await self.memory.read(at, 32))
            version = header.map_version if header is not None else st.applied_version
            self.missed = LinkAck(written, st.ack_code, version)
        self._report(st)

    async def _read_status(self) -> Status:
        try:
            st = decode_status(await self.memory.read(STATUS_AT, STATUS_SIZE),
                               len(self.axes) or 8)
        except ControllerMemoryError as exc:
            raise LinkError(str(exc)) from None
        now = asyncio.get_running_loop().time()
        if self._beat is None or st.heartbeat != self._beat[0]:
            self._beat = (st.heartbeat, now)
            self.last_heard = now
        self.status = st
        return st

    # -- running
    async def run(self) -> str:
        """Poll the status and write temperatures until the session ends; returns why."""
        writer = asyncio.create_task(self._temperature_writer(),
                                     name=f"{self._name}:temperatures")
        try:
            while self.closed_because is None:
                st = await self._read_status()
                assert self._beat is not None
                silent = asyncio.get_running_loop().time() - self._beat[1]
                if silent > self.dead_after_s:
                    raise LinkError(f"PLC heartbeat still for {silent:.1f} s: the PLC "
                                    "program is not running")
                self._resolve(st)
                self._report(st)
                with contextlib.suppress(TimeoutError):
                    async with asyncio.timeout(self.poll_s):
                        await self._closed.wait()
            return self.closed_because or "closed"
        except LinkError as exc:
            self.abort(None, str(exc))
            return str(exc)
        finally:
            writer.cancel()
            await asyncio.gather(writer, return_exceptions=True)
            await self.memory.close()

    def _resolve(self, st: Status) -> None:
        pending = self._pending
        if pending is None or st.ack_seq != pending[0]:
            return
        _seq, version, t0, future = pending
        if future.done():
            return
        latency = asyncio.get_running_loop().time() - t0
        if st.ack_code == AckCode.APPLIED:
            future.set_result(Verdict(version, True, None, "", latency))
        else:
            reason, text = reason_of(st.ack_code)
            future.set_result(Verdict(version, False, reason, text, latency))

    def _report(self, st: Status) -> None:
        if self.on_telemetry is None or self.identity is None:
            return
        mm = self.identity.increment_nm / 1e6
        state = "releasing" if st.state & 4 else _STATES.get(st.state & 1, "idle")
        self.on_telemetry({
            "timestamp_ms": int(time.time() * 1000), "state": state,
            "map_version": st.applied_version, "link": self.link,
            "axes": {a: {"position": st.positions[k] * mm, "compensation": st.applied[k] * mm}
                     for k, a in enumerate(self.axes[:len(st.positions)])},
            "temperatures": {},
        })

    # -- pushing
    async def push_map(self, version: int, payload: bytes, timeout_s: float) -> Verdict:
        """Write map ``version`` into the inactive buffer, switch, wait for the verdict.

        Raises
        ------
        TimeoutError
            No verdict within ``timeout_s`` (writing included).
        LinkClosed
            The link failed or the session ended.
        """
        if self.layout is None:
            raise LinkClosed("the session is not open")
        if self._pending is not None:
            raise RuntimeError(f"{self._name}: a map push is already in progress")
        loop = asyncio.get_running_loop()
        future: asyncio.Future[Verdict] = loop.create_future()
        try:
            # slots by model column: a record may name ``spindle`` or ``T_spindle_C``
            slots = {column_of(s): i for s, i in sensor_slots(
                [r.sensor for r in decode_payload(payload).thermal]).items()}
        except (MapFormatError, ControllerMemoryError) as exc:
            raise LinkClosed(f"map version {version} cannot be written: {exc}") from None
        try:
            async with asyncio.timeout(timeout_s):
                st = await self._read_status()
                target = 2 if st.active == 1 else 1
                seq = next_sequence(self._seq)
                writes = plan_map_write(self.layout, target, payload, version, seq,
                                        block=self.memory.block)
                self._pending = (seq, version, loop.time(), future)
                for w in writes:
                    await self.memory.write(w.offset, w.data)
                self._seq = seq
                verdict = await future
        except ControllerMemoryError as exc:
            raise LinkClosed(f"map version {version}: {exc}") from None
        except LinkError as exc:
            self.abort(None, str(exc))
            raise LinkClosed(str(exc)) from None
        finally:
            self._pending = None
            if future.done() and not future.cancelled():
                future.exception()  # retrieved: an abort during writing set it unread
        if verdict.applied:
            self._slots = slots
            self._temp_dirty.set()  # the new map's sensors get their readings at once
        return verdict

    # -- temperatures
    def send(self, msg: Message) -> None:
        """Take a message the center would send a machine: Temperatures are written to
        the sensor slots (others have no meaning here and are ignored)."""
        if self.closed_because is not None:
            raise LinkClosed(self.closed_because)
        if isinstance(msg, Temperatures):
            for r in msg.readings:
                self._temps[column_of(r.name)] = r.celsius
            self._temp_dirty.set()

    async def _temperature_writer(self) -> None:
        while True:
            await self._temp_dirty.wait()
            self._temp_dirty.clear()
            if not self._slots:
                continue
            values: list[float | None] = [None] * len(self._slots)
            for sensor, i in self._slots.items():
                values[i] = self._temps.get(sensor)
            self._temp_seq = self._temp_seq % 0xFFFF + 1
            w = plan_temperatures(values, self._temp_seq)
            try:
                for k in range(0, len(w.data), self.memory.block):
                    await self.memory.write(w.offset + k, w.data[k:k + self.memory.block])
            except LinkError as exc:
                self.abort(None, str(exc))
                return
            self.temperature_writes += 1

    # -- closing
    def abort(self, code: ErrorCode | None, text: str) -> None:
        """End the session (``code`` is the EDNC protocol's, kept for the interface)."""
        if self.closed_because is None:
            self.closed_because = text
        pending = self._pending
        if pending is not None and not pending[3].done():
            pending[3].set_exception(LinkClosed(text))
        self._closed.set()

    async def wait_closed(self) -> None:
        await self._closed.wait()
