"""A Fanuc-style machine takes a factored map and it compensates: the map built from the
simulated machine's geometry travels as bytes through the PMC's map store (chunks, swap
rule), and the ISO 230-6 body diagonals measured on the true machine with the shift the
ladder computes from what it received are cut by 95 %. (In process, not over TCP: the
center's push picks the kind itself, and the factored kind is not yet on by default for
Fanuc ladders.)"""

from __future__ import annotations

import asyncio
from contextlib import AsyncExitStack
from pathlib import Path

import numpy as np
import pytest

from machine_sim.fanuc import FanucConfig, FanucPMC
from machine_sim.lookup import FactoredLadder
from protocol.maptransfer import split_into_chunks
from protocol.messages import MapAck
from server.mapcodec import encode
from tests.support.integration import (
    DEADLINE_S,
    FANUC_5AX,
    campaign,
    center,
    check_diagonals,
    cnc,
    require_loopback_aliases,
    until,
)
from volumetric.compensate.factoredmap import build_factored_map
from volumetric.model.model import MachineModel

pytestmark = pytest.mark.slow

DIAGONALS = ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN")


def test_a_fanuc_ladder_with_a_factored_map_cuts_the_diagonals() -> None:
    sim, _, _ = campaign("gantry-02")
    m = sim.machine
    assert m.controller == "fanuc"
    fm = build_factored_map(m, MachineModel(m.name, sim.geometry), tolerance_um=1.0)
    pmc = FanucPMC(m.name, m.axis_names, FanucConfig(factored=True))
    reply = None
    for msg in split_into_chunks(encode(fm), fm.version):
        reply = pmc.feed_map(msg, 0.0)
    assert isinstance(reply, MapAck)
    received = pmc.store.active
    assert isinstance(received, FactoredLadder)
    check_diagonals(sim, received, f"factored ({fm.nbytes} B)")
    # the EMZPS shifts the ladder's scans settle on are the map's counts at that point
    q = np.array([0.5 * (a.travel[0] + a.travel[1]) for a in m.axes])
    for k in range(200):
        pmc.scan(0.008 * k, q)
    assert np.array_equal(pmc.shifts(), received.counts(q[None, :])[0])


async def test_a_five_axis_fanuc_machine_gets_a_factored_map_over_tcp(tmp_path: Path) -> None:
    require_loopback_aliases()
    s = FANUC_5AX
    sim, _, _ = await asyncio.to_thread(campaign, s.name)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        await plant.register(s)
        machine = await stack.enter_async_context(cnc(s, plant.port))
        await machine.ready.wait()
        assert await plant.fit_from_campaign(s.name) == 1
        await until(lambda: plant.current_applied(s.name))
        pmc = machine.runtime.controller
        await until(lambda: pmc.store.version == 1)
        received = pmc.store.active
        events = [e.kind for e in pmc.store.events]
    assert isinstance(received, FactoredLadder), type(received)
    assert events == ["applied"]
    check_diagonals(sim, received, f"({sim.machine.chain}) factored over TCP")
