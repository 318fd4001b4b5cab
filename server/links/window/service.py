"""The center as client of the machines whose controllers it reaches through their own
servers (registrations with a ``modbus`` or ``opcua`` link, :mod:`server.schemas.link`).

:class:`ControllerLinks` is an async context manager started with the machine services.
It looks at the registered machines every ``reconcile_s`` and keeps one task per machine
with a controller link: connect (with jittered, capped exponential backoff after a
failure), check the PLC program's identity, then serve the session exactly as an EDNC
session is served: it sits in the machine server's session table (so the temperature
forwarder reaches it and an EDNC login for that machine is refused as a duplicate), the
registry shows it connected with its telemetry, and the push scheduler's worker keeps its
map current. With leases (several center processes on one PostgreSQL) a node serves only
the machines whose lease it holds.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import random
from collections.abc import Callable, Coroutine, MutableMapping
from types import TracebackType
from typing import Any

from pydantic import TypeAdapter, ValidationError
from sqlalchemy import func, select
from sqlalchemy.exc import SQLAlchemyError
from sqlalchemy.orm import Session

from protocol import Controller
from protocol.backoff import Backoff
from protocol.limits import TELEMETRY_PERIOD_MS
from server.background import Background
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db.tables import AppliedRow, MachineRow
from server.events import EventKind
from server.feed import Feed
from server.leasing import LeaseKeeper
from server.links import memory_for
from server.links.pacing import BACKOFF, Pacer
from server.links.secret import read_secret
from server.links.state import LinkCondition, Throttle
from server.links.window.memory import LinkError, MemoryClient
from server.schemas.link import LinkSpec, ModbusLink, OpcuaLink
from volumetric.model.machine import parse_machine

from .session import ControllerSession, LinkAck, StatusPace, reason_of

__all__ = ["ControllerLinks", "link_of", "memory_for", "read_secret", "settle_missed",
           "window_of"]

log = logging.getLogger(__name__)

_SPEC: TypeAdapter[LinkSpec] = TypeAdapter(LinkSpec)

STOP_TRIES = 10
"""Cancels of a machine's task at the exit, one a second, before it is left behind."""

Worker = Callable[[Any, MachineRow], Coroutine[Any, Any, None]]


def link_of(description: dict[str, Any]) -> LinkSpec | None:
    """The link of a stored description (None: none given, or not readable)."""
    raw = description.get("link")
    if raw is None:
        return None
    try:
        return _SPEC.validate_python(raw)
    except ValidationError:
        return None


