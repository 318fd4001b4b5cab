"""Helpers of the whole-system tests (``tests/test_integration_*.py``).

A :func:`center` is ``ednc serve``'s app (``create_app`` with ``machine_services``) with its
lifespan running, a REST client talking to it in-process (with the API key), and the
machine TCP server on a real loopback port. Simulated machines (:func:`cnc`) connect to
it over TCP, each from its own loopback address (127.0.2.x). A :class:`Relay` sits between
a machine and the center when a test needs to cut the link or tamper with frames.

The fleet (:data:`FLEET`) is the demo fleet's mix (``ednc.fleet``): Fanuc and Siemens,
three 3-axis chains, a 5-axis machine and the two-spindle arch machine, plus a sixth
3-axis machine. Each machine's simulated laser campaign is computed once per session
(:func:`campaign`).
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import io
import socket
import struct
import uuid
import zlib
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import aiomqtt
import httpx
import numpy as np
from fastapi import FastAPI

from ednc.fleet import demo_fleet
from machine_sim.campaign import standard_campaign
from machine_sim.effects import Effects, Noise, ThermalDrift
from machine_sim.fanuc import FanucConfig
from machine_sim.instruments import SimulatedMachine
from machine_sim.link import MqttTarget, SimulatedCNC
from machine_sim.lookup import ActiveMap, FactoredLadder, GridLadder, GridMap
from machine_sim.runtime import MachineRuntime
from machine_sim.truth import random_geometry
from protocol.backoff import Backoff
from protocol.codes import MessageType
from server.app import create_app
from server.center import Center
from server.links.ednc import LinkTiming
from server.numeric import plain_json
from server.services import MachineServices, machine_services
from server.settings import load_settings
from tests.support.services import require
from volumetric.diagnose.diagnosis import diagnose
from volumetric.measure.measurement import Measurements, write_measurements
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import MachineModel, ThermalTerm

API_KEY = "integration-api-key-0123"
WRITE = {"X-API-Key": API_KEY}
DEADLINE_S = 300.0  # a hang guard, not a speed requirement (CI machines are shared)
TOLERANCE_UM = 1.0
"""Map tolerance of the test centers. The 5-axis machine is Siemens-style and gets a tables
map (a few kB, well under a second); a 5-axis *grid* at 1 µm would take ~25 s to build."""
HEARTBEAT_S = 0.5
NOISE = Noise(0.2, 0.3)
FAST_MQTT = {"backoff": Backoff(initial_s=0.05, cap_s=0.2), "stale_check_s": 0.05}
"""The MQTT bridge's options in tests: reconnect and notice staleness within 0.2 s."""
TRAVEL = {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}


@dataclass(frozen=True)
class Spec:
    """One machine of a test fleet: description, secret, simulation seed, hidden physics."""

    description: dict[str, Any]
    secret: str
    seed: int
    effects: Effects = field(default_factory=lambda: Effects(noise=NOISE))

    @property
    def name(self) -> str:
        return str(self.description["name"])

    @property
    def ip(self) -> str:
        return str(self.description["ip"])

    @property
    def machine(self) -> Machine:
        return parse_machine(self.description)


def _fleet() -> tuple[Spec, ...]:
    out = []
    for i, fm in enumerate(demo_fleet()):
        d = {**fm.description, "ip": f"127.0.2.{i + 1}"}
        if d["name"] == "5ax-04":
            # both rotary axes through the table centre, fixed here so the figures of these
            # tests do not move with the demo's choice (the R-tests need a reachable ball)
            d["pivots_mm"] = {"C": [400.0, 300.0, -200.0], "A": [400.0, 300.0, -150.0]}
        out.append(Spec(d, f"secret-of-{d['name']}-0123456789", fm.seed))
    out.append(Spec({"name": "vmc-06", "controller": "siemens", "ip": "127.0.2.6",
                     "chain": "w X b Y Z t", "travel_mm": TRAVEL, "tool_length_mm": 100.0},
                    "secret-of-vmc-06-0123456789", 16))
    return tuple(out)


FLEET = _fleet()
"""vmc-01 (Siemens, w X Y b Z t), gantry-02 (Fanuc, w b Y X Z t), hmc-03 (Fanuc, type 3),
5ax-04 (Siemens, w C A X b Y Z t), arch-05 (Fanuc, two spindles), vmc-06 (Siemens,
w X b Y Z t)."""

