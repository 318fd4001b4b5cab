"""The push scheduler: every connected machine gets its current error map.

One worker per session (started by the machine server after Welcome, see
:meth:`PushScheduler.serve`) keeps that machine's map current. It wakes:

* at once, when the session starts: the machine is sent its current map, so a machine
  that reconnects has it again whatever happened meanwhile;
* when the machine's model changes (a new upload, fit or diagnosis is committed: the
  scheduler watches committed ``models`` rows and updated ``machines`` rows through
  SQLAlchemy session events, so every path that stores a model is covered);
* when a temperature that its thermal model uses moves by more than ``threshold_K`` from
  the temperature its current map was built at (MQTT or Telemetry) -- only for a map that
  does not carry the thermal terms (a version-1 ``grid``): a ``tables`` map, and a grid
  with thermal records for a machine that declared ``MapEncoding.THERMAL``, carry them and
  the machine applies its latest temperatures itself, so a temperature change needs no
  new map (:func:`server.mapcodec.carries_thermal`);
* every ``period_s`` otherwise (catching whatever no event announced).

Then it rebuilds the map if its inputs changed (model version, machine description, and
temperatures for grids), picking the kind the machine evaluates (its Hello's map formats;
:func:`server.mapcodec.build_for`: the smallest that meets the tolerance), stores the new
version in ``map_versions`` with the temperatures used, and sends it; at a periodic wake
it re-sends the current map when the machine does not have it applied (its last answer or
its Telemetry say otherwise), except a version the machine rejected. A burst of wakes
while a build runs gives one more build, not one per wake.

Builds (:func:`server.mapcodec.build_for`) run on a thread pool of their own, so they
neither stall the event loop nor take the threads the database calls use.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
from collections.abc import Callable, Iterator, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any, Final

from sqlalchemy.exc import SQLAlchemyError

from protocol import ErrorCode, MapEncoding
from protocol.limits import MAP_VERDICT_TIMEOUT_MS
from server import mapcodec
from server.center import Center
from server.db.batch import GroupCommit
from server.db.tables import MachineRow, MapVersionRow, ModelRow
from server.events import EventKind
from server.feed import Feed, Notice
from server.links.base import Link, LinkClosed
from server.mapcodec import carries_thermal
from server.push import steps
from server.push.adapter import build_for, thermal_sensors
from server.push.watcher import CommitWatcher
from server.temperatures import TemperatureBoard

log = logging.getLogger(__name__)

THRESHOLD_K: Final = 0.05
"""A temperature change that triggers a new map: 0.05 K moves a 500 mm steel axis
(11.5 µm/(m·K)) by 0.3 µm, about the map's own interpolation tolerance."""

VERDICT_TIMEOUT_S: Final = MAP_VERDICT_TIMEOUT_MS / 1000
"""MapAck or MapReject within 30 s of sending (protocol README §9)."""

PREPARING: Final = 8
"""Refreshes in their database steps at once (load, build, store, note the delivery).
The steps share one FIFO of database threads: 1,000 machines woken together would each
take their first step before any took its second, so no map left before every machine's
steps but the last were done, and a controller link's wait for its PLC (a cycle and a
status poll, 1-2 s) came after all of them instead of beside them. Bounded, machines go
through their steps a few at a time and the first maps leave at once."""

KEPT_PAYLOAD_BYTES: Final = 256 * 1024
"""Largest map whose bytes a session keeps between pushes (:meth:`PushScheduler._stored`):
a thousand sessions keep at most 256 MB; a larger map is read again for each push."""

# -- the scheduler

