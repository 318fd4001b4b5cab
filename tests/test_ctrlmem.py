"""The controller-memory layout (protocol/README.md §13): golden bytes, the write plan's
order, the PLC side's checks, and the registers' byte orders."""

from __future__ import annotations

import struct
import zlib

import pytest

from protocol.codes import MapEncoding, MapRejectReason
from protocol.ctrlmem import (
    BUFFER_HEADER_SIZE,
    MODBUS_BLOCK,
    NO_TEMPERATURE,
    S7_300_BLOCK,
    S7_1500_BLOCK,
    SLOTS_VERSION_AT,
    SWITCH_AT,
    TEMP_SEQ_AT,
    TEMPERATURES_AT,
    AckCode,
    BufferHeader,
    ControllerMemoryError,
    Identity,
    Layout,
    State,
    Status,
    ack_is_verdict,
    check_buffer,
    decode_command,
    decode_identity,
    decode_status,
    encode_buffer_header,
    encode_identity,
    encode_status,
    from_registers,
    needs_push,
    next_sequence,
    next_switch_sequence,
    next_temperature_sequence,
    pack_switch,
    plan_delivery,
    plan_map_write,
    plan_temperatures,
    sensor_slots,
    to_registers,
    unpack_switch,
)

# a format-4 payload whose map version (offset 48) is 3, as the headers below say
PAYLOAD = (b"EDMP" + struct.pack("<H", 4) + bytes(range(42)) + struct.pack("<I", 3)
           + bytes(range(250)) * 3)


def test_identity_golden_bytes_and_round_trip() -> None:
    ident = Identity(MapEncoding.INT32_INCREMENTS | MapEncoding.FACTORED, 16384, 5, 1000,
                     "5ax-09")
    raw = encode_identity(ident)
    assert len(raw) == 64
    assert raw[:20].hex(" ") == ("45 44 43 4d 01 00 11 00 00 40 00 00 05 20 00 00 "
                                 "e8 03 00 00")
    assert raw[20:26] == b"5ax-09" and raw[26:] == bytes(38)
    assert decode_identity(raw) == ident
    with pytest.raises(ControllerMemoryError, match="magic"):
        decode_identity(b"EDCX" + raw[4:])
    with pytest.raises(ControllerMemoryError, match="layout version"):
        decode_identity(raw[:4] + b"\x02\x00" + raw[6:])


def test_status_round_trip_and_offsets() -> None:
    st = Status(7, 3, 0, 2, 1, 42, 9, (1, -2, 3), (-4, 5, -6))
    raw = encode_status(st)
    assert len(raw) == 128
    assert struct.unpack_from("<I", raw, 0)[0] == 7
    assert struct.unpack_from("<H", raw, 8)[0] == 2  # active at window byte 72
    assert struct.unpack_from("<I", raw, 12)[0] == 42
    assert struct.unpack_from("<3i", raw, 20) == (1, -2, 3)
    assert struct.unpack_from("<3i", raw, 52) == (-4, 5, -6)
    assert decode_status(raw, 3) == st


def test_switch_word_packs_buffer_and_sequence_in_one_register() -> None:
    assert pack_switch(1, 1) == 0b101
    assert unpack_switch(pack_switch(16383, 2)) == (16383, 2)
    assert next_sequence(16383) == 1 and next_sequence(0) == 1


@pytest.mark.parametrize(("switch_seq", "ack_seq", "expected"), [
    (0, 0, 1),          # nothing written yet
    (4, 4, 5),          # the usual case: the PLC handled the last switch
    (4, 5, 6),          # the next would equal ack_seq (a switch of another center): skip it
    (16383, 0, 1),      # the wrap: 16383 is followed by 1
    (16383, 1, 2),      # ... unless ack_seq is 1
    (16382, 16383, 1),  # skipping wraps too
])
def test_next_switch_sequence_differs_from_switch_word_and_ack(
        switch_seq: int, ack_seq: int, expected: int) -> None:
    s = next_switch_sequence(switch_seq, ack_seq)
    assert s == expected and s not in (switch_seq, ack_seq) and 1 <= s <= 16383


def test_temperature_sequence_wraps_to_one_never_zero() -> None:
    assert next_temperature_sequence(0) == 1
    assert next_temperature_sequence(65534) == 65535
    assert next_temperature_sequence(65535) == 1


