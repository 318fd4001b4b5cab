"""Shared material for the protocol tests: hand-written golden payloads, a literal frame
builder, a sample error map and an in-memory pump between two Connections.

The golden payloads are written out byte by byte from the layouts in protocol/README.md,
not produced by the encoder, so a change to the wire format fails the tests.
"""

from __future__ import annotations

import zlib

from protocol import (
    NEED_DATA,
    AuthResponse,
    AxisReading,
    Challenge,
    Connection,
    Controller,
    Error,
    ErrorCode,
    ErrorMapPayload,
    GridAxis,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAck,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapEnd,
    MapReject,
    MapRejectReason,
    Message,
    OutputAxis,
    Reject,
    ReleaseCompensation,
    Released,
    SensorReading,
    Telemetry,
    TemperatureReading,
    Temperatures,
    Welcome,
    pack_values,
)

SECRET = b"0123456789abcdef-vmc-01-secret"


HELLO = Hello("vmc-01", "10.0.0.21", Controller.FANUC, MapEncoding.INT32_INCREMENTS, "1.0.0",
              chain="w X Y b Z t")


def frame(type_code: int, seq: int, payload: bytes) -> bytes:
    """A frame laid out literally from the README: header, payload, CRC-32 (zlib)."""
    head = (b"EDNC" + bytes([1, type_code, 0, 0]) + seq.to_bytes(4, "big")
            + len(payload).to_bytes(4, "big"))
    return head + payload + zlib.crc32(head + payload).to_bytes(4, "big")


def h(text: str) -> bytes:
    """Bytes from hex digits, spaces allowed between bytes."""
    return bytes.fromhex(text)


# (message, type byte, payload) — one row per message type, two for Hello.
GOLDEN: list[tuple[Message, int, bytes]] = [
    (HELLO, 0x01, h(
        "06 766d632d3031"              # name "vmc-01"
        "09 31302e302e302e3231"        # ip "10.0.0.21"
        "01"                           # controller fanuc
        "01"                           # map formats: int32 increments
        "05 312e302e30"                # software version "1.0.0"
        "0b 77 20 58 20 59 20 62 20 5a 20 74"  # chain "w X Y b Z t"
        "00 00")),                     # translational, rotary type: not given
    (Hello("arch-2", "192.168.1.7", Controller.SIEMENS,
           MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM, "sim-0.1",
           translational_type=3, rotary_type=2), 0x01, h(
        "06 617263682d32"
        "0b 3139322e3136382e312e37"
        "02" "03"
        "07 73696d2d302e31"
        "00"
        "03 02")),
    (Challenge(bytes(range(32))), 0x02, bytes(range(32))),
    (AuthResponse(b"\xab" * 32), 0x03, b"\xab" * 32),
    (Welcome(5000, 1000), 0x04, h("00001388 000003e8")),
    (Reject(ErrorCode.AUTH_FAILED, "bad mac"), 0x05, h("0004 07 626164206d6163")),
    (MapBegin(7, 20000, 3, bytes(range(32, 64))), 0x10,
     h("00000007 00004e20 00000003") + bytes(range(32, 64))),
    (MapChunk(7, 2, b"\x01\x02\x03"), 0x11, h("00000007 00000002 010203")),
    (MapEnd(7), 0x12, h("00000007")),
    (MapAck(7), 0x13, h("00000007")),
    (MapReject(7, MapRejectReason.CHECKSUM_MISMATCH, "sha"), 0x14, h("00000007 0004 03 736861")),
    (Telemetry(1_700_000_000_000, "run", 7, (AxisReading("X", 12.5, -0.001),),
               (SensorReading("spindle", 21.25),)), 0x20, h(
        "0000018bcfe56800"             # timestamp ms
        "00000007"                     # applied map version
        "03 72756e"                    # state "run"
        "01" "01 58 4029000000000000 bf50624dd2f1a9fc"   # 1 axis: X 12.5 mm, -0.001 mm
        "01" "07 7370696e646c65 4035400000000000")),     # 1 sensor: spindle 21.25 °C
    (Heartbeat(0xDEADBEEF), 0x21, h("deadbeef")),
    (HeartbeatReply(0xDEADBEEF), 0x22, h("deadbeef")),
    (ReleaseCompensation(2000, "thermal"), 0x23, h("000007d0 07 746865726d616c")),
    (Released(), 0x24, b""),
    (Temperatures(1_700_000_000_000, (TemperatureReading("spindle", 21.25, 150),
                                      TemperatureReading("air", 20.5))), 0x25, h(
        "0000018bcfe56800"             # timestamp ms (center clock at sending)
        "02"                           # 2 sensors
        "07 7370696e646c65 4035400000000000 00000096"   # spindle 21.25 °C, 150 ms old
        "03 616972 4034800000000000 00000000")),        # air 20.5 °C, fresh
    (Error(ErrorCode.PROTOCOL_ERROR, ""), 0x7F, h("0001 00")),
]


def sample_map(machine: str = "vmc-01", version: int = 7,
               encoding: MapEncoding = MapEncoding.INT32_INCREMENTS) -> ErrorMapPayload:
    """A 21 x 11 x 3 map (X, Y grid; X, Y, Z corrections) with distinct values."""
    grid = (GridAxis("X", 0.0, 25.0, 21), GridAxis("Y", -10.0, 30.0, 11))
    outputs = (OutputAxis("X", 4), OutputAxis("Y"), OutputAxis("Z", -2))
    n = 21 * 11 * 3
    if encoding is MapEncoding.INT32_INCREMENTS:
        values = pack_values(encoding, [(i * 37) % 201 - 100 for i in range(n)])
        return ErrorMapPayload(machine, version, encoding, grid, outputs, values, 0.001, 3600)
    values = pack_values(encoding, [((i * 37) % 201 - 100) * 1e-3 for i in range(n)])
    outputs = (OutputAxis("X", 0.004), OutputAxis("Y"), OutputAxis("Z", -0.002))
    return ErrorMapPayload(machine, version, encoding, grid, outputs, values, 0.0, 3600)


def deliver(sender: Connection, receiver: Connection, msg: Message) -> Message:
    """Send ``msg`` from one end, feed the bytes to the other, return what it decoded."""
    receiver.receive_data(sender.send(msg))
    event = receiver.next_event()
    assert event is not NEED_DATA
    assert isinstance(event, type(msg))
    assert receiver.next_event() is NEED_DATA
    return event