@dataclass
class _Target:
    """What the scheduler knows about one connected machine."""

    name: str
    machine_id: int
    session: Link
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    why: list[str] = field(default_factory=list)
    sensors: frozenset[str] = frozenset()
    built_temps: dict[str, float] = field(default_factory=dict)
    acked: int | None = None
    rejected: int | None = None
    failed: tuple[Any, ...] | None = None
    waiting_for: frozenset[str] = frozenset()
    resend: bool = False
    thermal_in_map: bool | None = None
    """Whether the current map carries the thermal terms (None: not known yet)."""
    model: tuple[int, dict[str, Any]] | None = None
    """The current model row's id and body (a row never changes: its body is read once,
    :func:`~server.push.steps.load_inputs`); ``sensors`` are its thermal columns."""
    payload: tuple[tuple[int, int, str], bytes] | None = None
    """The last map's bytes read or built in this session, keyed by its row's id, version
    and SHA-256 (:meth:`PushScheduler._stored`)."""

    @property
    def formats(self) -> MapEncoding | None:
        hello = self.session.hello
        return None if hello is None else hello.map_formats

    def poke(self, why: str, *, resend: bool = False) -> None:
        self.why.append(why)
        self.resend = self.resend or resend
        self.wake.set()


@dataclass(frozen=True, slots=True)
class Delivery:
    """One push and its outcome, for observers (benchmarks, the MQTT status)."""

    machine: str
    version: int
    outcome: str
    """``applied``, ``rejected`` or ``failed``."""
    latency_s: float | None
    why: str


class _Slot:
    """One refresh's place among the :data:`PREPARING`; given back once (at the push, or
    when the refresh ends without one)."""

    def __init__(self, semaphore: asyncio.Semaphore) -> None:
        self._semaphore = semaphore
        self._held = False

    async def acquire(self) -> None:
        await self._semaphore.acquire()
        self._held = True

    def release(self) -> None:
        if self._held:
            self._held = False
            self._semaphore.release()