class ControllerLinks:
    """Sessions with the machines registered with a controller link (module docstring).

    Parameters
    ----------
    center
        The service's center (database, registry, metrics).
    feed : Feed
    sessions : mutable mapping of name to session
        The machine server's session table, shared.
    worker : callable
        ``PushScheduler.serve``: keeps one session's map current until cancelled.
    leases : LeaseKeeper, optional
    reconcile_s : float
        How often the registrations are read again, s.
    backoff : Backoff
    telemetry_s : float
        The center's telemetry period (what EDNC machines are told in Welcome), s: a
        controller's status becomes telemetry at most this often (at once when the map
        or the machine's state changes).
    """

    def __init__(self, center: Any, feed: Feed, sessions: MutableMapping[str, Any],
                 worker: Worker | None, *, leases: LeaseKeeper | None = None,
                 reconcile_s: float = 2.0, backoff: Backoff | None = None,
                 telemetry_s: float = TELEMETRY_PERIOD_MS / 1000) -> None:
        self.center = center
        self.feed = feed
        self.sessions = sessions
        self.worker = worker
        self.leases = leases
        self.reconcile_s = reconcile_s
        self.backoff = backoff or BACKOFF
        self.telemetry_s = telemetry_s
        self.status_pace = StatusPace()
        """Idle status reads spread over this center's sessions (at most 200 a second)."""
        self.pacers: dict[str, Pacer] = {}
        """Retry schedules by machine, kept while its registration stays the same (a
        changed one starts afresh: the operator may have corrected it)."""
        self._bg = Background(grace_s=5.0)
        self._tasks: dict[str, tuple[Any, asyncio.Task[None]]] = {}
        self._rng = random.Random()
        self._reports: set[asyncio.Task[None]] = set()
        self.throttle = Throttle()
        """Events and warnings of link failures: the first of each reason, then at most
        one a minute per reason and machine."""
        self._mark: tuple[Any, ...] | None = None
        """The registrations as :meth:`reconcile` last read them whole."""
        self.registration_reads = 0
        """Times :meth:`reconcile` read every registration (not every look: only when
        they changed)."""
        self.connects = 0
        self.failures = 0
        self.missed_settled = 0
        """Deliveries answered from a controller's status after a center restart."""

    async def __aenter__(self) -> ControllerLinks:
        self._bg.start(self._reconcile_loop(), "controller-links")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        # the reconcile loop first: left running, it sees the cancelled machines without a
        # task and starts a new session for each (a fleet's shutdown reconnected all of
        # them over and over, each new session replacing one still closing)
        await self._bg.stop()
        tasks = {t for _, t in self._tasks.values()} | self._reports
        for name in self._tasks:  # a session ends by itself too, even if a cancel is lost
            session = self.sessions.get(name)
            if isinstance(session, ControllerSession):
                session.abort(None, "the center stops")
        self._tasks.clear()
        # cancelled again until done: Python 3.11's wait_for (pymodbus awaits every
        # answer with it) swallows a cancel that arrives with the answer, and the session
        # then goes on; one in a few hundred did at 1,000 PMCs, and the exit hung on it
        for _ in range(STOP_TRIES):
            if not tasks:
                break
            for t in tasks:
                t.cancel()
            _, tasks = await asyncio.wait(tasks, timeout=1.0)
        for t in tasks:
            log.error("%s did not stop", t.get_name())

    def linked(self) -> list[str]:
        """Names of the machines served through a controller link now (connected or
        trying)."""
        return sorted(self._tasks)

    async def _reconcile_loop(self) -> None:
        while True:
            try:
                await self.reconcile()
            except SQLAlchemyError as exc:
                log.warning("controller links: registrations not read: %s",
                            str(exc).splitlines()[0])
            await asyncio.sleep(self.reconcile_s)

    async def reconcile(self) -> None:
        """Start a task for each machine with a controller link, stop those whose link
        went away or changed.

        The registrations are read whole only when they changed (their count, newest
        change or highest id) or a machine's task ended: reading and parsing 1,000
        descriptions every ``reconcile_s`` cost the center about 20 ms of CPU a second
        with nothing to do."""
        mark = await self.center.db.run(_registrations_mark)
        if mark == self._mark and not any(t.done() for _k, t in self._tasks.values()):
            return
        rows: list[MachineRow] = await self.center.db.run(_machines)
        self._mark = mark
        self.registration_reads += 1
        want: dict[str, tuple[Any, MachineRow]] = {}
        windows: dict[tuple[Any, ...], str] = {}
        for row in rows:  # by name: of two machines on one window the first is served
            spec = link_of(row.description)
            if not isinstance(spec, ModbusLink | OpcuaLink):
                continue
            window = window_of(spec, row.ip)
            first = windows.setdefault(window, row.name)
            if first != row.name:
                # two registrations writing one controller's window would overwrite each
                # other's maps: the second is refused until one of them changes
                await self._report(row.name, spec.kind, LinkCondition(
                    "refused", "duplicate_link", f"the same controller window as {first} "
                    "(give each its own host, port, unit id or window)"))
                continue
            key = (spec.model_dump_json(), row.ip, row.updated_at)
            want[row.name] = (key, row)
        for name in list(self._tasks):
            key, task = self._tasks[name]
            if name not in want or want[name][0] != key or task.done():
                del self._tasks[name]
                task.cancel()
                with contextlib.suppress(asyncio.CancelledError, Exception):
                    await task
                if name not in want or want[name][0] != key:
                    # the registration changed (a byte order corrected...): try it now
                    self.pacers.pop(name, None)
                    self.throttle.forget(name)
        for name, (key, row) in want.items():
            if name not in self._tasks:
                task = asyncio.create_task(self._serve(row), name=f"{name}:controller-link")
                self._tasks[name] = (key, task)

    async def _serve(self, row: MachineRow) -> None:
        spec = link_of(row.description)
        assert isinstance(spec, ModbusLink | OpcuaLink)
        machine = parse_machine(row.description)
        controller = Controller.FANUC if row.controller == "fanuc" else Controller.SIEMENS
        pacer = self.pacers.setdefault(row.name, Pacer(self.backoff, rng=self._rng))
        loop = asyncio.get_running_loop()
        self.center.registry.condition(row.name, "connecting", "", f"{spec.kind} link")
        while True:
            await asyncio.sleep(pacer.delay(loop.time()))
            pacer.attempt(loop.time())
            try:
                memory = memory_for(spec, row.ip)
            except LinkError as exc:  # e.g. a password reference not set
                pacer.failed()
                await self._report(row.name, spec.kind, exc.condition)
                continue
            session = ControllerSession(
                row.name, row.ip, controller, machine.axis_names, memory,
                link=spec.kind, chain=machine.chain, poll_s=spec.poll_ms / 1000.0,
                telemetry_s=self.telemetry_s, pace=self.status_pace,
                on_telemetry=self._telemetry_of(row.name),
                on_condition=self._condition_of(row.name, spec.kind))
            ended = await self._session(row, session)
            for at in session.push_times:
                pacer.pushed(at)
            if session.healthy:  # proved: the next failure starts the backoff afresh
                pacer.healthy()
                self.throttle.forget(row.name)
            if ended.state not in ("connecting", "offline"):
                pacer.failed()
            await self._report(row.name, spec.kind, ended)

    def _condition_of(self, name: str, link: str) -> Callable[[LinkCondition], None]:
        """What a session says of its link while it is open (the PLC stopped, running
        again): shown and reported like a failure, the session going on."""
        def changed(condition: LinkCondition) -> None:
            if self.sessions.get(name) is None:
                return  # not (or no longer) serving: the session's end says why
            if condition.state == "connected" and not condition.reason:
                self.center.registry.condition(name, "connected")
                return
            task = asyncio.create_task(self._report(name, link, condition),
                                       name=f"{name}:link-report")
            self._reports.add(task)
            task.add_done_callback(self._reports.discard)
        return changed

    async def _report(self, name: str, link: str, ended: LinkCondition) -> None:
        """Show why a link is down: the registry (API status, dashboard, metric) at once;
        an event and a warning for the first of each reason, then at most once a minute
        per reason (:class:`~server.links.state.Throttle`)."""
        self.center.registry.condition(name, ended.state, ended.reason, ended.text)
        if ended.state in ("connecting", "offline") or not ended.reason:
            return
        self.failures += 1
        if not self.throttle.allow(name, ended.reason or ended.state,
                                   asyncio.get_running_loop().time()):
            return
        log.warning("%s: %s link %s", name, link, ended.summary)
        await self.feed.record(EventKind.LINK, name, f"{link} link {ended.summary}")

    def _telemetry_of(self, name: str) -> Callable[[dict[str, Any]], None]:
        def seen(telemetry: dict[str, Any]) -> None:
            self.center.registry.seen(name, telemetry)
        return seen

    async def _warnings(self, name: str, memory: MemoryClient) -> None:
        """A memory's warnings for the operator (OPC UA security None, a certificate
        trusted on first use: server/links/opcua.py) as events, each once."""
        take = getattr(memory, "take_notices", None)
        for text in take() if take is not None else ():
            await self.feed.record(EventKind.WARNING, name, text)

    async def _session(self, row: MachineRow, session: ControllerSession) -> LinkCondition:
        """Open and serve one session; returns why it ended."""
        name = row.name
        try:
            await session.open()
        except LinkError as exc:
            await session.memory.close()
            await self._warnings(name, session.memory)
            return exc.condition
        except asyncio.CancelledError:
            await session.memory.close()
            raise
        await self._warnings(name, session.memory)
        if self.leases is not None:
            refusal = await self.leases.claim(row.id, name, session,
                                              lambda why: session.abort(None, why))
            if refusal is not None:
                await session.memory.close()
                return LinkCondition("offline", "", refusal)  # another node serves it
        old = self.sessions.get(name)
        if old is not None:
            old.abort(None, f"replaced by the {session.link} link to {session.address}")
        self.sessions[name] = session
        self.connects += 1
        self.center.registry.connected(name, session.address)
        await self.feed.record(EventKind.CONNECTED, name,
                               f"{session.link} link to {session.address}")
        missed = session.missed
        if missed is not None:  # a verdict written while no center read it: not lost
            try:
                settled = await self.center.db.run(settle_missed, row.id, name, missed)
            except SQLAlchemyError as exc:
                log.warning("%s: the controller's last verdict not stored: %s", name,
                            str(exc).splitlines()[0])
            else:
                if settled:
                    self.missed_settled += 1
        why = "session ended"
        try:
            async with asyncio.TaskGroup() as tg:
                work: asyncio.Task[None] | None = None
                if self.worker is not None:
                    work = tg.create_task(self.worker(session, row), name=f"{name}:push")
                try:
                    why = await session.run()
                finally:
                    if work is not None:
                        work.cancel()
        except* Exception as group:  # a worker's bug ends this session only
            for failure in group.exceptions:
                log.error("%s: controller link task failed", name, exc_info=failure)
            why = f"internal error: {group.exceptions[0]!r}"
            session.failure = session.failure or LinkCondition("failed", "internal", why)
            session.abort(None, why)
        finally:
            if self.sessions.get(name) is session:
                del self.sessions[name]
                self.center.registry.disconnected(name)
                failure = session.failure
                if failure is not None:  # shown at once, not after the event is stored
                    self.center.registry.condition(name, failure.state, failure.reason,
                                                   failure.text)
            if self.leases is not None:
                self.leases.release(row.id, session)
        await self.feed.record(EventKind.DISCONNECTED, name, why)
        if session.failure is not None:
            return session.failure
        return LinkCondition("connecting", "", why)  # ended on purpose: try again


