"""What a controller link costs the center while nothing happens, and per push.

At 1,000 PMCs the status reads, the telemetry made of them and the requests of a push
are the Modbus link's own cost over the EDNC link's (issue 30's fleet targets,
``benchmarks/controller_links.py fleet``). Pinned here: the status is read at the link's
``poll_ms`` only while a push waits for its verdict and every ``idle_poll_s`` otherwise;
a status becomes telemetry when the map or the state changes, at the center's telemetry
period for moving axes, and every few seconds when nothing moves; a push's cleared
header travels with its first payload block; and a center that stops starts no new
session on its way out.
"""

from __future__ import annotations

import asyncio
import struct
from contextlib import AsyncExitStack
from pathlib import Path
from typing import Any

import pytest

from protocol import Controller
from protocol.ctrlmem import (
    BUFFER_HEADER_SIZE,
    SWITCH_AT,
    Layout,
    pack_switch,
    plan_map_write,
)
from server.links.modbus import ModbusMemory
from server.links.window.service import ControllerLinks
from server.links.window.session import (
    IDLE_POLL_S,
    STATUS_READS_PER_S,
    TELEMETRY_REFRESH_S,
    ControllerSession,
    StatusPace,
    map_writes,
)
from tests.support.integration import center, spec, until
from tests.support.pmc import REGISTER, linked, payload, pmc

pytestmark = pytest.mark.timeout(120)

GANTRY = spec("gantry-02")
M = GANTRY.machine


def session(port: int) -> ControllerSession:
    return ControllerSession(M.name, "127.0.0.1", Controller.FANUC, M.axis_names,
                             ModbusMemory("127.0.0.1", port, register=REGISTER),
                             link="modbus", chain=M.chain, poll_s=0.01)


def relayed_session(port: int) -> tuple[ModbusMemory, ControllerSession]:
    """A session through a fault relay at ``port``: 1-s time-outs, status every 20 ms."""
    memory = ModbusMemory("127.0.0.1", port, register=REGISTER, timeout_s=1.0)
    return memory, ControllerSession(M.name, "127.0.0.1", Controller.FANUC, M.axis_names,
                                     memory, link="modbus", chain=M.chain, poll_s=0.02,
                                     idle_poll_s=0.02)


def test_a_push_clears_the_header_in_its_first_payload_request() -> None:
    p1 = payload(1)
    layout = Layout(4096)
    planned = plan_map_write(layout, 2, p1, 7, 3, block=246)
    sent = map_writes(layout, 2, p1, 7, 3, block=246)
    at = layout.buffer_at(2)
    body = len(p1) + len(p1) % 2
    # one request fewer: the 32 zero bytes and the payload are one region of the window
    assert len(sent) == len(planned) - 1 == -(-(BUFFER_HEADER_SIZE + body) // 246) + 2
    assert all(len(w.data) <= 246 for w in sent)
    first = sent[0]
    assert first.offset == at and first.data[:BUFFER_HEADER_SIZE] == bytes(32)
    assert first.data[BUFFER_HEADER_SIZE:] == p1[:246 - BUFFER_HEADER_SIZE]
    # the region holds what the plan writes, in address order, before header and switch
    region = b"".join(w.data for w in sent[:-2])
    assert region == bytes(32) + p1 + bytes(len(p1) % 2)
    assert [w.offset for w in sent[:-2]] == [at + k for k in range(0, len(region), 246)]
    assert sent[-2] == planned[-2] and sent[-2].offset == at  # the header after the payload
    assert sent[-1] == planned[-1] and sent[-1].offset == SWITCH_AT
    assert sent[-1].data == struct.pack("<H", pack_switch(3, 2))


async def test_the_status_is_read_fast_only_while_a_push_waits_for_its_verdict() -> None:
    p1 = await asyncio.to_thread(payload, 1)
    told: list[dict[str, Any]] = []
    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc:
        s = session(cnc.server.port)  # type: ignore[attr-defined]
        s.poll_s, s.idle_poll_s, s.telemetry_s = 0.02, 0.5, 30.0
        s.on_telemetry = told.append
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            reads0 = s.status_reads
            await asyncio.sleep(2.0)
            idle = s.status_reads - reads0
            assert 3 <= idle <= 6, idle  # every 0.5 s, not every 0.02 s (100)
            assert s.plc_running  # the heartbeat watch works at the idle pace
            # a push's verdict is read at the link's pace from its switch word on, not at
            # the next idle read: well within the idle period of 0.5 s (PLC cycle 5 ms)
            n = len(told)
            verdict = await s.push_map(1, p1, 20.0)
            assert verdict.applied and verdict.latency_s < 0.3, verdict
            # the new map is telemetry at once, although the period is 30 s
            await until(lambda: any(t["map_version"] == 1 for t in told[n:]), 2.0)
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_push_s_own_status_read_counts_as_the_idle_read() -> None:
    # in a re-push to every machine, each push reads the status before writing: the idle
    # read is due idle_poll_s after that read, not beside it
    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc:
        s = session(cnc.server.port)  # type: ignore[attr-defined]
        s.poll_s, s.idle_poll_s, s.telemetry_s = 0.02, 0.5, 30.0
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            await asyncio.sleep(0.1)
            reads0, own = s.status_reads, 0
            for _ in range(8):  # a read like a push's every 0.3 s, for 2.4 s
                await s._read_status()
                own += 1
                await asyncio.sleep(0.3)
            idle = s.status_reads - reads0 - own
            assert idle <= 1, idle  # without the rule: one every 0.5 s, 4-5
            assert s.plc_running
            reads1 = s.status_reads
            await asyncio.sleep(1.6)
            assert 2 <= s.status_reads - reads1 <= 4  # idle reads again once alone
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_status_becomes_telemetry_at_the_centers_period_not_at_each_read() -> None:
    told: list[dict[str, Any]] = []
    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc:
        s = session(cnc.server.port)  # type: ignore[attr-defined]
        s.poll_s = s.idle_poll_s = 0.02  # 50 reads a second
        s.telemetry_s = 0.5
        s.on_telemetry = told.append
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            await asyncio.sleep(2.0)
            reads = s.status_reads
        finally:
            s.abort(None, "test over")
            await runner
    assert reads >= 40, reads
    # the simulated axes move: one telemetry per 0.5 s (and the one at open), not per read
    assert 3 <= len(told) <= 6, (len(told), reads)
    assert TELEMETRY_REFRESH_S <= 5.0  # half the dashboard's 10 s stale limit at most


async def test_a_stopping_center_starts_no_new_session(tmp_path: Path) -> None:
    async with asyncio.timeout(90), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(GANTRY))
        await plant.register(linked(GANTRY, cnc.server.port))  # type: ignore[attr-defined]

        async def slow_worker(_session: Any, _row: Any) -> None:
            try:
                await asyncio.Event().wait()
            finally:  # a worker that takes a while to stop (a push being recorded)
                await asyncio.sleep(0.5)

        # its own table of sessions: the plant's link service serves the machine as well
        links = ControllerLinks(plant.center, plant.services.feed, {}, slow_worker,
                                reconcile_s=0.0)
        async with links:
            await until(lambda: links.connects == 1)
        # the reconcile loop ran while the session closed: it must not have started a
        # session again for the machine it saw without a task
        assert links.linked() == []
        await asyncio.sleep(1.0)
        assert links.connects == 1


