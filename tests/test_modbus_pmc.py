"""The simulated PMC's Modbus/TCP server as a client written from the Modbus spec sees it
(issue 30): every request of a pipelined segment answered in order, exception 03 for a
count or byte count out of range, and the window (status, buffers, the center's command)
kept across a power cycle in its nonvolatile file, so the PLC program's start-up path
(protocol/README.md §13.3) takes the map in use again."""

from __future__ import annotations

import asyncio
import contextlib
import socket
import struct
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from machine_sim.fleet import generated_fleet, served_machine
from machine_sim.modbus_server import PmcArea, PmcModbusServer
from machine_sim.windowcnc import WindowCNC
from protocol.ctrlmem import (
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    Layout,
    decode_status,
    plan_map_write,
    plan_temperatures,
)
from protocol.mapfactored import FactoredAxis, FactoredPayload, TermTable, encode_factored
from tests.support.integration import spec

pytestmark = pytest.mark.timeout(120)

RULES_A = (Path(__file__).parent / "vectors" / "rules_a.bin").read_bytes()


def _adu(tid: int, pdu: bytes, unit: int = 1) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


def _read(addr: int, count: int) -> bytes:
    return struct.pack(">BHH", 0x03, addr, count)


def _write(addr: int, values: list[int], count: int | None = None,
           nbytes: int | None = None) -> bytes:
    n = len(values) if count is None else count
    body = struct.pack(f">{len(values)}H", *values)
    return struct.pack(">BHHB", 0x10, addr, n, len(body) if nbytes is None else nbytes) + body


def test_the_area_answers_the_modbus_limits_with_exception_03() -> None:
    area = PmcArea(bytearray(b"EDCM" + bytes(996)), 100, "little", 1)
    assert area.answer(1, _read(100, 2)) == bytes([3, 4]) + struct.pack(">2H", 0x4445,
                                                                        0x4D43)
    for count in (0, 126, 2000):
        assert area.answer(1, _read(100, count)) == b"\x83\x03", count
    assert area.answer(1, _read(100, 2) + b"\x00") == b"\x83\x03"  # a PDU too long
    assert area.answer(1, _write(100, [1] * 124)) == b"\x90\x03"
    assert area.answer(1, _write(100, [1, 2], nbytes=2)) == b"\x90\x03"  # byte count
    assert area.answer(1, _read(99, 2)) == b"\x83\x02"
    assert area.answer(1, _read(100 + 500, 1)) == b"\x83\x02"
    assert area.answer(1, bytes([0x06, 0, 100, 0, 1])) == b"\x86\x01"
    assert area.answer(2, _read(100, 2)) == b"\x83\x0b"  # another unit
    rw = struct.pack(">BHHHHB", 0x17, 100, 1, 110, 1, 2) + b"\x12\x34"
    assert area.answer(1, rw) == bytes([0x17, 2, 0x44, 0x45])
    assert area.window[20:22] == b"\x34\x12"  # little: the low byte at the even address
    bad_rw = struct.pack(">BHHHHB", 0x17, 100, 126, 110, 1, 2) + b"\x00\x01"
    assert area.answer(1, bad_rw) == b"\x97\x03" and area.window[20:22] == b"\x34\x12"
    assert area.refused == 11 and area.requests == 13


@contextlib.asynccontextmanager
async def _pmc(path: Path | None = None) -> AsyncIterator[tuple[WindowCNC, PmcModbusServer]]:
    servers: list[PmcModbusServer] = []

    def factory(cnc: WindowCNC) -> PmcModbusServer:
        srv = PmcModbusServer(cnc, port=0, register=0, nonvolatile=path, flush_s=0.01)
        servers.append(srv)
        return srv

    machine = spec("gantry-02").machine
    async with WindowCNC(machine, factory, cycle_s=0.005) as cnc:
        yield cnc, servers[0]


async def _exchange(port: int, data: bytes, n: int) -> list[bytes]:
    """Send ``data`` in one write; read ``n`` response frames."""
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        writer.write(data)
        await writer.drain()
        out = []
        for _ in range(n):
            head = await asyncio.wait_for(reader.readexactly(6), 5.0)
            (length,) = struct.unpack_from(">H", head, 4)
            out.append(head + await asyncio.wait_for(reader.readexactly(length), 5.0))
        return out
    finally:
        writer.close()


async def test_pipelined_requests_in_one_segment_are_all_answered_in_order() -> None:
    async with _pmc() as (cnc, srv):
        segment = (_adu(1, _read(0, 2)) + _adu(2, _write(200, [7, 8]))
                   + _adu(3, _read(200, 2)) + _adu(4, _read(0, 0)))
        answers = await _exchange(srv.port, segment, 4)
        assert [struct.unpack_from(">H", a, 0)[0] for a in answers] == [1, 2, 3, 4]
        assert answers[0][7:] == bytes([3, 4]) + b"EDCM"[1::-1] + b"EDCM"[3:1:-1]
        assert answers[1][7:] == _write(200, [7, 8])[:5]
        assert answers[2][7:] == bytes([3, 4, 0, 7, 0, 8])  # the write came first
        assert answers[3][7:] == b"\x83\x03"  # a read of 0 registers: illegal data value
        assert bytes(cnc.window[400:404]) == b"\x07\x00\x08\x00"


