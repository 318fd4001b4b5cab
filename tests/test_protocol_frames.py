"""Frame layer and message validation: every malformed frame is refused with a clear
RemoteProtocolError, oversize frames from their header alone, and no message that breaks
a limit can be built."""

from __future__ import annotations

import re
from collections.abc import Callable

import pytest

from protocol import (
    CONNECTION_CLOSED,
    NEED_DATA,
    AuthResponse,
    AxisReading,
    Challenge,
    Connection,
    Controller,
    Error,
    ErrorCode,
    Heartbeat,
    Hello,
    LocalProtocolError,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapReject,
    MapRejectReason,
    Message,
    Reject,
    ReleaseCompensation,
    RemoteProtocolError,
    Role,
    SensorReading,
    Telemetry,
    TemperatureReading,
    Temperatures,
    Welcome,
)
from protocol.codec import decode_payload, encode_payload
from protocol.codes import MessageType
from protocol.limits import MAX_CHUNK_BYTES, MAX_FRAME, MAX_PAYLOAD
from tests.support.protocol import HELLO, frame


def center_with(data: bytes) -> Connection:
    conn = Connection(Role.CENTER)
    conn.receive_data(data)
    return conn


def expect_remote(conn: Connection, pattern: str) -> RemoteProtocolError:
    with pytest.raises(RemoteProtocolError, match=pattern) as info:
        conn.next_event()
    return info.value


GOOD = frame(0x01, 0, encode_payload(HELLO))


@pytest.mark.parametrize(("wire", "pattern"), [
    (b"GET / HTTP/1.1\r\n", r"bad magic b'GET ', expected b'EDNC' \(frame at stream offset 0\)"),
    (b"EDNX", r"bad magic b'EDNX'"),
    (b"ED\x00", r"bad magic b'ED\\x00'"),  # refused before the header is complete
    (b"EDNC\x02" + GOOD[5:], r"protocol version 2, this end speaks 1"),
    (b"EDNC\x02", r"protocol version 2, this end speaks 1"),  # before the header is whole
    (b"EDNC\x01\x99", r"unknown message type 0x99"),         # likewise
    (GOOD[:5] + b"\x99" + GOOD[6:], r"unknown message type 0x99"),
    (GOOD[:6] + b"\x00\x01" + GOOD[8:], r"reserved header field is 0x0001, must be 0"),
    (GOOD[:-1] + bytes([GOOD[-1] ^ 1]), r"CRC mismatch in HELLO frame seq 0: computed 0x"),
    (GOOD[:20] + bytes([GOOD[20] ^ 0x80]) + GOOD[21:], r"CRC mismatch"),
])
def test_bad_frame_is_refused(wire: bytes, pattern: str) -> None:
    expect_remote(center_with(wire), pattern)


def test_oversize_frame_refused_from_its_header_alone() -> None:
    header = b"EDNC\x01\x11\x00\x00" + (0).to_bytes(4, "big") + (MAX_PAYLOAD + 1).to_bytes(4, "big")
    assert len(header) == 16
    conn = center_with(header)  # no payload byte sent at all
    expect_remote(conn, rf"MAP_CHUNK frame announces {MAX_PAYLOAD + 1} payload bytes, "
                        rf"limit {MAX_PAYLOAD}")


def test_largest_allowed_header_waits_for_payload() -> None:
    header = b"EDNC\x01\x11\x00\x00" + (0).to_bytes(4, "big") + MAX_PAYLOAD.to_bytes(4, "big")
    assert center_with(header).next_event() is NEED_DATA


def test_error_offset_counts_earlier_frames() -> None:
    conn = center_with(GOOD + b"XXXX")
    assert conn.next_event() == HELLO
    expect_remote(conn, rf"stream offset {len(GOOD)}\)")


def test_error_is_sticky_and_only_error_may_be_sent() -> None:
    conn = center_with(b"NOPE")
    first = expect_remote(conn, "bad magic")
    conn.receive_data(GOOD)
    with pytest.raises(RemoteProtocolError) as again:
        conn.next_event()
    assert again.value is first
    with pytest.raises(LocalProtocolError, match="only Error may follow"):
        conn.send(Welcome(5000, 1000))
    assert conn.send(Error(ErrorCode.PROTOCOL_ERROR, "bad magic"))[:4] == b"EDNC"


def test_eof_inside_a_frame() -> None:
    conn = center_with(GOOD[:-3])
    assert conn.next_event() is NEED_DATA
    conn.receive_data(b"")
    expect_remote(conn, rf"stream closed inside a frame \({len(GOOD) - 3} bytes of it received\)")


