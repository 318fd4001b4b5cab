"""A simulated CNC on the network: the machine side of the EDNC protocol over TCP.

:class:`SimulatedCNC` is an async context manager. Inside it three named tasks run:

* ``plc``: the controller cycle (:class:`~machine_sim.runtime.MachineRuntime`) every
  ``cycle_s``, connected or not: losing the link does not release compensation;
* ``link``: connect to the center, Hello, answer the Challenge with the machine secret,
  then one receive loop dispatching every message with ``match`` (map chunks to the
  controller's map store and back MapAck/MapReject, Heartbeat → HeartbeatReply,
  ReleaseCompensation → ramp, Error/close → reconnect). Telemetry goes out every period
  Welcome gave; a Siemens-style machine adds its temperatures to it. After any failure it
  reconnects with jittered, capped exponential backoff (:class:`Backoff`);
  given several centers (one plant served by several center processes), it tries the next
  one at once after a refusal (another node owns the machine), a connection failure or a
  lost session, and waits the backoff only once every center has failed in turn;
* ``mqtt`` (Fanuc-style machines, when a broker is given): publishes every sensor to
  ``<prefix>/<machine>/temperature/<sensor>`` as JSON ``{"celsius": 21.4,
  "timestamp_ms": 1763820000000}`` every telemetry period (aiomqtt; reconnects likewise).

The protocol itself is :mod:`protocol` (sans-I/O): this module only moves its bytes.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import json
import logging
import random
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from types import TracebackType
from typing import cast

from protocol import (
    CONNECTION_CLOSED,
    NEED_DATA,
    AuthResponse,
    AxisReading,
    Challenge,
    Connection,
    Controller,
    Error,
    ErrorCode,
    Heartbeat,
    HeartbeatReply,
    Hello,
    LocalProtocolError,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    Message,
    ProtocolError,
    Reject,
    ReleaseCompensation,
    Released,
    Role,
    SensorReading,
    State,
    Telemetry,
    Temperatures,
    Welcome,
    compute_mac,
)
from protocol.backoff import Backoff
from protocol.limits import HANDSHAKE_TIMEOUT_MS, HEARTBEAT_PERIOD_MS, MISSED_HEARTBEATS
from volumetric.model.machine import Machine

from .runtime import MachineRuntime
from .siemens import SiemensNC

__all__ = ["Backoff", "LinkStats", "MqttTarget", "SimulatedCNC"]

log = logging.getLogger(__name__)
READ_BYTES = 65536
HANDSHAKE_S = HANDSHAKE_TIMEOUT_MS / 1000  # protocol README section 9
DEAD_PEER_PERIODS = MISSED_HEARTBEATS


def _is_loopback(address: str) -> bool:
    try:
        return ipaddress.ip_address(address).is_loopback
    except ValueError:
        return address == "localhost"


@dataclass(frozen=True)
class MqttTarget:
    """Where a Fanuc-style machine publishes its temperatures."""

    host: str
    port: int = 1883
    prefix: str = "ednc"


@dataclass
class LinkStats:
    """What happened on the link (for tests, logs and the CLI's summary)."""

    connects: int = 0
    welcomes: int = 0
    maps_acked: int = 0
    maps_rejected: int = 0
    releases: int = 0
    telemetry_sent: int = 0
    mqtt_published: int = 0
    temperatures_received: int = 0
    last_error: str = ""
    rejects: list[str] = field(default_factory=list)


def _centers(center: tuple[str, int] | Sequence[tuple[str, int]]
             ) -> tuple[tuple[str, int], ...]:
    """One (host, port) or several, as a non-empty tuple of pairs."""
    if len(center) == 2 and isinstance(center[0], str):
        return ((center[0], int(cast(int, center[1]))),)
    pairs = cast("Sequence[tuple[str, int]]", center)
    out = tuple((str(h), int(p)) for h, p in pairs)
    if not out:
        raise ValueError("a simulated machine needs at least one center")
    return out


class _Closed(Exception):
    """The session ended (peer closed, Reject or Error); reconnect."""


class SimulatedCNC:
    """A simulated machine that keeps a session with the center.

    Parameters
    ----------
    machine : Machine
    center : (host, port) or sequence of them
        The center's machine port, or several centers of one plant, tried in turn.
    secret : bytes
        The machine's secret, as registered at the center (>= 16 bytes).
    runtime : MachineRuntime, optional
        Motion, temperatures and controller; built from ``machine`` and ``seed`` if omitted.
    ip : str, optional
        Address to announce in Hello; the description's ``ip`` by default.
    cycle_s : float, optional
        Controller cycle; the controller's own (8 ms Fanuc, 4 ms Siemens) by default.
    backoff : Backoff
    mqtt : MqttTarget, optional
        Broker for a Fanuc-style machine's temperatures.
    seed : int
    software_version : str
    """

    def __init__(self, machine: Machine,
                 center: tuple[str, int] | Sequence[tuple[str, int]], secret: bytes, *,
                 runtime: MachineRuntime | None = None, ip: str | None = None,
                 cycle_s: float | None = None, backoff: Backoff | None = None,
                 mqtt: MqttTarget | None = None, seed: int = 0,
                 software_version: str = "edncsim-1") -> None:
        self.machine = machine
        self.centers = _centers(center)
        self._which = 0
        self.connected_to: tuple[str, int] | None = None
        """The center of the current session (after Welcome), None between sessions."""
        self.secret = secret
        self.runtime = runtime or MachineRuntime(machine, seed=seed)
        self.ip = ip or machine.ip
        self.cycle_s = cycle_s or self.runtime.cycle_s
        self.backoff = backoff or Backoff()
        self.mqtt = mqtt
        self.software_version = software_version
        self.stats = LinkStats()
        self.ready = asyncio.Event()
        self._rng = random.Random(seed)
        self._t0 = 0.0
        self._tasks: list[asyncio.Task[None]] = []
        self._conn: Connection | None = None
        self._writer: asyncio.StreamWriter | None = None
        self._telemetry_s = 1.0
        self._heartbeat_s = HEARTBEAT_PERIOD_MS / 1000  # until Welcome says
        self._welcomed_this_time = False
        self._release_pending = False
        self._stopping = False

    # -- lifetime
    async def __aenter__(self) -> SimulatedCNC:
        self._t0 = asyncio.get_running_loop().time()
        name = self.machine.name
        self._tasks = [asyncio.create_task(self._plc_loop(), name=f"{name}:plc"),
                       asyncio.create_task(self._link_loop(), name=f"{name}:link")]
        if self.mqtt is not None and self.machine.controller == "fanuc":
            self._tasks.append(asyncio.create_task(self._mqtt_loop(self.mqtt),
                                                   name=f"{name}:mqtt"))
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        # The flag as well as the cancel: a library that turns the CancelledError into its
        # own error (aiomqtt does, mid-publish) must not keep a loop alive.
        self._stopping = True
        for t in self._tasks:
            t.cancel()
        results = await asyncio.gather(*self._tasks, return_exceptions=True)
        self._tasks = []
        await self._close_writer()
        for r in results:
            if isinstance(r, Exception):
                raise r

    @property
    def center(self) -> tuple[str, int]:
        """The center the machine connects to now (the next is tried after a failure)."""
        return self.centers[self._which]

    def stopping(self) -> bool:
        """The context is being left: loops end at their next turn."""
        return self._stopping

    def now(self) -> float:
        """Machine time since start, s."""
        return asyncio.get_running_loop().time() - self._t0

    # -- the PLC
    async def _plc_loop(self) -> None:
        loop = asyncio.get_running_loop()
        next_t = loop.time()
        while not self.stopping():
            self.runtime.step(self.now())
            if self.runtime.controller.take_released() and self._release_pending:
                self._release_pending = False
                await self._send(Released())
            next_t += self.cycle_s
            delay = next_t - loop.time()
            if delay < -10 * self.cycle_s:  # far behind (a stalled loop): resynchronise
                next_t = loop.time()
            await asyncio.sleep(max(delay, 0.0))

    # -- the link
    async def _link_loop(self) -> None:
        attempt = 0
        failed_in_turn = 0  # centers that failed one after the other since the last sleep
        while not self.stopping():
            try:
                await self._session()
            except (OSError, ProtocolError, _Closed, TimeoutError) as exc:
                self.stats.last_error = f"{type(exc).__name__}: {exc}"
                log.info("%s: link down (%s)", self.machine.name, self.stats.last_error)
            finally:
                self.ready.clear()
                self.connected_to = None
                await self._close_writer()
            if self.stats.welcomes and self._welcomed_this_time:
                attempt, failed_in_turn = 0, 0
            self._which = (self._which + 1) % len(self.centers)
            failed_in_turn += 1
            if failed_in_turn < len(self.centers):
                continue  # another center may serve us now: no reason to wait
            failed_in_turn = 0
            await asyncio.sleep(self.backoff.delay(attempt, self._rng))
            attempt += 1

    async def _close_writer(self) -> None:
        w, self._writer, self._conn = self._writer, None, None
        if w is not None:
            w.close()
            with contextlib.suppress(OSError, ConnectionError):
                await w.wait_closed()

    async def _send(self, msg: Message) -> None:
        conn, w = self._conn, self._writer
        if conn is None or w is None:
            return
        try:
            data = conn.send(msg)
        except LocalProtocolError as exc:  # e.g. the session closed meanwhile
            log.debug("%s: not sent: %s", self.machine.name, exc)
            return
        w.write(data)
        with contextlib.suppress(OSError, ConnectionError):
            await w.drain()

    def _hello(self) -> Hello:
        fanuc = self.machine.controller == "fanuc"
        return Hello(
            name=self.machine.name, ip=self.ip,
            controller=Controller.FANUC if fanuc else Controller.SIEMENS,
            # what the controller's map store takes: Fanuc int32 grids; Siemens float32
            # grids and tables maps
            map_formats=self.runtime.controller.store.assembler.accepted,
            software_version=self.software_version, chain=self.machine.chain,
        )

    async def _session(self) -> None:
        self._welcomed_this_time = False
        host, port = self.center
        # The center knows machines by their address. On one host every 127.x.y.z address
        # is the loopback, so a simulated machine with such an ip connects *from* it, as a
        # real CNC connects from its own address.
        local = (self.ip, 0) if _is_loopback(self.ip) and _is_loopback(host) else None
        # asyncio.timeout, not wait_for: wait_for can swallow a cancellation that arrives
        # as the inner call completes (under load), and the link task would never end
        async with asyncio.timeout(HANDSHAKE_S):
            reader, writer = await asyncio.open_connection(host, port, local_addr=local)
        self.stats.connects += 1
        self._conn, self._writer = Connection(Role.MACHINE), writer
        self._release_pending = False
        await self._send(self._hello())
        telemetry: asyncio.Task[None] | None = None
        try:
            async with asyncio.timeout(HANDSHAKE_S):
                while not self._welcomed_this_time:
                    await self._receive(reader)
            telemetry = asyncio.create_task(self._telemetry_loop(),
                                            name=f"{self.machine.name}:telemetry")
            while True:
                await self._receive(reader)
        finally:
            if telemetry is not None:
                telemetry.cancel()
                with contextlib.suppress(asyncio.CancelledError):
                    await telemetry

    async def _receive(self, reader: asyncio.StreamReader) -> None:
        """Read once (with the dead-peer timeout once running) and handle every event."""
        conn = self._conn
        assert conn is not None
        timeout = (DEAD_PEER_PERIODS * self._heartbeat_s if self._welcomed_this_time
                   else None)
        async with asyncio.timeout(timeout):  # see _session: never wait_for
            data = await reader.read(READ_BYTES)
        conn.receive_data(data)
        while True:
            try:
                event = conn.next_event()
            except ProtocolError as exc:
                w = self._writer
                if w is not None:
                    w.write(conn.send_error(ErrorCode.PROTOCOL_ERROR, str(exc)))
                raise
            if event is NEED_DATA:
                return
            if event is CONNECTION_CLOSED:
                raise _Closed("the center closed the connection")
            await self._dispatch(event)

    async def _dispatch(self, msg: Message) -> None:
        """Act on one message from the center; every message type is a case (mypy checks
        the names and fields the cases bind)."""
        ctl = self.runtime.controller
        match msg:
            case Challenge(nonce=nonce):
                await self._send(AuthResponse(compute_mac(self.secret, nonce,
                                                          self.machine.name)))
            case Welcome(heartbeat_period_ms=hb, telemetry_period_ms=tm):
                self._heartbeat_s = hb / 1000.0
                self._telemetry_s = tm / 1000.0
                self._welcomed_this_time = True
                self.connected_to = self.center
                self.stats.welcomes += 1
                self.ready.set()
            case Reject(code=code, text=text):
                self.stats.rejects.append(f"{code.name}: {text}")
                raise _Closed(f"rejected: {code.name} {text}")
            case MapBegin() | MapChunk() | MapEnd():
                reply = ctl.feed_map(msg, self.now())
                if reply is not None:
                    if isinstance(reply, MapAck):
                        self.stats.maps_acked += 1
                    else:
                        self.stats.maps_rejected += 1
                    await self._send(reply)
            case Heartbeat(token=token):
                await self._send(HeartbeatReply(token))
            case ReleaseCompensation(ramp_ms=ramp_ms):
                self.stats.releases += 1
                self._release_pending = True
                ctl.release(self.now(), ramp_ms / 1000.0)
            case Temperatures():
                # stored for the next cycle; never answered (protocol rule 10)
                ctl.temperatures.apply(msg, self.now())
                self.stats.temperatures_received += 1
            case Error(code=code, text=text):
                raise _Closed(f"center error {code.name}: {text}")
            case _:
                raise _Closed(f"unexpected {type(msg).__name__} from the center")

    def telemetry(self) -> Telemetry:
        """The Telemetry message for now (temperatures only where the PLC reads its own
        sensors: a Siemens-style machine by default): the readings its PLC holds, without
        the stale ones, so that a sensor that stopped answering ages on the center's board
        and the dashboard shows it stale (its last value would otherwise look fresh)."""
        rt = self.runtime
        comp = rt.controller.applied_mm()
        axes = tuple(AxisReading(a, float(rt.positions[j]), float(comp[j]))
                     for j, a in enumerate(rt.controller.axes))
        temps: tuple[SensorReading, ...] = ()
        if isinstance(rt.controller, SiemensNC):
            store = rt.controller.temperatures
            stale = store.stale(self.now())
            temps = tuple(SensorReading(k, r.celsius) for k, r in store.readings().items()
                          if r.source == "sensor" and k not in stale)
        return Telemetry(int(time.time() * 1000), rt.controller.state,
                         rt.controller.store.version, axes, temps)

    async def _telemetry_loop(self) -> None:
        while True:
            conn = self._conn
            if conn is None or conn.session is not State.READY:
                return
            await self._send(self.telemetry())
            self.stats.telemetry_sent += 1
            await asyncio.sleep(self._telemetry_s)

    # -- MQTT
    async def _mqtt_loop(self, target: MqttTarget) -> None:
        try:
            import aiomqtt
        except ImportError:  # optional: the machine then only speaks the protocol
            log.warning("%s: aiomqtt is not installed, no MQTT temperatures",
                        self.machine.name)
            return
        attempt = 0
        while not self.stopping():
            try:
                # a fresh client id per connection: two simulators of one fleet (or a
                # stale session) must not keep kicking each other off the broker
                ident = f"edncsim-{self.machine.name}-{self._rng.getrandbits(32):08x}"
                async with aiomqtt.Client(target.host, target.port,
                                          identifier=ident) as client:
                    attempt = 0
                    while not self.stopping():
                        stamp = int(time.time() * 1000)
                        for sensor, value in self.runtime.temperatures(self.now()).items():
                            topic = f"{target.prefix}/{self.machine.name}/temperature/{sensor}"
                            body = json.dumps({"celsius": round(value, 4),
                                               "timestamp_ms": stamp})
                            await client.publish(topic, body)
                            self.stats.mqtt_published += 1
                        await asyncio.sleep(self._telemetry_s)
            except aiomqtt.MqttError as exc:
                if self.stopping():
                    return
                self.stats.last_error = f"MQTT: {exc}"
            await asyncio.sleep(self.backoff.delay(attempt, self._rng))
            attempt += 1
