"""The whole system under faults: impostors refused (and seen in events and metrics), a
machine's link cut and restored, the center restarted on its PostgreSQL database, the MQTT
broker away and back, and a map corrupted or truncated on its way to the machine.

Every machine is a simulated CNC over real TCP from its own loopback address; the center is
``ednc serve``'s app with its lifespan; Mosquitto and PostgreSQL are the real ones."""

from __future__ import annotations

import asyncio
import functools
import uuid
from collections.abc import Callable, Iterator
from contextlib import AsyncExitStack
from pathlib import Path
from typing import Any

import aiomqtt
import numpy as np
import pytest
from sqlalchemy import create_engine

from machine_sim.link import SimulatedCNC
from server.db.tables import Base
from server.numeric import plain_json
from tests.support.db import postgres_url  # noqa: F401  (fixture)
from tests.support.integration import (
    DEADLINE_S,
    FAST_MQTT,
    THERMAL,
    Plant,
    Relay,
    Spec,
    campaign,
    center,
    cnc,
    map_chunk_hook,
    require_loopback_aliases,
    spec,
    until,
)
from tests.support.mqtt import TcpProxy
from volumetric.diagnose.diagnosis import diagnose

pytestmark = pytest.mark.slow

VMC = spec("vmc-01")       # Siemens, 127.0.2.1
GANTRY = spec("gantry-02")  # Fanuc, 127.0.2.2
CODES = {"auth": "AUTH_FAILED", "address": "ADDRESS_MISMATCH", "unknown": "UNKNOWN_MACHINE"}


def _sqlite(tmp_path: Path) -> str:
    return f"sqlite:///{tmp_path / 'center.db'}"


async def _new_model_version(plant: Plant, name: str) -> int:
    """Store the machine's latest model again as a new version (a re-upload): the
    scheduler must build and push a new map version."""
    r = await plant.client.get(f"/api/machines/{name}/models/latest")
    assert r.status_code == 200, r.text
    return await plant.post_model(name, r.json()["body"])


def _states(rows: list[dict[str, Any]]) -> list[tuple[int, str]]:
    """Deliveries oldest first, as (map version, state)."""
    return [(d["map_version"], d["state"]) for d in reversed(rows)]


def _has_deliveries(plant: Plant, name: str, want: list[tuple[int, str]]
                    ) -> Callable[[], Any]:
    async def check() -> bool:
        return _states(await plant.deliveries(name)) == want

    return check


# -- 3. impostors

