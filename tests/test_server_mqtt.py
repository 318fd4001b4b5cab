"""The MQTT bridge: temperature payloads, and against the real Mosquitto (each test on a
topic prefix of its own): a published temperature gives the machine a new map, bad
payloads are counted, status and events are published, a broker outage keeps the last
temperatures (stale) and the bridge comes back by itself."""

from __future__ import annotations

import asyncio
import contextlib
import json
import socket
import time
import uuid
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import aiomqtt
import paho.mqtt.client as paho
import pytest

from protocol.backoff import Backoff
from server import mqtt as bridge_module
from server.db import maps as map_repo
from server.mqtt import MqttBridge, PayloadError, ack_at_once, parse_temperature
from server.temperatures import TemperatureBoard, column_of
from tests.support.link import DEADLINE_S, Rig, model_body, rig, simulator, until
from tests.support.mqtt import TcpProxy, publisher

pytestmark = pytest.mark.services

FAST = {"backoff": Backoff(initial_s=0.05, cap_s=0.2), "stale_check_s": 0.05}


@pytest.mark.parametrize(("payload", "celsius", "stamp"), [
    (b"21.4", 21.4, None),
    (b" 21.4\n", 21.4, None),
    (b"-5", -5.0, None),
    (b'{"celsius": 21.4}', 21.4, None),
    (b'{"celsius": "21.4", "time": 1763820000.5}', 21.4, 1763820000.5),
    (b'{"celsius": 20, "time": "2025-11-22T14:00:00Z"}', 20.0, 1763820000.0),
    (b'{"celsius": 20, "timestamp_ms": 1763820000000}', 20.0, 1763820000.0),
])
def test_good_temperature_payloads(payload: bytes, celsius: float,
                                   stamp: float | None) -> None:
    assert parse_temperature(payload) == (pytest.approx(celsius), stamp)


@pytest.mark.parametrize(("payload", "why"), [
    (b"", "empty"),
    (b"warm", "must be a number"),
    (b"nan", "not a finite temperature"),
    (b"1e9", r"outside -20..100 °C"),
    (b"293.15", "kelvin"),
    (b'{"celsius": 20, "time": 1763820000500}', "milliseconds"),
    (b'{"celsius": 20, "timestamp_ms": 1763820000}', "like seconds"),
    (b"\xff\xfe", "UTF-8"),
    (b"[21.4]", "must be a number"),
    (b'{"temp": 21.4}', '"celsius"'),
    (b'{"celsius": true}', "must be a number"),
    (b'{"celsius": 21.4', "not valid JSON"),
    (b'{"celsius": 20, "time": "yesterday"}', "ISO 8601"),
    (b'{"celsius": 20, "timestamp_ms": "now"}', "timestamp_ms"),
])
def test_bad_temperature_payloads_say_why(payload: bytes, why: str) -> None:
    with pytest.raises(PayloadError, match=why):
        parse_temperature(payload)


def test_sensor_names_become_model_columns() -> None:
    assert column_of("spindle") == "T_spindle_C"
    assert column_of("T_spindle_C") == "T_spindle_C"


async def test_old_readings_turn_stale_and_are_kept() -> None:
    board = TemperatureBoard(stale_after_s=0.05)
    board.update("m", "spindle", 22.0, source="mqtt")
    board.update("m", "air", 20.0, source="telemetry")
    assert board.mark_stale() == 0
    await asyncio.sleep(0.1)
    board.update("m", "air", 20.5, source="telemetry")
    assert board.mark_stale() == 1
    readings = board.readings("m")
    assert readings["T_spindle_C"].stale and readings["T_spindle_C"].celsius == 22.0
    assert not readings["T_air_C"].stale
    assert board.mark_stale(source="telemetry") == 1
    assert board.columns("m", ["T_air_C", "T_x_C"]) == {"T_air_C": 20.5}


def prefix() -> str:
    return f"ednc-test-{uuid.uuid4().hex[:12]}"


