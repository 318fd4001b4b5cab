"""The Modbus/TCP link over real loopback sockets.

A Fanuc-style simulated machine serves its memory window through the Modbus/TCP Server
function's subset (machine_sim/modbus_server.py); the center's
:class:`~server.links.window.session.ControllerSession` writes maps into it through
:class:`~server.links.modbus.ModbusMemory`. Faults are injected at every write of a
push (the center dying after it), with writes repeated and reordered, a second center
writing at the same time, and the PLC restarting.
"""

from __future__ import annotations

import asyncio

import numpy as np
import pytest
from pymodbus.client import AsyncModbusTcpClient

from machine_sim.fanuc import FanucConfig
from machine_sim.lookup import active_map
from machine_sim.modbus_server import PmcModbusServer
from machine_sim.runtime import MachineRuntime
from machine_sim.windowcnc import WindowCNC
from protocol import Controller, MapEncoding, TemperatureReading, Temperatures
from protocol.ctrlmem import STATUS_AT, STATUS_SIZE, Layout, decode_status, plan_map_write
from protocol.maptables import decode_payload
from server.links.modbus import ModbusMemory
from server.links.window.memory import LinkError
from server.links.window.session import ControllerSession, map_writes
from server.mapcodec import encode, with_version
from server.push.adapter import build_for
from server.temperatures import column_of
from tests.support.gantry import GANTRY, machine, memory, payloads, session
from tests.support.integration import spec

pytestmark = pytest.mark.timeout(300)


async def until(check: object, timeout_s: float = 20.0) -> None:
    async with asyncio.timeout(timeout_s):
        while not check():  # type: ignore[operator]
            await asyncio.sleep(0.01)


def corrections(payload: bytes, q: np.ndarray) -> np.ndarray:
    return active_map(decode_payload(payload)).lookup(q)


async def test_the_server_answers_only_what_a_fanuc_pmc_answers() -> None:
    async with machine() as (cnc, srv):
        client = AsyncModbusTcpClient("127.0.0.1", port=srv.port, retries=0)
        await client.connect()
        try:
            ok = await client.read_holding_registers(1000, count=2, device_id=1)
            assert not ok.isError() and ok.registers == [0x4445, 0x4d43]  # "EDCM" LE words
            for call in (client.read_coils(1000, count=1, device_id=1),
                         client.read_input_registers(1000, count=1, device_id=1),
                         client.write_register(1100, 7, device_id=1),
                         client.read_discrete_inputs(1000, count=1, device_id=1)):
                r = await call
                assert r.isError() and r.exception_code == 1, r  # illegal function
            outside = await client.read_holding_registers(999, count=2, device_id=1)
            assert outside.isError() and outside.exception_code == 2
            end = 1000 + len(cnc.window) // 2
            past = await client.write_registers(end - 1, [0, 0], device_id=1)
            assert past.isError() and past.exception_code == 2
            rw = await client.readwrite_registers(read_address=1000, read_count=2,
                                                  write_address=1200, values=[1, 2],
                                                  device_id=1)
            assert not rw.isError() and rw.registers == [0x4445, 0x4d43]
            assert bytes(cnc.window[400:404]) == b"\x01\x00\x02\x00"
        finally:
            client.close()