THERMAL = Spec({"name": "hot-07", "controller": "fanuc", "ip": "127.0.2.7",
                "chain": "w X Y b Z t", "travel_mm": TRAVEL, "tool_length_mm": 100.0},
               "secret-of-hot-07-0123456789", 17,
               Effects(drift=(ThermalDrift("z", "spindle", -2.5, reference_C=20.0),),
                       noise=NOISE))
"""A Fanuc machine whose spindle grows along z (-2.5 µm/K), for the thermal tests."""

THERMAL_TABLES = Spec({**THERMAL.description, "name": "hot-08", "controller": "siemens",
                       "ip": "127.0.2.8"},
                      "secret-of-hot-08-0123456789", 18, THERMAL.effects)
"""The same spindle growth on a Siemens-style machine: it gets a tables map, which carries
the thermal terms, and its temperatures come from MQTT through the center."""


FANUC_5AX = Spec({**next(s for s in FLEET if s.name == "5ax-04").description,
                  "name": "5ax-09", "controller": "fanuc", "ip": "127.0.2.9"},
                 "secret-of-5ax-09-0123456789", 19)
"""The fleet's 5-axis chain and pivots under a Fanuc-style ladder (it gets a factored map:
its grid's rotary corrections, rounded to 0.001°, would miss by micrometres)."""


def diagnosed_spindle(s: Spec) -> tuple[MachineModel, ThermalTerm]:
    """The diagnosis of ``s``'s campaign, which must find its spindle growing along z on
    ``T_spindle_C``: the model and its one thermal term."""
    sim, readings, _ = campaign(s.name)
    d = diagnose(sim.machine, readings)
    assert (d.effect, d.axis, d.sensor) == ("thermal_drift", "z", "T_spindle_C"), d
    terms = [t for t in d.model.terms if isinstance(t, ThermalTerm)]
    assert len(terms) == 1 and terms[0].sensor == "T_spindle_C", terms
    return d.model, terms[0]


def spec(name: str) -> Spec:
    for s in (*FLEET, THERMAL, THERMAL_TABLES, FANUC_5AX):
        if s.name == name:
            return s
    raise KeyError(name)


@functools.cache
def campaign(name: str) -> tuple[SimulatedMachine, Measurements, str]:
    """The simulated machine, its standard laser campaign and that campaign as CSV text
    (computed once per test session: the simulation is deterministic by seed)."""
    s = spec(name)
    m = s.machine
    rng = np.random.default_rng(s.seed)
    sim = SimulatedMachine(m, random_geometry(m, rng, scale=2.0), s.effects, seed=s.seed)
    readings = standard_campaign(sim, rng)
    buf = io.StringIO()
    write_measurements(buf, readings)
    return sim, readings, buf.getvalue()


def require_loopback_aliases() -> None:
    ok = True
    with socket.socket() as s:
        try:
            s.bind(("127.0.2.1", 0))
        except OSError:
            ok = False
    require("loopback aliases", ok, "127.0.0.0/8 must all be loopback")


# -- the center