@contextlib.asynccontextmanager
async def spindle_bridge(tmp_path: Path, broker: tuple[str, int], top: str
                         ) -> AsyncIterator[tuple[Rig, MqttBridge, aiomqtt.Client, int]]:
    """A center whose bridge is connected under ``top``, vmc-01 registered (its id last)
    with a model that has a spindle thermal term (a known sensor), and a publisher."""
    async with rig(tmp_path, mqtt=broker, prefix=top, mqtt_options=FAST) as r, \
            publisher(broker) as pub:
        mid = await r.register(model=model_body(thermal_sensor="T_spindle_C"))
        bridge = r.services.mqtt
        assert bridge is not None
        await bridge.connected.wait()
        yield r, bridge, pub, mid


async def test_published_temperature_gives_the_machine_a_new_map(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    top = prefix()
    async with asyncio.timeout(DEADLINE_S), \
            spindle_bridge(tmp_path, mqtt_broker, top) as (r, _, pub, mid):
        # a ladder without thermal records: each temperature gives a new map
        async with simulator(r.port, thermal_records=False) as sim:
            await sim.ready.wait()
            await pub.publish(f"{top}/vmc-01/temperature/spindle", "23.5")
            await until(lambda: sim.runtime.controller.store.version == 1)
            await pub.publish(f"{top}/vmc-01/temperature/spindle",
                              json.dumps({"celsius": 25.0, "time": 1763820000}))
            await until(lambda: sim.runtime.controller.store.version == 2)
        maps = await r.db.run(map_repo.list_map_versions, mid)
        assert [m.temperatures for m in maps] == [{"T_spindle_C": 25.0},
                                                  {"T_spindle_C": 23.5}]


async def test_bad_payloads_are_counted_and_the_bridge_goes_on(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    top = prefix()
    async with asyncio.timeout(DEADLINE_S), \
            spindle_bridge(tmp_path, mqtt_broker, top) as (r, bridge, pub, _):
        for body in (b"warm", b"nan", b'{"celsius": null}', b"\xff"):
            await pub.publish(f"{top}/vmc-01/temperature/spindle", body)
        await pub.publish(f"{top}/vmc-01/temperature/bad-name!", b"20")
        await pub.publish(f"{top}/vmc-01/temperature/spindle", b"21.25")
        await until(lambda: "T_spindle_C" in r.services.temperatures.readings("vmc-01"))
        assert r.services.temperatures.readings("vmc-01")["T_spindle_C"].celsius == 21.25
        assert bridge.stats.bad_payloads == 5
        assert r.center.metrics.registry.get_sample_value(
            "ednc_mqtt_bad_payloads_total") == 5
        assert any("bad-name!" in e for e in bridge.stats.bad_examples)


async def test_a_burst_is_taken_in_one_wake_up_and_nothing_is_lost(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    """Messages waiting in the bridge's socket are all taken in one event-loop turn (not
    one per turn: with a thousand sessions on the loop that queued them for seconds),
    every one of them, in order."""
    top = prefix()
    topic = f"{top}/vmc-01/temperature/spindle"
    async with asyncio.timeout(DEADLINE_S), \
            spindle_bridge(tmp_path, mqtt_broker, top) as (r, bridge, pub, _):
        await pub.publish(topic, b"20")
        await until(lambda: "T_spindle_C" in r.services.temperatures.readings("vmc-01"))
        seen: list[float] = []
        r.services.temperatures.subscribe(lambda m, c, celsius: seen.append(celsius))
        values = [20.0 + 0.01 * k for k in range(1, 201)]

        def burst() -> None:
            """Publish from another client and thread while this loop is blocked, so that
            all of it waits in the bridge's socket."""
            client = paho.Client(paho.CallbackAPIVersion.VERSION2)
            client.connect(*mqtt_broker)
            client.loop_start()
            infos = [client.publish(topic, f"{v:.2f}", qos=1) for v in values]
            for info in infos:
                info.wait_for_publish(5.0)
            client.loop_stop()
            client.disconnect()
            time.sleep(0.3)  # the broker passes them on to the bridge meanwhile

        burst()  # blocks the loop on purpose
        loop = asyncio.get_running_loop()
        turns = 0

        def tick() -> None:
            nonlocal turns
            turns += 1
            if bridge.stats.received < 1 + len(values):
                loop.call_soon(tick)

        loop.call_soon(tick)
        await until(lambda: bridge.stats.received == 1 + len(values))
        assert seen == pytest.approx(values)
        assert turns <= 5, f"{turns} event-loop turns to take 200 waiting messages"


def spindle_celsius(r: Rig) -> float | None:
    reading = r.services.temperatures.readings("vmc-01").get("T_spindle_C")
    return None if reading is None else reading.celsius


def quickack(sock: socket.socket) -> int:
    return sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_QUICKACK)


@pytest.mark.skipif(not hasattr(socket, "TCP_QUICKACK"), reason="Linux only")
def test_ack_at_once_takes_a_connection_out_of_delayed_acks() -> None:
    """The kernel delays ACKs on a connection that answers what it receives (the bridge
    publishing statuses); the broker's Nagle then holds temperatures up to 40 ms for
    that ACK. ack_at_once makes the next ones immediate."""
    with socket.create_server(("127.0.0.1", 0)) as server, \
            socket.create_connection(server.getsockname()) as ours:
        theirs, _ = server.accept()
        with theirs:
            for _ in range(3):  # an exchange: received, then sent soon after
                theirs.sendall(b"t")
                ours.recv(16)
                ours.sendall(b"s")
                theirs.recv(16)
            assert quickack(ours) == 0  # delayed ACKs: what the fix is for
            ack_at_once(ours)
            assert quickack(ours) == 1


@pytest.mark.skipif(not hasattr(socket, "TCP_QUICKACK"), reason="Linux only")
async def test_the_bridge_acknowledges_at_once_after_each_read(
        tmp_path: Path, mqtt_broker: tuple[str, int], monkeypatch: pytest.MonkeyPatch
        ) -> None:
    top = prefix()
    armed: list[int] = []

    def recording(sock: socket.socket) -> None:
        ack_at_once(sock)
        armed.append(quickack(sock))

    monkeypatch.setattr(bridge_module, "ack_at_once", recording)
    async with asyncio.timeout(DEADLINE_S), \
            spindle_bridge(tmp_path, mqtt_broker, top) as (r, _, pub, _):
        for k in range(3):
            await pub.publish(f"{top}/vmc-01/temperature/spindle", f"{20 + k}".encode())
            await until(lambda k=k: spindle_celsius(r) == 20 + k)
    assert len(armed) >= 3 and set(armed) == {1}


class PubackWithTheCancel:
    """A client whose PUBACK comes in the same loop turn as a cancel of the publisher: as
    aiomqtt waits for it (``asyncio.wait_for``), which in Python 3.11 then returns and
    drops the cancel."""

    def __init__(self) -> None:
        self.published: list[str] = []
        self.victim: asyncio.Task[None] | None = None

    async def publish(self, topic: str, payload: str, *, qos: int, retain: bool,
                      timeout: float) -> None:
        self.published.append(topic)
        acked = asyncio.Event()
        assert self.victim is not None
        loop = asyncio.get_running_loop()
        loop.call_soon(lambda: (acked.set(), self.victim.cancel()))  # one turn: both
        await asyncio.wait_for(acked.wait(), timeout)


async def test_a_cancel_that_comes_with_the_puback_still_stops_the_publisher(
        tmp_path: Path) -> None:
    """The bridge's publisher, cancelled (shutdown, or a lost broker) in the loop turn of
    a PUBACK, stops: it once went on waiting for work and held the shutdown 10 s."""
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        bridge = MqttBridge(r.center, r.services.feed, r.services.temperatures,
                            host="127.0.0.1", status_refresh_s=3600.0)
        client = PubackWithTheCancel()
        bridge._events.append({"kind": "connected", "machine": "vmc-01"})
        bridge._wake.set()
        task = asyncio.create_task(bridge._publish(client))  # type: ignore[arg-type]
        client.victim = task
        done, _ = await asyncio.wait({task}, timeout=2.0)
        assert task in done, "the publisher lost its cancel and went on waiting"
        assert task.cancelled() and client.published == ["ednc/events"]
        task.cancel()  # (without the fix: stop it for the test's own exit)


async def test_status_and_events_are_published(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    top = prefix()
    async with asyncio.timeout(DEADLINE_S), publisher(mqtt_broker) as watch:
        await watch.subscribe(f"{top}/#", qos=1)
        async with rig(tmp_path, mqtt=mqtt_broker, prefix=top, mqtt_options=FAST) as r:
            await r.register(model=model_body())
            async with simulator(r.port) as sim:
                await until(lambda: sim.runtime.controller.store.version == 1)
                events: list[dict[str, Any]] = []
                status: dict[str, Any] = {}
                async for message in watch.messages:
                    assert isinstance(message.payload, bytes)
                    body = json.loads(message.payload)
                    if message.topic.value == f"{top}/events":
                        events.append(body)
                    elif message.topic.value == f"{top}/vmc-01/status":
                        status = body
                    if status.get("map_version_applied") == 1 and any(
                            e["kind"] == "applied" for e in events):
                        break
        assert status["connected"] is True and status["map_version_sent"] == 1
        assert status["last_seen"] is not None
        kinds = [e["kind"] for e in events]
        assert kinds[:3] == ["connected", "pushed", "applied"]
        assert events[1]["version"] == 1 and events[1]["machine"] == "vmc-01"
        # retained: a late subscriber gets the status at once
        async with publisher(mqtt_broker) as late:
            await late.subscribe(f"{top}/vmc-01/status")
            async for message in late.messages:
                assert message.retain
                break
            await late.publish(f"{top}/vmc-01/status", b"", retain=True)  # clean up


async def test_broker_outage_keeps_temperatures_stale_and_recovers(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    top = prefix()
    proxy = TcpProxy(mqtt_broker)
    await proxy.start()
    try:
        async with asyncio.timeout(DEADLINE_S), \
                rig(tmp_path, mqtt=("127.0.0.1", proxy.port), prefix=top,
                    mqtt_options=FAST) as r, publisher(mqtt_broker) as pub:
            await r.register(model=model_body(thermal_sensor="T_spindle_C"))
            bridge = r.services.mqtt
            board = r.services.temperatures
            assert bridge is not None
            await bridge.connected.wait()
            await pub.publish(f"{top}/vmc-01/temperature/spindle", b"22.0")
            await until(lambda: "T_spindle_C" in board.readings("vmc-01"))
            assert not board.readings("vmc-01")["T_spindle_C"].stale

            await proxy.stop()  # the broker goes away
            await until(lambda: not bridge.connected.is_set())
            reading = board.readings("vmc-01")["T_spindle_C"]
            assert reading.stale and reading.celsius == 22.0
            await asyncio.sleep(0.3)  # a few failed reconnects
            assert not bridge.connected.is_set()

            await proxy.start()  # and comes back on the same port
            await bridge.connected.wait()
            assert bridge.stats.connects == 2
            await pub.publish(f"{top}/vmc-01/temperature/spindle", b"22.5")
            await until(lambda: board.readings("vmc-01")["T_spindle_C"].celsius == 22.5)
            assert not board.readings("vmc-01")["T_spindle_C"].stale
    finally:
        await proxy.stop()


async def test_without_a_broker_mqtt_is_off_and_machines_are_served(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        assert r.services.mqtt is None
        await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: sim.runtime.controller.store.version == 1)
