"""The machine TCP server on a real loopback socket (port 0) with SQLite in tmp_path:
handshake and authentication, refusals (unknown name, address, secret), the first map
pushed and acknowledged, bad frames and silent peers closing only their own connection."""

from __future__ import annotations

import asyncio
import struct
import zlib
from pathlib import Path

import pytest

from protocol import (
    NEED_DATA,
    Connection,
    Error,
    ErrorCode,
    Message,
    Reject,
    Role,
    Welcome,
)
from server.db import maps as map_repo
from server.events import EventKind
from tests.support.link import DEADLINE_S, RawMachine, Rig, model_body, rig, simulator, until


def frame(kind: int, payload: bytes, seq: int = 0, length: int | None = None) -> bytes:
    head = b"EDNC" + struct.pack(">BBHII", 1, kind, 0, seq,
                                 len(payload) if length is None else length)
    return head + payload + struct.pack(">I", zlib.crc32(head + payload))


# --- the happy path

async def test_machine_authenticates_gets_its_map_and_the_db_records_it(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: r.acked_version(mid))
            assert await r.acked_version(mid) == 1
            await until(lambda: sim.runtime.controller.store.version == 1)
            link = r.center.registry.get("vmc-01")
            assert link.connected and link.address is not None
            await until(lambda: r.center.registry.get("vmc-01").telemetry.get(
                "map_version") == 1)
            stored = await r.db.run(map_repo.get_map_version, mid, 1)
            assert stored is not None and stored.model_version == 1
        kinds = [e.kind for e in reversed(await r.events())]
        assert kinds[:3] == ["connected", "pushed", "applied"]
        await until(lambda: not r.center.registry.get("vmc-01").connected)

        async def disconnected() -> bool:
            return (await r.events())[0].kind == "disconnected"

        await until(disconnected)