@dataclass
class Plant:
    """A running center: the app, a REST client with the API key, the machine services."""

    app: FastAPI
    client: httpx.AsyncClient
    services: MachineServices

    @property
    def center(self) -> Center:
        center = self.app.state.center
        assert isinstance(center, Center)
        return center

    @property
    def port(self) -> int:
        return self.services.server.port

    async def register(self, s: Spec) -> None:
        r = await self.client.post("/api/machines", json={**s.description, "secret": s.secret})
        assert r.status_code == 201, r.text

    async def fit_from_campaign(self, name: str) -> int:
        """Upload the machine's campaign and fit its model through the REST API; the
        model version."""
        _, _, text = await asyncio.to_thread(campaign, name)
        r = await self.client.post(f"/api/machines/{name}/measurements",
                                   params={"set_name": "campaign"}, content=text,
                                   headers={"Content-Type": "text/csv"})
        assert r.status_code == 201, r.text
        r = await self.client.post(f"/api/machines/{name}/models/fit",
                                   json={"measurement_sets": ["campaign"]})
        assert r.status_code == 201, r.text
        return int(r.json()["version"])

    async def post_model(self, name: str, body: dict[str, Any]) -> int:
        r = await self.client.post(f"/api/machines/{name}/models",
                                   json={"source": "upload", "body": body})
        assert r.status_code == 201, r.text
        return int(r.json()["version"])

    async def status(self, name: str) -> dict[str, Any]:
        r = await self.client.get(f"/api/machines/{name}/status")
        assert r.status_code == 200, r.text
        body: dict[str, Any] = r.json()
        return body

    async def deliveries(self, name: str) -> list[dict[str, Any]]:
        r = await self.client.get(f"/api/machines/{name}/deliveries")
        assert r.status_code == 200, r.text
        rows: list[dict[str, Any]] = r.json()
        return rows

    async def maps(self, name: str) -> list[dict[str, Any]]:
        r = await self.client.get(f"/api/machines/{name}/maps")
        assert r.status_code == 200, r.text
        rows: list[dict[str, Any]] = r.json()
        return rows

    async def events(self, **params: Any) -> list[dict[str, Any]]:
        r = await self.client.get("/api/events", params={"limit": 1000, **params})
        assert r.status_code == 200, r.text
        rows: list[dict[str, Any]] = r.json()
        return rows

    async def metric(self, name: str, **labels: str) -> float:
        """One sample of ``/metrics`` (0 when absent)."""
        r = await self.client.get("/metrics")
        assert r.status_code == 200, r.text
        want = name + ("{" + ",".join(f'{k}="{v}"' for k, v in labels.items()) + "}"
                       if labels else "")
        for line in r.text.splitlines():
            key, _, value = line.rpartition(" ")
            if key == want:
                return float(value)
        return 0.0

    async def applied_version(self, name: str) -> int | None:
        v = (await self.status(name))["map_version_applied"]
        return None if v is None else int(v)

    def applied(self, name: str, version: int) -> Callable[[], Awaitable[bool]]:
        """A check for :func:`until`: the database shows ``version`` applied by ``name``."""

        async def check() -> bool:
            return await self.applied_version(name) == version

        return check

    async def current_applied(self, name: str) -> bool:
        """The machine has applied the newest map built for it."""
        st = await self.status(name)
        latest = st["map_version_latest"]
        return latest is not None and st["map_version_applied"] == latest


@asynccontextmanager
async def center(database_url: str, *, machine_port: int = 0,
                 mqtt: tuple[str, int] | None = None, prefix: str = "ednc",
                 machines_file: Path | None = None, period_s: float = 1.0,
                 stale_after_s: float = 60.0,
                 mqtt_options: dict[str, Any] | None = None) -> AsyncIterator[Plant]:
    """``ednc serve``'s app and services, lifespan running, machine port on loopback."""
    settings = load_settings(
        database_url=database_url, api_key=API_KEY, machine_host="127.0.0.1",
        machine_port=machine_port, heartbeat_s=HEARTBEAT_S, push_period_s=period_s,
        mqtt_host=mqtt[0] if mqtt else None, mqtt_port=mqtt[1] if mqtt else 1883,
        mqtt_topic_prefix=prefix, machines_file=machines_file)
    found: dict[str, MachineServices] = {}

    @asynccontextmanager
    async def services(c: Center) -> AsyncIterator[MachineServices]:
        timing = LinkTiming(handshake_s=5.0, heartbeat_s=HEARTBEAT_S, telemetry_period_ms=100)
        async with machine_services(c, timing=timing, stale_after_s=stale_after_s,
                                    push_options={"tolerance_um": TOLERANCE_UM},
                                    mqtt_options=mqtt_options) as svc:
            found["svc"] = svc
            yield svc

    app = create_app(settings, services=[services])
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://center",
                                     headers=WRITE, timeout=120) as client:
            yield Plant(app, client, found["svc"])


def machines_file(path: Path, specs: list[Spec]) -> Path:
    """A machines file (``EDNC_MACHINES_FILE``) naming ``specs``."""
    import json

    path.write_text(json.dumps({"machines": [{"machine": s.description, "secret": s.secret}
                                             for s in specs]}))
    return path


# -- machines

def cnc(s: Spec, port: int, *, secret: str | None = None, ip: str | None = None,
        host: str = "127.0.0.1", mqtt: MqttTarget | None = None,
        own_sensors: bool | None = None, thermal_records: bool = True,
        factored: bool = True) -> SimulatedCNC:
    """The simulated CNC of ``s`` connecting to ``host:port`` from its own address;
    ``thermal_records=False``: a Fanuc ladder that takes version-1 grids only (the center
    rebuilds its map when a temperature moves); ``factored=False``: one that takes grids,
    not factored maps."""
    m = s.machine
    runtime = MachineRuntime(m, seed=s.seed,
                             fanuc=FanucConfig(max_step_counts=1000,
                                               thermal_records=thermal_records,
                                               factored=factored and thermal_records),
                             own_sensors=own_sensors)
    return SimulatedCNC(m, (host, port), (secret or s.secret).encode(), runtime=runtime,
                        ip=ip, cycle_s=0.02,
                        backoff=Backoff(initial_s=0.05, factor=2.0, cap_s=0.5), mqtt=mqtt)


