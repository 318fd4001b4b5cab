"""Whole system over the OPC UA link: ``ednc serve``'s app and services, Siemens-style
machines registered with an ``opcua`` link, each serving its PLC window and NC data
through a SINUMERIK-shaped OPC UA server on loopback. The center logs in as a user with
PlcWrite (its password from the environment, named by the link's reference), fits each
machine's model from the uploaded campaign and writes its tables map into the data block;
the PLC programs apply them. ISO 230-6 body diagonals on the true machines with what each
NC received are cut by >= 95 % (3-axis and 5-axis), and a spindle-growth tables map's
thermal records follow temperatures posted to the center under one map version."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim.opcua_server import PLC_WRITER, OpcuaUser, sinumerik_server
from machine_sim.runtime import MachineRuntime
from machine_sim.windowcnc import WindowCNC
from server.numeric import plain_json
from tests.support.integration import (
    DEADLINE_S,
    THERMAL_TABLES,
    Spec,
    applied_map,
    campaign,
    center,
    check_diagonals,
    diagnosed_spindle,
    follow_temperatures,
    spec,
)

pytestmark = pytest.mark.slow

PASSWORD_ENV = "EDNC_TEST_OPCUA_PASSWORD"


@pytest.fixture(autouse=True)
def password(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(PASSWORD_ENV, "plc-writer-pw-0123")


def linked(s: Spec, port: int) -> Spec:
    link = {"kind": "opcua", "endpoint": f"opc.tcp://127.0.0.1:{port}", "user": "ednc",
            "password_ref": f"env:{PASSWORD_ENV}", "poll_ms": 100}
    return Spec({**s.description, "link": link}, s.secret, s.seed, s.effects)


@asynccontextmanager
async def nc(s: Spec, **runtime: Any) -> AsyncIterator[WindowCNC]:
    users = {"ednc": OpcuaUser("plc-writer-pw-0123", PLC_WRITER)}
    rt = MachineRuntime(s.machine, seed=s.seed, **runtime)
    async with WindowCNC(s.machine, sinumerik_server(users), runtime=rt,
                         cycle_s=0.02) as cnc:
        yield cnc


@pytest.mark.parametrize("name", ["vmc-06", "5ax-04"])
async def test_a_sinumerik_over_opcua_gets_its_map_and_compensates(
        tmp_path: Path, name: str) -> None:
    base = spec(name)
    sim, _, _ = await asyncio.to_thread(campaign, name)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(nc(base))
        s = linked(base, cnc.server.port)
        await plant.register(s)
        assert await plant.fit_from_campaign(s.name) == 1
        received = await applied_map(plant, cnc.runtime.controller.store, s.name)
        st = await plant.status(s.name)
        assert st["connected"] is True and st["telemetry"]["link"] == "opcua", st
        assert [e.kind for e in cnc.runtime.controller.store.events] == ["applied"]
    check_diagonals(sim, received, "over OPC UA", increment_mm=None)


async def test_thermal_records_follow_temperatures_over_opcua(tmp_path: Path) -> None:
    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL_TABLES)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(nc(THERMAL_TABLES, own_sensors=False))
        s = linked(THERMAL_TABLES, cnc.server.port)
        await plant.register(s)
        await plant.post_model(s.name, plain_json(model.to_json()))
        active = await applied_map(plant, cnc.runtime.controller.store, s.name)
        sensor = term.sensor.removeprefix("T_").removesuffix("_C")
        q = np.array([[400.0, 300.0, -250.0]])
        z = cnc.machine.axis_names.index("Z")
        ctl = cnc.runtime.controller
        seen = await follow_temperatures(
            plant, ctl, s.name, sensor,
            lambda: float(ctl.store.active.lookup(q)[0][z]))  # type: ignore[union-attr]
        assert ctl.store.version == 1 and ctl.store.active is active
        # the correction moves by -coefficient per K along z, in mm
        np.testing.assert_allclose(np.diff(seen) * 1000.0, -term.coefficient * 5.0, atol=0.2)