async def test_a_machine_without_a_model_is_served_without_a_map(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register()
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            await until(lambda: bool(r.center.registry.get("vmc-01").telemetry))
        assert await r.acked_version(mid) is None
        assert sim.stats.rejects == []


# --- refusals

async def test_wrong_secret_is_refused_and_recorded(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register(model=model_body())
        async with simulator(r.port, secret="not-the-right-secret!") as sim:
            await until(lambda: bool(sim.stats.rejects))
        assert sim.stats.rejects[0].startswith("AUTH_FAILED")
        assert sim.stats.welcomes == 0
        refused = await r.wait_events(EventKind.REFUSED)
        assert refused and "authentication failed" in refused[-1].detail
        assert refused[-1].machine == "vmc-01"
        assert r.center.metrics.refusals.labels(reason="auth")._value.get() >= 1
        assert not r.center.registry.get("vmc-01").connected


async def test_connection_from_another_address_is_refused(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register(ip="10.0.0.21", model=model_body())
        await r.register("vmc-02")  # at 127.0.0.1: connections from lo are let in
        async with simulator(r.port, ip="10.0.0.21") as sim:  # announces it, comes from lo
            await until(lambda: bool(sim.stats.rejects))
        assert sim.stats.rejects[0].startswith("ADDRESS_MISMATCH")
        refused = await r.wait_events(EventKind.REFUSED)
        assert refused[-1].machine == "127.0.0.1"  # the peer, not the name it claimed
        assert "registered at 10.0.0.21" in refused[-1].detail
        assert r.center.metrics.refusals.labels(reason="address")._value.get() >= 1


async def test_unknown_machine_name_is_refused(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register()  # at 127.0.0.1, so the connection is let in
        raw = await RawMachine.connect(r.port)
        answer = await raw.login("nobody-01")
        assert isinstance(answer, Reject) and answer.code is ErrorCode.UNKNOWN_MACHINE
        assert answer.text == ""  # the code only: the detail is for the center's side
        assert await raw.closed() == b""
        refused = await r.events(EventKind.REFUSED)
        assert refused[0].machine == "127.0.0.1" and "nobody-01" in refused[0].detail


async def test_second_live_session_is_refused(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, heartbeat_s=5.0) as r:
        await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            raw = await RawMachine.connect(r.port)
            answer = await raw.login()
            assert isinstance(answer, Reject) and answer.code is ErrorCode.DUPLICATE_SESSION
            raw.close()
            assert r.center.registry.get("vmc-01").connected
            assert sim.stats.connects == 1


# --- bad peers close only their own connection

async def served(r: Rig, name: str) -> None:
    """The machine keeps being heard from (its telemetry time moves on)."""
    first = r.center.registry.get(name).last_seen
    await until(lambda: r.center.registry.get(name).last_seen != first)


@pytest.mark.parametrize("garbage", [
    b"GET / HTTP/1.1\r\nHost: x\r\n\r\n",                     # a stray HTTP client
    frame(0x01, b"\x00" * 10, length=100_000),                # announces an oversized frame
    frame(0x01, b"\x06vmc-01") [:-4] + b"\x00\x00\x00\x00",   # wrong CRC
    frame(0x13, struct.pack(">I", 1)),                        # MapAck before Hello
])
async def test_bad_frames_close_only_that_connection(tmp_path: Path, garbage: bytes) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            raw = await RawMachine.connect(r.port)
            raw.writer.write(garbage)
            reply = Connection(Role.MACHINE)
            reply.receive_data(await raw.closed())
            error = reply.next_event()
            assert isinstance(error, Error) and error.code is ErrorCode.PROTOCOL_ERROR
            assert error.text
            await served(r, "vmc-01")
            assert sim.stats.connects == 1
        refused = await r.events(EventKind.REFUSED)
        assert refused and refused[-1].detail.startswith("protocol error")


async def test_bad_frame_after_welcome_ends_only_that_session(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register(model=model_body())
        await r.register("vmc-02", ip="127.0.0.2")
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            reader, writer = await asyncio.open_connection("127.0.0.1", r.port,
                                                           local_addr=("127.0.0.2", 0))
            raw = RawMachine(reader, writer)
            assert isinstance(await raw.login("vmc-02", ip="127.0.0.2"), Welcome)
            assert r.center.registry.get("vmc-02").connected
            raw.writer.write(frame(0x20, b"\x01\x02", seq=2))  # Telemetry too short
            raw.conn.receive_data(await raw.closed())
            last = None
            while isinstance(e := raw.conn.next_event(), Message):
                last = e
            assert isinstance(last, Error) and last.code is ErrorCode.PROTOCOL_ERROR
            await until(lambda: not r.center.registry.get("vmc-02").connected)
            await served(r, "vmc-01")
            assert sim.stats.connects == 1


async def test_silent_peer_is_dropped_after_the_handshake_timeout(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, handshake_s=0.3) as r:
        await r.register(model=model_body())
        r.services.server.slots.per_address = 20  # all from 127.0.0.1 here
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            silent = [await RawMachine.connect(r.port) for _ in range(20)]
            for peer in silent:
                c = Connection(Role.MACHINE)
                c.receive_data(await peer.closed())
                error = c.next_event()
                assert isinstance(error, Error) and error.code is ErrorCode.TIMEOUT
            await served(r, "vmc-01")
            assert r.center.metrics.refusals.labels(reason="timeout")._value.get() == 20
            refused = await r.events(EventKind.REFUSED)
            # one row for the first, the other 19 counted until the minute is over
            assert len(refused) == 1 and "no Hello within" in refused[0].detail
            await r.services.server.refusal_log.flush(everything=True)  # as at a minute's end
            refused = await r.events(EventKind.REFUSED)
        assert [e.detail.split(" ")[0] for e in refused] == ["19", "no"]


async def test_machine_that_stops_answering_is_dropped(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, heartbeat_s=0.2) as r:
        await r.register()  # no model: nothing but heartbeats flows
        raw = await RawMachine.connect(r.port)
        assert isinstance(await raw.login(), Welcome)
        assert r.center.registry.get("vmc-01").connected
        c = raw.conn
        c.receive_data(await raw.closed())  # we never answer: heartbeats, then Error
        events = []
        while (e := c.next_event()) is not NEED_DATA and isinstance(e, Message):
            events.append(e)
        assert isinstance(events[-1], Error) and events[-1].code is ErrorCode.TIMEOUT
        assert "3 heartbeat periods" in events[-1].text
        assert not r.center.registry.get("vmc-01").connected


async def test_a_flood_of_connections_is_cut_off_and_machines_still_get_in(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, handshake_s=5.0,
                                               max_handshakes=8) as r:
        await r.register(model=model_body())
        await r.register("vmc-02", ip="127.0.0.2", model=model_body("vmc-02"))
        r.services.server.slots.per_address = 8  # the whole flood from 127.0.0.1
        async with simulator(r.port) as sim:
            await sim.ready.wait()
            flood = [await RawMachine.connect(r.port) for _ in range(8)]  # silent, holding
            await until(lambda: r.services.server.handshaking == 8)
            extra = [await RawMachine.connect(r.port) for _ in range(20)]
            for peer in extra:  # beyond the limit: closed at once, nothing sent
                assert await peer.closed() == b""
            assert r.center.metrics.refusals.labels(reason="busy")._value.get() == 20
            await served(r, "vmc-01")  # the established session never noticed
            # a machine from another address takes the slot of the oldest silent holder
            reader, writer = await asyncio.open_connection("127.0.0.1", r.port,
                                                           local_addr=("127.0.0.2", 0))
            late = RawMachine(reader, writer)
            assert isinstance(await late.login("vmc-02", ip="127.0.0.2"), Welcome)
            assert await flood[0].closed() == b""
            assert r.services.server.slots.evicted == 1
            late.close()
            for peer in flood:
                peer.close()
            await until(lambda: r.services.server.handshaking == 0)
