"""The center's window session follows protocol/README.md §13.2 where it differs from a
plain reading: the switch sequence skips ack_seq (also after a wrap), the temperature
slots carry the map version they were planned for (and are written again for the new map
at a swap), and code 100 (a torn header) is never taken for the PLC's verdict.

The controller here is a window in a bytearray with a minimal PLC program behind it
(:class:`FakePLC`): it answers each switch whose sequence differs from its ack_seq, as
§13.3 step 1 does, so a switch the center writes with a stale sequence goes unanswered.
"""

from __future__ import annotations

import asyncio
import functools
import struct
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import pytest

from protocol import Controller, MapEncoding, TemperatureReading, Temperatures
from protocol.ctrlmem import (
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    TEMP_SEQ_AT,
    Command,
    Identity,
    Layout,
    Status,
    decode_buffer_header,
    decode_command,
    encode_identity,
    encode_status,
    pack_switch,
    unpack_switch,
)
from protocol.maptables import decode_payload
from server.links.ednc.session import LinkClosed
from server.links.window.session import ControllerSession
from server.mapcodec import encode, with_version
from server.push.adapter import build_for
from tests.support.integration import THERMAL, diagnosed_spindle, until

pytestmark = pytest.mark.timeout(120)

M = THERMAL.machine
CAPACITY = 16_384


class FakePLC:
    """A controller's window (a :class:`~server.links.window.memory.MemoryClient`) whose
    PLC program answers every new switch at once with ``code`` (0: applied).

    ``switch_seq``, ``ack_seq`` and ``ack_code`` are what the window holds when the
    center opens it (a previous center's switch and the PLC's answer)."""

    block = 246
    address = "fake-plc"

    def __init__(self, *, switch_seq: int = 0, ack_seq: int = 0, ack_code: int = 0,
                 code: int = 0) -> None:
        self.layout = Layout(CAPACITY)
        self.window = bytearray(self.layout.size)
        formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
        self.window[:64] = encode_identity(Identity(formats, CAPACITY, len(M.axis_names),
                                                    1000, M.name))
        if switch_seq:
            struct.pack_into("<H", self.window, SWITCH_AT, pack_switch(switch_seq, 1))
        zeros = (0,) * len(M.axis_names)
        self.status = Status(0, ack_seq, ack_code, 0, 0, 0, 0, zeros, zeros)
        self.code = code
        self.switches: list[int] = []
        """Sequences of the switch words the center wrote, in order."""
        self.temperatures: list[Command] = []
        """The command area after each temperature write."""

    async def connect(self) -> None:
        pass

    async def close(self) -> None:
        pass

    async def read(self, offset: int, size: int) -> bytes:
        if offset == STATUS_AT:  # the program runs: each status read sees a new scan
            self.status = replace(self.status, heartbeat=self.status.heartbeat + 1)
        self.window[STATUS_AT:STATUS_AT + STATUS_SIZE] = encode_status(self.status)
        return bytes(self.window[offset:offset + size])

    async def write_many(self, writes: Sequence[tuple[int, bytes]], *,
                         read: tuple[int, int] | None = None) -> bytes:
        got = await self.read(*read) if read is not None else b""
        for offset, data in writes:
            await self.write(offset, data)
        return got

    async def write(self, offset: int, data: bytes) -> None:
        self.window[offset:offset + len(data)] = data
        if offset <= TEMP_SEQ_AT < offset + len(data):
            self.temperatures.append(decode_command(self.window))
        if offset != SWITCH_AT:
            return
        seq, buffer = unpack_switch(struct.unpack_from("<H", self.window, SWITCH_AT)[0])
        self.switches.append(seq)
        if seq == self.status.ack_seq:
            return  # §13.3 step 1: the switch already handled
        if self.code:
            self.status = replace(self.status, ack_seq=seq, ack_code=self.code)
            return
        header = decode_buffer_header(self.window[self.layout.buffer_at(buffer):])
        assert header is not None
        self.status = replace(self.status, ack_seq=seq, ack_code=0, active=buffer,
                              applied_version=header.map_version, state=1, temp_ack=0)


@functools.cache
def thermal_map() -> Any:
    """The map the center builds for the THERMAL machine's factored-map ladder, with its
    spindle's thermal record (a ``MapContent``)."""
    model, _term = diagnosed_spindle(THERMAL)
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    return build_for(THERMAL.description, "fanuc", model.to_json(), {}, 1.0, formats)


def payload(version: int) -> bytes:
    """:func:`thermal_map` as map ``version``, encoded."""
    return encode(with_version(thermal_map(), version))


