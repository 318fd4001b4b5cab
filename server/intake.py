"""Temperature intake: every reading the center gets, checked, kept and forwarded.

Readings arrive by MQTT (:mod:`server.mqtt`), by REST (``POST
/api/machines/{name}/temperatures``) and in Siemens-style machines' Telemetry
(:mod:`server.links.ednc`). All of them pass the :class:`~server.temperatures.TemperatureBoard`,
on which :class:`TemperatureIntake` installs its screen, so one set of rules holds for
every path. A reading is refused (counted in ``ednc_temperatures_refused{reason}``,
kept in the intake's recent refusals, logged at most once per machine, sensor and reason
every 10 minutes, and then also recorded as an ``error`` event when the value itself is
bad: not finite, out of range, too fast) when

* ``not_finite``: it is NaN or infinite;
* ``out_of_range``: it is outside the plausible range (-20..100 °C by default, the limits
  of :mod:`volumetric.plausible.temperatures` that every entry point shares), with the
  likely unit when one explains it (293: kelvin);
* ``bad_time``: its time stamp is before 2000 or more than a day ahead, with the likely
  unit (milliseconds in a seconds field, :mod:`volumetric.plausible.times`);
* ``unknown_machine``: no machine of that name is registered;
* ``unknown_sensor``: the sensor is not one of the machine's: the temperature columns of
  its current model's terms, or those its description lists under ``"sensors"``
  (e.g. ``["spindle", "air"]``, to record sensors no model uses yet). A machine's own
  Telemetry names its sensors itself, so this check does not apply to it;
* ``too_fast``: it moved from the sensor's last good reading by more than
  ``max_rate_K_per_s`` times the time between them plus ``jump_allowance_K`` (a sensor
  fault or a unit mix-up, not a machine warming up; ``EDNC_TEMPERATURE_MAX_RATE`` and
  ``EDNC_TEMPERATURE_JUMP``, 1 K/s and 10 K by default).

A refused reading changes nothing: the board and the machine keep the last good value.

An accepted reading is

* kept on the board (the latest value per sensor, with staleness; the dashboard, the
  MQTT status and the push scheduler read it);
* appended to the ``temperature_readings`` time series, written in batches every
  ``flush_s`` (bounded buffer: when the database is away the oldest unwritten readings
  are dropped and counted); rows older than ``retention_days``, and the oldest beyond
  ``max_rows``, are pruned hourly, in batches of :data:`PRUNE_BATCH` rows (one
  transaction each, so that the writes of the intake and the push are not held up);
* forwarded to the machine in a Temperatures message by the
  :class:`~server.forward.TemperatureForwarder` unless it came from the machine itself
  (coalesced: at most one message per machine per ``forward_interval_s``). A machine
  that connects gets every reading the board holds for it at once.

The known machines and sensors are cached: loaded at start, reloaded every
``refresh_s`` (10 min: the full reload reads every machine's model, and only a sensor
dropped from a model waits for it), and for one machine when a reading names a machine
or a sensor the cache does not know (at most every 2 s per machine): such a reading is
held until the lookup returns and then screened again, so a machine registered or a
model uploaded a moment ago loses no reading.
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import logging
import math
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Final, Protocol

import numpy as np
from prometheus_client import Counter
from sqlalchemy import func, select
from sqlalchemy.exc import SQLAlchemyError
from sqlalchemy.orm import Session

from server.db import Database
from server.db import temperatures as reading_repo
from server.db.tables import MachineRow, ModelRow
from server.db.temperatures import NewReading
from server.events import EventKind
from server.feed import Feed, Notice
from server.forward import INTERVAL_S, TemperatureForwarder
from server.links.ednc.session import MachineSession
from server.metrics import Metrics
from server.settings import TEMPERATURE_JUMP, TEMPERATURE_MAX_RATE, Settings
from server.temperatures import Source, TemperatureBoard, column_of, valid_sensor
from volumetric.model.lag import first_order_lag, lag_step
from volumetric.model.live import LiveLag, LiveNeeds, live_needs
from volumetric.plausible.temperatures import TEMPERATURE, temperature_problem
from volumetric.plausible.times import stamp_problem

log = logging.getLogger(__name__)

PLAUSIBLE_C: Final = (TEMPERATURE.lo, TEMPERATURE.hi)
"""A machine tool's temperatures in a shop; outside is a sensor or unit fault: the limits
every entry point shares (:mod:`volumetric.plausible.temperatures`)."""

MAX_RATE_K_PER_S: Final = TEMPERATURE_MAX_RATE
"""Default of ``EDNC_TEMPERATURE_MAX_RATE``, K/s (why: :mod:`server.settings`)."""

JUMP_ALLOWANCE_K: Final = TEMPERATURE_JUMP
"""Default of ``EDNC_TEMPERATURE_JUMP``, K (why: :mod:`server.settings`)."""

RETENTION_DAYS: Final = 30.0
"""Readings kept this long (re-identification wants weeks of warm-ups)."""

MAX_ROWS: Final = 100_000_000
"""Readings kept at most, whatever their age (the oldest go first): 30 days at a plant's
500/s would be 1.3 billion rows; 100 million are 2.3 days of that, or 30 days of 40/s, a
few GB. A center with the disk for more raises it."""

PRUNE_BATCH: Final = 50_000
"""Rows deleted per transaction when pruning (each holds the database's write lock)."""

PRUNE_EVERY_S: Final = 3600.0
RETRY_PRUNE_S: Final = 60.0
"""The first pruning this long after start, and again this long after a failed one (the
database locked by a long write)."""

MAX_BUFFER: Final = 200_000
"""Readings waiting for the database at most (~7 min at 500/s) before the oldest go."""

LAG_HISTORY_TAUS: Final = 5.0
LAG_HISTORY_ROWS: Final = 50_000
"""A lag state is warmed from the readings of its last 5 time constants (what is older
weighs below e^-5 = 0.7 %), at most 50,000 of them (two days at 4 s): one query per
sensor, for all its time constants, when the center first sees it."""

REASONS: Final = ("not_finite", "out_of_range", "unknown_machine", "unknown_sensor",
                   "too_fast", "too_many_sensors", "bad_time")
"""Every reason a reading is refused for (the ``reason`` label of the counter)."""

EVENT_EVERY_S: Final = 600.0
_EVENTED: Final = frozenset({"not_finite", "out_of_range", "too_fast", "bad_time"})
"""Refusals that say a sensor is faulty get an event; a sensor or machine the center does
not know (a plant publishing more than the models use) only the log and the counter."""
RELOAD_EVERY_S: Final = 2.0


class IntakeCenter(Protocol):
    """What the intake needs of the :class:`~server.center.Center` (importing the center
    here would close a circle: the center types its ``intake`` with this module)."""

    @property
    def settings(self) -> Settings: ...

    @property
    def db(self) -> Database: ...

    @property
    def metrics(self) -> Metrics: ...


@dataclass(frozen=True, slots=True)
class Refusal:
    """A refused reading: which, why (``reason`` a fixed label, ``text`` for people)."""

    machine: str
    sensor: str
    celsius: float
    source: str
    reason: str
    text: str
    time: float
    """When it was refused, s since the epoch."""


@dataclass(frozen=True, slots=True)
class _Known:
    id: int
    columns: frozenset[str]
    lags: tuple[LiveLag, ...] = ()
    """The lag states of its model's lagged thermal terms, which the center follows."""
    created_at: dt.datetime | None = None
    """When its row was made: with the id, which machine this is (SQLite gives a deleted
    last row's id to the next one)."""


def model_columns(body: Mapping[str, Any]) -> frozenset[str]:
    """The temperature columns a stored model's terms use (every term naming a sensor:
    the thermal ones, and whatever thermal kind is added later; a lagged thermal
    model's sensors and the lag states the center sends as ``T_lag1_C`` ...)."""
    terms = body.get("terms") or []
    named = frozenset(column_of(str(t["sensor"])) for t in terms
                      if isinstance(t, Mapping) and isinstance(t.get("sensor"), str))
    needs = _live_needs(terms)
    return named if needs is None else named | needs.inputs | needs.records


def _live_needs(terms: Any) -> LiveNeeds | None:
    """The live needs of a model's terms; None when a lagged term cannot be read (the
    push refuses that model with the reason; its plain sensors still count)."""
    try:
        return live_needs(terms if isinstance(terms, list) else [])
    except (ValueError, KeyError, TypeError):
        return None


def follows(lag: LiveLag) -> str:
    """What a lag state follows, for people (the dashboard's ``follows``)."""
    minutes = f"{lag.tau_s / 60:.0f} min"
    if len(lag.weights) == 1:
        return f"{lag.sources[0]} through a {minutes} lag"
    return f"a weighted sum of {len(lag.weights)} sensors through a {minutes} lag"


def description_columns(description: Mapping[str, Any]) -> frozenset[str]:
    """The columns a machine description lists under ``"sensors"`` (optional)."""
    listed = description.get("sensors")
    if not isinstance(listed, list):
        return frozenset()
    return frozenset(column_of(s) for s in listed if isinstance(s, str) and valid_sensor(s))


def load_known(session: Session, name: str | None = None) -> dict[str, _Known]:
    """Machines (all, or the one named) with their known temperature columns."""
    latest = (select(ModelRow.machine_id, func.max(ModelRow.version).label("version"))
              .group_by(ModelRow.machine_id).subquery())
    query = (select(MachineRow.id, MachineRow.name, MachineRow.description, ModelRow.body,
                    MachineRow.created_at)
             .outerjoin(latest, latest.c.machine_id == MachineRow.id)
             .outerjoin(ModelRow, (ModelRow.machine_id == MachineRow.id)
                        & (ModelRow.version == latest.c.version)))
    if name is not None:
        query = query.where(MachineRow.name == name)
    out: dict[str, _Known] = {}
    for machine_id, machine, description, body, created_at in session.execute(query):
        columns = description_columns(description or {})
        lags: tuple[LiveLag, ...] = ()
        if isinstance(body, Mapping):
            columns |= model_columns(body)
            needs = _live_needs(body.get("terms"))
            lags = needs.lags if needs is not None else ()
        out[machine] = _Known(machine_id, columns, lags, created_at)
    return out


@dataclass
class IntakeStats:
    accepted: int = 0
    refused: int = 0
    stored: int = 0
    unstored: int = 0
    """Readings dropped from a full buffer (database away too long)."""
    store_cpu_s: float = 0.0
    """CPU time of the database thread building and running the batched INSERTs, s."""


class TemperatureIntake:
    """Checks, keeps and forwards temperatures (module docstring); an async context
    manager that hooks itself on ``board`` while it runs.

    Parameters
    ----------
    center : IntakeCenter
        The :class:`~server.center.Center`.
    board : TemperatureBoard
    feed : Feed, optional
        For refusal events and for sending a machine its readings when it connects.
    sessions : mapping of machine name to MachineSession, optional
        This node's live sessions (``MachineServer.sessions``); without them nothing is
        forwarded.
    plausible_C : (float, float)
    max_rate_K_per_s, jump_allowance_K : float, optional
        The rate rule (module docstring), K/s and K; the settings'
        ``temperature_max_rate`` and ``temperature_jump`` by default.
    forward_interval_s : float
    flush_s : float
        How often accepted readings are written to the database, s.
    retention_days : float
    max_rows : int
        Readings kept at most (:data:`MAX_ROWS`).
    refresh_s : float
        Full reload of the known machines and sensors, s.
    """

    def __init__(self, center: IntakeCenter, board: TemperatureBoard, feed: Feed | None = None, *,
                 sessions: Mapping[str, MachineSession] | None = None,
                 plausible_C: tuple[float, float] = PLAUSIBLE_C,
                 max_rate_K_per_s: float | None = None,
                 jump_allowance_K: float | None = None,
                 forward_interval_s: float = INTERVAL_S, flush_s: float = 0.5,
                 retention_days: float = RETENTION_DAYS, max_rows: int = MAX_ROWS,
                 refresh_s: float = 600.0) -> None:
        if max_rate_K_per_s is None:
            max_rate_K_per_s = center.settings.temperature_max_rate
        if jump_allowance_K is None:
            jump_allowance_K = center.settings.temperature_jump
        lo, hi = plausible_C
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"plausible_C must be a finite (low, high), got {plausible_C!r}")
        if not (max_rate_K_per_s > 0 and jump_allowance_K >= 0 and flush_s > 0
                and retention_days > 0 and refresh_s > 0 and max_rows > 0):
            raise ValueError("max_rate_K_per_s, flush_s, retention_days, max_rows and "
                             "refresh_s must be > 0, jump_allowance_K >= 0")
        self.center = center
        self.board = board
        self.feed = feed
        self.plausible_C = (float(lo), float(hi))
        self.max_rate_K_per_s = float(max_rate_K_per_s)
        self.jump_allowance_K = float(jump_allowance_K)
        self.flush_s = float(flush_s)
        self.retention_days = float(retention_days)
        self.max_rows = int(max_rows)
        self.refresh_s = float(refresh_s)
        self.forwarder = TemperatureForwarder(sessions if sessions is not None else {},
                                              interval_s=forward_interval_s)
        self.stats = IntakeStats()
        self.refusals: deque[Refusal] = deque(maxlen=200)
        """The latest refusals, newest last (the REST view shows them)."""
        self._known: dict[str, _Known] = {}
        self._lag_states: dict[tuple[str, str, float], tuple[float, float, float]] = {}
        """(machine, sensor column, τ) -> (time s, input °C, lag state °C)."""
        self._reloaded: dict[str, float] = {}
        self._deferred: dict[str, list[tuple[str, float, Source, float]]] = {}
        self._orphans: dict[str, list[NewReading]] = {}
        self._buffer: deque[NewReading] = deque()
        self._last_refusal: Refusal | None = None
        self._evented: dict[tuple[str, str, str], float] = {}
        self._tasks: set[asyncio.Task[None]] = set()
        self._unhook: list[Callable[[], None]] = []
        registry = center.metrics.registry
        self._refused = Counter("ednc_temperatures_refused",
                                "Temperature readings refused, by reason.", ["reason"],
                                registry=registry)
        self._accepted = Counter("ednc_temperatures_accepted",
                                 "Temperature readings accepted, by source.", ["source"],
                                 registry=registry)
        # the labelled children, looked up once: labels() takes a lock and builds a key,
        # a few µs on every reading of a plant's hundreds a second
        self._accepted_by: dict[str, Any] = {}
        # every reason from the start, so that the metrics endpoint shows 0 rather than
        # nothing until the first refusal (and a flood of bad readings costs no lookup)
        self._refused_by: dict[str, Any] = {
            reason: self._refused.labels(reason=reason) for reason in REASONS}

    # -- lifetime
    async def __aenter__(self) -> TemperatureIntake:
        self._known = await self.center.db.run(load_known)
        if self.board.screen is not None:
            raise RuntimeError("the temperature board already has a screen")
        self.board.screen = self.screen
        self._unhook.append(self._clear_screen)
        self._unhook.append(self.board.subscribe(self._on_stored))
        if self.feed is not None:
            self._unhook.append(self.feed.subscribe(self._on_notice))
        for coro, name in ((self._flush_loop(), "temperatures:flush"),
                           (self._retention_loop(), "temperatures:retention"),
                           (self._refresh_loop(), "temperatures:refresh")):
            self._spawn(coro, name)
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        for unhook in reversed(self._unhook):
            unhook()
        self._unhook.clear()
        self.forwarder.close()
        tasks, self._tasks = list(self._tasks), set()
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        with contextlib.suppress(SQLAlchemyError):  # the last batch, if the database is up
            await self.flush()

    def _clear_screen(self) -> None:
        if self.board.screen == self.screen:
            self.board.screen = None

    def _spawn(self, coro: Any, name: str) -> None:
        task = asyncio.create_task(coro, name=name)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    # -- the entry points
    def take(self, machine: str, sensor: str, celsius: float, *, source: Source = "rest",
             at: float | None = None) -> Refusal | None:
        """Take one reading (``sensor`` a name or a column, ``at`` s since the epoch,
        arrival by default); returns the refusal, or None when it was accepted."""
        self._last_refusal = None
        if not valid_sensor(sensor):
            return self._refuse(machine, sensor, celsius, source, "unknown_sensor",
                                "sensor names are 1..64 letters, digits and '_'")
        if self.board.update(machine, sensor, celsius, source=source, at=at):
            return None
        refusal = self._last_refusal
        if refusal is None and machine in self._deferred:
            return None  # held for the lookup, taken (or refused) when it returns
        if refusal is None:  # the board's own bound on distinct sensors
            refusal = self._refuse(machine, sensor, celsius, source, "too_many_sensors",
                                   "the board keeps no more distinct sensors")
        return refusal

    def forget(self, machine: str) -> None:
        """Forget everything held for ``machine`` (deleted or renamed): its readings on the
        board, its lag states, its cached sensors, readings waiting for it and its recent
        refusals, so that a new machine of the same name starts clean."""
        self.board.forget(machine)
        self._known.pop(machine, None)
        self._reloaded.pop(machine, None)
        self._deferred.pop(machine, None)
        self._orphans.pop(machine, None)
        for key in [k for k in self._lag_states if k[0] == machine]:
            del self._lag_states[key]
        kept = [r for r in self.refusals if r.machine != machine]
        self.refusals.clear()
        self.refusals.extend(kept)
        self.forwarder.forget(machine)

    def forward(self, machine: str) -> None:
        """Send ``machine`` every forwardable reading the board holds, as soon as the
        forwarding interval allows (what happens by itself when it connects)."""
        self.forwarder.resend(machine, (
            (column, r.celsius, r.time) for column, r in self.board.readings(machine).items()
            if r.source != "telemetry"))

    # -- the screen and what follows acceptance
    def screen(self, machine: str, column: str, celsius: float, source: Source,
               taken: float) -> str | None:
        """The board's screen: None to accept, else the refusal text (module docstring)."""
        lo, hi = self.plausible_C
        if not isinstance(celsius, int | float) or not math.isfinite(celsius):
            return self._refuse(machine, column, celsius, source, "not_finite",
                                f"{celsius!r} is not a finite number").text
        if not lo <= celsius <= hi:
            # the words of every entry point, with the cause when one explains it (293
            # is kelvin, 21500 m°C); a center configured with other limits says those
            text = (temperature_problem(celsius) if (lo, hi) == PLAUSIBLE_C else None) \
                or f"{celsius:g} °C is outside {lo:g}..{hi:g} °C"
            return self._refuse(machine, column, celsius, source, "out_of_range", text).text
        # a plant system's stamp in the wrong unit; a machine's own clock (Telemetry) is
        # the machine's business, and a lag state is the center's
        stamp = stamp_problem(taken) if source in ("mqtt", "rest") else None
        if stamp is not None:
            return self._refuse(machine, column, celsius, source, "bad_time", stamp).text
        known = self._known.get(machine)
        if known is None and source == "telemetry" and machine in self.forwarder.sessions:
            # a machine with a live session here is registered and authenticated: take its
            # own readings now (the push may build a map on them at once) and look it up
            # for the time series meanwhile
            self._lookup_soon(machine)
        elif known is None:
            if self._defer(machine, column, celsius, source, taken):
                return "deferred: the machine is looked up in the database"
            return self._refuse(machine, column, celsius, source, "unknown_machine",
                                f"no machine named {machine[:64]!r} is registered").text
        elif source != "telemetry" and column not in known.columns:
            if self._defer(machine, column, celsius, source, taken):
                return "deferred: the machine's sensors are looked up in the database"
            have = ", ".join(sorted(known.columns)) or "none"
            return self._refuse(machine, column, celsius, source, "unknown_sensor",
                                f"{column} is not a sensor of {machine} (its model and "
                                f"description name: {have})").text
        last = self.board.reading(machine, column)
        if last is not None:
            gap = max(taken - last.time, time.monotonic() - last.received, 0.0)
            allowed = self.max_rate_K_per_s * gap + self.jump_allowance_K
            if abs(celsius - last.celsius) > allowed:
                return self._refuse(
                    machine, column, celsius, source, "too_fast",
                    f"{celsius:g} °C is {abs(celsius - last.celsius):.2f} K from the last "
                    f"good {last.celsius:g} °C {gap:.1f} s earlier (allowed "
                    f"{allowed:.2f} K)").text
        return None

    def _on_stored(self, machine: str, column: str, celsius: float) -> None:
        r = self.board.reading(machine, column)
        if r is None:
            return
        self.stats.accepted += 1
        counter = self._accepted_by.get(r.source)
        if counter is None:
            counter = self._accepted_by[r.source] = self._accepted.labels(source=r.source)
        counter.inc()
        known = self._known.get(machine)
        row = NewReading(known.id if known else 0, column, float(celsius),
                         dt.datetime.fromtimestamp(r.time, dt.UTC), r.source)
        if r.source == "lag":
            pass  # derived from stored readings: not stored again
        elif known is None:  # a connected machine being looked up: stored when it is known
            waiting = self._orphans.setdefault(machine, [])
            if len(waiting) < 1024:
                waiting.append(row)
        else:
            self._store(row)
        if r.source != "telemetry":  # the machine has its own readings already
            self.forwarder.note(machine, column, float(celsius), r.time)
        if known is not None and known.lags and r.source != "lag":
            self._follow_lags(machine, known, column, float(celsius), r.time)

    def _follow_lags(self, machine: str, known: _Known, column: str, celsius: float,
                     taken: float) -> None:
        """Step the lag states of ``column`` to this reading and send on every lag state
        of ``machine`` that weighs it, as a reading of its own (source ``lag``,
        :mod:`volumetric.model.live`).

        The center follows one state per sensor and time constant, and sends a lag of a
        weighted sum as the weighted sum of its sensors' states (the lag is linear), so
        that readings of different sensors at different times need nothing special. A
        state starts at rest with the first reading it sees (what ``ednc predict`` does
        for readings without history) and is then warmed from the readings stored before
        it (:meth:`_warm_lags`). A reading older than the state's last one is left out:
        the lag runs forward in time only."""
        moved: dict[float, bool] = {}
        fresh: list[float] = []
        for lag in known.lags:
            if column not in lag.sources:
                continue
            tau = lag.tau_s
            if tau not in moved:
                key = (machine, column, tau)
                state = self._lag_states.get(key)
                if state is None:
                    self._lag_states[key] = (taken, celsius, celsius)
                    fresh.append(tau)
                elif taken >= state[0]:
                    t0, x0, y0 = state
                    self._lag_states[key] = (taken, celsius,
                                             lag_step(y0, x0, celsius, taken - t0, tau))
                moved[tau] = state is None or taken >= state[0]
            if moved[tau]:
                self._send_lag(machine, lag)
        if fresh:
            self._spawn(self._warm_lags(machine, known.id, column, tuple(fresh), taken),
                        f"lag:{machine}")

    async def _warm_lags(self, machine: str, machine_id: int, source: str,
                         taus: tuple[float, ...], before: float) -> None:
        """Replace lag states of ``source`` started at rest by ones run over the readings
        stored before them (the last ``LAG_HISTORY_TAUS`` of the longest time constant, at
        most ``LAG_HISTORY_ROWS`` rows, from rest at the oldest; one query for all its
        time constants), stepped on to each state's latest reading: after a restart of
        the center, a lag of hours is right at once instead of hours later."""
        since = dt.datetime.fromtimestamp(before - LAG_HISTORY_TAUS * max(taus), dt.UTC)
        try:
            rows = await self.center.db.run(
                reading_repo.list_readings, machine_id, sensor=source, since=since,
                until=dt.datetime.fromtimestamp(before, dt.UTC), limit=LAG_HISTORY_ROWS)
        except SQLAlchemyError as exc:
            log.warning("%s: lags of %s start at rest, stored readings not read: %s",
                        machine, source, str(exc).splitlines()[0])
            return
        if not rows:
            return
        rows.reverse()  # oldest first
        t = np.array([r.time.timestamp() for r in rows])
        x = np.array([r.celsius for r in rows])
        for tau in taus:
            key = (machine, source, tau)
            keep = t >= before - LAG_HISTORY_TAUS * tau
            if not keep.any():
                continue
            y = float(first_order_lag(t[keep], x[keep], tau)[-1])
            t_now, x_now, _ = self._lag_states[key]  # set before this task was spawned
            self._lag_states[key] = (
                t_now, x_now, lag_step(y, float(x[-1]), x_now, t_now - float(t[-1]), tau))
        known = self._known.get(machine)
        for lag in known.lags if known is not None else ():
            if source in lag.sources and lag.tau_s in taus:
                self._send_lag(machine, lag)

    def _send_lag(self, machine: str, lag: LiveLag) -> None:
        """Put a lag state on the board as its column's reading (which sends it to the
        machine), once every sensor it weighs has a state; dated by the oldest of them, so
        that a weighted sum is as stale as its stalest sensor (the machine and the
        dashboard judge staleness by that date)."""
        states = []
        for source in lag.sources:
            state = self._lag_states.get((machine, source, lag.tau_s))
            if state is None:
                return
            states.append(state)
        value = lag.state({s: st[2] for s, st in zip(lag.sources, states, strict=True)})
        self.board.notes[(machine, lag.column)] = follows(lag)
        self.board.update(machine, lag.column, value, source="lag",
                          at=min(st[0] for st in states))

    def _store(self, row: NewReading) -> None:
        if len(self._buffer) >= MAX_BUFFER:
            self._buffer.popleft()
            self.stats.unstored += 1
        self._buffer.append(row)

    def _on_notice(self, notice: Notice) -> None:
        if notice.kind is EventKind.CONNECTED:
            self.forward(notice.machine)
        elif notice.kind is EventKind.DISCONNECTED:
            self.forwarder.forget(notice.machine)

    def _refuse(self, machine: str, sensor: str, celsius: float, source: str, reason: str,
                text: str) -> Refusal:
        now = time.time()
        refusal = Refusal(machine, sensor, celsius, source, reason, text, now)
        self._last_refusal = refusal
        self.refusals.append(refusal)
        self.stats.refused += 1
        counter = self._refused_by.get(reason)
        if counter is None:
            counter = self._refused_by[reason] = self._refused.labels(reason=reason)
        counter.inc()
        key = (machine, sensor, reason)
        if now - self._evented.get(key, -math.inf) >= EVENT_EVERY_S:
            if len(self._evented) > 10_000:  # names come from the network: bound the memory
                self._evented.clear()
            self._evented[key] = now
            # a bad value is a fault to look at; a sensor no model uses is a plant
            # publishing more than the center needs (the demo's machines do)
            level = logging.WARNING if reason in _EVENTED else logging.INFO
            log.log(level, "temperature %s of %s (%s) refused: %s", sensor, machine, source,
                    text)
            if self.feed is not None and reason in _EVENTED:
                self._spawn(self.feed.record(EventKind.ERROR, machine,
                                             f"temperature {sensor} refused: {text}"),
                            "temperatures:event")
        return refusal

    # -- the cache of known machines and sensors
    def _defer(self, machine: str, column: str, celsius: float, source: Source,
               taken: float) -> bool:
        """Hold a reading the cache does not know while the machine is looked up (at
        most every RELOAD_EVERY_S per machine); False: the lookup is recent, refuse."""
        waiting = self._deferred.get(machine)
        if waiting is None:
            now = time.monotonic()
            if now - self._reloaded.get(machine, -math.inf) < RELOAD_EVERY_S:
                return False
            if len(self._reloaded) > 10_000:  # names come from the network
                self._reloaded.clear()
            self._reloaded[machine] = now
            waiting = self._deferred[machine] = []
            self._spawn(self._reload(machine), "temperatures:reload")
        if len(waiting) < 64:
            waiting.append((column, celsius, source, taken))
        return True

    def _lookup_soon(self, machine: str) -> None:
        """Look a connected machine up (at most every RELOAD_EVERY_S), holding nothing."""
        if machine in self._deferred:
            return  # a lookup is under way
        now = time.monotonic()
        if now - self._reloaded.get(machine, -math.inf) < RELOAD_EVERY_S:
            return
        self._reloaded[machine] = now
        self._deferred[machine] = []
        self._spawn(self._reload(machine), "temperatures:reload")

    async def _reload(self, machine: str) -> None:
        """Look one machine up again, then take the readings held for it."""
        try:
            found = await self.center.db.run(load_known, machine)
        except SQLAlchemyError as exc:
            log.warning("could not reload machine %s: %s", machine, exc)
            found = {}
        finally:
            waiting = self._deferred.pop(machine, [])
        self._take_known(found)
        orphans = self._orphans.pop(machine, [])
        if machine in found:
            for row in orphans:
                self._store(NewReading(found[machine].id, row.sensor, row.celsius, row.time,
                                       row.source))
        for column, celsius, source, taken in waiting:  # screened again, now for good
            self.board.update(machine, column, celsius, source=source, at=taken)

    async def lookup(self, machine: str) -> frozenset[str] | None:
        """Reload ``machine`` from the database now; its known columns, None if unknown."""
        self._reloaded[machine] = time.monotonic()
        found = await self.center.db.run(load_known, machine)
        if machine not in found and machine in self._known:
            self.forget(machine)  # deleted, maybe through another node
        self._take_known(found)
        return self.knows(machine)

    def _take_known(self, found: dict[str, _Known], *, whole: bool = False) -> None:
        """Adopt machines looked up again. A name now held by another machine row (deleted
        and registered anew, maybe through another center node, whose deletion this node
        never heard of) or, on a ``whole`` reload, gone, is forgotten first: the old
        machine's readings must not show on, or be stored for, the new one."""
        gone = [m for m, k in self._known.items()
                if (m in found and (found[m].id, found[m].created_at) != (k.id, k.created_at))
                or (whole and m not in found)]
        for machine in gone:
            self.forget(machine)
        if whole:
            self._known = dict(found)
        else:
            self._known.update(found)

    async def _refresh_loop(self) -> None:
        while True:
            await asyncio.sleep(self.refresh_s)
            try:
                self._take_known(await self.center.db.run(load_known), whole=True)
            except SQLAlchemyError as exc:
                log.warning("could not refresh the known sensors: %s", exc)

    def knows(self, machine: str) -> frozenset[str] | None:
        """The known columns of ``machine``, None when it is not known."""
        known = self._known.get(machine)
        return None if known is None else known.columns

    # -- the time series
    async def flush(self) -> int:
        """Write the buffered readings now (one transaction); returns how many."""
        if not self._buffer:
            return 0
        batch = list(self._buffer)
        self._buffer.clear()
        try:
            n = await self.center.db.run(self._add_readings, batch)
        except SQLAlchemyError:
            room = MAX_BUFFER - len(self._buffer)  # put them back in front, if room
            keep = batch[-room:] if room > 0 else []
            self.stats.unstored += len(batch) - len(keep)
            self._buffer.extendleft(reversed(keep))
            raise
        self.stats.stored += n
        return n

    def _add_readings(self, session: Session, batch: list[NewReading]) -> int:
        cpu0 = time.thread_time()  # on the database's worker thread
        try:
            return reading_repo.add_readings(session, batch)
        finally:
            self.stats.store_cpu_s += time.thread_time() - cpu0

    async def _flush_loop(self) -> None:
        while True:
            await asyncio.sleep(self.flush_s)
            try:
                await self.flush()
            except SQLAlchemyError as exc:
                log.warning("temperature readings not stored yet: %s",
                            str(exc).splitlines()[0])

    async def prune_once(self, *, batch: int = PRUNE_BATCH) -> int:
        """Delete the readings older than the retention period and the oldest beyond
        ``max_rows``, ``batch`` rows per transaction; returns how many."""
        cutoff = dt.datetime.now(dt.UTC) - dt.timedelta(days=self.retention_days)
        total = 0
        while n := await self.center.db.run(reading_repo.delete_readings_before, cutoff,
                                            limit=batch):
            total += n
        while n := await self.center.db.run(reading_repo.delete_readings_beyond,
                                            self.max_rows, limit=batch):
            total += n
        return total

    async def _retention_loop(self) -> None:
        # not at once: start-up is when the machines are loaded, registered and connect,
        # and a pruning then only waits for (and holds up) their writes
        await asyncio.sleep(RETRY_PRUNE_S)
        while True:
            pause = PRUNE_EVERY_S
            try:
                deleted = await self.prune_once()
                if deleted:
                    log.info("deleted %d temperature readings (older than %g days or "
                             "beyond %d)", deleted, self.retention_days, self.max_rows)
            except SQLAlchemyError as exc:
                log.warning("temperature retention failed, again in %g s: %s",
                            RETRY_PRUNE_S, str(exc).splitlines()[0])
                pause = RETRY_PRUNE_S
            await asyncio.sleep(pause)


__all__ = ["JUMP_ALLOWANCE_K", "MAX_RATE_K_PER_S", "MAX_ROWS", "PLAUSIBLE_C", "RETENTION_DAYS",
           "Refusal",
           "TemperatureIntake", "description_columns", "load_known", "model_columns"]
