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
    until,
)

pytestmark = pytest.mark.slow

PASSWORD_ENV = "EDNC_TEST_OPCUA_PASSWORD"


@pytest.fixture(autouse=True)
def password(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv(PASSWORD_ENV, "plc-writer-pw-0123")
    monkeypatch.setenv("EDNC_OPCUA_PKI_DIR", str(tmp_path / "pki"))  # the center's own


def linked(s: Spec, port: int, **more: Any) -> Spec:
    link = {"kind": "opcua", "endpoint": f"opc.tcp://127.0.0.1:{port}", "user": "ednc",
            "password_ref": f"env:{PASSWORD_ENV}", "poll_ms": 100, **more}
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


async def test_the_center_links_securely_by_default_and_warns_of_security_none(
        tmp_path: Path) -> None:
    """The link's defaults: SignAndEncrypt, the controller's certificate trusted on first
    use (a warning event names its thumbprint), the map applied. A second machine whose
    link asks for security None is served too, with a warning event that its password
    crosses the network in clear, once (not per reconnect)."""
    from server.links.opcuapki import pki_at, thumbprint

    secure_spec, plain_spec = spec("vmc-06"), spec("5ax-04")
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        secure = await stack.enter_async_context(nc(secure_spec))
        plain = await stack.enter_async_context(nc(plain_spec))
        s1 = linked(secure_spec, secure.server.port)
        s2 = linked(plain_spec, plain.server.port, security_policy="None")
        await plant.register(s1)
        await plant.register(s2)
        for s in (s1, s2):
            assert await plant.fit_from_campaign(s.name) == 1
        await applied_map(plant, secure.runtime.controller.store, s1.name)
        await applied_map(plant, plain.runtime.controller.store, s2.name)
        warnings = await plant.events(kind="warning")
        by = {s.name: [e["detail"] for e in warnings if e["machine"] == s.name]
              for s in (s1, s2)}
        kept = pki_at().pinned(f"opc.tcp://127.0.0.1:{secure.server.port}")
        assert kept is not None
        assert by[s1.name] == [f"opc.tcp://127.0.0.1:{secure.server.port}: the "
                               f"controller's certificate (thumbprint {thumbprint(kept)}) "
                               "trusted on first use"], by
        (clear,) = by[s2.name]
        assert "security None" in clear and "clear text" in clear
        st = await plant.status(s2.name)
        assert st["connected"] is True


async def test_a_mistyped_password_is_seen_within_seconds_without_a_login_storm(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 30: a plant engineer who mistypes the OPC UA password sees why within 10 s
    (the link refused, reason login, the text naming the user) and the center does not
    hammer the controller with logins meanwhile."""
    monkeypatch.setenv("EDNC_TEST_OPCUA_WRONG", "plc-writer-pw-0124")
    base = spec("vmc-06")
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(nc(base))
        s = linked(base, cnc.server.port, password_ref="env:EDNC_TEST_OPCUA_WRONG")
        internal = cnc.server._internal  # type: ignore[attr-defined]
        logins: list[str] = []
        check = internal.user_manager.get_user

        def counted(*args: Any, **kw: Any) -> Any:
            logins.append(str(kw.get("username")))
            return check(*args, **kw)

        internal.user_manager.get_user = counted
        loop = asyncio.get_running_loop()
        t0 = loop.time()
        await plant.register(s)

        async def refused() -> bool:
            st = await plant.status(s.name)
            return bool(st["link_state"] == "refused" and st["link_reason"] == "login")

        async with asyncio.timeout(10.0):
            await until(refused, 0.2)
        seen = loop.time() - t0
        st = await plant.status(s.name)
        assert "login as 'ednc' refused" in st["link_text"], st
        await asyncio.sleep(max(0.0, 20.0 - seen))
        assert 1 <= logins.count("ednc") <= 4, logins  # paced: not a login per second