def test_eof_at_a_boundary_and_data_after_eof() -> None:
    conn = center_with(GOOD)
    conn.receive_data(b"")
    assert conn.next_event() == HELLO
    assert conn.next_event() is CONNECTION_CLOSED
    with pytest.raises(LocalProtocolError, match="after the end of the stream"):
        conn.receive_data(b"x")


@pytest.mark.parametrize(("code", "payload", "pattern"), [
    (0x01, encode_payload(HELLO) + b"\x00", r"bad HELLO payload: 1 unexpected bytes after the "
                                            r"last field \(offset 39\)"),
    (0x01, encode_payload(HELLO)[:10], r"bad HELLO payload: ip needs 9 bytes at offset 8, "
                                       r"only 2 left"),
    (0x01, b"\x02\xff\xfe" + encode_payload(HELLO)[7:], r"name is not valid UTF-8"),
    (0x01, encode_payload(HELLO).replace(b"\x01\x01\x05", b"\x07\x01\x05"),
     r"controller 7 is not a known Controller"),
    (0x01, encode_payload(HELLO).replace(b"\x01\x01\x05", b"\x01\x00\x05"),
     r"Hello.map_formats must name at least one known format"),
    (0x02, bytes(31), r"bad CHALLENGE payload: nonce needs 32 bytes"),
    (0x04, bytes(8), r"Welcome.heartbeat_period_ms must be in \[100, "),
    (0x05, b"\x00\x63\x00", r"code 99 is not a known ErrorCode"),
    (0x14, b"\x00\x00\x00\x01\x00\x00\x00", r"reason 0 is not a known MapRejectReason"),
    (0x10, bytes(12 + 32), r"MapBegin.version must be in \[1, "),
    (0x11, b"\x00\x00\x00\x01\x00\x00\x00\x00", r"MapChunk.data must be 1 to 8192 bytes, got 0"),
    (0x20, bytes(12) + b"\x00\x00\x00", r"Telemetry.state must not be empty"),
    (0x20, bytes(12) + b"\x01A\x01\x01X" + b"\x7f\xf8" + bytes(14) + b"\x00",
     r"axis X position must be finite, got nan"),
    (0x24, b"\x00", r"bad RELEASED payload: 1 unexpected bytes"),
])
def test_bad_payload_names_message_and_field(code: int, payload: bytes, pattern: str) -> None:
    with pytest.raises(RemoteProtocolError, match=pattern):
        decode_payload(MessageType(code), payload)


def _longest_chain() -> str:
    tokens = [f"{a}{d}" for a in "XYZABC" for d in "0123456789"]
    chain = "w"
    for t in tokens:
        if len(f"{chain} {t} b t") > 64:
            break
        chain += f" {t}"
    return chain + " b t"


def _largest() -> list[Message]:
    text = "é" * 127 + "x"  # 255 bytes of UTF-8
    label = "n" * 16
    return [
        Hello("m" * 32, "2001:db8:1234:5678:9abc:def0:1234:5678", Controller.SIEMENS,
              MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM, label,
              _longest_chain(), 255, 255),
        Reject(ErrorCode.AUTH_FAILED, text),
        MapReject(1, MapRejectReason.APPLY_FAILED, text),
        ReleaseCompensation(2**32 - 1, text),
        Error(ErrorCode.INTERNAL, text),
        Telemetry(2**64 - 1, label, 2**32 - 1,
                  tuple(AxisReading(f"{i:x}" * 16, 1e300, -1e300) for i in range(16)),
                  tuple(SensorReading(f"{i:02d}" * 8, -273.15) for i in range(32))),
        MapChunk(2**32 - 1, 2**32 - 1, b"\xff" * MAX_CHUNK_BYTES),
        Temperatures(2**64 - 1, tuple(TemperatureReading(f"{i:02d}" * 8, 1e300, 2**32 - 1)
                                      for i in range(32))),
    ]


@pytest.mark.parametrize("msg", _largest(), ids=lambda m: type(m).__name__)
def test_largest_message_of_each_kind_fits_one_frame(msg: Message) -> None:
    assert len(_longest_chain().encode()) <= 64
    size = len(encode_payload(msg))
    assert size <= MAX_PAYLOAD
    if isinstance(msg, MapChunk):
        assert size == MAX_PAYLOAD and size + 20 == MAX_FRAME


