"""Whole system over the Modbus/TCP link: ``ednc serve``'s app and services, Fanuc-style
machines registered with a ``modbus`` link, each serving its PMC window through its own
Modbus/TCP server on loopback. The center connects to them, fits their models from the
uploaded campaigns and writes the maps into controller memory; the PLC programs apply
them. ISO 230-6 body diagonals measured on the true machines with what each ladder
received are cut by >= 95 % (3-axis and 5-axis), and a spindle-growth map's thermal
records follow temperatures posted to the center under one map version."""

from __future__ import annotations

import asyncio
import datetime as dt
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim.fanuc import FanucConfig
from machine_sim.lookup import FactoredLadder
from machine_sim.modbus_server import PmcModbusServer
from machine_sim.runtime import MachineRuntime
from machine_sim.windowcnc import WindowCNC
from server.numeric import plain_json
from tests.support.integration import (
    DEADLINE_S,
    FANUC_5AX,
    THERMAL,
    Plant,
    Spec,
    applied_map,
    campaign,
    center,
    check_diagonals,
    diagnosed_spindle,
    follow_temperatures,
    until,
)

pytestmark = pytest.mark.slow


def linked(s: Spec, port: int) -> Spec:
    """``s`` registered with a modbus link to a PMC server on loopback ``port``."""
    link = {"kind": "modbus", "host": "127.0.0.1", "port": port, "start_register": 2000,
            "poll_ms": 20}
    return Spec({**s.description, "link": link}, s.secret, s.seed, s.effects)


@asynccontextmanager
async def pmc(s: Spec, **runtime: Any) -> AsyncIterator[WindowCNC]:
    def factory(cnc: WindowCNC) -> PmcModbusServer:
        return PmcModbusServer(cnc, port=0, register=2000)

    rt = MachineRuntime(s.machine, seed=s.seed, fanuc=FanucConfig(max_step_counts=1000),
                        **runtime)
    async with WindowCNC(s.machine, factory, runtime=rt, cycle_s=0.02) as cnc:
        yield cnc


async def _map_applied(plant: Plant, cnc: WindowCNC, s: Spec) -> FactoredLadder:
    active = await applied_map(plant, cnc.runtime.controller.store, s.name)
    assert isinstance(active, FactoredLadder), type(active)
    return active


@pytest.mark.parametrize("name", ["gantry-02", FANUC_5AX.name])
async def test_a_fanuc_pmc_over_modbus_gets_its_map_and_compensates(
        tmp_path: Path, name: str) -> None:
    from tests.support.integration import spec

    base = spec(name)
    sim, _, _ = await asyncio.to_thread(campaign, name)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(base))
        s = linked(base, cnc.server.port)
        await plant.register(s)
        assert await plant.fit_from_campaign(s.name) == 1
        received = await _map_applied(plant, cnc, s)
        st = await plant.status(s.name)
        assert st["connected"] is True, st
        assert st["telemetry"]["link"] == "modbus"
        events = [e["kind"] for e in await plant.events(machine=s.name)]
        assert "connected" in events and "applied" in events, events
        # the dashboard and the metrics say how the center reaches it
        r = await plant.client.get("/api/dashboard")
        card = next(c for c in r.json()["machines"] if c["name"] == s.name)
        assert card["link"] == "modbus" and card["connected"] is True, card
        assert await plant.metric("ednc_machine_link_info", link="modbus",
                                  machine=s.name) == 1.0
        assert await plant.metric("ednc_machine_connected", machine=s.name) == 1.0
        assert [e.kind for e in cnc.runtime.controller.store.events] == ["applied"]
    check_diagonals(sim, received, f"({sim.machine.chain}) factored over Modbus/TCP")


async def test_an_ednc_login_of_a_modbus_machine_is_refused(tmp_path: Path) -> None:
    from tests.support.integration import cnc as ednc_cnc
    from tests.support.integration import require_loopback_aliases, spec

    require_loopback_aliases()
    base = spec("gantry-02")
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        await plant.register(linked(base, 1))
        machine = await stack.enter_async_context(ednc_cnc(base, plant.port))
        await until(lambda: bool(machine.stats.rejects or machine.stats.last_error))
        assert not machine.stats.welcomes
        refused = [e for e in await plant.events(machine=base.name)
                   if e["kind"] == "refused"]
        assert any("modbus link" in (e.get("detail") or "") for e in refused), refused


