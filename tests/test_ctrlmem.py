"""The controller-memory layout (protocol/README.md §13): golden bytes, the write plan's
order, the PLC side's checks, and the registers' byte orders."""

from __future__ import annotations

import struct
import zlib

import pytest

from protocol.codes import MapEncoding, MapRejectReason
from protocol.ctrlmem import (
    BUFFER_HEADER_SIZE,
    SWITCH_AT,
    TEMP_SEQ_AT,
    TEMPERATURES_AT,
    AckCode,
    BufferHeader,
    ControllerMemoryError,
    Identity,
    Layout,
    Status,
    check_buffer,
    decode_identity,
    decode_status,
    encode_buffer_header,
    encode_identity,
    encode_status,
    from_registers,
    next_sequence,
    pack_switch,
    plan_map_write,
    plan_temperatures,
    sensor_slots,
    to_registers,
    unpack_switch,
)

PAYLOAD = b"EDMP" + struct.pack("<H", 4) + bytes(range(250)) * 3  # a format-4 payload


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


def test_temperature_slots_in_milli_celsius_with_the_sequence_after_them() -> None:
    w = plan_temperatures([21.2345, None, -0.0015], 77)
    assert w.offset == TEMPERATURES_AT and len(w.data) == TEMP_SEQ_AT - TEMPERATURES_AT + 2
    values = struct.unpack_from("<3i", w.data, 0)
    assert values == (21235, -2**31, -1)  # half up: -1.5 m°C -> -1
    assert struct.unpack_from("<H", w.data, len(w.data) - 2)[0] == 77
    assert sensor_slots(["spindle", "air", "spindle", "bed"]) == {"spindle": 0, "air": 1,
                                                                  "bed": 2}


@pytest.mark.parametrize("order", ["little", "big"])
def test_registers_put_the_layout_bytes_into_memory(order: str) -> None:
    data = bytes(range(10))
    regs = to_registers(data, order)  # type: ignore[arg-type]
    assert from_registers(regs, order) == data  # type: ignore[arg-type]
    assert regs[0] == (0x0100 if order == "little" else 0x0001)
