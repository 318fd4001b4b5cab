"""The native SINUMERIK link: the center writes the NC's temperature compensation itself.

For a SINUMERIK that runs nothing of ours in its PLC (issue 31, item 4): the geometry is
loaded once as CEC tables (``ednc export --format cec``), and the thermal part goes to the
NC's own temperature compensation, setting data SD43900 (offset), SD43910 (slope tan β)
and SD43920 (reference position) per axis, which the NC applies every interpolation cycle
as ``SD43900 + SD43910 · (P - SD43920)`` (function manual K3). The center computes them
from the model's drift and expansion terms at the latest temperatures
(:func:`~volumetric.compensate.tempcomp.temp_comp_setting_data`), decides what to write
and when (:class:`~server.links.sdwrites.SdWritePlanner`: only changes, at most once per
100 ms per axis, within the limits) and writes them here.

* :class:`SdSession`: one OPC UA session (asyncua's client) as a user with ``SeaWrite``
  (setting data; ``SinuReadAll`` or ``SeaRead`` to read them back), the nodes by BTSS
  path ``ns=2;s=/NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_ABS_VALUE[u<k>]`` (machine axis k, 1-based)
  unless ``sd_nodes`` names others; all data due are written in one Write request.
* :class:`SdFollower`: keeps one machine's setting data current (an async context
  manager): it connects (after a failure, the window links' backoff, 4 to 60 s), reads
  what the NC holds (so only differences are written), then writes whenever the temperatures or the
  model's terms change, reads the data back every ``verify_s`` (a value changed at the
  machine is written again; a dead session is found), and says what it did
  (:attr:`SdFollower.writes`, the last error, :class:`FollowerEvents`).

Failures raise or report :class:`~server.links.window.memory.LinkError` with a text that
says what to fix (a user without ``SeaWrite``, a datum MD32750 does not enable, a value
the NC refuses), and a state and reason as the window link gives them: both OPC UA links
log in and classify their failures alike (:mod:`server.links.opcualogin`), so a wrong
password is ``refused (login)``, an untrusted controller ``refused
(server_certificate)``, a silent host ``unreachable (no_answer)`` on either.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import random
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from types import TracebackType
from typing import Final, Protocol

from asyncua import ua
from asyncua.ua.attribute_ids import AttributeIds

from protocol.backoff import Backoff
from server.links.opcualogin import (
    HINTS,
    RETRY_DELAYS_S,
    OpcuaClient,
    OpcuaSecurity,
    status_error,
)
from server.links.opcuapki import Pki
from server.links.pacing import BACKOFF, HEALTHY_AFTER_S
from server.links.sdwrites import (
    SD_ABS_VALUE,
    SD_REF_POSITION,
    SD_SLOPE,
    SdWrite,
    SdWritePlanner,
)
from server.links.state import LinkCondition
from server.links.window.memory import LinkError
from server.schemas.link import SinumerikSdLink
from volumetric.compensate.tempcomp import TempCompLimits, temp_comp_setting_data

__all__ = ["FollowerEvents", "SdFollower", "SdSession", "WriteOutcome"]

log = logging.getLogger(__name__)

_NAMES: Final = {SD_ABS_VALUE: "TEMP_COMP_ABS_VALUE", SD_SLOPE: "TEMP_COMP_SLOPE",
                 SD_REF_POSITION: "TEMP_COMP_REF_POSITION"}
_WHY: Final = {
    **HINTS,
    "BadUserAccessDenied": "the user lacks SeaWrite (setting data)",
    "BadNotWritable": "MD32750 (TEMP_COMP_TYPE) does not enable this datum on the axis",
    "BadOutOfRange": "the NC refuses the value (beyond its limit)",
    "BadNodeIdUnknown": "no such setting datum on the controller (check sd_nodes)",
    "BadTypeMismatch": "the node does not hold a Double",
}
"""What a status code asks the operator to fix, for setting data."""


class FollowerEvents(Protocol):
    """What a :class:`SdFollower` tells its owner (the service: registry, event log)."""

    def connected(self) -> None: ...

    def lost(self, why: LinkCondition) -> None:
        """The session failed or could not be opened (state, reason, text)."""

    def held(self, data: Mapping[str, Mapping[int, float]]) -> None:
        """What the NC holds now per axis and datum (after a read or a write)."""

    def refused(self, text: str) -> None:
        """A write the NC refused (said once per distinct text)."""


@dataclass(frozen=True, slots=True)
class WriteOutcome:
    """One axis's write and what the NC answered.

    Attributes
    ----------
    write : SdWrite
    error : str or None
        None when every datum was taken; else what was refused and why.
    """

    write: SdWrite
    error: str | None


class SdSession(OpcuaClient):
    """An OPC UA session that reads and writes SD43900/43910/43920.

    Parameters
    ----------
    endpoint : str
        ``opc.tcp://host:port``.
    user : str
    password : str
    axes : sequence of str
        The machine axes in the NC's order (machine axis 1, 2, ...).
    sd_nodes : mapping of str to str, optional
        Node ids keyed ``"<AXIS>.<number>"`` (``"X.43900"``) where the default path does
        not apply.
    namespace : int
        Namespace index of the BTSS paths (2 on a SINUMERIK).
    timeout_s : float
        Per request; the login may take twice this.
    security : OpcuaSecurity, optional
        How the channel is secured, as for the window link (default: Basic256Sha256
        SignAndEncrypt, the controller's certificate trusted on first use). Security
        None: the password crosses the network in clear (warned, :meth:`take_notices`).
    pki : Pki, optional
        The center's certificates (default: :func:`~server.links.opcuapki.pki_at`).
    retry_delays_s : sequence of float
        Waits before each new login after a busy answer.
    """

    def __init__(self, endpoint: str, user: str, password: str, axes: Sequence[str], *,
                 sd_nodes: Mapping[str, str] | None = None, namespace: int = 2,
                 timeout_s: float = 5.0, security: OpcuaSecurity | None = None,
                 pki: Pki | None = None,
                 retry_delays_s: Sequence[float] = RETRY_DELAYS_S) -> None:
        super().__init__(endpoint, user, security=security, pki=pki, timeout_s=timeout_s,
                         retry_delays_s=retry_delays_s)
        self._password = password
        self.axes = [a.upper() for a in axes]
        self.sd_nodes = dict(sd_nodes or {})
        self.namespace = namespace

    @classmethod
    def from_link(cls, link: SinumerikSdLink, password: str, axes: Sequence[str], *,
                  timeout_s: float = 5.0, pki: Pki | None = None) -> SdSession:
        """The session of a machine registered with ``link`` (``password``: the resolved
        ``password_ref``; ``axes`` the machine's, in the NC's order)."""
        return cls(link.endpoint, link.user, password, axes, sd_nodes=link.sd_nodes,
                   timeout_s=timeout_s, security=OpcuaSecurity.of(link), pki=pki)

    def node(self, axis: str, number: int) -> ua.NodeId:
        """The node of SD``number`` of ``axis``."""
        given = self.sd_nodes.get(f"{axis.upper()}.{number}")
        if given is not None:
            return ua.NodeId.from_string(given)
        k = self.axes.index(axis.upper()) + 1
        return ua.NodeId(ua.String(f"/NC/_N_AX_SEA_ACX/$SA_{_NAMES[number]}[u{k}]"),
                         ua.Int16(self.namespace))

    async def connect(self) -> None:
        """Open the session; raises :class:`LinkError` (classified as the window link's:
        :mod:`server.links.opcualogin`)."""
        await self._open(self._password)

    async def read(self) -> dict[str, dict[int, float]]:
        """What the NC holds per axis and datum, in one Read request; raises
        :class:`LinkError`."""
        params = ua.ReadParameters()
        keys = [(a, n) for a in self.axes for n in _NAMES]
        for a, n in keys:
            rv = ua.ReadValueId()
            rv.NodeId = self.node(a, n)
            rv.AttributeId = AttributeIds.Value
            params.NodesToRead.append(rv)
        values = await self._ask(lambda: self._session().uaclient.read(params),
                                 f"{self.endpoint}: read of SD4390x", "SinuReadAll", _WHY)
        out: dict[str, dict[int, float]] = {a: {} for a in self.axes}
        for (a, n), dv in zip(keys, values, strict=True):
            if dv.StatusCode is not None and not dv.StatusCode.is_good():
                raise status_error(dv.StatusCode.name,
                                   f"{self.endpoint}: read of SD{n} axis {a}",
                                   user=self.user, right="SinuReadAll", hints=_WHY)
            v = dv.Value.Value if dv.Value is not None else None
            if not isinstance(v, float | int) or isinstance(v, bool):
                raise LinkError(f"{self.endpoint}: SD{n} axis {a} holds "
                                f"{type(v).__name__}, not a number")
            out[a][n] = float(v)
        return out

    async def write(self, writes: Sequence[SdWrite]) -> list[WriteOutcome]:
        """Write every datum of ``writes`` in one Write request; per axis what the NC
        answered. Raises :class:`LinkError` when the request itself fails, or the user
        lacks ``SeaWrite`` (that is the login's, not an axis's refusal: the window link
        ends its session on it too)."""
        params = ua.WriteParameters()
        owners: list[tuple[int, int]] = []
        for i, w in enumerate(writes):
            for n, v in w.values:
                wv = ua.WriteValue()
                wv.NodeId = self.node(w.axis, n)
                wv.AttributeId = AttributeIds.Value
                wv.Value = ua.DataValue(ua.Variant(float(v), ua.VariantType.Double))
                params.NodesToWrite.append(wv)
                owners.append((i, n))
        if not owners:
            return []
        codes = await self._ask(lambda: self._session().uaclient.write(params),
                                f"{self.endpoint}: write of SD4390x", "SeaWrite", _WHY)
        if any(c is not None and c.name == "BadUserAccessDenied" for c in codes):
            raise status_error("BadUserAccessDenied", f"{self.endpoint}: write of SD4390x",
                               user=self.user, right="SeaWrite")
        errors: dict[int, list[str]] = {}
        for (i, n), code in zip(owners, codes, strict=True):
            if code is not None and not code.is_good():
                errors.setdefault(i, []).append(
                    f"SD{n}: {_WHY.get(code.name, 'refused')} ({code.name})")
        return [WriteOutcome(w, None if i not in errors else
                             f"axis {w.axis}: " + "; ".join(errors[i]))
                for i, w in enumerate(writes)]


class SdFollower:
    """Keeps one machine's SD43900/43910/43920 current (module docstring).

    Parameters
    ----------
    name : str
        The machine's name (for logs).
    session : SdSession
    terms : iterable
        The model's terms (its thermal terms are used).
    limits : TempCompLimits, optional
    min_interval_s : float
        At most one write per axis per this, s.
    backoff : Backoff, optional
        Waits after failures in a row (default: the window links',
        :data:`~server.links.pacing.BACKOFF`, 4, 12, 36, 60 s); only a session that
        stayed up :data:`~server.links.pacing.HEALTHY_AFTER_S` starts it afresh.
    clock : callable
        Seconds, monotonic (the planner's time).
    events : FollowerEvents, optional
    refused_hold_s : float
        A write the NC refused is tried again after this, s (its machine data may change).
    verify_s : float
        What the NC holds is read back this often, s, and written again where it differs.
    """

    def __init__(self, name: str, session: SdSession, terms: Iterable[object] = (), *,
                 limits: TempCompLimits | None = None, min_interval_s: float = 0.1,
                 backoff: Backoff | None = None,
                 clock: Callable[[], float] = time.monotonic,
                 events: FollowerEvents | None = None,
                 refused_hold_s: float = 10.0, verify_s: float = 10.0) -> None:
        self.name = name
        self.events = events
        self.refused_hold_s = float(refused_hold_s)
        self.verify_s = float(verify_s)
        self._verified_s = float("-inf")
        self.session = session
        self.limits = limits or TempCompLimits()
        self.planner = SdWritePlanner(session.axes, limits=self.limits,
                                      min_interval_s=min_interval_s)
        self.backoff = backoff or BACKOFF
        self.clock = clock
        self._terms = tuple(terms)
        self._temps: dict[str, float] = {}
        self._wake = asyncio.Event()
        self._task: asyncio.Task[None] | None = None
        self._rng = random.Random()
        self.writes: list[WriteOutcome] = []
        """Every write sent and its answer (the last 1,000)."""
        self.last_error: str | None = None
        self.waiting: dict[str, tuple[str, ...]] = {}
        """Axes held at what the NC has, with the temperatures they lack."""
        self.connected = False
        self.nc_holds: dict[str, dict[int, float]] = {}
        """What the NC holds per axis and datum: read at connect, updated by writes."""

    # -- inputs

    def set_terms(self, terms: Iterable[object]) -> None:
        """The model changed: its terms from now on."""
        self._terms = tuple(terms)
        self._wake.set()

    def set_temperature(self, column: str, celsius: float) -> None:
        """A new reading (°C by column, ``T_spindle_C``)."""
        self._temps[column] = float(celsius)
        self._wake.set()

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        self._temps.update({k: float(v) for k, v in temperatures.items()})
        self._wake.set()

    # -- the loop

    async def __aenter__(self) -> SdFollower:
        self._task = asyncio.create_task(self._run(), name=f"{self.name}:sinumerik-sd")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
        await self.session.close()

    async def _run(self) -> None:
        attempt = 0
        since = 0.0
        while True:
            try:
                await self.session.connect()
                held = await self.session.read()
                self._verified_s = since = self.clock()
                for axis, values in held.items():
                    self.planner.held(axis, values)
                self.connected = True
                self.nc_holds = held
                if self.events is not None:
                    self.events.connected()
                    self.events.held(held)
                await self._follow()
            except LinkError as exc:
                if str(exc) != self.last_error:
                    log.warning("%s: native SINUMERIK link: %s", self.name, exc)
                if self.events is not None and (self.connected or str(exc) != self.last_error):
                    self.events.lost(exc.condition)
                if self.connected and self.clock() - since >= HEALTHY_AFTER_S:
                    attempt = 0  # the session proved the link: this failure is news
                self.connected = False
                self.last_error = str(exc)
                await self.session.close()
                # paced as the window links are (issue 30: no storms): a login refused
                # once is refused again, and a session that opens and fails at its first
                # write (a user without SeaWrite) must not reset the backoff
                await asyncio.sleep(self.backoff.delay(attempt, self._rng))
                attempt = min(attempt + 1, 16)

    def _plan(self) -> None:
        try:
            got = temp_comp_setting_data(self._terms, self._temps, self.session.axes,
                                         self.limits)
        except ValueError as exc:  # a term on an axis the NC lacks: the model is wrong
            if str(exc) != self.last_error:
                log.warning("%s: %s", self.name, exc)
            self.last_error = str(exc)
            return
        self.waiting = got.waiting
        self.planner.want(got.axes)

    async def _follow(self) -> None:
        while True:
            self._wake.clear()
            self._plan()
            due = self.planner.due(self.clock())
            if due:
                try:
                    outcomes = await self.session.write(due)
                except LinkError:
                    now = self.clock()
                    for w in due:
                        self.planner.failed(w, now)
                    raise
                now = self.clock()
                for o in outcomes:
                    if o.error is None:
                        self.planner.sent(o.write, now)
                        self.nc_holds.setdefault(o.write.axis, {}).update(o.write.values)
                        continue
                    self.planner.failed(o.write, now, self.refused_hold_s)
                    if o.error != self.last_error:
                        log.warning("%s: %s", self.name, o.error)
                        if self.events is not None:
                            self.events.refused(o.error)
                    self.last_error = o.error
                self.writes = [*self.writes[-999:], *outcomes]
                if self.events is not None:
                    self.events.held(self.nc_holds)
            now = self.clock()
            if now - self._verified_s >= self.verify_s:
                # read back what the NC holds: a value changed at the machine (an operator,
                # a restored archive) is written again, and a dead session shows here
                held = await self.session.read()
                self._verified_s = self.clock()
                for axis, values in held.items():
                    self.planner.held(axis, values)
                self.nc_holds = held
                if self.events is not None:
                    self.events.held(held)
                continue
            wake_at = [self._verified_s + self.verify_s]
            nxt = self.planner.next_due_s()
            if nxt is not None:
                wake_at.append(nxt)
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(max(0.0, min(wake_at) - now)):
                    await self._wake.wait()