class PushScheduler:
    """Keeps every connected machine's map current; an async context manager.

    Parameters
    ----------
    center, feed, temperatures
        The service's collaborators.
    period_s : float, optional
        Periodic wake; ``center.settings.push_period_s`` by default.
    threshold_K : float
    tolerance_um : float
        Interpolation tolerance of the maps built (build_map's), µm.
    verdict_timeout_s : float
    build_workers : int, optional
        Threads for map builds (CPU count by default).
    """

    def __init__(self, center: Center, feed: Feed, temperatures: TemperatureBoard, *,
                 period_s: float | None = None, threshold_K: float = THRESHOLD_K,
                 tolerance_um: float = 0.5, verdict_timeout_s: float = VERDICT_TIMEOUT_S,
                 build_workers: int | None = None) -> None:
        self.center = center
        self.db = center.db
        self.feed = feed
        self.temperatures = temperatures
        self.period_s = period_s if period_s is not None else center.settings.push_period_s
        self.threshold_K = threshold_K
        self.tolerance_um = tolerance_um
        self.verdict_timeout_s = verdict_timeout_s
        self.build_workers = build_workers or os.cpu_count() or 2
        self.observers: list[Callable[[Delivery], None]] = []
        self.commit_listeners: list[Callable[[set[int]], None]] = []
        """Told the machine ids of every committed model or machine change (the native
        SINUMERIK links follow models this way: one CommitWatcher per process sees them)."""
        self._targets: dict[str, _Target] = {}
        self._by_id: dict[int, _Target] = {}
        self._preparing = asyncio.Semaphore(PREPARING)
        self._pool: ThreadPoolExecutor | None = None
        self._stack = contextlib.ExitStack()
        self.writes = GroupCommit(self.db)
        """The deliveries and answers written (:mod:`server.db.batch`): a thousand pushes
        at once share their commits instead of waiting for one fsync each."""

    async def __aenter__(self) -> PushScheduler:
        self._pool = ThreadPoolExecutor(self.build_workers, thread_name_prefix="mapbuild")
        await self.writes.__aenter__()
        self._stack.enter_context(
            CommitWatcher(self.db, asyncio.get_running_loop(), self._on_commit))
        self._stack.callback(self.temperatures.subscribe(self._on_temperature))
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        self._stack.close()
        await self.writes.__aexit__(exc_type, exc, tb)
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)

    # -- triggers
    def request(self, name: str, why: str = "requested", *, resend: bool = False) -> bool:
        """Wake ``name``'s worker now (rebuilding if its inputs changed); ``resend`` sends
        the current map even if the machine has it. False when it is not connected."""
        target = self._targets.get(name)
        if target is not None:
            target.poke(why, resend=resend)
        return target is not None

    def _on_commit(self, machine_ids: set[int]) -> None:
        for listener in list(self.commit_listeners):
            listener(machine_ids)
        for machine_id in machine_ids:
            target = self._by_id.get(machine_id)
            if target is not None:
                target.poke("model or machine changed")

    def _on_temperature(self, machine: str, column: str, celsius: float) -> None:
        target = self._targets.get(machine)
        if target is None or column not in target.sensors or target.thermal_in_map:
            return  # a map that carries its thermal terms needs no rebuild
        built = target.built_temps.get(column)
        if built is None or abs(celsius - built) > self.threshold_K:
            target.poke(f"{column} now {celsius:.2f} °C")

    # -- the worker
    async def serve(self, session: Link, machine: MachineRow) -> None:
        """Keep ``machine`` served over ``session`` until cancelled (one per session)."""
        target = _Target(machine.name, machine.id, session)
        self._targets[machine.name] = target
        self._by_id[machine.id] = target
        try:
            first, periodic = True, False
            while True:
                why = ", ".join(dict.fromkeys(target.why)) or ("period" if periodic else "")
                target.why.clear()
                resend, target.resend = target.resend, False
                slot = _Slot(self._preparing)
                try:
                    await slot.acquire()
                    await self._refresh(target, slot, send_anyway=first or resend,
                                        periodic=periodic, why=why or "session start",
                                        first=first and not resend)
                except SQLAlchemyError as exc:  # e.g. a busy database: try again later
                    log.warning("%s: push skipped, database error: %s", target.name,
                                str(exc).splitlines()[0])
                    target.resend = target.resend or first or resend
                finally:
                    slot.release()
                first = False
                try:
                    async with asyncio.timeout(self.period_s):
                        await target.wake.wait()
                    periodic = False
                except TimeoutError:
                    periodic = True
                target.wake.clear()
        finally:
            if self._targets.get(machine.name) is target:
                del self._targets[machine.name]
            if self._by_id.get(machine.id) is target:
                del self._by_id[machine.id]

    async def _refresh(self, target: _Target, slot: _Slot, *, send_anyway: bool,
                       periodic: bool, why: str, first: bool = False) -> None:
        inputs = await self.db.run(steps.load_inputs, target.machine_id, target.model)
        machine, model, current = inputs.machine, inputs.model, inputs.map
        if machine is None:
            target.session.abort(ErrorCode.SHUTDOWN, "the machine is no longer registered")
            return
        if model is None:
            if send_anyway:
                log.info("%s: no model yet, no map to push", target.name)
            return
        if target.model is None or target.model[0] != model.id:
            target.model = (model.id, model.body)
            target.sensors = thermal_sensors(model.body)
        temps = self.temperatures.columns(target.name, sorted(target.sensors))
        if current is not None and target.thermal_in_map is None:
            stored = await self._stored(target, current)
            target.thermal_in_map = carries_thermal(stored) if stored else None
        rebuild = self._rebuild_reason(machine, model, current,
                                       {} if target.thermal_in_map else temps)
        payload: bytes | None = None
        applied_id: int | None = None
        if rebuild:
            # a kind that carries the thermal terms is built without today's temperatures
            carries = bool(target.formats is None
                           or target.formats & (MapEncoding.TABLES | MapEncoding.THERMAL))
            missing = set() if carries else target.sensors - temps.keys()
            if missing:
                if missing != target.waiting_for:
                    target.waiting_for = frozenset(missing)
                    log.warning("%s: cannot build a map (%s) without temperatures of %s",
                                target.name, rebuild, sorted(missing))
            else:
                target.waiting_for = frozenset()
                built = await self._build(target, machine, model, temps, f"{why}: {rebuild}")
                if built is not None:
                    (current, applied_id), payload = built, built[0].payload
                    if len(payload) <= KEPT_PAYLOAD_BYTES:
                        target.payload = ((current.id, current.version, current.sha256),
                                          payload)
        if current is None:
            return
        target.built_temps = {k: float(v) for k, v in current.temperatures.items()
                              if isinstance(v, int | float)}
        fresh = payload is not None
        if first and not fresh and target.session.reported_version == current.version:
            # the controller reports this map applied (protocol/README.md §13.2 step 0):
            # sending it again at every session start would only load the PLC
            target.acked = current.version
            send_anyway = False
            stored = await self._stored(target, current)
            if stored is not None:  # its temperature slots follow that map all the same
                target.session.adopt(current.version, stored)
        # what the machine has: its own Telemetry when it sent one, else its last answer
        reported = self.center.registry.get(target.name).telemetry.get("map_version")
        on_machine = reported if isinstance(reported, int) else target.acked
        lacking = target.acked != current.version or on_machine != current.version
        resend = periodic and lacking and target.rejected != current.version
        if not (send_anyway or fresh or resend):
            return
        if payload is None:
            payload = await self._stored(target, current)
            if payload is None:
                return
        await self._deliver(target, slot, current, payload,
                            f"{why}: {rebuild}" if fresh else f"{why}: re-send", applied_id)

    async def _stored(self, target: _Target, current: MapVersionRow) -> bytes | None:
        """The bytes of the machine's map ``current``: read once per session and map
        version, then kept (a re-push to a thousand machines read each one's map again,
        one transaction per push). The key has the row's id and SHA-256, so bytes kept
        are only ever sent for the row they were read from."""
        key = (current.id, current.version, current.sha256)
        if target.payload is not None and target.payload[0] == key:
            return target.payload[1]
        stored = await self.db.run(steps.stored_payload, target.machine_id, current.version)
        if stored is not None and len(stored) <= KEPT_PAYLOAD_BYTES:
            target.payload = (key, stored)
        return stored

    def _rebuild_reason(self, machine: MachineRow, model: ModelRow,
                        current: MapVersionRow | None, temps: Mapping[str, float]) -> str:
        if current is None:
            return "first map"
        if current.model_version != model.version:
            return f"model version {model.version}"
        if machine.updated_at > current.created_at:
            return "machine description changed"
        for column, celsius in temps.items():
            was = current.temperatures.get(column)
            if not isinstance(was, int | float) or abs(celsius - was) > self.threshold_K:
                return f"{column} moved to {celsius:.2f} °C"
        return ""

    async def _build(self, target: _Target, machine: MachineRow, model: ModelRow,
                     temps: dict[str, float], why: str) -> tuple[MapVersionRow, int] | None:
        signature = (model.version, machine.updated_at, tuple(sorted(temps.items())))
        if signature == target.failed:
            return None  # the same inputs failed already: wait for new ones
        assert self._pool is not None, "PushScheduler used outside its context"
        loop = asyncio.get_running_loop()
        try:
            built = await loop.run_in_executor(
                self._pool, build_for, machine.description, machine.controller, model.body,
                temps, self.tolerance_um, target.formats)
            row, applied_id = await self.db.run(steps.store_and_send, target.machine_id,
                                                target.name, built, model.version, temps, why)
        except (ValueError, ArithmeticError) as exc:
            target.failed = signature
            await self.feed.record(EventKind.ERROR, target.name,
                                   f"map build failed ({why}): {exc}")
            return None
        target.failed = None
        target.thermal_in_map = carries_thermal(built)
        log.info("%s: built %s map version %d%s (%s)", target.name, mapcodec.kind_of(built),
                 row.version, " with thermal terms" if target.thermal_in_map else "", why)
        return row, applied_id

    async def _deliver(self, target: _Target, slot: _Slot, current: MapVersionRow,
                       payload: bytes, why: str, applied_id: int | None = None) -> None:
        """Send map ``current`` and record the answer; ``applied_id``: its delivery row,
        if the build already wrote it. ``slot`` is given back once the delivery is noted:
        the wait for the machine's answer takes no place among the refreshes preparing."""
        name, version = target.name, current.version
        detail = steps.detail_of(version, len(payload), why)
        if applied_id is None:
            applied_id = await self.writes.run(steps.record_sent, target.machine_id, name,
                                               version, current.id, detail)
        self.center.metrics.events.labels(kind=EventKind.PUSHED.value).inc()
        self.feed.publish(Notice(EventKind.PUSHED, name, detail, version))
        slot.release()
        try:
            verdict = await target.session.push_map(version, payload, self.verdict_timeout_s)
        except TimeoutError:
            failure = f"no answer to map version {version} within {self.verdict_timeout_s:g} s"
            await self._failed(target, applied_id, version, failure, why)
            target.session.abort(ErrorCode.TIMEOUT, failure)
            return
        except LinkClosed as exc:
            await self._failed(target, applied_id, version,
                               f"session ended before the answer to map version {version}: "
                               f"{exc}", why)
            return
        except asyncio.CancelledError:  # the session ended under us: still say so
            await asyncio.shield(self._failed(
                target, applied_id, version,
                f"session ended before the answer to map version {version}", why))
            raise
        if verdict.applied:
            target.acked, kind = version, EventKind.APPLIED
            reason, text = None, f"map version {version} applied"
            if self.center.intake is not None:
                # a map that carries thermal terms evaluates them with the machine's
                # latest temperatures: send what the center holds at once
                self.center.intake.forward(target.name)
        else:
            target.rejected, kind = version, EventKind.REJECTED
            label = verdict.reason.name if verdict.reason is not None else "?"
            reason = f"{label}: {verdict.text}" if verdict.text else label
            text = f"map version {version} rejected: {reason}"
        outcome = "applied" if verdict.applied else "rejected"
        self.center.metrics.pushes.labels(outcome=outcome).inc()
        self.center.metrics.push_latency.observe(verdict.latency_s)
        self.center.metrics.events.labels(kind=kind.value).inc()
        await self._record_answer(applied_id, name, kind, acked=verdict.applied,
                                  reason=reason, detail=text)
        self._tell(Notice(kind, name, text, version),
                   Delivery(name, version, outcome, verdict.latency_s, why))

    async def _failed(self, target: _Target, applied_id: int, version: int, failure: str,
                      why: str) -> None:
        """A delivery without an answer: the transport failed, not the map (the delivery
        is ``failed``, not ``rejected``; the map goes again at the next session or wake)."""
        self.center.metrics.pushes.labels(outcome="failed").inc()
        self.center.metrics.events.labels(kind=EventKind.ERROR.value).inc()
        try:
            await asyncio.shield(self.writes.run(steps.record_failure, applied_id,
                                                 target.name, failure=failure))
        except SQLAlchemyError as exc:
            log.warning("%s: failure of delivery %d not stored: %s", target.name, applied_id,
                        str(exc).splitlines()[0])
        self._tell(Notice(EventKind.ERROR, target.name, failure, version),
                   Delivery(target.name, version, "failed", None, why))

    async def _record_answer(self, applied_id: int, name: str, kind: EventKind, *,
                             acked: bool, reason: str | None, detail: str) -> None:
        """Store the machine's answer; a machine deleted meanwhile (its delivery rows went
        with it) is logged, not fatal: the next refresh closes its session.

        Shielded: a machine that answers and closes at once ends its session, which
        cancels this task; a write still queued behind busy worker threads would be
        cancelled with it, and an answer the center received lost."""
        try:
            await asyncio.shield(self.writes.run(steps.record_answer, applied_id, name, kind,
                                                 acked=acked, reason=reason, detail=detail))
        except SQLAlchemyError as exc:
            log.warning("%s: answer to delivery %d not stored: %s", name, applied_id,
                        str(exc).splitlines()[0])

    def _tell(self, notice: Notice, delivery: Delivery) -> None:
        self.feed.publish(notice)
        for observer in list(self.observers):
            observer(delivery)

    def connected(self) -> Iterator[str]:
        """Names of the machines with a worker now."""
        return iter(list(self._targets))


__all__ = ["PREPARING", "THRESHOLD_K", "Delivery", "PushScheduler"]