def session(plc: FakePLC) -> ControllerSession:
    return ControllerSession(M.name, "127.0.0.1", Controller.FANUC, M.axis_names, plc,
                             link="modbus", chain=M.chain, poll_s=0.005)


async def _served(plc: FakePLC) -> tuple[ControllerSession, asyncio.Task[str]]:
    s = session(plc)
    await s.open()
    return s, asyncio.create_task(s.run())


async def _end(s: ControllerSession, runner: asyncio.Task[str]) -> None:
    s.abort(None, "test over")
    await runner


@pytest.mark.parametrize(("switch_seq", "ack_seq", "expected"), [
    (16383, 1, 2),   # next(max(16383, 1)) = 1 = ack_seq: the PLC would ignore the switch
    (5, 16383, 6),   # a PLC that handled a switch from before the wrap
    (4, 5, 6),       # next(4) = 5 = ack_seq (another center's switch)
])
async def test_the_switch_sequence_differs_from_switch_word_and_ack_seq(
        switch_seq: int, ack_seq: int, expected: int) -> None:
    plc = FakePLC(switch_seq=switch_seq, ack_seq=ack_seq, ack_code=0)
    s, runner = await _served(plc)
    try:
        verdict = await s.push_map(1, await asyncio.to_thread(payload, 1), 2.0)
        assert plc.switches == [expected] and verdict.applied
    finally:
        await _end(s, runner)


async def _applied_and_warm(s: ControllerSession, plc: FakePLC, payload_1: bytes,
                            sensors: list[str]) -> None:
    """Map version 1 pushed and applied, then 30 °C on every sensor until the PLC took it."""
    assert (await s.push_map(1, payload_1, 2.0)).applied
    s.send(Temperatures(0, tuple(TemperatureReading(n, 30.0) for n in sensors)))
    await until(lambda: any(c.slots[0] == 30_000 for c in plc.temperatures), 0.005)


async def test_temperature_slots_carry_the_map_version_and_follow_a_swap() -> None:
    one, two = await asyncio.to_thread(lambda: (payload(1), payload(2)))
    sensors = sorted({r.sensor for r in decode_payload(one).thermal})
    assert sensors, "the map carries thermal records"
    plc = FakePLC()
    s, runner = await _served(plc)
    try:
        async with asyncio.timeout(10):
            await _applied_and_warm(s, plc, one, sensors)
            assert {c.slots_version for c in plc.temperatures} == {1}
            written = len(plc.temperatures)
            assert (await s.push_map(2, two, 2.0)).applied
            # §13.2 step 7: the new map's slots at once, stamped with its version
            await until(lambda: len(plc.temperatures) > written, 0.005)
        after = plc.temperatures[written:]
        assert all(c.slots_version == 2 and c.slots[0] == 30_000 for c in after), after
        assert after[0].temp_seq != plc.temperatures[written - 1].temp_seq
    finally:
        await _end(s, runner)


async def test_temperatures_go_on_from_the_windows_sequence() -> None:
    # a previous center's last temperature write (sequence 7) was taken by the PLC: a new
    # session starting again at 1..7 would write sequences the PLC may take for old ones
    one = await asyncio.to_thread(payload, 1)
    sensors = sorted({r.sensor for r in decode_payload(one).thermal})
    plc = FakePLC()
    struct.pack_into("<H", plc.window, TEMP_SEQ_AT, 7)
    plc.status = replace(plc.status, temp_ack=7)
    s, runner = await _served(plc)
    try:
        async with asyncio.timeout(10):
            await _applied_and_warm(s, plc, one, sensors)
        assert plc.temperatures[0].temp_seq == 8, plc.temperatures
    finally:
        await _end(s, runner)


@pytest.mark.parametrize(("ack_code", "verdict"), [(100, False), (4, True), (0, True)])
async def test_a_code_100_read_at_open_is_no_missed_verdict(ack_code: int,
                                                           verdict: bool) -> None:
    plc = FakePLC(switch_seq=9, ack_seq=9, ack_code=ack_code)
    s = session(plc)
    await s.open()
    try:
        if verdict:
            assert s.missed is not None and (s.missed.seq, s.missed.code) == (9, ack_code)
        else:  # nothing to store: §13.2 step 0 decides whether the map goes again
            assert s.missed is None
    finally:
        s.abort(None, "test over")


async def test_code_100_twice_is_no_rejection() -> None:
    plc = FakePLC(code=100)
    s, runner = await _served(plc)
    try:
        with pytest.raises(LinkClosed, match="PLC code 100"):
            await s.push_map(1, await asyncio.to_thread(payload, 1), 2.0)
        assert s.torn_rewrites == 1 and plc.switches == [1, 2]
    finally:
        await _end(s, runner)
