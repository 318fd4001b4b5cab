"""A busy controller is asked again, not left.

Modbus exception 05 (acknowledge) and 06 (server device busy) mean "ask again later":
each request is retried a few times within the session with a short pause, and only a
controller busy for seconds ends it. Before, any exception ended the session: at 30 %
busy answers, 9-20 session drops and a map applied after 20-45 s.
"""

from __future__ import annotations

import asyncio

import pytest

from protocol import Controller
from server.links.modbus import BUSY_RETRIES, ModbusMemory
from server.links.state import LinkCondition
from server.links.window.memory import LinkError
from server.links.window.session import ControllerSession
from tests.support.integration import spec
from tests.support.pmc import REGISTER, Faults, built_map, payload, pmc

pytestmark = pytest.mark.timeout(300)

GANTRY = spec("gantry-02")
M = GANTRY.machine


def _session(port: int) -> ControllerSession:
    return ControllerSession(M.name, "127.0.0.1", Controller.FANUC, M.axis_names,
                             ModbusMemory("127.0.0.1", port, register=REGISTER),
                             link="modbus", chain=M.chain, poll_s=0.02)


async def test_at_30_percent_busy_answers_every_map_is_applied_within_10_s() -> None:
    await asyncio.to_thread(built_map)
    faults = Faults(busy=0.3)
    async with asyncio.timeout(200), pmc(GANTRY, faults=faults, cycle_s=0.01) as cnc:
        s = _session(cnc.server.port)  # type: ignore[attr-defined]
        told: list[LinkCondition] = []
        s.on_condition = told.append
        await s.open()
        runner = asyncio.create_task(s.run())
        loop = asyncio.get_running_loop()
        try:
            for attempt in range(10):
                version = attempt + 1
                data = payload(version)
                t0 = loop.time()
                verdict = await s.push_map(version, data, 10.0)
                assert verdict.applied, (attempt, verdict)
                assert loop.time() - t0 < 10.0
                assert cnc.runtime.controller.store.version == version
            assert not runner.done(), "the session ended"
            assert s.failure is None
            assert faults.busy_answers > 20, faults.busy_answers  # busy answers were met
            assert s.memory.busy_retries == faults.busy_answers  # type: ignore[attr-defined]
            # shown, not hidden: the link stays connected with the reason busy
            assert told and all(c.state == "connected" for c in told), told
            assert told[0].reason == "busy" and "exception 06" in told[0].text, told
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_controller_busy_for_seconds_ends_the_session_as_failed() -> None:
    faults = Faults(busy=1.0)
    async with asyncio.timeout(60), pmc(GANTRY, faults=faults) as cnc:
        s = _session(cnc.server.port)  # type: ignore[attr-defined]
        with pytest.raises(LinkError) as info:
            await s.open()
        await s.memory.close()
        assert (info.value.state, info.value.reason) == ("failed", "exception_06")
        assert faults.busy_answers == BUSY_RETRIES + 1