async def test_a_map_written_over_modbus_is_applied_as_the_ednc_path_applies_it() -> None:
    p1, _ = payloads()
    async with machine(order="big") as (cnc, srv):
        s = session(srv, order="big")
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            verdict = await s.push_map(1, p1, 20.0)
            assert verdict.applied, verdict
            store = cnc.runtime.controller.store
            assert store.version == 1
            rng = np.random.default_rng(3)
            q = np.column_stack([rng.uniform(lo, hi, 50) for lo, hi in
                                 (a.travel for a in spec(GANTRY).machine.axes)])
            assert store.active is not None
            np.testing.assert_array_equal(store.active.lookup(q), corrections(p1, q))
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_center_dying_after_any_write_leaves_the_last_good_map() -> None:
    p1, p2 = payloads()
    async with machine() as (cnc, srv):
        s = session(srv)
        await s.open()
        runner = asyncio.create_task(s.run())
        assert (await s.push_map(1, p1, 20.0)).applied
        s.abort(None, "the center dies")
        await runner
        store = cnc.runtime.controller.store
        layout = Layout(cnc.layout.capacity)
        st = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        target = 2 if st.active == 1 else 1
        # the requests the center sends (the cleared header in the first payload block's)
        writes = map_writes(layout, target, p2, 2, st.ack_seq + 1, block=s.memory.block)
        mem = memory(srv)
        await mem.connect()
        try:
            for k in range(len(writes)):  # the center killed after write k-1, every k
                for w in writes[:k]:
                    await mem.write(w.offset, w.data)
                await asyncio.sleep(0.03)  # several scans
                assert store.version == 1, k
                # repeated and out of order, still without the switch: nothing changes
                for w in reversed(writes[:k]):
                    await mem.write(w.offset, w.data)
                await asyncio.sleep(0.03)
                assert store.version == 1, k
        finally:
            await mem.close()
        # a new center resumes: it learns the sequence and pushes again
        s2 = session(srv)
        await s2.open()
        runner = asyncio.create_task(s2.run())
        try:
            assert (await s2.push_map(2, p2, 20.0)).applied
            assert store.version == 2
        finally:
            s2.abort(None, "test over")
            await runner