def test_code_100_is_not_a_verdict_and_an_applied_map_is_not_pushed_again() -> None:
    assert not ack_is_verdict(AckCode.BAD_HEADER)
    assert all(ack_is_verdict(c) for c in (0, 3, 4, 5, 6, 10, 11, AckCode.BAD_BUFFER))
    st = Status(1, 2, 0, 1, 1, 42, 0, (0,), (0,))
    assert not needs_push(st, 42) and needs_push(st, 43)
    assert needs_push(Status(1, 2, 0, 0, 0, 0, 0, (0,), (0,)), 42)


def test_state_bits_and_temp_refused_at_148() -> None:
    assert [int(b) for b in State] == [1, 2, 4, 8, 16, 32]
    st = Status(1, 2, 0, 1, int(State.MAP_IN_USE | State.RAMPING), 7, 65535, (1,), (2,),
                temp_refused=(1 << 31) | 5)
    raw = encode_status(st)
    assert struct.unpack_from("<I", raw, 148 - 64)[0] == (1 << 31) | 5
    assert raw[152 - 64:] == bytes(40)
    assert decode_status(raw, 1) == st


def test_the_command_area_as_the_plc_reads_it() -> None:
    window = bytearray(Layout(64).size)
    struct.pack_into("<H", window, SWITCH_AT, pack_switch(9, 2))
    w = plan_temperatures([21.5, None], 300, map_version=12)
    window[w.offset:w.offset + len(w.data)] = w.data
    cmd = decode_command(window)
    assert (cmd.switch_seq, cmd.switch_buffer, cmd.temp_seq, cmd.slots_version) == \
        (9, 2, 300, 12)
    assert cmd.slots[:3] == (21500, NO_TEMPERATURE, NO_TEMPERATURE) and len(cmd.slots) == 32
    with pytest.raises(ControllerMemoryError):
        pack_switch(0, 1)
    with pytest.raises(ControllerMemoryError):
        pack_switch(5, 3)


def test_the_write_plan_clears_writes_then_heads_then_switches() -> None:
    layout = Layout(1024)
    writes = plan_map_write(layout, 2, PAYLOAD, 12, 5)
    at = layout.buffer_at(2)
    assert writes[0].offset == at and writes[0].data == bytes(BUFFER_HEADER_SIZE)
    body = b"".join(w.data for w in writes[1:-2])
    assert body[:len(PAYLOAD)] == PAYLOAD and len(body) == len(PAYLOAD) + len(PAYLOAD) % 2
    assert all(len(w.data) <= 246 and len(w.data) % 2 == 0 for w in writes)
    header = writes[-2]
    assert header.offset == at
    assert header.data[:4] == b"EDBF"
    assert struct.unpack_from("<HHIII", header.data, 4) == (
        4, 0, 12, len(PAYLOAD), zlib.crc32(PAYLOAD))
    assert struct.unpack_from("<I", header.data, 20)[0] == zlib.crc32(header.data[:20])
    assert writes[-1].offset == SWITCH_AT and writes[-1].data == struct.pack("<H", 5 << 2 | 2)
    with pytest.raises(ControllerMemoryError, match="does not fit"):
        plan_map_write(Layout(512), 1, PAYLOAD, 1, 1)


def _window_with(layout: Layout, buffer: int, payload: bytes, header: bytes) -> bytearray:
    window = bytearray(layout.size)
    at = layout.buffer_at(buffer)
    window[at:at + BUFFER_HEADER_SIZE] = header
    window[at + BUFFER_HEADER_SIZE:at + BUFFER_HEADER_SIZE + len(payload)] = payload
    return window