async def test_a_request_not_answered_once_in_an_open_session_is_asked_again() -> None:
    from machine_sim.faultrelay import FaultRelay, Faults

    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc, FaultRelay(
            ("127.0.0.1", cnc.server.port)) as relay:  # type: ignore[attr-defined]
        memory, s = relayed_session(relay.port)
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            relay.faults = Faults(swallow=True)  # the next request gets no answer...
            await until(lambda: relay.swallowed >= 1, 0.005)
            relay.faults = Faults()  # ...and the one after it does
            reads = s.status_reads
            await until(lambda: s.status_reads >= reads + 5 or runner.done())
            assert not runner.done() and s.failure is None, s.failure
            assert memory.no_answer_retries == 1
        finally:
            s.abort(None, "test over")
            await runner
    # a second time-out in a row still ends the session: a controller that stays silent
    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc, FaultRelay(
            ("127.0.0.1", cnc.server.port)) as relay:  # type: ignore[attr-defined]
        memory, s = relayed_session(relay.port)
        await s.open()
        runner = asyncio.create_task(s.run())
        relay.faults = Faults(swallow=True)
        await runner
        assert s.failure is not None and s.failure.reason == "no_answer", s.failure
        assert memory.no_answer_retries == 1 and relay.swallowed == 2


async def test_many_sessions_read_their_idle_status_less_often() -> None:
    """The idle reads of one center's sessions share a budget (``StatusPace``): with as
    many sessions as the budget's reads per second times the idle period, each reads
    less often; the heartbeat watch keeps working at that pace."""
    async with asyncio.timeout(60), pmc(GANTRY, cycle_s=0.005) as cnc:
        counts = []
        for others in (0, 7):  # 8 sessions at 2 reads a second: one read every 4 s
            pace = StatusPace(reads_per_s=2.0)
            pace.sessions = others
            s = session(cnc.server.port)  # type: ignore[attr-defined]
            s.poll_s, s.idle_poll_s, s.telemetry_s, s.pace = 0.02, 0.5, 30.0, pace
            s.dead_after_s = 10.0
            await s.open()
            runner = asyncio.create_task(s.run())
            try:
                await until(lambda p=pace, n=others: p.sessions == n + 1, 2.0)  # type: ignore[misc]
                reads0 = s.status_reads
                await asyncio.sleep(3.0)
                counts.append(s.status_reads - reads0)
                assert s.plc_running
            finally:
                s.abort(None, "test over")
                await runner
            assert pace.sessions == others  # an ended session leaves the budget
    alone, crowded = counts
    assert 5 <= alone <= 7, alone  # every 0.5 s: the session's own idle period
    assert crowded <= 1, crowded  # every 4 s
    assert StatusPace().idle_s(IDLE_POLL_S) == IDLE_POLL_S
    busy = StatusPace()
    busy.sessions = 1000
    assert busy.idle_s(IDLE_POLL_S) == 1000 / STATUS_READS_PER_S == 5.0