def window_of(spec: ModbusLink | OpcuaLink, ip: str) -> tuple[Any, ...]:
    """Which controller window a link writes: several controllers behind one address (a
    Modbus gateway) are told apart by unit id, several windows of one controller by their
    start register or data block."""
    if isinstance(spec, ModbusLink):
        return ("modbus", spec.host or ip, spec.port, spec.unit_id, spec.start_register)
    return ("opcua", spec.endpoint, spec.window_node)


def settle_missed(session: Session, machine_id: int, name: str, ack: LinkAck) -> bool:
    """Store the verdict a controller wrote while no center read it (the center died
    between the switch and the ack) on the newest unanswered delivery of that version."""
    row = session.scalars(
        select(AppliedRow).where(AppliedRow.machine_id == machine_id,
                                 AppliedRow.map_version == ack.version)
        .order_by(AppliedRow.id.desc()).limit(1)).first()
    # unanswered (the center was killed), or failed because the center stopped before
    # the answer came: the controller's status has the answer
    if row is None or map_repo.delivery_state(row) not in ("pending", "failed",
                                                           "superseded"):
        return False
    if ack.applied:
        kind, reason = EventKind.APPLIED, None
        text = f"map version {ack.version} applied (read from the controller's status)"
    else:
        label, why = reason_of(ack.code)
        kind, reason = EventKind.REJECTED, f"{label.name}: {why}"
        text = f"map version {ack.version} rejected: {reason} (read from the controller)"
    map_repo.record_answer(session, row.id, acked=ack.applied, reject_reason=reason)
    event_repo.add_event(session, kind=kind.value, machine=name, detail=text)
    return True


def _registrations_mark(session: Session) -> tuple[Any, ...]:
    """What changes when a machine is registered, changed or deleted: the count, the
    newest ``updated_at`` and the highest id (a deletion and a registration between two
    looks change the last two)."""
    return tuple(session.execute(select(func.count(), func.max(MachineRow.updated_at),
                                        func.max(MachineRow.id))).one())


def _machines(session: Session) -> list[MachineRow]:
    rows = machine_repo.list_machines(session)
    for row in rows:  # loaded now: the rows leave their session
        _ = (row.description, row.updated_at)
    return rows
