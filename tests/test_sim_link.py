"""Simulated CNCs on a real socket against a minimal in-test center (port 0): handshake
with the secret, map push and ack, telemetry, heartbeats, release, bad push, reconnect."""

from __future__ import annotations

import asyncio
import random
from collections.abc import AsyncIterator

import numpy as np
import pytest

from machine_sim.fanuc import FanucConfig
from machine_sim.fleet import Fleet, generated_fleet
from machine_sim.link import MqttTarget, SimulatedCNC
from machine_sim.runtime import MachineRuntime
from protocol import (
    ErrorMapPayload,
    GridAxis,
    Heartbeat,
    HeartbeatReply,
    MapAck,
    MapEncoding,
    MapReject,
    MapRejectReason,
    Message,
    OutputAxis,
    ReleaseCompensation,
    Released,
    Telemetry,
    encode_map,
    split_into_chunks,
)
from protocol.backoff import Backoff
from tests.support.sim_link import SECRET, MiniCenter, Session
from volumetric.model.machine import Machine, parse_machine

DEADLINE_S = 20.0  # a hang guard, not a speed requirement


def machine(controller: str, name: str = "sim-01") -> Machine:
    return parse_machine({"name": name, "controller": controller, "ip": "127.0.0.1",
                          "chain": "w X Y b Z t",
                          "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
                          "tool_length_mm": 100.0})


@pytest.fixture
async def center() -> AsyncIterator[MiniCenter]:
    c = MiniCenter(SECRET)
    server = await asyncio.start_server(c.handle, "127.0.0.1", 0)
    c.port = server.sockets[0].getsockname()[1]
    async with server:
        yield c


def cnc(m: Machine, port: int, secret: bytes = SECRET, **kw: object) -> SimulatedCNC:
    runtime = MachineRuntime(m, seed=1, fanuc=FanucConfig(max_step_counts=1000))
    return SimulatedCNC(m, ("127.0.0.1", port), secret, runtime=runtime, cycle_s=0.004,
                        backoff=Backoff(initial_s=0.02, factor=2.0, cap_s=0.1), **kw)  # type: ignore[arg-type]


def map_payload(name: str, value: float, encoding: MapEncoding, version: int = 1
                ) -> ErrorMapPayload:
    grid = (GridAxis("X", 0.0, 250.0, 3), GridAxis("Y", 0.0, 300.0, 2))
    int32 = encoding is MapEncoding.INT32_INCREMENTS
    vals = np.full((6, 3), round(value * 1000) if int32 else value)
    raw = vals.astype("<i4" if int32 else "<f4").tobytes()
    return ErrorMapPayload(name, version, encoding, grid,
                           (OutputAxis("X"), OutputAxis("Y"), OutputAxis("Z")), raw,
                           0.001 if int32 else 0.0)


async def push(s: Session, p: ErrorMapPayload, chunk: int = 64) -> Message:
    for msg in split_into_chunks(encode_map(p), p.version, chunk):
        await s.send(msg)
    return await s.expect((MapAck, MapReject))  # type: ignore[arg-type]


@pytest.mark.parametrize(("controller", "encoding"), [
    ("fanuc", MapEncoding.INT32_INCREMENTS), ("siemens", MapEncoding.FLOAT32_MM)])
async def test_session_map_telemetry_heartbeat_release(center: MiniCenter, controller: str,
                                                       encoding: MapEncoding) -> None:
    m = machine(controller)
    formats = encoding | (MapEncoding.TABLES if controller == "siemens"
                          else MapEncoding.THERMAL | MapEncoding.FACTORED)
    async with asyncio.timeout(DEADLINE_S), cnc(m, center.port) as sim:
        s = await center.sessions.get()
        assert s.hello is not None and s.hello.name == m.name
        assert s.hello.map_formats == formats and s.hello.chain == m.chain
        ack = await push(s, map_payload(m.name, 0.012, encoding))
        assert isinstance(ack, MapAck) and ack.version == 1
        while True:  # the telemetry shows the map applied once the ramp is done
            t = await s.expect(Telemetry, ())
            assert isinstance(t, Telemetry)
            if t.map_version == 1 and all(abs(a.compensation - 0.012) < 1e-6 for a in t.axes):
                break
        assert [a.name for a in t.axes] == ["X", "Y", "Z"]
        if controller == "siemens":
            assert {r.name for r in t.temperatures} >= {"spindle", "air"}
        else:
            assert t.temperatures == ()  # Fanuc-style machines publish them to MQTT
        await s.send(Heartbeat(77))
        reply = await s.expect(HeartbeatReply)
        assert isinstance(reply, HeartbeatReply) and reply.token == 77
        await s.send(ReleaseCompensation(100, "test"))
        await s.expect(Released)
        while True:
            t = await s.expect(Telemetry, ())
            assert isinstance(t, Telemetry)
            if t.map_version == 0:
                break
        assert all(a.compensation == 0.0 for a in t.axes)
        assert sim.stats.maps_acked == 1 and sim.stats.releases == 1


