"""The center's native SINUMERIK links, one follower per registered machine.

:class:`NativeSdLinks` is an async context manager started with the machine services. It
reads the registrations every ``reconcile_s`` and keeps one
:class:`~server.links.sinumerik_sd.SdFollower` per machine registered with a
``sinumerik_sd`` link (:class:`~server.schemas.link.SinumerikSdLink`), and feeds it:

* the model's terms: the machine's latest stored model, read at start and again whenever
  a transaction commits a new model or a changed machine row (told by the push
  scheduler's ``commit_listeners``: its :class:`~server.push.watcher.CommitWatcher` is the
  one that sees commits);
* the temperatures: every reading the center takes for that machine (MQTT, Telemetry, the
  REST API) through the :class:`~server.temperatures.TemperatureBoard`'s listeners, so a
  change reaches the NC within one write interval, and the board's latest values when a
  follower starts.

No map is built or pushed for such a machine: the push scheduler serves sessions, and
this machine has none; everything it receives goes through the follower. With leases
(several center nodes on one database) the links do not run: two nodes would each write
at the allowed rate, together twice as often (not yet claimed through the leases).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import Callable, Mapping
from types import TracebackType
from typing import TYPE_CHECKING, Any

from pydantic import TypeAdapter, ValidationError
from sqlalchemy.orm import Session

from server.db import error_models as model_repo
from server.db import machines as machine_repo
from server.events import EventKind
from server.feed import Feed
from server.links.state import LinkCondition, Throttle
from server.links.window.memory import LinkError
from server.links.window.service import read_secret
from server.schemas.link import LinkSpec, SinumerikSdLink
from server.temperatures import TemperatureBoard
from volumetric.compensate.tempcomp import TempCompLimits
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel, ThermalTerm

if TYPE_CHECKING:
    from server.links.sinumerik_sd import SdFollower, SdSession

__all__ = ["NativeSdLinks"]

log = logging.getLogger(__name__)

_SPEC: TypeAdapter[LinkSpec] = TypeAdapter(LinkSpec)


def native_link(description: dict[str, Any]) -> SinumerikSdLink | None:
    """The ``sinumerik_sd`` link of a stored description (None: another or none)."""
    raw = description.get("link")
    if not isinstance(raw, dict) or raw.get("kind") != "sinumerik_sd":
        return None
    try:
        spec = _SPEC.validate_python(raw)
    except ValidationError:
        return None
    return spec if isinstance(spec, SinumerikSdLink) else None


class _Events:
    """A follower's news into the registry (status, dashboard, metric) and the event log:
    a failure's state and reason at once, as the window links show theirs, an event for
    the first of each reason and then at most once a minute
    (:class:`~server.links.state.Throttle`)."""

    def __init__(self, links: NativeSdLinks, name: str, session: SdSession) -> None:
        self.links = links
        self.name = name
        self.session = session
        self.endpoint = session.endpoint
        self.was_connected = False

    def _notices(self) -> None:
        for text in self.session.take_notices():  # security None, first-use trust
            self.links.record(EventKind.WARNING, self.name, text)

    def connected(self) -> None:
        address = self.endpoint.removeprefix("opc.tcp://").split("/", 1)[0]
        self.was_connected = True
        self.links.center.registry.connected(self.name, address)
        self.links.throttle.forget(self.name)
        self._notices()
        self.links.record(EventKind.CONNECTED, self.name,
                          f"sinumerik_sd link to {self.endpoint}")

    def lost(self, why: LinkCondition) -> None:
        self._notices()
        registry = self.links.center.registry
        if self.was_connected:
            self.was_connected = False
            registry.disconnected(self.name)
            self.links.record(EventKind.DISCONNECTED, self.name, why.text)
        self.links.report(self.name, why)

    def held(self, data: Mapping[str, Mapping[int, float]]) -> None:
        self.links.center.registry.seen(self.name, {
            "timestamp_ms": int(time.time() * 1000), "state": "compensating",
            "link": "sinumerik_sd", "map_version": None,
            "axes": {a: {f"sd{n}": v for n, v in sorted(d.items())} for a, d in data.items()},
            "temperatures": {}})

    def refused(self, text: str) -> None:
        self.links.record(EventKind.ERROR, self.name, f"setting data refused: {text}")


def _registrations(session: Session) -> list[tuple[int, str, dict[str, Any], Any]]:
    return [(r.id, r.name, dict(r.description), r.updated_at)
            for r in machine_repo.list_machines(session)]


def _terms(session: Session, machine_id: int) -> tuple[ThermalTerm, ...]:
    row = model_repo.get_model(session, machine_id)
    if row is None:
        return ()
    try:
        model = MachineModel.from_json(row.body)
    except (TypeError, KeyError, ValueError) as exc:
        log.warning("machine %d: stored model cannot be read: %s", machine_id, exc)
        return ()
    return tuple(t for t in model.terms if isinstance(t, ThermalTerm))


class NativeSdLinks:
    """One :class:`SdFollower` per machine with a ``sinumerik_sd`` link.

    Parameters
    ----------
    center
        The service's center (database, settings).
    feed : Feed
    temperatures : TemperatureBoard
    commit_listeners : list of callable, optional
        Where to hear of committed model changes (``PushScheduler.commit_listeners``);
        without it a model is read when its follower starts only.
    reconcile_s : float
    enabled : bool
        False: run nothing (several center nodes, see the module docstring).
    """

    def __init__(self, center: Any, feed: Feed, temperatures: TemperatureBoard, *,
                 commit_listeners: list[Callable[[set[int]], None]] | None = None,
                 reconcile_s: float = 2.0, enabled: bool = True) -> None:
        self.center = center
        self.feed = feed
        self.temperatures = temperatures
        self.reconcile_s = reconcile_s
        self.enabled = enabled
        self.followers: dict[str, SdFollower] = {}
        self._keys: dict[str, tuple[str, Any]] = {}
        self._ids: dict[int, str] = {}
        self._task: asyncio.Task[None] | None = None
        self._unsubscribe: Any = None
        self.commit_listeners = commit_listeners
        self._reloads: set[asyncio.Task[None]] = set()
        self._records: set[asyncio.Task[None]] = set()
        self.throttle = Throttle()

    async def __aenter__(self) -> NativeSdLinks:
        if not self.enabled:
            return self
        self._unsubscribe = self.temperatures.subscribe(self._on_temperature)
        if self.commit_listeners is not None:
            self.commit_listeners.append(self._on_commit)
        self._task = asyncio.create_task(self._loop(), name="native-sinumerik-links")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
        for t in list(self._reloads):
            t.cancel()
        if self._records:
            await asyncio.wait(list(self._records), timeout=5.0)
        for name in list(self.followers):
            await self._stop(name)
        if self.commit_listeners is not None and self._on_commit in self.commit_listeners:
            self.commit_listeners.remove(self._on_commit)
        if self._unsubscribe is not None:
            self._unsubscribe()

    def record(self, kind: EventKind, name: str, text: str) -> None:
        """Store an event in the background (followers report from sync callbacks)."""
        task = asyncio.create_task(self.feed.record(kind, name, text))
        self._records.add(task)
        task.add_done_callback(self._records.discard)

    def report(self, name: str, why: LinkCondition) -> None:
        """Show why a machine's native link is down: the registry at once, a warning and
        an event for the first of each reason, then at most once a minute per reason."""
        self.center.registry.condition(name, why.state, why.reason, why.text)
        if not self.throttle.allow(name, why.reason or why.state, time.monotonic()):
            return
        log.warning("%s: sinumerik_sd link %s", name, why.summary)
        self.record(EventKind.LINK, name, f"sinumerik_sd link {why.summary}")

    # -- inputs

    def _on_temperature(self, machine: str, column: str, celsius: float) -> None:
        follower = self.followers.get(machine)
        if follower is not None:
            follower.set_temperature(column, celsius)

    def _on_commit(self, machine_ids: set[int]) -> None:
        for machine_id in machine_ids:
            name = self._ids.get(machine_id)
            if name is not None:
                task = asyncio.create_task(self._reload(machine_id, name))
                self._reloads.add(task)
                task.add_done_callback(self._reloads.discard)

    async def _reload(self, machine_id: int, name: str) -> None:
        terms = await self.center.db.run(_terms, machine_id)
        follower = self.followers.get(name)
        if follower is not None:
            follower.set_terms(terms)

    # -- the followers

    async def _loop(self) -> None:
        while True:
            try:
                await self.reconcile()
            except Exception as exc:  # a database hiccup: the next round tries again
                log.warning("native SINUMERIK links: registrations not read: %s",
                            str(exc).splitlines()[0])
            await asyncio.sleep(self.reconcile_s)

    async def reconcile(self) -> None:
        """Start a follower per ``sinumerik_sd`` registration, stop the others."""
        rows = await self.center.db.run(_registrations)
        want: dict[str, tuple[int, dict[str, Any], SinumerikSdLink, tuple[str, Any]]] = {}
        for machine_id, name, description, updated in rows:
            spec = native_link(description)
            if spec is not None:
                want[name] = (machine_id, description, spec,
                              (spec.model_dump_json(), updated))
        for name in list(self.followers):
            if name not in want or want[name][3] != self._keys.get(name):
                await self._stop(name)
        for name, (machine_id, description, spec, key) in want.items():
            if name not in self.followers:
                await self._start(machine_id, name, description, spec, key)

    async def _start(self, machine_id: int, name: str, description: dict[str, Any],
                     spec: SinumerikSdLink, key: tuple[str, Any]) -> None:
        try:
            password = read_secret(spec.password_ref, f"OPC UA user {spec.user!r}")
            axes = parse_machine(description).axis_names
        except (LinkError, ValueError) as exc:
            if self._keys.get(name) != key:  # said once per registration
                self._keys[name] = key
                if isinstance(exc, LinkError):  # a password reference not set: refused
                    self.report(name, exc.condition)
                else:
                    await self.feed.record(EventKind.ERROR, name, f"native link: {exc}")
            return
        # asyncua is imported only where OPC UA is used (as server.links.window.service does)
        from server.links.sinumerik_sd import SdFollower, SdSession

        try:
            session = SdSession.from_link(spec, password, axes)
        except LinkError as exc:  # security fields that do not go together
            self._keys[name] = key
            self.report(name, exc.condition)
            return
        self.center.registry.condition(name, "connecting", "", "sinumerik_sd link")
        terms = await self.center.db.run(_terms, machine_id)
        follower = SdFollower(name, session, terms,
                              limits=TempCompLimits(spec.max_offset_mm, spec.max_slope),
                              min_interval_s=spec.min_interval_ms / 1000.0,
                              events=_Events(self, name, session))
        sensors = {t.sensor for t in terms}
        follower.set_temperatures(self.temperatures.columns(name, sensors))
        await follower.__aenter__()
        self.followers[name] = follower
        self._keys[name] = key
        self._ids[machine_id] = name
        log.info("%s: native SINUMERIK link to %s (%d thermal terms)", name, spec.endpoint,
                 len(terms))

    async def _stop(self, name: str) -> None:
        follower = self.followers.pop(name, None)
        self._keys.pop(name, None)
        for machine_id, n in list(self._ids.items()):
            if n == name:
                del self._ids[machine_id]
        if follower is not None:
            await follower.__aexit__(None, None, None)
            if follower.connected:
                self.center.registry.disconnected(name)