async def test_wrong_secret_and_unknown_address_are_refused(tmp_path: Path) -> None:
    require_loopback_aliases()
    # Impostors come from addresses where machines are registered (a peer from any other
    # address is closed at accept, without a Reject: checked last), each from its own, as
    # failed logins from one address throttle the next ones (AUTH_FAILED).
    bystanders = [spec("vmc-06"), THERMAL]  # registered, never connected: 127.0.2.6/.7
    ghost = Spec({**VMC.description, "name": "ghost-09", "ip": bystanders[1].description["ip"]},
                 "secret-of-ghost-09-012345", 9)
    stranger = bystanders[0].description["ip"]
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(_sqlite(tmp_path)))
        for s in (VMC, GANTRY, *bystanders):
            await plant.register(s)
        await plant.fit_from_campaign(GANTRY.name)
        honest = await stack.enter_async_context(cnc(GANTRY, plant.port))
        impostors = {
            "auth": cnc(VMC, plant.port, secret="not-the-registered-secret"),
            "address": cnc(GANTRY, plant.port, ip=stranger),  # its name, another host
            "unknown": cnc(ghost, plant.port),
        }
        async with AsyncExitStack() as bad:
            for sim in impostors.values():
                await bad.enter_async_context(sim)
            for sim in impostors.values():
                await until(lambda s=sim: bool(s.stats.rejects))
        # the honest machine is served all along, from its own address: never refused
        await until(plant.applied(GANTRY.name, 1))
        assert honest.stats.rejects == [] and honest.stats.welcomes == 1
        assert not plant.center.registry.get(VMC.name).connected
        refused = await plant.events(kind="refused")
        print("\n".join(f"\nevent: {e['machine']}: {e['detail']}" for e in refused))
        for reason, sim in impostors.items():
            # the first refusal says why; retries within the throttle's delay: AUTH_FAILED
            assert sim.stats.rejects[0].startswith(CODES[reason]), sim.stats.rejects
            assert all(r.startswith((CODES[reason], "AUTH_FAILED")) for r in sim.stats.rejects)
            assert sim.stats.welcomes == 0
            count = await plant.metric("ednc_connections_refused_total", reason=reason)
            assert count >= 1, reason
            print(f"\nrefused ({reason}): {sim.stats.rejects[0]}")
        # who (the name when known, else the peer address) and why, as the dashboard lists;
        # the impostors learnt the code only
        seen = {(e["machine"], e["detail"]) for e in refused}
        assert seen >= {
            (VMC.name, "authentication failed: wrong response to the challenge"),
            (stranger, f"machine 'gantry-02' is registered at {GANTRY.description['ip']}, "
                       f"this connection comes from {stranger}"),
            (ghost.description["ip"], "no machine named 'ghost-09' is registered"),
        }
        assert all("throttled" in d for _, d in seen - {
            (VMC.name, "authentication failed: wrong response to the challenge")}
            if "registered" not in d), seen
        assert not any(r.split(":", 1)[1].strip() for sim in impostors.values()
                       for r in sim.stats.rejects)
        # one row per peer and minute, every refusal counted
        total = sum([await plant.metric("ednc_connections_refused_total", reason=r)
                     for r in ("auth", "address", "unknown", "throttled")])
        assert total >= len(refused)
        # a peer where no machine is registered: closed at accept, counted, no row
        async with cnc(ghost, plant.port, ip="127.0.2.99") as nowhere:
            await until(lambda: nowhere.stats.connects >= 2)
            assert nowhere.stats.rejects == []
        assert await plant.metric("ednc_connections_refused_total",
                                  reason="unregistered") >= 2
        assert len(await plant.events(kind="refused")) == len(refused)


# -- 4a. a machine's link drops and comes back

async def test_a_machine_that_drops_and_reconnects_gets_the_current_map(
        tmp_path: Path) -> None:
    require_loopback_aliases()
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(_sqlite(tmp_path), period_s=600.0))
        await plant.register(VMC)
        await plant.fit_from_campaign(VMC.name)
        relay = await stack.enter_async_context(Relay(plant.port, VMC.ip))
        sim = await stack.enter_async_context(cnc(VMC, relay.port, ip=VMC.ip))
        store = sim.runtime.controller.store
        await until(plant.applied(VMC.name, 1))

        async def cut() -> None:
            await relay.stop()
            await until(lambda: not plant.center.registry.get(VMC.name).connected)
            await until(lambda: not sim.ready.is_set())

        # dropped and back, nothing changed meanwhile: the same map again
        await cut()
        assert store.version == 1  # a lost link does not release compensation
        await relay.start()
        await until(_has_deliveries(plant, VMC.name, [(1, "applied"), (1, "applied")]))
        # dropped, and the model changes while it is away: the new map on return
        await cut()
        assert await _new_model_version(plant, VMC.name) == 2
        await asyncio.sleep(0.3)
        assert store.version == 1 and sim.stats.welcomes == 2
        await relay.start()
        await until(lambda: store.version == 2)
        await until(_has_deliveries(plant, VMC.name,
                                    [(1, "applied"), (1, "applied"), (2, "applied")]))
        assert sim.stats.welcomes == 3 and sim.stats.maps_acked == 3
        assert [m["version"] for m in await plant.maps(VMC.name)] == [2, 1]


# -- 4b. the center restarts