async def test_bad_push_is_rejected_and_the_good_map_stays(center: MiniCenter) -> None:
    m = machine("fanuc")
    async with asyncio.timeout(DEADLINE_S), cnc(m, center.port) as sim:
        s = await center.sessions.get()
        assert isinstance(await push(s, map_payload(m.name, 0.005,
                                                    MapEncoding.INT32_INCREMENTS)), MapAck)
        bad = await push(s, map_payload("someone-else", 0.05, MapEncoding.INT32_INCREMENTS, 2))
        assert isinstance(bad, MapReject) and bad.reason == MapRejectReason.WRONG_MACHINE
        wrong = await push(s, map_payload(m.name, 0.05, MapEncoding.FLOAT32_MM, 3))
        assert isinstance(wrong, MapReject)
        assert wrong.reason == MapRejectReason.UNSUPPORTED_ENCODING
        t = await s.expect(Telemetry, ())
        assert isinstance(t, Telemetry) and t.map_version == 1
        assert sim.stats.maps_rejected == 2


async def test_machine_reconnects_and_keeps_its_map(center: MiniCenter) -> None:
    m = machine("fanuc")
    async with asyncio.timeout(DEADLINE_S), cnc(m, center.port) as sim:
        s = await center.sessions.get()
        assert isinstance(await push(s, map_payload(m.name, 0.007,
                                                    MapEncoding.INT32_INCREMENTS)), MapAck)
        s.writer.close()  # the center goes away
        s2 = await center.sessions.get()  # the machine comes back by itself
        t = await s2.expect(Telemetry, ())
        assert isinstance(t, Telemetry) and t.map_version == 1  # still compensating
        assert sim.stats.connects >= 2 and sim.stats.welcomes >= 2


async def test_wrong_secret_is_refused_and_retried_with_backoff(center: MiniCenter) -> None:
    m = machine("siemens")
    async with asyncio.timeout(DEADLINE_S), cnc(m, center.port, b"a-wrong-secret-16b") as sim:
        while len(sim.stats.rejects) < 2:
            await asyncio.sleep(0.01)
        assert sim.stats.welcomes == 0
        assert "AUTH_FAILED" in sim.stats.rejects[0]
        assert center.sessions.empty()


def test_backoff_grows_is_capped_and_jittered() -> None:
    b = Backoff(initial_s=1.0, factor=2.0, cap_s=60.0, jitter=0.5)
    rng = random.Random(0)
    delays = [b.delay(n, rng) for n in range(12)]
    for n, d in enumerate(delays):
        base = min(60.0, 2.0 ** n)
        assert base * 0.5 <= d <= base
    assert len({round(d, 6) for d in delays[8:]}) > 1  # capped yet not in lock step


@pytest.mark.services
async def test_fanuc_machine_publishes_its_temperatures_to_mqtt(
        center: MiniCenter, mqtt_broker: tuple[str, int]) -> None:
    import json
    import uuid

    import aiomqtt

    host, port = mqtt_broker
    prefix = f"ednc-test-{uuid.uuid4().hex[:8]}"  # a topic tree of this test's own
    m = machine("fanuc", "sim-mqtt")
    async with asyncio.timeout(DEADLINE_S), aiomqtt.Client(host, port) as client:
        await client.subscribe(f"{prefix}/#")
        async with cnc(m, center.port, mqtt=MqttTarget(host, port, prefix)):
            seen: dict[str, float] = {}
            async for message in client.messages:
                sensor = str(message.topic).split("/")[-1]
                assert str(message.topic) == f"{prefix}/sim-mqtt/temperature/{sensor}"
                assert isinstance(message.payload, bytes)
                body = json.loads(message.payload)
                assert set(body) == {"celsius", "timestamp_ms"}
                seen[sensor] = body["celsius"]
                if {"spindle", "x_screw", "air"} <= set(seen):
                    break
    assert all(10.0 < v < 40.0 for v in seen.values())


async def test_a_generated_fleet_all_connect_and_sum_up(center: MiniCenter) -> None:
    entries = generated_fleet(6, SECRET.decode(), seed=3)
    async with asyncio.timeout(DEADLINE_S), Fleet(entries, ("127.0.0.1", center.port),
                                                  cycle_s=0.02) as fleet:
        names = set()
        while len(names) < 6:
            s = await center.sessions.get()
            assert s.hello is not None
            names.add(s.hello.name)
            formats = {"fanuc": MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL
                       | MapEncoding.FACTORED,
                       "siemens": MapEncoding.FLOAT32_MM | MapEncoding.TABLES}
            kind = next(e.machine.controller for e in entries if e.machine.name == s.hello.name)
            assert s.hello.map_formats == formats[kind]
        await asyncio.gather(*(c.ready.wait() for c in fleet.machines))
        summary = fleet.summary()
    assert names == {f"sim-{i:03d}" for i in range(1, 7)}
    assert summary["machines"] == 6 and summary["welcomes"] >= 6 and summary["refused"] == 0
