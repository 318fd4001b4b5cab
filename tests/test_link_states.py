"""Every refusal and failure of a controller link is visible, with its reason.

A wrong machine name, magic, layout or byte order, a controller that never answers, one
that refuses the connection, a stopped PLC program: each is classified where it is seen
(:class:`~server.links.window.memory.LinkError`'s state and reason), and the center shows
it within seconds in the machine's status, the dashboard row, the metric
``ednc_machine_link_state`` and one event (the first of each reason, then at most one a
minute), while it keeps retrying.
"""

from __future__ import annotations

import asyncio
import struct
from contextlib import AsyncExitStack
from pathlib import Path

import pytest

from protocol import Controller, MapEncoding
from protocol.ctrlmem import Identity, encode_identity
from server.links.modbus import ModbusMemory
from server.links.state import LinkCondition, Throttle
from server.links.window.memory import LinkError
from server.links.window.session import ControllerSession, identity_of
from server.state import Registry, shown_state
from tests.support.integration import center, spec, until
from tests.support.pmc import REGISTER, linked, pmc, silent_server

GANTRY = spec("gantry-02")
M = GANTRY.machine


def _identity(name: str = "gantry-02") -> bytes:
    return encode_identity(Identity(MapEncoding.INT32_INCREMENTS, 4096, 3, 1000, name))


def _swapped(raw: bytes) -> bytes:
    return b"".join(raw[k + 1:k + 2] + raw[k:k + 1] for k in range(0, len(raw), 2))


# -- classification, pure

def test_an_identity_is_classified_by_what_is_wrong_with_it() -> None:
    good = _identity()
    assert identity_of(good, "pmc").name == "gantry-02"
    cases = {
        "byte_order": _swapped(good),
        "magic": bytes(64),
        "layout": good[:4] + struct.pack("<H", 9) + good[6:],  # layout version 9
    }
    for reason, raw in cases.items():
        with pytest.raises(LinkError) as info:
            identity_of(raw, "pmc")
        assert (info.value.state, info.value.reason) == ("refused", reason), info.value


def test_a_reason_is_reported_first_then_once_a_minute_per_machine() -> None:
    t = Throttle(repeat_s=60.0)
    assert t.allow("a", "byte_order", 0.0)
    assert not t.allow("a", "byte_order", 30.0)
    assert t.allow("a", "no_answer", 31.0)  # another reason is news
    assert t.allow("b", "byte_order", 31.0)  # another machine too
    assert t.allow("a", "byte_order", 61.0)
    assert t.suppressed == 1
    assert LinkCondition("refused", "magic", "x").summary == "refused (magic): x"


# -- classification over a real socket

def _session(port: int, *, name: str = M.name, register: int = REGISTER,
             order: str = "little", timeout_s: float = 2.0) -> ControllerSession:
    memory = ModbusMemory("127.0.0.1", port, register=register,
                          byte_order=order, timeout_s=timeout_s)  # type: ignore[arg-type]
    return ControllerSession(name, "127.0.0.1", Controller.FANUC, M.axis_names, memory,
                             link="modbus", chain=M.chain, poll_s=0.01, dead_after_s=0.5)


async def _open_fails(s: ControllerSession) -> LinkError:
    try:
        with pytest.raises(LinkError) as info:
            await s.open()
    finally:
        await s.memory.close()
    return info.value


async def test_each_refusal_of_a_pmc_names_its_reason() -> None:
    async with asyncio.timeout(60), pmc(GANTRY) as cnc:
        port = cnc.server.port  # type: ignore[attr-defined]
        cases = [
            (_session(port, name="not-gantry"), "refused", "identity_name"),
            (_session(port, order="big"), "refused", "byte_order"),
            (_session(port, register=REGISTER + 1), "refused", "magic"),
            (_session(port, register=0), "refused", "exception_02"),
        ]
        for s, state, reason in cases:
            exc = await _open_fails(s)
            assert (exc.state, exc.reason) == (state, reason), exc


async def test_no_server_and_a_silent_one_are_unreachable() -> None:
    async with asyncio.timeout(30):
        async with silent_server() as port:
            exc = await _open_fails(_session(port, timeout_s=0.3))
            assert (exc.state, exc.reason) == ("unreachable", "no_answer"), exc
        exc = await _open_fails(_session(port))  # closed now: connection refused
        assert (exc.state, exc.reason) == ("unreachable", "connect"), exc