def test_the_plc_check_takes_only_a_whole_buffer() -> None:
    layout = Layout(1024)
    good = encode_buffer_header(BufferHeader(4, 3, len(PAYLOAD), zlib.crc32(PAYLOAD)))
    ok = check_buffer(_window_with(layout, 1, PAYLOAD, good), layout, 1)
    assert ok[0] == PAYLOAD
    torn = bytearray(good)
    torn[9] ^= 1  # map version bit flipped: the header's own CRC catches it
    assert check_buffer(_window_with(layout, 1, PAYLOAD, bytes(torn)), layout, 1)[0] == \
        AckCode.BAD_HEADER
    bad = bytearray(PAYLOAD)
    bad[100] ^= 0xFF
    assert check_buffer(_window_with(layout, 1, bytes(bad), good), layout, 1)[0] == \
        MapRejectReason.CHECKSUM_MISMATCH
    long = encode_buffer_header(BufferHeader(4, 3, 2000, 0))
    assert check_buffer(_window_with(layout, 1, PAYLOAD, long), layout, 1)[0] == \
        MapRejectReason.WRONG_SIZE
    other = encode_buffer_header(BufferHeader(2, 3, len(PAYLOAD), zlib.crc32(PAYLOAD)))
    assert check_buffer(_window_with(layout, 1, PAYLOAD, other), layout, 1)[0] == \
        MapRejectReason.DECODE_ERROR
    assert check_buffer(_window_with(layout, 1, PAYLOAD, good), layout, 3)[0] == \
        AckCode.BAD_BUFFER
    assert check_buffer(bytearray(layout.size), layout, 2)[0] == AckCode.BAD_HEADER
    # §13.3 step 2, last check: the header's map version against the payload's (offset 48)
    wrong = encode_buffer_header(BufferHeader(4, 4, len(PAYLOAD), zlib.crc32(PAYLOAD)))
    code, why = check_buffer(_window_with(layout, 1, PAYLOAD, wrong), layout, 1)
    assert code == MapRejectReason.WRONG_VERSION and int(code) == 5
    assert "map version 3" in str(why)


def test_temperature_slots_in_milli_celsius_with_the_sequence_after_them() -> None:
    w = plan_temperatures([21.2345, None, -0.0015, 20.0005, float("nan")], 77,
                          map_version=9)
    # one write from byte 256 to 391: slots, sequence, reserved, the slots' map version
    assert w.offset == TEMPERATURES_AT == 256 and len(w.data) == 136
    values = struct.unpack_from("<5i", w.data, 0)
    # the exact value of each double, halves up: -0.0015 is -0.00150000000000000003 (so
    # -1.5000…03 m°C -> -2), 20.0005 is 20.00049999999999883 (so 20000, where
    # floor(c·1000 + 0.5) in doubles gives 20001); NaN is nothing to say
    assert values == (21235, -2**31, -2, 20000, -2**31)
    assert struct.unpack_from("<H", w.data, TEMP_SEQ_AT - TEMPERATURES_AT)[0] == 77
    assert struct.unpack_from("<HI", w.data, 130) == (0, 9)
    assert SLOTS_VERSION_AT - TEMPERATURES_AT == 132
    assert struct.unpack_from("<I", plan_temperatures([20.0], 1).data, 132)[0] == 0
    with pytest.raises(ControllerMemoryError, match="sequence"):
        plan_temperatures([20.0], 0)  # 0 means no slots written yet
    assert sensor_slots(["spindle", "air", "spindle", "bed"]) == {"spindle": 0, "air": 1,
                                                                  "bed": 2}


@pytest.mark.parametrize("order", ["little", "big"])
def test_registers_put_the_layout_bytes_into_memory(order: str) -> None:
    data = bytes(range(10))
    regs = to_registers(data, order)  # type: ignore[arg-type]
    assert from_registers(regs, order) == data  # type: ignore[arg-type]
    assert regs[0] == (0x0100 if order == "little" else 0x0001)


def test_plan_delivery_follows_13_2_steps_0_to_5() -> None:
    layout = Layout(1024)
    applied = Status(1, 7, 0, 2, 1, 3, 0, (0,), (0,))
    assert plan_delivery(layout, applied, 7, PAYLOAD, 3) is None  # step 0: it has it
    writes = plan_delivery(layout, applied, 7, PAYLOAD, 4, block=S7_300_BLOCK)
    assert writes is not None
    assert writes[0].offset == layout.buffer_at(1)  # not the active buffer 2
    assert all(len(w.data) <= 240 for w in writes)
    assert unpack_switch(struct.unpack("<H", writes[-1].data)[0]) == (8, 1)
    # ack_seq 1 after a switch word of 16383: 1 is skipped, 2 it is; no map yet: buffer 1
    fresh = Status(1, 1, 0, 0, 0, 0, 0, (0,), (0,))
    writes = plan_delivery(layout, fresh, 16383, PAYLOAD, 1)
    assert writes is not None and writes[0].offset == layout.buffer_at(1)
    assert unpack_switch(struct.unpack("<H", writes[-1].data)[0]) == (2, 1)
    assert (MODBUS_BLOCK, S7_300_BLOCK, S7_1500_BLOCK) == (246, 240, 960)
