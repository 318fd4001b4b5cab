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
* :meth:`run` polls the status, every ``poll_s`` while a push waits for its verdict and
  every ``idle_poll_s`` otherwise: the heartbeat must move (else the PLC program is not
  running and the session waits for it), the ack of a pending push resolves it, and
  positions, corrections and the applied version become the machine's telemetry: at once
  when the map or the state changes, at most every ``telemetry_s`` (the center's
  telemetry period, as for an EDNC machine) when only positions and corrections move,
  and every :data:`TELEMETRY_REFRESH_S` when nothing does;
* :meth:`push_map` writes the map into the buffer that is not active (header cleared
  first, payload, header, switch word last: :func:`map_writes`) and waits for the PLC's
  verdict;
* :meth:`send` takes a Temperatures message and writes the map's sensor slots.
"""

from __future__ import annotations

import asyncio
import contextlib
import hashlib
import logging
import struct
import time
from collections.abc import Callable, Sequence
from typing import Any, Final

from protocol import Controller, ErrorCode, Hello, MapEncoding, MapRejectReason, Message
from protocol.ctrlmem import (
    IDENTITY_MAGIC,
    IDENTITY_SIZE,
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    TEMP_SEQ_AT,
    AckCode,
    ControllerMemoryError,
    Identity,
    Layout,
    Status,
    Write,
    ack_is_verdict,
    decode_buffer_header,
    decode_identity,
    decode_status,
    next_switch_sequence,
    pack_switch,
    plan_map_write,
    plan_temperatures,
    sensor_slots,
    unpack_switch,
)
from protocol.limits import TELEMETRY_PERIOD_MS
from protocol.mapformat import MapFormatError
from protocol.maptables import decode_payload
from protocol.messages import Temperatures
from server.links.ednc.session import LinkClosed, Verdict
from server.links.pacing import HEALTHY_AFTER_S
from server.links.state import LinkCondition
from server.temperatures import column_of

from .memory import LinkError, MemoryClient

__all__ = ["IDLE_POLL_S", "STATUS_READS_PER_S", "TELEMETRY_REFRESH_S", "ControllerSession",
           "LinkAck", "StatusPace",
           "identity_of", "map_slots", "map_writes"]

log = logging.getLogger(__name__)

DEAD_AFTER_S: Final = 3.0
"""A PLC heartbeat that has not moved for this long ends the session (the PLC program
stopped, or the controller's server answers from memory no program reads)."""

IDLE_POLL_S: Final = 2.0
"""Status reads while no push waits for its verdict, s (the link's ``poll_ms`` when that
is longer). Below :data:`DEAD_AFTER_S`, so a heartbeat standing still is seen within
2-5 s (one read that finds it unmoved); a push polls at the link's ``poll_ms`` from its
switch word on. At 1,000 PMCs a status read every 1 s cost about 0.3 s of the center's
CPU per second with no push anywhere."""

STATUS_READS_PER_S: Final = 200.0
"""Idle status reads per second across one center's controller sessions: with more than
``IDLE_POLL_S`` x this many sessions, each idle read comes less often (1,000 PMCs: every
5 s), so a fleet's polling takes a bounded share of the center. At 1,000 PMCs, reads every
2 s cost 0.16 s of CPU a second and, in a re-push to all, about a fifth of the center's
CPU per push (each read is a send and a receive on the socket, 0.4 ms of system time on
this 2-core machine). A heartbeat standing still is then seen within DEAD_AFTER_S + 5 s."""


class StatusPace:
    """How often an idle session reads its controller's status, shared by one center's
    controller sessions (:data:`STATUS_READS_PER_S` among all of them)."""

    def __init__(self, reads_per_s: float = STATUS_READS_PER_S) -> None:
        self.reads_per_s = reads_per_s
        self.sessions = 0
        """Sessions running (:meth:`ControllerSession.run`)."""

    def idle_s(self, base_s: float) -> float:
        """The idle period of a session whose own is ``base_s``, s."""
        return max(base_s, self.sessions / self.reads_per_s)


TELEMETRY_REFRESH_S: Final = 5.0
"""A status that changed only in its heartbeat (and ack or temperature fields, which are
not telemetry) is told to the registry this often all the same, s: half the dashboard's
stale limit (10 s). Each telemetry told is a row the center writes to its database."""

_STATES: Final = {0: "idle", 1: "compensating"}

BUSY_TELL_S: Final = 10.0
"""Busy answers go on being retried silently; the link's reason says so this often, s."""


class LinkAck:
    """The PLC's verdict read from the status (also one a previous center missed)."""

    __slots__ = ("applied", "code", "seq", "version")

    def __init__(self, seq: int, code: int, version: int) -> None:
        self.seq = seq
        self.code = code
        self.version = version
        self.applied = code == AckCode.APPLIED


def reason_of(code: int) -> tuple[MapRejectReason, str]:
    """A MapReject reason and text for an ack code (memory codes map to the nearest); the
    text names the PLC's own code, so a rejection says exactly what the PLC said."""
    if code == AckCode.BAD_HEADER:
        return MapRejectReason.CHECKSUM_MISMATCH, "PLC code 100: buffer header magic or CRC wrong"
    if code == AckCode.BAD_BUFFER:
        return MapRejectReason.DECODE_ERROR, "PLC code 101: switch named no buffer"
    try:
        reason = MapRejectReason(code)
    except ValueError:
        return MapRejectReason.APPLY_FAILED, f"PLC code {code}"
    return reason, f"PLC code {code}: {reason.name.lower().replace('_', ' ')}"


SLOTS_KEPT: Final = 4096
"""Maps whose sensor slots :func:`map_slots` remembers (a digest and a few names each)."""
_slots_of: dict[bytes, dict[str, int]] = {}


def map_slots(payload: bytes) -> dict[str, int]:
    """The temperature slot of each sensor of a map, by model column (a record may name
    ``spindle`` or ``T_spindle_C``).

    Remembered by the payload's digest: a decode of a factored map costs about 2 ms of
    the center's CPU, and the same map goes to the same machine again and again (at each
    session start, on a re-push), so a fleet re-push would decode it once per machine.
    A map that does not decode is not remembered (it raises each time).

    Raises
    ------
    MapFormatError, ControllerMemoryError
        The payload does not decode, or it names more sensors than there are slots.
    """
    key = hashlib.blake2b(payload, digest_size=16).digest()
    slots = _slots_of.get(key)
    if slots is None:
        slots = {column_of(s): i for s, i in sensor_slots(
            [r.sensor for r in decode_payload(payload).thermal]).items()}
        if len(_slots_of) >= SLOTS_KEPT:
            _slots_of.pop(next(iter(_slots_of)))  # the oldest
        _slots_of[key] = slots
    return dict(slots)  # the session's own: the remembered one stays as it is


def map_writes(layout: Layout, buffer: int, payload: bytes, map_version: int, seq: int,
               *, block: int) -> list[Write]:
    """The requests of a push (:func:`protocol.ctrlmem.plan_map_write`'s writes, §13.2
    steps 2-5) with neighbouring writes joined up to ``block`` bytes: the cleared header
    and the payload behind it are one region, so the header's 32 zero bytes go in the
    first payload block's request (one request fewer per push: a 1,090-byte map in 7
    instead of 8). The order is kept: within that first request the header's registers
    come first; the header and the switch word stay writes of their own, after the
    payload (a push sends all but the switch word in one exchange, the switch word after
    their answers: :meth:`ControllerSession._write_and_wait`).
    """
    out: list[Write] = []
    run: list[Write] = []

    def flush() -> None:
        if run:
            data = b"".join(w.data for w in run)
            at = run[0].offset
            out.extend(Write(at + k, data[k:k + block]) for k in range(0, len(data), block))
            run.clear()

    for w in plan_map_write(layout, buffer, payload, map_version, seq, block=block):
        if run and run[-1].offset + len(run[-1].data) != w.offset:
            flush()
        run.append(w)
    flush()
    return out


def identity_of(raw: bytes, address: str) -> Identity:
    """The identity block read at ``address``, or a :class:`LinkError` saying what is
    wrong with it: ``magic`` (no EDNC program there, or the window's start is wrong),
    ``byte_order`` (the magic with each register's bytes swapped), ``layout`` (another
    layout version, or sizes this center cannot use)."""
    try:
        return decode_identity(raw)
    except ControllerMemoryError as exc:
        magic = bytes(raw[:4])
        if magic[1::-1] + magic[3:1:-1] == IDENTITY_MAGIC:
            raise LinkError(
                f"{address}: the identity reads {magic!r}, {IDENTITY_MAGIC!r} with each "
                "register's two bytes swapped: the link's byte order is not the "
                "controller's", state="refused", reason="byte_order") from None
        reason = "magic" if magic != IDENTITY_MAGIC else "layout"
        raise LinkError(f"{address}: {exc}", state="refused", reason=reason) from None


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
        Status reads while a push waits for its verdict, s.
    idle_poll_s : float
        Status reads otherwise, s (``poll_s`` when that is longer; longer when ``pace``
        says so).
    pace : StatusPace, optional
        Shared by the center's sessions: many sessions read their idle status less often.
    telemetry_s : float
        Positions and corrections that move become telemetry at most this often, s.
    """

    def __init__(self, name: str, ip: str, controller: Controller, axes: Sequence[str],
                 memory: MemoryClient, *, link: str, chain: str, poll_s: float = 0.1,
                 on_telemetry: Callable[[dict[str, Any]], None] | None = None,
                 dead_after_s: float = DEAD_AFTER_S,
                 on_condition: Callable[[LinkCondition], None] | None = None,
                 healthy_after_s: float = HEALTHY_AFTER_S,
                 idle_poll_s: float = IDLE_POLL_S, pace: StatusPace | None = None,
                 telemetry_s: float = TELEMETRY_PERIOD_MS / 1000) -> None:
        self._name = name
        self.ip = ip
        self.controller = controller
        self.axes = tuple(axes)
        self.chain = chain
        self.memory = memory
        self.link = link
        self.poll_s = poll_s
        self.idle_poll_s = max(poll_s, idle_poll_s)
        self.pace = pace
        self.telemetry_s = telemetry_s
        self.on_telemetry = on_telemetry
        self.dead_after_s = dead_after_s
        self.on_condition = on_condition
        self.healthy_after_s = healthy_after_s
        self.plc_running = True
        """False while the PLC's heartbeat stands still (the session waits for it)."""
        self._stopped_total = 0.0
        self._stopped_since: float | None = None
        """Loop time the heartbeat last moved before the stop in force (None: it runs)."""
        self.healthy = False
        """The link proved itself in this session: a map applied, or a healthy poll cycle
        (up ``healthy_after_s`` with the heartbeat moving and no push in flight)."""
        self._opened_at = 0.0
        self.opened_status: Status | None = None
        self._busy_seen = 0
        self._busy_last = 0.0
        self._busy_told: float | None = None
        self.push_times: list[float] = []
        """When each push of this session started (loop time, s), for the pacing."""
        self.last_code: int | None = None
        """The PLC's ack code of the last push answered in this session."""
        self.torn_rewrites = 0
        """Pushes written again after code 100 (a torn header)."""
        self.status_reads = 0
        """Status reads in this session (the polls and the read before each push)."""
        self._read_at = float("-inf")  # loop time of the last status read, anyone's
        self.address = memory.address
        self.hello: Hello | None = None
        self.identity: Identity | None = None
        self.layout: Layout | None = None
        self.status: Status | None = None
        self.missed: LinkAck | None = None
        """The verdict of a switch this session did not write (a previous center's)."""
        self.closed_because: str | None = None
        self.failure: LinkCondition | None = None
        """What ended the session when a request failed (None: it was ended on purpose)."""
        self.secret_digest = b""
        self.last_heard = asyncio.get_running_loop().time()
        self._seq = 0
        """The switch word's sequence: the last this session wrote, or read at open."""
        self._pending: tuple[int, int, float, asyncio.Future[Verdict]] | None = None
        self._slots: dict[str, int] = {}
        self._slots_version = 0
        """The map version whose thermal records ``_slots`` follows (stamped on the slots,
        §13.1 byte 388, so the PLC never reads them in another map's order)."""
        self._temps: dict[str, float] = {}
        self._temp_seq = 0
        self._temp_dirty = asyncio.Event()
        self._closed = asyncio.Event()
        self._wake = asyncio.Event()
        """Set when a push wrote its switch word (and at abort): the poll loop's wait
        starts again at the push's pace."""
        self._switched_at: float | None = None
        """When the pending push wrote its switch word (loop time, s); None otherwise."""
        self._told: tuple[Any, ...] | None = None
        self._told_at = 0.0
        self._beat: tuple[int, float] | None = None
        self.temperature_writes = 0

    @property
    def name(self) -> str:
        return self._name

    @property
    def reported_version(self) -> int | None:
        """The map version the PLC's status said applied when the session opened."""
        return None if self.opened_status is None else self.opened_status.applied_version

    # -- opening
    async def open(self) -> None:
        """Connect, check the identity, read the status (raises :class:`LinkError`)."""
        await self.memory.connect()
        ident = identity_of(await self.memory.read(0, IDENTITY_SIZE), self.address)
        if ident.name != self._name:
            raise LinkError(f"the window at {self.address} declares machine "
                            f"{ident.name!r}, not {self._name!r}", state="refused",
                            reason="identity_name")
        formats = ident.formats
        if not formats & (MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM):
            raise LinkError(f"the PLC program declares no map format it evaluates "
                            f"({int(formats)})", state="refused", reason="formats")
        self.identity, self.layout = ident, Layout(ident.capacity)
        self.hello = Hello(name=self._name, ip=self.ip, controller=self.controller,
                           map_formats=formats, software_version=f"plc/{self.link}",
                           chain=self.chain)
        st = await self._read_status()
        (word,) = struct.unpack("<H", await self.memory.read(SWITCH_AT, 2))
        written, buffer = unpack_switch(word)
        self._seq = written
        # temperatures go on from the window's own sequence: starting again at 1 would
        # repeat what the PLC last took (a previous center's), and it would take nothing
        (self._temp_seq,) = struct.unpack("<H", await self.memory.read(TEMP_SEQ_AT, 2))
        if (written and st.ack_seq == written and buffer in (1, 2)
                and ack_is_verdict(st.ack_code)):  # code 100 says nothing of the map
            # the verdict on the last switch, whoever wrote it: the buffer's header says
            # which map version it was about (the status has only the applied one)
            at = self.layout.buffer_at(buffer)
            header = decode_buffer_header(await self.memory.read(at, 32))
            version = header.map_version if header is not None else st.applied_version
            self.missed = LinkAck(written, st.ack_code, version)
        self._opened_at = asyncio.get_running_loop().time()
        self.opened_status = st
        self._report(st)

    async def _read_status(self) -> Status:
        return self._took_status(await self.memory.read(STATUS_AT, STATUS_SIZE))

    def _took_status(self, raw: bytes) -> Status:
        """The status read as ``raw``, noted (the heartbeat's last move, the read's time)."""
        try:
            st = decode_status(raw, len(self.axes) or 8)
        except ControllerMemoryError as exc:
            raise LinkError(f"{self.address}: {exc}", state="refused",
                            reason="status") from None
        self.status_reads += 1
        now = asyncio.get_running_loop().time()
        self._read_at = now
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
        if self.pace is not None:
            self.pace.sessions += 1
        try:
            while self.closed_because is None:
                st = await self._read_status()
                self._watch_heartbeat()
                self._watch_busy()
                self._resolve(st)
                self._report(st)
                await self._next_poll(asyncio.get_running_loop().time())
            return self.closed_because or "closed"
        except LinkError as exc:
            self._fail(exc)
            return str(exc)
        finally:
            if self.pace is not None:
                self.pace.sessions -= 1
            writer.cancel()
            await asyncio.gather(writer, return_exceptions=True)
            await self.memory.close()

    async def _next_poll(self, polled: float) -> None:
        """Wait for the next status read after the one at ``polled`` (loop time, s):
        ``poll_s`` after it, or after the switch word, while a push waits for its
        verdict; ``idle_poll_s`` after it otherwise. A push writing its switch word wakes
        the wait, so its verdict is read ``poll_s`` after the switch whatever the idle
        pace was. An idle read is due ``idle_poll_s`` after the last status read of any
        kind: the read a push makes before writing serves as one (a re-push to every
        machine need not cost each an idle read beside its own)."""
        loop = asyncio.get_running_loop()
        idle_s = self.idle_poll_s if self.pace is None else self.pace.idle_s(self.idle_poll_s)
        while self.closed_because is None:
            self._wake.clear()
            switched = self._switched_at
            due = (max(polled, self._read_at) + idle_s if switched is None
                   else max(polled, switched) + self.poll_s)
            left = due - loop.time()
            if left <= 0:
                return
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(left):
                    await self._wake.wait()

    def _watch_heartbeat(self) -> None:
        """A PLC program that stopped is waited for, not left: the session stays open
        (a reconnect would re-send the map into a PLC that cannot take it), the link
        shows ``plc_stopped``, and a push in flight keeps its verdict clock stopped."""
        assert self._beat is not None
        now = asyncio.get_running_loop().time()
        silent = now - self._beat[1]
        running = silent <= self.dead_after_s
        if running != self.plc_running:
            self.plc_running = running
            # the stop started when the heartbeat last moved; it ends now
            if running and self._stopped_since is not None:
                self._stopped_total += now - self._stopped_since
                self._stopped_since = None
            elif not running:
                self._stopped_since = self._beat[1]
            if running:
                log.info("%s: the PLC program runs again", self._name)
                self._condition(LinkCondition("connected"))
            else:
                self._condition(LinkCondition(
                    "plc_stopped", "heartbeat", f"{self.address}: PLC heartbeat still for "
                    f"{silent:.1f} s: the PLC program is not running (the center waits)"))
        if (running and not self.healthy and self._pending is None
                and now - self._opened_at >= self.healthy_after_s):
            self.healthy = True

    def _watch_busy(self) -> None:
        """Busy answers asked again (a memory's ``busy_retries``) keep the session but
        are shown: the link stays ``connected`` with reason ``busy`` (told at most every
        :data:`BUSY_TELL_S`), back to no reason after a minute without any."""
        retries = int(getattr(self.memory, "busy_retries", 0))
        now = asyncio.get_running_loop().time()
        if retries != self._busy_seen:
            self._busy_seen = retries
            self._busy_last = now
            if self._busy_told is None or now - self._busy_told >= BUSY_TELL_S:
                self._busy_told = now
                note = getattr(self.memory, "busy_note", "")
                self._condition(LinkCondition(
                    "connected", "busy", f"{retries} requests answered busy and asked "
                    f"again in this session (the last: {note})"))
        elif self._busy_told is not None and now - self._busy_last >= 60.0:
            self._busy_told = None
            self._condition(LinkCondition("connected"))

    def _condition(self, condition: LinkCondition) -> None:
        if self.on_condition is not None:
            self.on_condition(condition)

    def _resolve(self, st: Status) -> None:
        pending = self._pending
        if pending is None or st.ack_seq != pending[0]:
            return
        _seq, version, t0, future = pending
        if future.done():
            return
        latency = asyncio.get_running_loop().time() - t0
        self.last_code = st.ack_code
        if st.ack_code == AckCode.APPLIED:
            future.set_result(Verdict(version, True, None, "", latency))
        else:
            reason, text = reason_of(st.ack_code)
            future.set_result(Verdict(version, False, reason, text, latency))

    def _report(self, st: Status) -> None:
        """The status as the machine's telemetry (module docstring: at once for a new map
        or state, at most every ``telemetry_s`` for moving axes, every
        :data:`TELEMETRY_REFRESH_S` for an unchanged status): each one told is a registry
        update the center writes to its database, as an EDNC machine's Telemetry is."""
        if self.on_telemetry is None or self.identity is None:
            return
        told = (st.state, st.applied_version, st.positions, st.applied)
        now = asyncio.get_running_loop().time()
        last = self._told
        age = now - self._told_at
        if last is not None and age < TELEMETRY_REFRESH_S and (
                told == last or (told[:2] == last[:2] and age < self.telemetry_s)):
            return
        self._told, self._told_at = told, now
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
            The link failed, the session ended, or the PLC answered code 100 (a torn
            header, no verdict on the map) to the map written twice.
        """
        if self.layout is None:
            raise LinkClosed("the session is not open")
        if self._pending is not None:
            raise RuntimeError(f"{self._name}: a map push is already in progress")
        try:
            slots = map_slots(payload)
        except (MapFormatError, ControllerMemoryError) as exc:
            raise LinkClosed(f"map version {version} cannot be written: {exc}") from None
        verdict = await self._write_and_wait(version, payload, timeout_s)
        if not verdict.applied and not ack_is_verdict(self.last_code or 0):
            # a torn header is no verdict on the map (§13.2): written again, once, the
            # header alone after the blocks (a server that took the header before the
            # cleared one in the same exchange tears it so)
            self.torn_rewrites += 1
            log.info("%s: map version %d: buffer header torn (code 100), written again",
                     self._name, version)
            verdict = await self._write_and_wait(version, payload, timeout_s,
                                                 header_alone=True)
            if not verdict.applied and not ack_is_verdict(self.last_code or 0):
                # torn twice: still no verdict on the map, so none is stored (a failed
                # delivery, the map goes again), never a rejection
                raise LinkClosed(f"map version {version}: {verdict.text}, twice")
        if verdict.applied:
            self.healthy = True
            self._slots, self._slots_version = slots, version
            self._temp_dirty.set()  # the new map's sensors get their readings at once
        return verdict

    def adopt(self, version: int, payload: bytes) -> None:
        """The PLC runs map ``version`` already (its status said so at open; the map is
        not written again): its temperature slots follow that map's thermal records from
        now on, as after a push, so a restarted center feeds them at once."""
        try:
            slots = map_slots(payload)
        except (MapFormatError, ControllerMemoryError) as exc:
            log.warning("%s: map version %d: thermal records not read: %s", self._name,
                        version, exc)
            return
        self._slots, self._slots_version = slots, version
        self._temp_dirty.set()

    async def _write_and_wait(self, version: int, payload: bytes, timeout_s: float,
                              *, header_alone: bool = False) -> Verdict:
        assert self.layout is not None
        loop = asyncio.get_running_loop()
        future: asyncio.Future[Verdict] = loop.create_future()
        started = loop.time()
        self.push_times.append(started)
        try:
            async with asyncio.timeout(timeout_s):
                # Steps 0-4 in one exchange: the status read and the writes into the
                # buffer that was not active at the last read. Only this session writes
                # switch words, so that buffer is still not active unless someone else
                # switched meanwhile: the fresh status says so before the switch word
                # goes, and then the map is written again into the other buffer (the
                # PLC runs its own checked copy, never the window's: 13.3).
                t_write = loop.time()  # the verdict's latency counts from here
                self._pending = (-1, version, t_write, future)  # no switch yet
                known = self.status
                target = 2 if known is not None and known.active == 1 else 1
                writes = self._buffer_writes(target, payload, version)
                st = self._took_status(await self.memory.write_many(
                    writes[:-1] if header_alone else writes, read=(STATUS_AT, STATUS_SIZE)))
                if st.active == target:
                    log.warning("%s: buffer %d became active without this center's switch "
                                "(another writer?): map version %d written into the other",
                                self._name, target, version)
                    target = 2 if st.active == 1 else 1
                    writes = self._buffer_writes(target, payload, version)
                    await self.memory.write_many(writes[:-1] if header_alone else writes)
                if header_alone:
                    await self.memory.write(*writes[-1])
                seq = next_switch_sequence(self._seq, st.ack_seq)
                self._pending = (seq, version, t_write, future)
                # the switch word (step 5) alone, once everything before is answered
                await self.memory.write(SWITCH_AT, struct.pack("<H", pack_switch(seq, target)))
                self._seq = seq
                self._switched_at = loop.time()
                self._wake.set()  # the verdict is polled at the push's pace from now
            return await self._verdict(future, timeout_s - (loop.time() - started))
        except ControllerMemoryError as exc:
            raise LinkClosed(f"map version {version}: {exc}") from None
        except LinkError as exc:
            self._fail(exc)
            raise LinkClosed(str(exc)) from None
        finally:
            self._pending = None
            self._switched_at = None
            if future.done() and not future.cancelled():
                future.exception()  # retrieved: an abort during writing set it unread

    def _buffer_writes(self, target: int, payload: bytes, version: int
                       ) -> list[tuple[int, bytes]]:
        """Steps 2-4 into buffer ``target``: the cleared header with the first payload
        block, the other blocks, the header last (:func:`map_writes` without the switch
        word). A server taking them out of order may land the header before a block; the
        buffer is not active and the PLC checks the payload's CRC on the switch, which
        comes only when all of them are answered."""
        assert self.layout is not None
        *writes, _switch = map_writes(self.layout, target, payload, version, 1,
                                      block=self.memory.block)
        return [(w.offset, w.data) for w in writes]

    async def _verdict(self, future: asyncio.Future[Verdict], timeout_s: float) -> Verdict:
        """The PLC's verdict within ``timeout_s`` of PLC running time: while its heartbeat
        stands still the clock stops (it answers when it runs again; a time-out would
        end the session and the map would be sent again into a stopped PLC)."""
        loop = asyncio.get_running_loop()
        left = timeout_s
        while True:
            t0, stopped0 = loop.time(), self._stopped_s(loop.time())
            try:
                # one wait for the whole time left (a wake-up every quarter second cost
                # each push of a fleet re-push four turns of the event loop)
                async with asyncio.timeout(max(0.0, left)):
                    return await asyncio.shield(future)
            except TimeoutError:
                now = loop.time()
                left -= max(0.0, (now - t0) - (self._stopped_s(now) - stopped0))
                if left <= 0:
                    raise

    def _stopped_s(self, now: float) -> float:
        """How long the PLC program has stood still in this session so far, s (the
        verdict's clock does not run meanwhile)."""
        since = self._stopped_since
        return self._stopped_total + (now - since if since is not None else 0.0)

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
            w = plan_temperatures(values, self._temp_seq, map_version=self._slots_version)
            try:
                for k in range(0, len(w.data), self.memory.block):
                    await self.memory.write(w.offset + k, w.data[k:k + self.memory.block])
            except LinkError as exc:
                self._fail(exc)
                return
            self.temperature_writes += 1

    # -- closing
    def _fail(self, exc: LinkError) -> None:
        if self.failure is None and self.closed_because is None:
            self.failure = exc.condition
        self.abort(None, str(exc))

    def abort(self, code: ErrorCode | None, text: str) -> None:
        """End the session (``code`` is the EDNC protocol's, kept for the interface)."""
        if self.closed_because is None:
            self.closed_because = text
        pending = self._pending
        if pending is not None and not pending[3].done():
            pending[3].set_exception(LinkClosed(text))
        self._closed.set()
        self._wake.set()

    async def wait_closed(self) -> None:
        await self._closed.wait()