async def mqtt_plant(stack: contextlib.AsyncExitStack, tmp_path: Path,
                     broker: tuple[str, int], prefix: str) -> tuple[Plant, aiomqtt.Client]:
    """A center on SQLite in ``stack`` whose MQTT bridge is connected under ``prefix``
    (fast reconnects and stale checks), and a client to publish with."""
    plant = await stack.enter_async_context(center(
        f"sqlite:///{tmp_path / 'center.db'}", mqtt=broker, prefix=prefix,
        mqtt_options=FAST_MQTT))
    pub = await stack.enter_async_context(aiomqtt.Client(
        *broker, identifier=f"it-{uuid.uuid4().hex[:8]}"))
    assert plant.services.mqtt is not None
    await plant.services.mqtt.connected.wait()
    return plant, pub


async def with_model(stack: contextlib.AsyncExitStack, plant: Plant, s: Spec,
                     model: MachineModel, **options: Any) -> SimulatedCNC:
    """``s`` registered with ``model``, its simulated CNC (``cnc`` with ``options``)
    connected in ``stack`` and holding map version 1."""
    await plant.register(s)
    await plant.post_model(s.name, plain_json(model.to_json()))
    sim = await stack.enter_async_context(cnc(s, plant.port, **options))
    await sim.ready.wait()
    await until(lambda: sim.runtime.controller.store.version == 1)
    return sim


def before_rounding(active: ActiveMap, q: np.ndarray) -> np.ndarray:
    """A machine's map corrections at positions ``q`` (N, inputs) before its ladder rounds
    them, with the thermal part it holds now, mm (N, K)."""
    if isinstance(active, FactoredLadder):
        d = len(active.outputs)
        out: np.ndarray = active.fields(q)[:, :d] + active.thermal_mm[0] + \
            active.thermal_mm[1] * q
        return out
    if isinstance(active, GridLadder):  # the interpolation before the ladder rounds it
        return GridMap.lookup(active, q)
    return active.lookup(q)


async def until(check: Callable[[], Awaitable[bool]] | Callable[[], bool],
                step_s: float = 0.05) -> None:
    """Poll ``check`` until it holds (the caller's asyncio.timeout bounds the wait)."""
    while True:
        result = check()
        if not isinstance(result, bool):
            result = await result
        if result:
            return
        await asyncio.sleep(step_s)


# -- a relay between a machine and the center

FrameHook = Callable[[int, bytes], bytes | None]
"""Center → machine frames: ``hook(kind, payload)`` returns a new payload or None (keep)."""

_HEAD = struct.Struct(">4sBBHII")
_CRC = struct.Struct(">I")


def reframe(frame: bytes, hook: FrameHook) -> bytes:
    """One whole frame after ``hook``: a changed payload gets its length and CRC fixed, so
    the frame layer passes it and only the layer above can tell."""
    head = frame[:_HEAD.size]
    magic, version, kind, flags, seq, length = _HEAD.unpack(head)
    payload = frame[_HEAD.size:_HEAD.size + length]
    new = hook(kind, payload)
    if new is None:
        return frame
    head = _HEAD.pack(magic, version, kind, flags, seq, len(new))
    return head + new + _CRC.pack(zlib.crc32(head + new))