@pytest.fixture
def pg_database(postgres_url: str) -> Iterator[str]:  # noqa: F811
    yield postgres_url
    engine = create_engine(postgres_url)
    Base.metadata.drop_all(engine)
    engine.dispose()


async def _snapshot(plant: Plant) -> dict[str, Any]:
    """What the center has stored: machines, models, map versions and deliveries."""
    machines = (await plant.client.get("/api/machines")).json()
    out: dict[str, Any] = {"machines": machines}
    for m in machines:
        name = m["name"]
        out[f"{name}/models"] = (await plant.client.get(f"/api/machines/{name}/models")).json()
        out[f"{name}/maps"] = await plant.maps(name)
        out[f"{name}/deliveries"] = await plant.deliveries(name)
    return out


@pytest.mark.services
async def test_center_restart_loses_nothing_and_machines_come_back(pg_database: str) -> None:
    require_loopback_aliases()
    machines = (VMC, GANTRY)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        async with center(pg_database) as first:
            port = first.port
            for s in machines:
                await first.register(s)
                await first.fit_from_campaign(s.name)
            sims = [await stack.enter_async_context(cnc(s, port)) for s in machines]
            for s in machines:
                await until(first.applied(s.name, 1))
            before = await _snapshot(first)
        # the center is gone: machines keep their maps and retry with backoff
        for sim in sims:
            await until(lambda x=sim: not x.ready.is_set())
        await asyncio.sleep(0.5)
        for sim in sims:
            assert sim.runtime.controller.store.version == 1
            assert sim.stats.welcomes == 1
            print(f"\n{sim.machine.name} while the center is down: {sim.stats.last_error}")
            assert "ConnectionRefused" in sim.stats.last_error  # it kept trying
        async with center(pg_database, machine_port=port) as second:
            for sim in sims:
                await sim.ready.wait()
            for s in machines:
                await until(_has_deliveries(second, s.name, [(1, "applied"), (1, "applied")]))
            after = await _snapshot(second)
            for key, rows in before.items():
                if key.endswith("/deliveries"):
                    assert after[key][1:] == rows  # the old ones kept, one new on top
                else:
                    assert after[key] == rows, key
            # maps resume: a new model is pushed as a new version
            for s in machines:
                assert await _new_model_version(second, s.name) == 2
            for s, sim in zip(machines, sims, strict=True):
                await until(second.applied(s.name, 2))
                assert sim.runtime.controller.store.version == 2
                assert sim.stats.welcomes == 2


# -- 4c. the broker goes away and comes back

@functools.cache
def _thermal_model_body() -> dict[str, Any]:
    sim, readings, _ = campaign(THERMAL.name)
    body: dict[str, Any] = plain_json(diagnose(sim.machine, readings).model.to_json())
    return body