async def test_a_corrupted_buffer_is_refused_and_the_old_map_kept() -> None:
    p1, p2 = payloads()
    async with machine() as (cnc, srv):
        s = session(srv)
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            assert (await s.push_map(1, p1, 20.0)).applied
            broken = bytearray(p2)
            broken[len(broken) // 2] ^= 0x40  # the payload no longer matches... its CRC
            st = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
            target = 2 if st.active == 1 else 1
            writes = plan_map_write(Layout(cnc.layout.capacity), target, p2, 2,
                                    st.ack_seq + 1)
            # the header says p2's CRC, the payload bytes are broken in transit
            at = writes[1].offset
            mem = memory(srv)
            await mem.connect()
            for w in writes[:-1]:
                await mem.write(w.offset, w.data)
            mid = len(p2) // 2
            block = (mid // 246) * 246
            chunk = bytes(broken[block:block + 246])
            await mem.write(at + block, chunk + bytes(len(chunk) % 2))
            await mem.write(writes[-1].offset, writes[-1].data)
            await mem.close()
            await until(lambda: decode_status(
                cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE]).ack_seq == st.ack_seq + 1)
            st2 = decode_status(cnc.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
            assert st2.ack_code == 4  # CHECKSUM_MISMATCH
            assert cnc.runtime.controller.store.version == 1 and st2.active == st.active
        finally:
            s.abort(None, "test over")
            await runner


async def test_two_centers_writing_at_once_never_give_a_mixed_map() -> None:
    p1, p2 = payloads()
    rng = np.random.default_rng(5)
    q = np.column_stack([rng.uniform(lo, hi, 20) for lo, hi in
                         (a.travel for a in spec(GANTRY).machine.axes)])
    good = [corrections(p1, q), corrections(p2, q)]
    async with machine(delay_s=0.001) as (cnc, srv):
        for _round in range(3):
            a, b = session(srv), session(srv)
            await a.open()
            await b.open()
            runs = [asyncio.create_task(a.run()), asyncio.create_task(b.run())]
            verdicts = await asyncio.gather(a.push_map(1, p1, 20.0), b.push_map(2, p2, 20.0),
                                            return_exceptions=True)
            for x in (a, b):
                x.abort(None, "round over")
            await asyncio.gather(*runs)
            active = cnc.runtime.controller.store.active
            if active is not None:
                got = active.lookup(q)
                assert any(np.array_equal(got, g) for g in good), "a mixed map applied"
            assert all(isinstance(v, Exception) or v.version in (1, 2) for v in verdicts)


async def test_a_plc_restart_takes_its_active_buffer_again_and_the_ack_is_not_lost() -> None:
    p1, _ = payloads()
    async with machine() as (cnc, srv):
        s = session(srv)
        await s.open()
        runner = asyncio.create_task(s.run())
        assert (await s.push_map(1, p1, 20.0)).applied
        s.abort(None, "the center restarts")
        await runner
        cnc.restart_plc()
        await asyncio.sleep(0.05)
        assert cnc.runtime.controller.store.version == 1
        s2 = session(srv)
        await s2.open()
        assert s2.missed is not None and s2.missed.applied and s2.missed.version == 1
        await s2.memory.close()


async def test_temperatures_reach_the_map_thermal_records() -> None:
    from tests.support.integration import THERMAL, diagnosed_spindle

    model, _term = diagnosed_spindle(THERMAL)
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    built = build_for(THERMAL.description, "fanuc", model.to_json(), {}, 1.0, formats)
    payload = encode(with_version(built, 1))
    sensors = [r.sensor for r in decode_payload(payload).thermal]
    assert sensors, "the map carries thermal records"

    def factory(c: WindowCNC) -> PmcModbusServer:
        return PmcModbusServer(c, port=0, register=1000)

    rt = MachineRuntime(THERMAL.machine, seed=1, fanuc=FanucConfig(max_step_counts=100_000),
                        own_sensors=False)
    async with WindowCNC(THERMAL.machine, factory, runtime=rt, cycle_s=0.005) as cnc:
        m = THERMAL.machine
        s = ControllerSession(m.name, "127.0.0.1", Controller.FANUC, m.axis_names,
                              ModbusMemory("127.0.0.1", cnc.server.port, register=1000),
                              link="modbus", chain=m.chain, poll_s=0.01)
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            assert (await s.push_map(1, payload, 20.0)).applied
            s.send(Temperatures(0, tuple(TemperatureReading(n, 30.0) for n in sensors)))
            store = cnc.runtime.controller.temperatures
            await until(lambda: all(abs(store.values().get(column_of(n), 0) - 30.0) < 1e-9
                                    for n in sensors))
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_window_of_another_machine_or_none_is_refused() -> None:
    async with machine() as (_cnc, srv):
        m = spec(GANTRY).machine
        other = ControllerSession("not-" + m.name, "127.0.0.1", Controller.FANUC,
                                  m.axis_names, memory(srv), link="modbus",
                                  chain=m.chain)
        with pytest.raises(LinkError, match="declares machine"):
            await other.open()
        await other.memory.close()
        wrong = ControllerSession(m.name, "127.0.0.1", Controller.FANUC, m.axis_names,
                                  ModbusMemory("127.0.0.1", srv.port, register=1001),
                                  link="modbus", chain=m.chain)
        with pytest.raises(LinkError, match="magic"):
            await wrong.open()
        await wrong.memory.close()


def test_a_maps_sensor_slots_are_decoded_once_per_map(monkeypatch: pytest.MonkeyPatch) -> None:
    """A re-push of the same map does not decode it again (2 ms of center CPU a push at
    fleet scale); another map is decoded, and a map that does not decode raises each
    time."""
    from protocol.mapformat import MapFormatError
    from server.links.window import session as session_module
    from tests.support.integration import THERMAL, diagnosed_spindle

    model, _term = diagnosed_spindle(THERMAL)
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    built = build_for(THERMAL.description, "fanuc", model.to_json(), {}, 1.0, formats)
    one, two = encode(with_version(built, 101)), encode(with_version(built, 102))
    decoded: list[bytes] = []

    def counting(data: bytes) -> object:
        decoded.append(data)
        return decode_payload(data)

    monkeypatch.setattr(session_module, "decode_payload", counting)
    monkeypatch.setattr(session_module, "_slots_of", {})
    expected = {column_of(s): i for i, s in enumerate(
        dict.fromkeys(r.sensor for r in decode_payload(one).thermal))}
    assert expected, "the map carries thermal records"
    first = session_module.map_slots(one)
    first["T_other_C"] = 9  # a caller's change does not reach the remembered slots
    assert session_module.map_slots(one) == expected
    assert session_module.map_slots(two) == expected
    assert decoded == [one, two]
    for _ in range(2):
        with pytest.raises(MapFormatError):
            session_module.map_slots(one[:40])
    assert len(decoded) == 4
