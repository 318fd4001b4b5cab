"""Whole system with the compiled Structured Text program as the PLC: ``ednc serve``'s
app and services, a Fanuc-style machine registered with a ``modbus`` link, whose
Modbus/TCP server serves the window variable of the program ``plc/`` compiled by MATIEC
and gcc (machine_sim/stplc.py). The center fits the model from the campaign and writes
the map into that window; the program checks it, applies it and reports it; the ISO
230-6 body diagonals measured on the true machine with the corrections the program
computes (its own evaluation, reversal and clamp, at every reading's position and
direction) improve by >= 97 %."""

from __future__ import annotations

import asyncio
import struct
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from pathlib import Path
from typing import Any, cast

import numpy as np
import pytest
from numpy.typing import NDArray

from machine_sim.modbus_server import PmcModbusServer
from machine_sim.stplc import StPlc, StWindowCNC
from protocol.ctrlmem import TEMP_SEQ_AT, TEMPERATURES_AT
from tests.support.integration import (
    DEADLINE_S,
    DIAGONALS,
    FANUC_5AX,
    Spec,
    campaign,
    center,
    until,
)
from tests.support.stplc import status

pytestmark = pytest.mark.slow


def linked(s: Spec, port: int) -> Spec:
    link = {"kind": "modbus", "host": "127.0.0.1", "port": port, "start_register": 2000,
            "poll_ms": 20}
    return Spec({**s.description, "link": link}, s.secret, s.seed, s.effects)


@asynccontextmanager
async def st_pmc(s: Spec) -> AsyncIterator[StWindowCNC]:
    def factory(cnc: StWindowCNC) -> PmcModbusServer:
        return PmcModbusServer(cast(Any, cnc), port=0, register=2000)

    async with StWindowCNC(s.machine, factory, seed=s.seed, cycle_s=0.02,
                           max_step=1000) as cnc:
        yield cnc


def taken(window: memoryview, slot_mC: int) -> bool:
    """The temperature slots hold ``slot_mC`` and the program has taken their sequence."""
    slots = struct.unpack_from("<32i", window, TEMPERATURES_AT)
    (seq,) = struct.unpack_from("<H", window, TEMP_SEQ_AT)
    return slot_mC in slots and status(window).temp_ack == seq


def st_compensation(plc: StPlc) -> Any:
    """The shift the compiled program applies at each reading: positions rounded to
    counts, each axis approaching from the reading's direction (machine_sim.campaign's
    Compensation)."""
    def shift(q: NDArray[np.float64], direction: NDArray[np.int8]) -> NDArray[np.float64]:
        counts = np.rint(q * 1000.0).astype(np.int64)
        out = np.array([plc.lookup(counts[i].tolist(), (direction[i] < 0).tolist())
                        for i in range(q.shape[0])], dtype=np.float64)
        return out * 0.001
    return shift


@pytest.mark.parametrize("name", ["gantry-02", FANUC_5AX.name])
async def test_the_compiled_st_program_over_modbus_gets_its_map_and_compensates(
        tmp_path: Path, name: str) -> None:
    from machine_sim.campaign import run_campaign
    from machine_sim.testprograms import diagonal_test
    from tests.support.integration import spec
    from volumetric.verify.iso230_6 import diagonal_ranges, improvement

    base = spec(name)
    sim, _, _ = await asyncio.to_thread(campaign, name)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(st_pmc(base))
        s = linked(base, cnc.server.port)
        await plant.register(s)
        assert await plant.fit_from_campaign(s.name) == 1
        await until(lambda: plant.current_applied(s.name))
        st = status(cnc.window)
        assert (st.ack_code, st.applied_version) == (0, 1) and st.active in (1, 2), st
        assert cnc.plc.state & 1  # a map in use
        got = await plant.status(s.name)
        assert got["connected"] is True and got["telemetry"]["link"] == "modbus", got
        # a second PLC restarted from a copy of the window: it takes the active buffer
        # again and evaluates what the running one does
        twin = StPlc(cnc.machine.name, cnc.machine.axis_names, channel_limit=500,
                     max_step=1 << 20)
        twin.window[:] = bytes(cnc.window)
        twin.restart()
        twin.scan([0] * len(twin.axes))
        assert status(twin.window).applied_version == 1
    m = sim.machine
    programs = [diagonal_test(m, d, points=20, runs=2) for d in DIAGONALS]
    before = diagonal_ranges(run_campaign(sim, programs).measurements)
    after = diagonal_ranges(run_campaign(sim, programs,
                                         compensation=st_compensation(twin)).measurements)
    gain = improvement(before, after)
    print(f"\n{m.name} ST program over Modbus/TCP: ranges before "
          f"{ {k: round(v, 1) for k, v in before.items()} } µm, after "
          f"{ {k: round(v, 2) for k, v in after.items()} } µm, gain {gain}")
    assert max(before.values()) > 20.0
    assert gain["overall"] >= 0.97, gain


async def test_the_st_programs_thermal_records_follow_temperatures_posted_to_the_center(
        tmp_path: Path) -> None:
    """A spindle-growth model posted to the center: the map's thermal records reach the
    compiled program, temperatures posted to the center reach its slots over Modbus/TCP,
    and its z correction moves by the opposite of the growth, 5 K a step, under one map
    version."""
    from server.numeric import plain_json
    from tests.support.integration import THERMAL, diagnosed_spindle

    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL)
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(st_pmc(THERMAL))
        s = linked(THERMAL, cnc.server.port)
        await plant.register(s)
        await plant.post_model(s.name, plain_json(model.to_json()))
        await until(lambda: plant.current_applied(s.name))
        assert status(cnc.window).applied_version == 1
        sensor = term.sensor.removeprefix("T_").removesuffix("_C")
        z = cnc.machine.axis_names.index("Z")
        seen: list[int] = []
        for celsius in (20.0, 25.0, 30.0):
            r = await plant.client.post(f"/api/machines/{s.name}/temperatures",
                                        json={"readings": [{"sensor": sensor,
                                                            "celsius": celsius}]})
            assert r.status_code == 200, r.text
            # the center writes the slots with a new sequence; the program takes them.
            # Wait for this reading in the slots and its sequence taken, not for any new
            # sequence: a write of the center's own (the slots stamped for the map just
            # applied) may land between the post and this one
            await until(lambda c=celsius: taken(cnc.window, round(c * 1000)))
            # the thermal part of z's correction, counts: c0 / 2^16 at any position
            seen.append(round(cnc.plc.thermal_constants[0][z] / 65536))
        assert status(cnc.window).applied_version == 1   # one map version all along
    steps = np.diff(seen)
    np.testing.assert_allclose(steps, -term.coefficient * 5.0, atol=1.5)
