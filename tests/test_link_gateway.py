"""Several controllers behind one address: a Modbus/TCP gateway, one unit id each.

Each machine is registered with its own ``unit_id`` on the same host and port, and may
share its ``ip`` (the gateway's address) with the others: the ip keys EDNC logins only.
The center reaches each window through the one address and gives each its own map,
registered through the REST API or a machines file; ``ednc discover --unit-id`` finds
them all, and two registrations on one window are refused, visibly.
"""

from __future__ import annotations

import asyncio
from contextlib import AsyncExitStack
from pathlib import Path

import pytest

from machine_sim.lookup import ActiveMap
from server.links import BACKENDS, memory_for
from server.links.discover import discover
from server.links.modbus import ModbusMemory
from server.schemas.link import ModbusLink
from tests.support.integration import (
    DEADLINE_S,
    FANUC_5AX,
    Spec,
    applied_map,
    campaign,
    center,
    check_diagonals,
    machines_file,
    spec,
    until,
)
from tests.support.pmc import gateway, linked, modbus_link

GANTRY = spec("gantry-02")


def test_the_backend_is_chosen_by_the_link_name() -> None:
    assert set(BACKENDS) == {"modbus", "opcua"}
    link = ModbusLink(kind="modbus", unit_id=7, port=1502, block_registers=60)
    memory = memory_for(link, "10.0.0.9")
    assert isinstance(memory, ModbusMemory)
    assert (memory.address, memory.unit_id, memory.block) == ("10.0.0.9:1502", 7, 120)


async def test_two_pmcs_behind_one_address_are_found_and_served(tmp_path: Path) -> None:
    async with asyncio.timeout(180), AsyncExitStack() as stack:
        port, _cncs = await stack.enter_async_context(gateway({1: GANTRY, 2: FANUC_5AX}))
        found = await discover(["127.0.0.1"], modbus_port=port, opcua_port=None,
                               ednc_port=None, register=2000, unit_ids=(1, 2, 3))
        assert [f.machine for f in found[:2]] == [GANTRY.name, FANUC_5AX.name], found
        assert found[1].link["unit_id"] == 2 and "unit_id" not in found[0].link
        assert found[2].machine is None  # unit 3: no controller behind it

        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        specs: list[Spec] = [linked(GANTRY, port), linked(FANUC_5AX, port, unit_id=2)]
        for s in specs:
            await plant.register(s)

        async def both() -> bool:
            return all([(await plant.status(s.name))["connected"] for s in specs])

        await until(both)
        for s in specs:
            st = await plant.status(s.name)
            assert st["link_state"] == "connected" and st["telemetry"]["link"] == "modbus"

        # a third registration on gantry-02's window is refused, and says why
        third = Spec({**GANTRY.description, "name": "gantry-02b", "ip": "127.0.2.99",
                      "link": linked(GANTRY, port).description["link"]},
                     GANTRY.secret, GANTRY.seed, GANTRY.effects)
        await plant.register(third)

        async def refused() -> bool:
            st = await plant.status("gantry-02b")
            return bool(st["link_state"] == "refused")

        await until(refused)
        st = await plant.status("gantry-02b")
        assert st["link_reason"] == "duplicate_link" and GANTRY.name in st["link_text"], st
        assert (await plant.status(GANTRY.name))["connected"]


def at_gateway(s: Spec, port: int, unit: int) -> Spec:
    """``s`` behind the gateway on loopback ``port`` as unit ``unit``, registered at the
    gateway's address: its ``ip``, which the link's host defaults to."""
    link = {k: v for k, v in modbus_link(port, unit_id=unit).items() if k != "host"}
    return Spec({**s.description, "ip": "127.0.0.1", "link": link}, s.secret, s.seed,
                s.effects)


HMC = spec("hmc-03")  # a second Fanuc, another chain: another map


@pytest.mark.parametrize("via", ["rest", "machines file"])
async def test_two_pmcs_registered_at_the_gateways_address_get_their_own_maps(
        tmp_path: Path, via: str) -> None:
    # the laser campaigns come before the center is involved (off the clock)
    sims = {s.name: (await asyncio.to_thread(campaign, s.name))[0] for s in (GANTRY, HMC)}
    received: dict[int, ActiveMap] = {}
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        port, cncs = await stack.enter_async_context(gateway({1: GANTRY, 2: HMC}))
        specs = {1: at_gateway(GANTRY, port, 1), 2: at_gateway(HMC, port, 2)}
        listed = (machines_file(tmp_path / "machines.json", list(specs.values()))
                  if via == "machines file" else None)
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}",
                                                       machines_file=listed))
        if via == "rest":
            for s in specs.values():
                await plant.register(s)
        listing = (await plant.client.get("/api/machines")).json()
        assert sorted((m["name"], m["ip"]) for m in listing) == sorted(
            (s.name, "127.0.0.1") for s in specs.values()), listing
        for s in specs.values():
            assert await plant.fit_from_campaign(s.name) == 1
        for unit, s in specs.items():
            received[unit] = await applied_map(plant, cncs[unit].runtime.controller.store,
                                               s.name)
            assert (await plant.status(s.name))["telemetry"]["link"] == "modbus"
    # the map each unit applied compensates its own machine (not its neighbour)
    for unit, s in specs.items():
        check_diagonals(sims[s.name], received[unit], f"behind the gateway as unit {unit}")