async def test_a_stopped_plc_program_is_waited_for_not_left() -> None:
    seen: list[LinkCondition] = []
    async with asyncio.timeout(30), pmc(GANTRY) as cnc:
        s = _session(cnc.server.port)  # type: ignore[attr-defined]
        s.on_condition = seen.append
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            cnc.stop_plc()
            await until(lambda: bool(seen))
            assert (seen[0].state, seen[0].reason) == ("plc_stopped", "heartbeat")
            assert not runner.done() and s.failure is None  # the session goes on
            cnc.running = True
            await until(lambda: len(seen) == 2)
            assert seen[1].state == "connected"
        finally:
            s.abort(None, "test over")
            await runner


# -- the center shows it

async def test_a_wrong_byte_order_is_visible_within_seconds_and_reported_once(
        tmp_path: Path) -> None:
    async with asyncio.timeout(90), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(GANTRY))
        port = cnc.server.port  # type: ignore[attr-defined]
        await plant.register(linked(GANTRY, port, byte_order="big"))
        loop = asyncio.get_running_loop()
        t0 = loop.time()

        async def refused() -> bool:
            st = await plant.status(M.name)
            return bool(st["link_state"] == "refused")

        await until(refused)
        assert loop.time() - t0 < 10.0
        st = await plant.status(M.name)
        assert st["link_reason"] == "byte_order" and "swapped" in st["link_text"], st
        assert await plant.metric("ednc_machine_link_state", link="modbus", machine=M.name,
                                  reason="byte_order", state="refused") == 1.0
        r = await plant.client.get("/api/dashboard")
        card = next(c for c in r.json()["machines"] if c["name"] == M.name)
        assert card["link_state"] == "refused" and card["link_reason"] == "byte_order"
        assert card["health"] == "offline" and "swapped" in card["health_reason"], card
        # it keeps trying (with backoff) and says it once
        links = plant.services.controllers
        assert links is not None
        reads = links.registration_reads  # the registration is known
        await until(lambda: links.failures >= 3)
        events = [e for e in await plant.events(machine=M.name) if e["kind"] == "link"]
        assert len(events) == 1 and "byte_order" in events[0]["detail"], events
        # the registrations were looked at every 2 s meanwhile, not read whole again
        assert links.registration_reads == reads
        # corrected, it connects and the reason goes
        r = await plant.client.patch(f"/api/machines/{M.name}", json={
            "link": linked(GANTRY, port).description["link"]})
        assert r.status_code == 200, r.text

        async def connected() -> bool:
            st = await plant.status(M.name)
            return bool(st["connected"]) and st["link_state"] == "connected"

        await until(connected)
        assert (await plant.status(M.name))["link_reason"] == ""
        assert links.registration_reads == reads + 1  # read again for the change


def test_the_registry_shows_a_stopped_plc_during_its_session() -> None:
    reg = Registry()
    reg.condition("m", "unreachable", "connect", "10.0.0.5:502: cannot connect")
    assert shown_state(reg.get("m")) == "unreachable"
    reg.connected("m", "10.0.0.5:502")
    assert shown_state(reg.get("m")) == "connected" and reg.get("m").link_reason == ""
    reg.condition("m", "plc_stopped", "heartbeat", "still")
    assert shown_state(reg.get("m")) == "plc_stopped"
    reg.disconnected("m")
    assert shown_state(reg.get("m")) == "offline"


def test_ednc_serve_prints_a_link_warning_by_default(capsys: pytest.CaptureFixture[str]
                                                     ) -> None:
    import logging

    from ednc.commands.serve import configure_logging

    root = logging.getLogger()
    level = root.level
    handler = configure_logging("warning")
    try:
        logging.getLogger("server.links.window.service").warning(
            "gantry-02: modbus link refused (byte_order): swapped")
        logging.getLogger("server.links.window.service").info("not shown")
    finally:
        root.removeHandler(handler)
        root.setLevel(level)
    err = capsys.readouterr().err
    assert "WARNING server.links.window.service: gantry-02: modbus link refused" in err
    assert "not shown" not in err