@pytest.mark.services
async def test_broker_outage_keeps_stale_temperatures_and_recovers(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    require_loopback_aliases()
    body = await asyncio.to_thread(_thermal_model_body)
    top = f"ednc-it-{uuid.uuid4().hex[:12]}"
    topic = f"{top}/{THERMAL.name}/temperature/spindle"
    proxy = TcpProxy(mqtt_broker)
    await proxy.start()
    try:
        async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
            plant = await stack.enter_async_context(center(
                _sqlite(tmp_path), mqtt=("127.0.0.1", proxy.port), prefix=top,
                mqtt_options=FAST_MQTT))
            pub = await stack.enter_async_context(aiomqtt.Client(
                *mqtt_broker, identifier=f"it-{uuid.uuid4().hex[:8]}"))
            bridge, board = plant.services.mqtt, plant.services.temperatures
            assert bridge is not None
            await bridge.connected.wait()
            await plant.register(THERMAL)
            await plant.post_model(THERMAL.name, body)
            # a ladder without thermal records: the center rebuilds on temperatures
            sim = await stack.enter_async_context(cnc(THERMAL, plant.port,
                                                      thermal_records=False))
            store = sim.runtime.controller.store
            await pub.publish(topic, b"24.0")
            await until(plant.applied(THERMAL.name, 1))

            await proxy.stop()  # the broker goes away
            await until(lambda: not bridge.connected.is_set())
            reading = board.readings(THERMAL.name)["T_spindle_C"]
            assert reading.stale and reading.celsius == 24.0  # kept, marked stale
            await pub.publish(topic, b"27.0")  # nobody at the center hears this one
            await asyncio.sleep(0.5)
            assert not bridge.connected.is_set()
            assert store.version == 1 and sim.ready.is_set()  # the machine is unaffected
            assert board.readings(THERMAL.name)["T_spindle_C"].celsius == 24.0

            await proxy.start()  # back on the same port
            await bridge.connected.wait()
            await pub.publish(topic, b"28.5")
            await until(lambda: board.readings(THERMAL.name)["T_spindle_C"].celsius == 28.5)
            assert not board.readings(THERMAL.name)["T_spindle_C"].stale
            await until(lambda: store.version >= 2)
            await until(plant.applied(THERMAL.name, store.version))
            maps = await plant.maps(THERMAL.name)
            assert maps[0]["temperatures"] == {"T_spindle_C": 28.5}
            assert maps[-1]["temperatures"] == {"T_spindle_C": 24.0}
            assert bridge.stats.connects == 2
    finally:
        await proxy.stop()


# -- 4d. a damaged map on the wire

def _flip_middle_byte(data: bytes) -> bytes:
    i = len(data) // 2
    return data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:]


@pytest.mark.parametrize(("damage", "reason"), [
    (_flip_middle_byte, "CHECKSUM_MISMATCH"),
    (lambda data: data[:-1], "WRONG_SIZE"),
], ids=["corrupted", "truncated"])
async def test_a_damaged_map_is_refused_and_the_last_good_one_kept(
        tmp_path: Path, damage: Callable[[bytes], bytes], reason: str) -> None:
    require_loopback_aliases()
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(_sqlite(tmp_path), period_s=0.3))
        await plant.register(VMC)
        await plant.fit_from_campaign(VMC.name)
        relay = await stack.enter_async_context(Relay(plant.port, VMC.ip))
        sim: SimulatedCNC = await stack.enter_async_context(cnc(VMC, relay.port, ip=VMC.ip))
        ctl = sim.runtime.controller
        await until(plant.applied(VMC.name, 1))
        await until(lambda: bool(np.any(ctl.applied_mm() != 0.0)))
        good = ctl.store.active

        relay.hook = map_chunk_hook(2, damage)  # frames stay valid; the map does not
        assert await _new_model_version(plant, VMC.name) == 2
        await until(_has_deliveries(plant, VMC.name, [(1, "applied"), (2, "rejected")]))
        rows = await plant.deliveries(VMC.name)
        assert rows[0]["reject_reason"].startswith(reason), rows[0]
        rejected = await plant.events(kind="rejected", machine=VMC.name)
        assert len(rejected) == 1 and reason in rejected[0]["detail"]
        st = await plant.status(VMC.name)
        assert st["map_version_applied"] == 1 and st["last_reject_reason"].startswith(reason)
        # the machine kept its last good map and keeps applying it
        assert ctl.store.version == 1 and ctl.store.active is good
        assert sim.stats.maps_rejected == 1
        assert ctl.store.events[-1].kind == "rejected" and ctl.store.events[-1].version == 2
        print(f"\n{reason}: machine says {ctl.store.events[-1].text!r}")
        assert np.any(ctl.applied_mm() != 0.0)
        # a rejected version is not re-sent at every period (period 0.3 s) ...
        await asyncio.sleep(1.0)
        assert _states(await plant.deliveries(VMC.name)) == [(1, "applied"), (2, "rejected")]
        # ... and the next version, undamaged, is applied
        relay.hook = None
        assert await _new_model_version(plant, VMC.name) == 3
        await until(plant.applied(VMC.name, 3))
        assert ctl.store.version == 3