async def test_the_answers_to_one_segment_go_back_in_one() -> None:
    """A client that sends several requests together gets their answers in one send (one
    wake-up of the client, not one per answer): the first read returns all four."""
    async with _pmc() as (_cnc, srv):
        segment = b"".join(_adu(t, _read(0, 2)) for t in range(1, 5))

        def ask() -> bytes:
            with socket.create_connection(("127.0.0.1", srv.port), timeout=5.0) as sock:
                sock.sendall(segment)
                return sock.recv(65536)

        got = await asyncio.to_thread(ask)
        assert len(got) == 4 * (6 + 1 + 2 + 4), got
        assert [struct.unpack_from(">H", got, 13 * k)[0] for k in range(4)] == [1, 2, 3, 4]


async def test_a_restart_keeps_status_and_buffers(tmp_path: Path) -> None:
    """The window in a nonvolatile file: after the machine's process ends and a new one
    starts on the same file, the PLC program boots from the status it left (ack_seq,
    active buffer, applied version) and applies the active buffer again after checking
    it; the center's switch word and slots are there too."""
    nv = tmp_path / "gantry-02.pmc"
    layout = Layout(16_384)
    payload = bytearray(RULES_A)
    payload[16:48] = b"gantry-02".ljust(32, b"\0")  # the map names this machine
    async with _pmc(nv) as (cnc, _srv):
        # map A's axes (X, Z, C) are not all the gantry's: APPLY_FAILED (11)
        for w in plan_map_write(layout, 1, bytes(payload), 1, 1):
            cnc.window[w.offset:w.offset + len(w.data)] = w.data
        await asyncio.sleep(0.05)
        st = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        assert (st.ack_seq, st.ack_code, st.active) == (1, 11, 0)
    saved = nv.read_bytes()
    assert len(saved) == layout.size and struct.unpack_from("<H", saved, SWITCH_AT)[0] == 5
    async with _pmc(nv) as (cnc, _srv):
        st = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        assert (st.ack_seq, st.ack_code) == (1, 11)  # its last verdict, kept
        assert cnc.program.applied_switches == 0  # the old switch is not handled again


def _gantry_map(version: int) -> bytes:
    """A factored map for gantry-02 (axes Y X Z) naming its axes X Y Z: found by name."""
    axes = tuple(FactoredAxis(n, False, None, 100, 1, 0, 0) for n in ("X", "Y", "Z"))
    return encode_factored(FactoredPayload("gantry-02", version, 0, 1000, axes, (),
                                           (TermTable(0, 0, 0, (), (4,)),)))


async def test_a_restart_applies_the_active_buffer_again(tmp_path: Path) -> None:
    p1 = _gantry_map(1)
    nv = tmp_path / "gantry-02.pmc"
    async with _pmc(nv) as (cnc, _srv):
        for w in plan_map_write(cnc.layout, 2, p1, 1, 9):
            cnc.window[w.offset:w.offset + len(w.data)] = w.data
        w = plan_temperatures([21.0], 3, map_version=1)
        cnc.window[w.offset:w.offset + len(w.data)] = w.data
        for _ in range(100):
            await asyncio.sleep(0.01)
            if cnc.runtime.controller.store.version == 1:
                break
        assert cnc.runtime.controller.store.version == 1
        await asyncio.sleep(0.1)
        assert cnc.runtime.controller.applied_mm().tolist() == [0.0, 0.004, 0.0]  # X
    async with _pmc(nv) as (cnc, _srv):
        st = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        assert (st.ack_seq, st.ack_code, st.active, st.applied_version) == (9, 0, 2, 1)
        assert cnc.runtime.controller.store.version == 1  # checked and applied at boot
        # a file of another size (a layout change) is not taken: the PMC starts empty
    nv.write_bytes(b"\0" * 10)
    async with _pmc(nv) as (cnc, _srv):
        assert cnc.runtime.controller.store.version == 0


def test_a_fleet_gives_each_pmc_its_nonvolatile_file(tmp_path: Path) -> None:
    """``ednc sim --state-dir DIR``: each Modbus-served PMC keeps its window in
    DIR/<name>.pmc."""
    entries = generated_fleet(2, "a-secret-of-16-bytes", link="modbus")
    served = [served_machine(e, None, tmp_path) for e in entries]
    paths = [getattr(cnc.server, "nonvolatile", None) for cnc in served]
    assert paths == [tmp_path / f"{e.machine.name}.pmc" for e in entries]
    assert getattr(served_machine(entries[0]).server, "nonvolatile", 1) is None


async def test_a_switch_word_is_taken_within_a_ladder_scan_when_the_pmc_says_so() -> None:
    """A fleet's simulated PMCs scan once a second to fit on a few cores; with
    ``switch_scan_s`` a new switch word is taken by an extra scan that long after it
    arrives (a real PMC's ladder scans every 8-64 ms), and the regular scans keep their
    period."""
    from tests.support.gantry import GANTRY, payloads, runtime, session

    m = spec(GANTRY).machine
    versions = payloads()
    async with WindowCNC(m, lambda c: PmcModbusServer(c, port=0, register=1000),
                         runtime=runtime(), cycle_s=1.0, switch_scan_s=0.02) as cnc:
        srv = cnc.server
        assert isinstance(srv, PmcModbusServer)
        s = session(srv)
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            latencies = []
            for version in (1, 2, 2, 2):  # without the extra scan: each U(0, 1 s)
                verdict = await s.push_map(version, versions[version - 1], 20.0)
                assert verdict.applied, verdict
                latencies.append(verdict.latency_s)
            assert max(latencies) < 0.3, latencies
        finally:
            s.abort(None, "test over")
            await runner
