"""The machine TCP server: handshake, authentication, refusals, then one session per machine.

Per connection (one task, :meth:`MachineServer._handle`):

1. **Handshake**, within ``handshake_s`` (10 s, protocol README §9) from accept: Hello;
   the name must be registered, the peer address and Hello's ``ip`` must be the
   registered address, the controller and a map format must match; then Challenge and
   AuthResponse (HMAC-SHA256 with the machine's secret, compared in constant time). Any
   failure is a Reject with its code and a text saying what was wrong, a ``refused``
   event (the dashboard's refusal list) and a count in ``ednc_connections_refused``.
2. **Session**, after Welcome: one receive loop dispatching with ``match``; a heartbeat
   task; the push scheduler's worker for this machine. Nothing heard for 3 heartbeat
   periods ends it (Error TIMEOUT), as does a bad frame (Error PROTOCOL_ERROR): that one
   connection closes and every other keeps being served.

A second session for a machine that already has one is refused (DUPLICATE_SESSION) while
the first is alive; when the first has been silent for a heartbeat period or more (a
half-open connection after a cable pull), the authenticated newcomer replaces it.

With a :class:`~server.leasing.LeaseKeeper` (several nodes on one database), the node takes
the machine's lease after authentication and before Welcome; a machine whose lease another
node holds is refused (DUPLICATE_SESSION, "machine 'm' is owned by node X") and tries its
next center. A session whose lease is lost is closed; its end gives the lease back.

Unauthenticated peers are bounded (:mod:`server.links.ednc.admission`): a connection from an
address no machine is registered at is closed at accept; handshakes are limited per
address and in total (``max_handshakes``), a newcomer taking the slot of the longest
waiting one when all are taken; Hello must come within ``hello_s``; failed logins delay
the next try exponentially per address and per name; refusals are stored at most once per
peer per minute with a count. A refused peer learns only the refusal code (an empty
Reject text): what was wrong, which would tell a spoofer the registered address or
controller, goes to the log and the event (the dashboard) only.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable, Coroutine
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Final

from sqlalchemy.exc import SQLAlchemyError

from protocol import (
    AuthResponse,
    Challenge,
    Controller,
    Error,
    ErrorCode,
    HeartbeatReply,
    Hello,
    MapAck,
    MapEncoding,
    MapReject,
    Reject,
    Released,
    RemoteProtocolError,
    Telemetry,
    Welcome,
    clip_text,
    new_nonce,
    verify_mac,
)
from protocol.limits import (
    HANDSHAKE_TIMEOUT_MS,
    HEARTBEAT_PERIOD_MS,
    MISSED_HEARTBEATS,
    TELEMETRY_PERIOD_MS,
)
from protocol.messages import Heartbeat
from server.center import Center
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db.secretbox import SecretKeyError
from server.db.tables import MachineRow
from server.events import EventKind
from server.feed import Feed, Notice
from server.leasing import LeaseKeeper
from server.links.ednc.admission import (
    AddressBook,
    HandshakeSlots,
    LoginThrottle,
    OncePerWindow,
    RefusalLog,
    digest,
)
from server.links.ednc.session import LinkClosed, MachineSession, peer_ip
from server.temperatures import TemperatureBoard, valid_sensor

log = logging.getLogger(__name__)

HANDSHAKE_S: Final = HANDSHAKE_TIMEOUT_MS / 1000
HELLO_S: Final = 2.0
"""Accept to Hello, s. A machine sends Hello as soon as it is connected (a few ms on a
LAN); a peer that holds a handshake slot without speaking is dropped after this."""
MAX_HANDSHAKES_PER_ADDRESS: Final = 4
"""A machine has one address and needs one handshake at a time (two while a half-open
old connection lingers); four leave room and stop one address from taking all slots."""
DEAD_AFTER_PERIODS: Final = MISSED_HEARTBEATS
MAX_HANDSHAKES: Final = 256
"""Connections allowed between accept and Welcome at once. Each handshake waits for a few
database round trips (machine, lease, event) that the database serialises: measured ~23 ms
per handshake on SQLite (benchmarks/center_connections.py), so 256 queued ones finish in
~6 s, inside the 10 s handshake deadline. A larger bound lets a reconnect storm (5000
machines after a center restart) queue past the deadline, time out and retry: congestion
collapse. Beyond the bound a connection is closed at once and the machine backs off."""

ENCODING_OF: Final = {"fanuc": MapEncoding.INT32_INCREMENTS, "siemens": MapEncoding.FLOAT32_MM}

SessionWorker = Callable[[MachineSession, MachineRow], Coroutine[Any, Any, None]]
"""Runs alongside a session until cancelled (the push scheduler's per-machine worker)."""


class Refused(Exception):
    """The handshake failed: answer with Reject and record ``text`` under ``reason``.

    The Reject carries ``text`` only for a peer that has authenticated (``told``: a second
    session, a lease held elsewhere); anyone else gets the code alone.
    """

    def __init__(self, code: ErrorCode, text: str, reason: str, who: str, *,
                 told: bool = False) -> None:
        super().__init__(text)
        self.code = code
        self.text = text
        self.reason = reason
        self.who = who
        self.told = told


@dataclass(frozen=True, slots=True)
class LinkTiming:
    """Deadlines of the machine link, s."""

    handshake_s: float = HANDSHAKE_S
    hello_s: float = HELLO_S
    heartbeat_s: float = HEARTBEAT_PERIOD_MS / 1000  # the protocol's default, 5 s
    telemetry_period_ms: int = TELEMETRY_PERIOD_MS

    @property
    def dead_after_s(self) -> float:
        return DEAD_AFTER_PERIODS * self.heartbeat_s


def telemetry_fields(msg: Telemetry) -> dict[str, Any]:
    """Telemetry as the registry (and the status API) keeps it: plain JSON values."""
    return {
        "timestamp_ms": msg.timestamp_ms, "state": msg.state, "map_version": msg.map_version,
        "axes": {a.name: {"position": a.position, "compensation": a.compensation}
                 for a in msg.axes},
        "temperatures": {s.name: s.celsius for s in msg.temperatures},
    }


class _Admitting(asyncio.StreamReaderProtocol):
    """A stream protocol that closes a peer from an unregistered address on accept."""

    def __init__(self, server: MachineServer, reader: asyncio.StreamReader,
                 handle: Callable[[asyncio.StreamReader, asyncio.StreamWriter],
                                  Coroutine[Any, Any, None]],
                 loop: asyncio.AbstractEventLoop) -> None:
        super().__init__(reader, handle, loop=loop)
        self._machine_server = server

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        ip = peer_ip(transport)
        if not self._machine_server.addresses.admits(ip):
            self._machine_server._unregistered(ip)
            if isinstance(transport, asyncio.Transport):
                transport.abort()  # a reset: nothing lingers on our side
            else:
                transport.close()
            return
        super().connection_made(transport)


class MachineServer:
    """The asyncio TCP server the machines connect to; an async context manager.

    Parameters
    ----------
    center : Center
    feed : Feed
        Where events go (and from there to MQTT).
    temperatures : TemperatureBoard
        Receives the temperatures machines report in Telemetry.
    worker : callable, optional
        Started for every session after Welcome, cancelled when it ends.
    host, port : str, int
        Where to listen (port 0: any free port, see :attr:`port`).
    timing : LinkTiming
    max_handshakes, max_handshakes_per_address : int
        Handshakes in progress at once, in all and from one address.
    leases : LeaseKeeper, optional
        Machine leases of this node, when several nodes share the database.
    throttle : LoginThrottle, optional
        Delays after failed logins (exponential from 0.5 s by default).
    """

    def __init__(self, center: Center, feed: Feed, temperatures: TemperatureBoard, *,
                 worker: SessionWorker | None = None, host: str = "0.0.0.0", port: int = 0,
                 timing: LinkTiming | None = None,
                 max_handshakes: int = MAX_HANDSHAKES,
                 max_handshakes_per_address: int = MAX_HANDSHAKES_PER_ADDRESS,
                 leases: LeaseKeeper | None = None,
                 throttle: LoginThrottle | None = None) -> None:
        self.center = center
        self.feed = feed
        self.temperatures = temperatures
        self.worker = worker
        self.host = host
        self.requested_port = port
        self.timing = timing or LinkTiming(heartbeat_s=center.settings.heartbeat_s)
        self.max_handshakes = max_handshakes
        self.leases = leases
        self.sessions: dict[str, MachineSession] = {}
        self.addresses = AddressBook(center.db)
        self.slots = HandshakeSlots(max_handshakes, max_handshakes_per_address)
        self.throttle = throttle or LoginThrottle()
        self.refusal_log = RefusalLog(self._store_refusals)
        self._log_unregistered = OncePerWindow()
        self._log_refused = OncePerWindow()
        self._session_of: dict[int, MachineSession] = {}  # by machine id, for secret changes
        self._handlers: set[asyncio.Task[None]] = set()
        self._background: list[asyncio.Task[None]] = []
        self._server: asyncio.Server | None = None

    @property
    def handshaking(self) -> int:
        """Connections now between accept and Welcome."""
        return len(self.slots)

    @property
    def port(self) -> int:
        """The port actually listened on."""
        if self._server is None or not self._server.sockets:
            raise RuntimeError("the machine server is not running")
        return int(self._server.sockets[0].getsockname()[1])

    async def __aenter__(self) -> MachineServer:
        # the address book is read before the port opens: a machine connecting at once
        # must not be turned away by an empty book
        await self.addresses.refresh()
        self._background = [
            asyncio.create_task(self.addresses.run(self._secrets_changed), name="addresses"),
            asyncio.create_task(self.refusal_log.run(), name="refusal-log"),
        ]
        loop = asyncio.get_running_loop()

        def protocol() -> asyncio.StreamReaderProtocol:
            return _Admitting(self, asyncio.StreamReader(loop=loop), self._handle, loop=loop)

        # asyncio.start_server, but a peer from an unregistered address is closed in
        # connection_made: no task, no stream writer, no handler ever runs for it
        self._server = await loop.create_server(protocol, self.host, self.requested_port,
                                                backlog=4096)
        log.info("machine server listening on %s:%d", self.host, self.port)
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        server, self._server = self._server, None
        if server is not None:
            server.close()
        for session in list(self.sessions.values()):
            session.abort(ErrorCode.SHUTDOWN, "the control center is shutting down")
        for task in list(self._handlers):
            task.cancel()
        if self._handlers:
            await asyncio.gather(*self._handlers, return_exceptions=True)
        for task in self._background:
            task.cancel()
        await asyncio.gather(*self._background, return_exceptions=True)
        if server is not None:
            await server.wait_closed()

    # -- connections
    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        if task is not None:  # start_server runs each connection in a task of its own
            self._handlers.add(task)
            task.add_done_callback(self._handlers.discard)
        session = MachineSession(reader, writer)
        try:
            try:
                await self._serve(session)
            finally:
                await session.wait_closed()
        except asyncio.CancelledError:
            # the server is closing: this is the connection's top task and nobody awaits
            # it (asyncio's stream callback would log the cancellation as an error)
            session.abort(ErrorCode.SHUTDOWN, "the control center is shutting down")

    def _unregistered(self, ip: str) -> None:
        """Count (and log, once a minute per address) a peer closed at accept."""
        self.center.metrics.refusals.labels(reason="unregistered").inc()
        if self._log_unregistered(ip):
            log.warning("connection from %s, where no machine is registered: closed "
                        "(logged once a minute per address)", ip)

    async def _serve(self, session: MachineSession) -> None:
        metrics = self.center.metrics
        if not self.addresses.admits(session.ip):  # unregistered since the accept
            self._unregistered(session.ip)
            session.abort(None, "no machine is registered at this address")
            return

        def evict() -> None:
            metrics.handshake_evictions.inc()
            session.abort(None, "handshake slot given to another peer")

        slot = self.slots.acquire(session.ip, evict)
        if slot is None:
            # no Reject: the peer has not said Hello, and reading it would cost what this
            # limit protects; count it only (a flood must not flood the events table)
            metrics.refusals.labels(reason="busy").inc()
            session.abort(None, "too many handshakes at once")
            return
        # Each refusal is recorded before the socket closes, so that a peer that saw the
        # close finds the event in the table.
        try:
            try:
                async with asyncio.timeout(self.timing.handshake_s):
                    machine = await self._handshake(session, slot)
            finally:
                self.slots.release(slot)
        except Refused as r:
            with contextlib.suppress(LinkClosed):
                session.send(Reject(r.code, clip_text(r.text) if r.told else ""))
            if self._log_refused(r.who):  # the log must not grow with a flood either
                log.info("refused %s (%s): %s (logged once a minute per peer; the events "
                         "count them all)", session.address, r.reason, r.text)
            await self._refused(r.who, r.text, r.reason)
            session.abort(None, r.text)
            return
        except TimeoutError:
            hello_s = min(self.timing.hello_s, self.timing.handshake_s)
            text = (f"no Hello within {hello_s:g} s of connecting"
                    if session.hello is None else
                    f"no Welcome within {self.timing.handshake_s:g} s of connecting")
            await self._refused(session.ip, text, "timeout")
            session.abort(ErrorCode.TIMEOUT, "handshake timeout")
            return
        except RemoteProtocolError as exc:
            await self._refused(session.ip, f"protocol error before Welcome: {exc}", "protocol")
            session.abort(ErrorCode.PROTOCOL_ERROR, "protocol error")
            return
        except (LinkClosed, ConnectionError, OSError) as exc:
            log.debug("%s: closed during the handshake: %s", session.address, exc)
            return
        await self._run(session, machine)

    async def _refused(self, who: str, detail: str, reason: str) -> None:
        self.center.metrics.refusals.labels(reason=reason).inc()
        await self.refusal_log.refused(who, detail, reason)

    async def _store_refusals(self, rows: list[tuple[str, str, str]]) -> None:
        """Refusal rows (RefusalLog decides which, and batches them), told to the feed."""
        try:
            await self.center.db.run(event_repo.add_events, EventKind.REFUSED.value,
                                     [(who, detail) for who, detail, _ in rows])
            self.center.metrics.events.labels(kind=EventKind.REFUSED.value).inc(len(rows))
        except SQLAlchemyError:
            log.exception("could not store %d refusals", len(rows))
        for who, detail, _ in rows:
            self.feed.publish(Notice(EventKind.REFUSED, who, detail))

    def _secrets_changed(self, machine_ids: set[int]) -> None:
        """A session authenticated with a secret that is no longer the machine's ends."""
        for machine_id in machine_ids:
            session = self._session_of.get(machine_id)
            # a session that logged in with the new secret (after a change another node
            # made, reported here at the next refresh) is left alone
            if session is not None and session.secret_digest != self.addresses.digest(
                    machine_id):
                log.info("%s: secret changed, closing its session", session.name)
                session.abort(ErrorCode.AUTH_FAILED, "the machine's secret was changed")

    async def _handshake(self, session: MachineSession, slot: int) -> MachineRow:
        async with asyncio.timeout(self.timing.hello_s):
            hello = await session.receive()
        self.slots.waiting(slot, False)
        match hello:
            case Hello():
                session.hello = hello
            case Error(code=code, text=text):
                raise LinkClosed(f"machine error {code.name}: {text}")
            case _:  # the codec lets only Hello or Error through first
                raise LinkClosed(f"unexpected {type(hello).__name__}")
        peer = session.ip
        by_ip, by_name = f"ip:{peer}", f"name:{hello.name}"
        if self.throttle.blocked(by_ip, by_name) is not None:
            # refused before any work, whatever the answer would have been
            self.center.metrics.logins_throttled.inc()
            raise Refused(ErrorCode.AUTH_FAILED, f"login as {hello.name!r} throttled after "
                          "failed attempts", "throttled", peer)
        row = await self.center.db.run(machine_repo.get_machine, hello.name)
        if row is None:
            self.throttle.failed(by_ip)  # guessing names counts against the address
            raise Refused(ErrorCode.UNKNOWN_MACHINE,
                          f"no machine named {hello.name!r} is registered", "unknown", peer)
        if peer != row.ip:
            self.throttle.failed(by_ip)
            raise Refused(ErrorCode.ADDRESS_MISMATCH,
                          f"machine {hello.name!r} is registered at {row.ip}, this connection "
                          f"comes from {peer}", "address", peer)
        if hello.ip != row.ip:
            self.throttle.failed(by_ip)
            raise Refused(ErrorCode.ADDRESS_MISMATCH,
                          f"Hello says ip {hello.ip}, machine {hello.name!r} is registered at "
                          f"{row.ip}", "address", peer)
        if Controller(hello.controller).label != row.controller:
            raise Refused(ErrorCode.UNSUPPORTED,
                          f"Hello says controller {Controller(hello.controller).label}, "
                          f"{hello.name!r} is registered as {row.controller}",
                          "unsupported", row.name)
        link = row.description.get("link")
        kind = link.get("kind", "ednc") if isinstance(link, dict) else "ednc"
        if kind != "ednc":  # the center is the client of this machine's controller
            raise Refused(ErrorCode.UNSUPPORTED,
                          f"{hello.name!r} is registered with a {kind} link: the center "
                          "connects to its controller, it does not log in", "unsupported",
                          row.name)
        encoding = ENCODING_OF.get(row.controller)
        if encoding is None or not hello.map_formats & encoding:
            raise Refused(ErrorCode.UNSUPPORTED,
                          f"{row.controller} maps need encoding "
                          f"{encoding.name if encoding else '?'}, Hello accepts "
                          f"{MapEncoding(hello.map_formats)!r}", "unsupported", row.name)
        nonce = new_nonce()
        session.send(Challenge(nonce))
        self.slots.waiting(slot, True)
        answer = await session.receive()
        self.slots.waiting(slot, False)
        if isinstance(answer, Error):
            raise LinkClosed(f"machine error {answer.code.name}: {answer.text}")
        assert isinstance(answer, AuthResponse)  # the codec allows nothing else here
        try:
            secret = self.center.db.secrets.open(row.secret, row.id)
            good = verify_mac(secret.encode("utf-8"), nonce, row.name, answer.mac)
            session.secret_digest = digest(secret)
        except (ValueError, SecretKeyError) as exc:  # unusable secret, or not our key
            log.error("machine %s: %s", row.name, exc)
            good = False
        if not good:
            self.throttle.failed(by_ip, by_name)
            raise Refused(ErrorCode.AUTH_FAILED, "authentication failed: wrong response to "
                          "the challenge", "auth", row.name)
        self.throttle.succeeded(by_ip, by_name)
        old = self.sessions.get(row.name)
        if old is not None:
            silent = asyncio.get_running_loop().time() - old.last_heard
            if silent < self.timing.heartbeat_s:
                raise Refused(ErrorCode.DUPLICATE_SESSION,
                              f"machine {row.name!r} already has a live session from "
                              f"{old.address}", "duplicate", row.name, told=True)
            old.abort(ErrorCode.DUPLICATE_SESSION,
                      f"replaced by a new session from {session.address}")
        if self.leases is not None:
            refusal = await self.leases.claim(
                row.id, row.name, session,
                lambda why: session.abort(ErrorCode.DUPLICATE_SESSION, why))
            if refusal is not None:
                raise Refused(ErrorCode.DUPLICATE_SESSION, refusal, "owned", row.name, told=True)
        try:
            session.send(Welcome(int(self.timing.heartbeat_s * 1000),
                                 self.timing.telemetry_period_ms))
        except LinkClosed:
            if self.leases is not None:
                self.leases.release(row.id, session)
            raise
        return row

    async def _run(self, session: MachineSession, machine: MachineRow) -> None:
        name = machine.name
        self.sessions[name] = session
        self._session_of[machine.id] = session
        self.center.registry.connected(name, session.address)
        await self.feed.record(EventKind.CONNECTED, name, f"session from {session.address}")
        why = "session ended"
        try:
            async with asyncio.TaskGroup() as tg:
                beats = tg.create_task(self._heartbeats(session), name=f"{name}:heartbeat")
                work = (tg.create_task(self.worker(session, machine), name=f"{name}:push")
                        if self.worker is not None else None)
                try:
                    why = await self._receive_loop(session)
                finally:
                    beats.cancel()
                    if work is not None:
                        work.cancel()
        except* Exception as group:  # a worker's bug ends this session only
            for exc in group.exceptions:
                log.error("%s: session task failed", name, exc_info=exc)
            why = f"internal error: {group.exceptions[0]!r}"
            session.abort(ErrorCode.INTERNAL, "the control center failed internally")
        finally:
            if self.sessions.get(name) is session:
                del self.sessions[name]
                self.center.registry.disconnected(name)
            if self._session_of.get(machine.id) is session:
                del self._session_of[machine.id]
            if self.leases is not None:
                self.leases.release(machine.id, session)
        await self.feed.record(EventKind.DISCONNECTED, name, why)

    async def _receive_loop(self, session: MachineSession) -> str:
        """Dispatch the machine's messages until the session ends; returns why it ended."""
        loop = asyncio.get_running_loop()
        dead_s = self.timing.dead_after_s
        name = session.name
        try:
            async with asyncio.timeout(dead_s) as deadline:
                while True:
                    msg = await session.receive()
                    deadline.reschedule(loop.time() + dead_s)
                    match msg:
                        case Telemetry():
                            self.center.registry.seen(name, telemetry_fields(msg))
                            for s in msg.temperatures:
                                if valid_sensor(s.name):
                                    self.temperatures.update(
                                        name, s.name, s.celsius, source="telemetry",
                                        at=msg.timestamp_ms / 1000.0)
                        case HeartbeatReply():
                            self.center.registry.seen(name)
                        case MapAck() | MapReject():
                            self.center.registry.seen(name)
                            session.resolve(msg)
                        case Released():
                            self.center.registry.seen(name)
                        case Error(code=code, text=text):
                            return f"machine error {code.name}: {text}"
                        case _:  # the codec lets no other message through in READY
                            session.abort(ErrorCode.PROTOCOL_ERROR,
                                          f"unexpected {type(msg).__name__}")
                            return f"unexpected {type(msg).__name__}"
        except TimeoutError:
            text = f"nothing heard for {dead_s:g} s ({DEAD_AFTER_PERIODS} heartbeat periods)"
            session.abort(ErrorCode.TIMEOUT, text)
            return text
        except RemoteProtocolError as exc:
            await self.feed.record(EventKind.REFUSED, name, f"protocol error: {exc}",
                                   reason="protocol")
            session.abort(ErrorCode.PROTOCOL_ERROR, str(exc))
            return f"protocol error: {exc}"
        except LinkClosed as exc:
            return str(exc)
        except (ConnectionError, OSError) as exc:
            return f"connection lost: {exc}"

    async def _heartbeats(self, session: MachineSession) -> None:
        token = 0
        while True:
            await asyncio.sleep(self.timing.heartbeat_s)
            try:
                session.send(Heartbeat(token))
            except LinkClosed:
                return
            token = (token + 1) & 0xFFFFFFFF