class Relay:
    """Listen on 127.0.0.1 (port 0) and forward each connection to the center from
    ``source`` (the machine's address); can be cut and restored on the same port, and can
    pass the center's frames through a :data:`FrameHook`."""

    def __init__(self, center_port: int, source: str) -> None:
        self.center_port = center_port
        self.source = source
        self.port = 0
        self.hook: FrameHook | None = None
        self._server: asyncio.Server | None = None
        self._writers: set[asyncio.StreamWriter] = set()
        self._tasks: set[asyncio.Task[None]] = set()

    async def start(self) -> None:
        self._server = await asyncio.start_server(self._handle, "127.0.0.1", self.port)
        self.port = int(self._server.sockets[0].getsockname()[1])

    async def stop(self) -> None:
        """Stop listening and cut every forwarded connection."""
        if self._server is not None:
            self._server.close()
            self._server = None
        for w in list(self._writers):
            w.close()
        for t in list(self._tasks):
            t.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)

    async def __aenter__(self) -> Relay:
        await self.start()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.stop()

    async def _up(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        with contextlib.suppress(OSError, ConnectionError):
            while data := await reader.read(65536):
                writer.write(data)
                await writer.drain()
        writer.close()

    async def _down(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        buf = b""
        with contextlib.suppress(OSError, ConnectionError):
            while data := await reader.read(65536):
                buf += data
                out = b""
                while len(buf) >= _HEAD.size:
                    length = _HEAD.unpack(buf[:_HEAD.size])[5]
                    end = _HEAD.size + length + _CRC.size
                    if len(buf) < end:
                        break
                    frame, buf = buf[:end], buf[end:]
                    out += frame if self.hook is None else reframe(frame, self.hook)
                writer.write(out)
                await writer.drain()
        writer.close()

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        assert task is not None
        self._tasks.add(task)
        try:
            up_reader, up_writer = await asyncio.open_connection(
                "127.0.0.1", self.center_port, local_addr=(self.source, 0))
        except OSError:
            writer.close()
            self._tasks.discard(task)
            return
        self._writers |= {writer, up_writer}
        try:
            await asyncio.gather(self._up(reader, up_writer), self._down(up_reader, writer))
        except asyncio.CancelledError:
            writer.close()
            up_writer.close()
        finally:
            self._writers -= {writer, up_writer}
            self._tasks.discard(task)


def map_chunk_hook(version: int, change: Callable[[bytes], bytes]) -> FrameHook:
    """A hook passing the data of every MapChunk of map ``version`` through ``change``."""

    def hook(kind: int, payload: bytes) -> bytes | None:
        if kind != MessageType.MAP_CHUNK:
            return None
        v, _index = struct.unpack(">II", payload[:8])
        if v != version:
            return None
        return payload[:8] + change(payload[8:])

    return hook


DIAGONALS = ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN")


def check_diagonals(sim: SimulatedMachine, received: ActiveMap, label: str,
                    increment_mm: float | None = 0.001) -> None:
    """ISO 230-6 body diagonals on the true machine, without and with the shifts the
    controller computes from the map it received (rounded to ``increment_mm``, a Fanuc
    PMC's; None for a Siemens NC's float values): 95 % better overall."""
    from machine_sim.campaign import map_compensation, run_campaign
    from machine_sim.testprograms import diagonal_test
    from volumetric.verify.iso230_6 import diagonal_ranges, improvement

    m = sim.machine
    programs = [diagonal_test(m, d, points=20, runs=2) for d in DIAGONALS]
    before = diagonal_ranges(run_campaign(sim, programs).measurements)
    comp = map_compensation(m, received, increment_mm=increment_mm)
    after = diagonal_ranges(run_campaign(sim, programs, compensation=comp).measurements)
    gain = improvement(before, after)
    print(f"\n{m.name} {label}: ranges before "
          f"{ {k: round(v, 1) for k, v in before.items()} } µm, after "
          f"{ {k: round(v, 2) for k, v in after.items()} } µm")
    assert max(before.values()) > 20.0
    assert gain["overall"] >= 0.95, gain


async def applied_map(plant: Plant, store: Any, name: str) -> ActiveMap:
    """The map a machine applies once the center shows its newest map applied
    (``store``: the controller's map store)."""
    await until(lambda: plant.current_applied(name))
    await until(lambda: store.version >= 1)
    active: ActiveMap | None = store.active
    assert active is not None
    return active


async def follow_temperatures(plant: Plant, controller: Any, name: str, sensor: str,
                              read: Callable[[], float]) -> list[float]:
    """Post 20, 25 and 30 °C of ``sensor`` to the center for ``name``; after each, wait
    until the controller holds it and its cycles folded it into what ``read`` gives (the
    z correction at a point); the three values read."""
    seen: list[float] = []
    for celsius in (20.0, 25.0, 30.0):
        r = await plant.client.post(f"/api/machines/{name}/temperatures",
                                    json={"readings": [{"sensor": sensor,
                                                        "celsius": celsius}]})
        assert r.status_code == 200, r.text
        await until(lambda c=celsius: abs(
            controller.temperatures.values().get(f"T_{sensor}_C", -1) - c) < 1e-6)
        if seen:  # the next cycles fold the new temperature in
            await until(lambda: read() != seen[-1])
        else:
            await asyncio.sleep(0.3)
        seen.append(read())
    return seen