def _raises(fn: Callable[[], object], pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        fn()


@pytest.mark.parametrize(("build", "pattern"), [
    (lambda: Hello("vmc 01", "10.0.0.1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="w X b t"), r"Hello.name must be 1 to 32 ASCII letters"),
    (lambda: Hello("m", "10.0.0.256", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="w X b t"), r"Hello.ip '10.0.0.256' is not an IPv4 or IPv6 address"),
    (lambda: Hello("m", "2001:DB8::1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="w X b t"), r"must be written canonically: '2001:db8::1'"),
    (lambda: Hello("m", "10.0.0.1", 1, MapEncoding.FLOAT32_MM, "1",  # type: ignore[arg-type]
                   chain="w X b t"), r"Hello.controller must be a Controller"),
    (lambda: Hello("m", "10.0.0.1", Controller.FANUC, MapEncoding(0), "1", chain="w X b t"),
     r"Hello.map_formats must name at least one"),
    (lambda: Hello("m", "10.0.0.1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="X b t"), r"must start with 'w', end with 't'"),
    (lambda: Hello("m", "10.0.0.1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="w X Q b t"), r"unknown token 'Q'"),
    (lambda: Hello("m", "10.0.0.1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1",
                   chain="w X X b t"), r"repeats a token"),
    (lambda: Hello("m", "10.0.0.1", Controller.FANUC, MapEncoding.FLOAT32_MM, "1"),
     r"Hello needs a chain or a translational_type"),
    (lambda: Challenge(bytes(16)), r"Challenge.nonce must be 32 bytes, got 16"),
    (lambda: AuthResponse(bytearray(32)),  # type: ignore[arg-type]
     r"AuthResponse.mac must be bytes, got bytearray"),
    (lambda: Welcome(99, 1000), r"heartbeat_period_ms must be in \[100,"),
    (lambda: Reject(ErrorCode.AUTH_FAILED, "x" * 256), r"Reject.text is 256 bytes"),
    (lambda: Error(ErrorCode.AUTH_FAILED, "a\nb"), r"Error.text must be printable"),
    (lambda: MapBegin(1, 10, 11, bytes(32)), r"chunk_count 11 cannot carry 10 bytes"),
    (lambda: MapBegin(1, 20000, 2, bytes(32)), r"chunk_count 2 cannot carry 20000 bytes"),
    (lambda: MapBegin(1, 2**30, 2**20, bytes(32)), r"total_size 1073741824 exceeds"),
    (lambda: MapChunk(1, -1, b"x"), r"MapChunk.index must be in \[0, 4294967295\], got -1"),
    (lambda: MapChunk(1, 0, b"x" * 8193), r"MapChunk.data must be 1 to 8192 bytes, got 8193"),
    (lambda: Telemetry(0, "run", 0, (AxisReading("X", 0, 0), AxisReading("X", 1, 0))),
     r"Telemetry.axes names 'X' twice"),
    (lambda: Telemetry(0, "run", 0, tuple(AxisReading(f"A{i}", 0, 0) for i in range(17))),
     r"Telemetry has 17 axes, at most 16"),
    (lambda: AxisReading("X", float("inf"), 0), r"axis X position must be finite, got inf"),
    (lambda: SensorReading("s", float("nan")), r"sensor s temperature must be finite"),
    (lambda: Heartbeat(2**32), r"Heartbeat.token must be in \[0, 4294967295\]"),
    (lambda: Heartbeat(True), r"Heartbeat.token must be an int, got bool"),
])
def test_invalid_message_cannot_be_built(build: Callable[[], object], pattern: str) -> None:
    _raises(build, pattern)


def test_messages_are_frozen() -> None:
    with pytest.raises(AttributeError):
        HELLO.name = "other"  # type: ignore[misc]
    assert not hasattr(HELLO, "__dict__")


def test_error_messages_have_no_stray_characters() -> None:
    # every pattern above is matched with re.search; make sure one exact message reads well
    with pytest.raises(ValueError) as info:
        Challenge(bytes(3))
    assert re.fullmatch(r"Challenge\.nonce must be 32 bytes, got 3", str(info.value))


def test_send_error_after_a_remote_error_then_nothing() -> None:
    conn = center_with(b"EDNC\x07")
    with pytest.raises(RemoteProtocolError) as info:
        conn.next_event()
    wire = conn.send_error(ErrorCode.PROTOCOL_ERROR, str(info.value) * 10)
    machine = Connection(Role.MACHINE)
    machine.receive_data(wire)
    got = machine.next_event()
    assert isinstance(got, Error) and got.code is ErrorCode.PROTOCOL_ERROR
    assert got.text.startswith("protocol version 7, this end speaks 1")
    assert len(got.text.encode()) == 255
    assert conn.send_error(ErrorCode.PROTOCOL_ERROR, "again") == b""