async def test_thermal_records_follow_temperatures_over_modbus(tmp_path: Path) -> None:
    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(THERMAL, own_sensors=False))
        s = linked(THERMAL, cnc.server.port)
        await plant.register(s)
        await plant.post_model(s.name, plain_json(model.to_json()))
        active = await _map_applied(plant, cnc, s)
        assert active.version == 1
        sensor = term.sensor.removeprefix("T_").removesuffix("_C")
        q = np.array([[400.0, 300.0, -250.0]])
        z = cnc.machine.axis_names.index("Z")
        ctl = cnc.runtime.controller
        seen = await follow_temperatures(
            plant, ctl, s.name, sensor,
            lambda: float(ctl.store.active.counts(q)[0][z]))  # type: ignore[union-attr]
        assert ctl.store.version == 1  # one map version all along
        # the spindle grows by -term's coefficient per K along z: the correction moves
        # by the opposite, 5 K a step
        np.testing.assert_allclose(np.diff(seen), -term.coefficient * 5.0, atol=1.5)


async def test_a_restarted_center_feeds_the_slots_of_the_map_the_plc_runs(
        tmp_path: Path) -> None:
    """A new center process finds the PLC running its current map: the map is not sent
    again (§13.2 step 0), and the temperature slots of that map's thermal records are
    fed all the same: the correction follows temperatures posted to the new center."""
    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL)
    db = f"sqlite:///{tmp_path / 'c.db'}"
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        cnc = await stack.enter_async_context(pmc(THERMAL, own_sensors=False))
        s = linked(THERMAL, cnc.server.port)
        async with center(db) as plant:
            await plant.register(s)
            await plant.post_model(s.name, plain_json(model.to_json()))
            assert (await _map_applied(plant, cnc, s)).version == 1
        ctl = cnc.runtime.controller
        async with center(db) as plant:
            async def linked_up() -> bool:
                return bool((await plant.status(s.name))["connected"])

            await until(linked_up)
            sensor = term.sensor.removeprefix("T_").removesuffix("_C")
            q = np.array([[400.0, 300.0, -250.0]])
            z = cnc.machine.axis_names.index("Z")
            seen = await follow_temperatures(
                plant, ctl, s.name, sensor,
                lambda: float(ctl.store.active.counts(q)[0][z]))  # type: ignore[union-attr]
            assert len(await plant.deliveries(s.name)) == 1  # not sent again
        assert ctl.store.version == 1
        np.testing.assert_allclose(np.diff(seen), -term.coefficient * 5.0, atol=1.5)


async def test_no_acknowledgement_is_lost_when_the_center_restarts(tmp_path: Path) -> None:
    """The center stops after switching the PLC to a new map but before the PLC answered
    (its PLC program paused); the PLC then applies it; a new center process on the same
    database reads the verdict from the controller's status and stores it on that
    delivery."""
    from tests.support.integration import spec

    base = spec("gantry-02")
    db = f"sqlite:///{tmp_path / 'c.db'}"
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as outer:
        cnc = await outer.enter_async_context(pmc(base))
        s = linked(base, cnc.server.port)
        async with center(db) as plant:
            await plant.register(s)

            async def linked_up() -> bool:
                return bool((await plant.status(s.name))["connected"])

            await until(linked_up)  # the center has opened its session
            cnc.stop_plc()  # the switch will wait for the PLC
            await plant.fit_from_campaign(s.name)

            async def sent() -> bool:
                return bool(await plant.deliveries(s.name))

            await until(sent)
            # the switch is written (the window's switch word was 0 before any push)
            await until(lambda: cnc.window[192:194] != b"\0\0")
        cnc.running = True  # the PLC program runs on and applies the map
        await until(lambda: cnc.runtime.controller.store.version == 1)
        restart = dt.datetime.now(dt.UTC).isoformat().replace("+00:00", "Z")
        async with center(db) as plant:
            controllers = plant.services.controllers
            assert controllers is not None
            await until(lambda: controllers.missed_settled == 1)
            # the delivery the PLC answered was sent by the first center
            rows = await plant.deliveries(s.name)
            assert any(r["map_version"] == 1 and r["state"] == "applied" and
                       r["applied_at"] < restart for r in rows), rows
            events = await plant.events(machine=s.name)
            assert any("read from the controller's status" in (e.get("detail") or "")
                       for e in events), events
