"""A running center for the machine-link tests: ``rig`` (database, center and machine
services on port 0), simulated and hand-driven machines, a small error model, and
``until`` for polling under a deadline."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from machine_sim.fanuc import FanucConfig
from machine_sim.link import MqttTarget, SimulatedCNC
from machine_sim.runtime import MachineRuntime
from protocol import (
    NEED_DATA,
    AuthResponse,
    Challenge,
    Connection,
    Controller,
    Hello,
    MapEncoding,
    Message,
    Role,
    compute_mac,
)
from protocol.backoff import Backoff
from server.center import Center
from server.db import Database
from server.db import error_models as model_repo
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.events import EventKind
from server.links.ednc import LinkTiming
from server.services import MachineServices, machine_services
from server.settings import load_settings
from volumetric.model.machine import parse_machine

SECRET = "machine-secret-0123456789"


DEADLINE_S = 20.0  # a hang guard, not a speed requirement


def description(name: str = "vmc-01", controller: str = "fanuc",
                ip: str = "127.0.0.1") -> dict[str, Any]:
    return {"name": name, "controller": controller, "ip": ip, "chain": "w X Y b Z t",
            "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
            "tool_length_mm": 100.0}


def model_body(name: str = "vmc-01", slope: float = 0.01, *,
               thermal_sensor: str | None = None) -> dict[str, Any]:
    """A small model: a scale error of X, plus a spindle drift along z when asked."""
    terms = []
    if thermal_sensor is not None:
        terms.append({"effect": "thermal_drift", "axis": "z", "sensor": thermal_sensor,
                      "coefficient": 1.5, "t_ref_C": 20.0, "q_min": 0.0})
    return {"format": "ednc-model/1", "machine": name,
            "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, slope, 1e-5],
                                   "origin": 0.0, "scale": 1.0}},
            "locations": {}, "terms": terms, "info": {}}


@dataclass
class Rig:
    """A running center: database, Center and the machine services on port 0."""

    center: Center
    services: MachineServices

    @property
    def db(self) -> Database:
        return self.center.db

    @property
    def port(self) -> int:
        return self.services.server.port

    async def register(self, name: str = "vmc-01", *, controller: str = "fanuc",
                       ip: str = "127.0.0.1", secret: str = SECRET,
                       model: dict[str, Any] | None = None) -> int:
        row = await self.db.run(machine_repo.create_machine, name=name, ip=ip,
                                controller=controller,
                                description=description(name, controller, ip), secret=secret)
        if model is not None:
            await self.db.run(model_repo.add_model, row.id, source="upload", body=model)
        return row.id

    async def events(self, kind: EventKind | None = None) -> list[Any]:
        return await self.db.run(event_repo.list_events,
                                 kind=kind.value if kind else None, limit=1000)

    async def wait_events(self, kind: EventKind) -> list[Any]:
        """The events of ``kind`` once there is one (they are stored after the reply)."""
        while not (found := await self.events(kind)):
            await asyncio.sleep(0.02)
        return found

    async def acked_version(self, machine_id: int) -> int | None:
        row = await self.db.run(map_repo.latest_acked, machine_id)
        return None if row is None else row.map_version


@asynccontextmanager
async def rig(tmp_path: Path, *, heartbeat_s: float = 0.5, handshake_s: float = 2.0,
              mqtt: tuple[str, int] | None = None, prefix: str = "ednc",
              mqtt_options: dict[str, Any] | None = None, max_handshakes: int = 2048,
              **push: Any) -> AsyncIterator[Rig]:
    settings = load_settings(
        database_url=f"sqlite:///{tmp_path / 'center.db'}", machine_host="127.0.0.1",
        machine_port=0, heartbeat_s=heartbeat_s, push_period_s=push.pop("period_s", 600.0),
        mqtt_host=mqtt[0] if mqtt else None, mqtt_port=mqtt[1] if mqtt else 1883,
        mqtt_topic_prefix=prefix, leases="on")  # as several nodes would, also on SQLite
    async with Database.open(settings.database_url) as db:
        center = Center(settings=settings, db=db)
        timing = LinkTiming(handshake_s=handshake_s, heartbeat_s=heartbeat_s,
                            telemetry_period_ms=50)
        stale_after_s = push.pop("stale_after_s", 60.0)
        async with machine_services(center, timing=timing, push_options=push,
                                    mqtt_options=mqtt_options, max_handshakes=max_handshakes,
                                    stale_after_s=stale_after_s) as svc:
            yield Rig(center, svc)


def simulator(port: int, name: str = "vmc-01", *, controller: str = "fanuc",
              secret: str = SECRET, ip: str | None = None,
              mqtt: MqttTarget | None = None, thermal_records: bool = True,
              factored: bool = True) -> SimulatedCNC:
    """A simulated CNC; ``thermal_records=False``: a Fanuc ladder that takes version-1
    grids only (the center then rebuilds its map on temperature changes);
    ``factored=False``: one that does not declare factored maps (it gets grids)."""
    m = parse_machine(description(name, controller, ip or "127.0.0.1"))
    runtime = MachineRuntime(m, seed=1, fanuc=FanucConfig(max_step_counts=1000,
                                                          thermal_records=thermal_records,
                                                          factored=factored))
    return SimulatedCNC(m, ("127.0.0.1", port), secret.encode(), runtime=runtime,
                        cycle_s=0.004, backoff=Backoff(initial_s=0.05, factor=2.0, cap_s=0.2),
                        mqtt=mqtt)


async def until(check: Callable[[], Awaitable[bool]] | Callable[[], bool],
                step_s: float = 0.02) -> None:
    """Poll ``check`` until it holds (the caller's asyncio.timeout bounds the wait)."""
    while True:
        result = check()
        if not isinstance(result, bool):
            result = await result
        if result:
            return
        await asyncio.sleep(step_s)


class RawMachine:
    """A hand-driven machine end (sans-I/O codec over a real socket)."""

    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader, self.writer = reader, writer
        self.conn = Connection(Role.MACHINE)

    @classmethod
    async def connect(cls, port: int) -> RawMachine:
        return cls(*await asyncio.open_connection("127.0.0.1", port))

    async def send(self, msg: Message) -> None:
        self.writer.write(self.conn.send(msg))
        await self.writer.drain()

    async def next(self) -> Message | None:
        """The next message, or None when the center closed the connection."""
        while True:
            event = self.conn.next_event()
            if event is NEED_DATA:
                self.conn.receive_data(await self.reader.read(65536))
                continue
            if not isinstance(event, Message):  # CONNECTION_CLOSED
                return None
            return event

    async def login(self, name: str = "vmc-01", secret: str = SECRET,
                    ip: str = "127.0.0.1") -> Message | None:
        await self.send(Hello(name, ip, Controller.FANUC, MapEncoding.INT32_INCREMENTS,
                              "raw-1", "w X Y b Z t"))
        challenge = await self.next()
        if not isinstance(challenge, Challenge):
            return challenge
        await self.send(AuthResponse(compute_mac(secret.encode(), challenge.nonce, name)))
        return await self.next()

    async def closed(self) -> bytes:
        """Everything the center still sends until it closes."""
        return await self.reader.read()

    def close(self) -> None:
        self.writer.close()
