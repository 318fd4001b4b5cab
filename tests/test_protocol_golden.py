"""Golden bytes, both ways: every message type, one literal frame, and a whole
conversation fed to each role whole and one byte at a time."""

from __future__ import annotations

from pathlib import Path

import pytest

from protocol import (
    CONNECTION_CLOSED,
    NEED_DATA,
    AuthResponse,
    Challenge,
    Connection,
    Error,
    ErrorCode,
    Heartbeat,
    HeartbeatReply,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    Message,
    ReleaseCompensation,
    Released,
    Role,
    State,
    Telemetry,
    Welcome,
)
from protocol.codec import decode_payload, encode_payload
from protocol.frames import FrameBuffer, encode_frame
from protocol.messages import TYPE_OF
from tests.support.protocol import GOLDEN, HELLO, frame

# The worked example of protocol/README.md: the machine's first frame, every byte literal.
HELLO_FRAME = bytes.fromhex(
    "45444e43 01 01 0000 00000000 00000027"          # EDNC, v1, Hello, seq 0, 39 bytes
    "06 766d632d3031 09 31302e302e302e3231 01 01"    # "vmc-01", "10.0.0.21", fanuc, int32
    "05 312e302e30 0b 77 20 58 20 59 20 62 20 5a 20 74 00 00"  # "1.0.0", chain, 0, 0
    "03b25399"                                       # CRC-32
)


def crc32_bitwise(data: bytes) -> int:
    """CRC-32 as the README defines it, one bit at a time (reflected 0xEDB88320)."""
    crc = 0xFFFFFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ (0xEDB88320 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF


def test_crc_is_the_documented_crc32() -> None:
    assert crc32_bitwise(b"123456789") == 0xCBF43926  # the standard check value
    assert crc32_bitwise(HELLO_FRAME[:-4]) == int.from_bytes(HELLO_FRAME[-4:], "big")


def test_hello_frame_literal_both_ways() -> None:
    machine, center = Connection(Role.MACHINE), Connection(Role.CENTER)
    assert machine.send(HELLO) == HELLO_FRAME
    center.receive_data(HELLO_FRAME)
    assert center.next_event() == HELLO
    assert center.next_event() is NEED_DATA


@pytest.mark.parametrize(("msg", "code", "payload"), GOLDEN,
                         ids=[f"{type(m).__name__}-{i}" for i, (m, _, _) in enumerate(GOLDEN)])
def test_golden_message(msg: Message, code: int, payload: bytes) -> None:
    seq = 0x01020304
    assert TYPE_OF[type(msg)] == code
    assert encode_payload(msg) == payload
    wire = frame(code, seq, payload)
    assert encode_frame(TYPE_OF[type(msg)], seq, payload) == wire
    buf = FrameBuffer()
    buf.feed(wire)
    got = buf.next_frame()
    assert got is not None and (got.kind, got.seq, got.payload) == (code, seq, payload)
    assert decode_payload(got.kind, got.payload) == msg
    assert buf.next_frame() is None and buf.pending == 0


def _golden(kind: type) -> Message:
    return next(m for m, _, _ in GOLDEN if type(m) is kind)


def _script() -> list[tuple[Role, Message]]:
    c, m = Role.CENTER, Role.MACHINE
    return [
        (m, HELLO), (c, _golden(Challenge)), (m, _golden(AuthResponse)),
        (c, _golden(Welcome)), (m, _golden(Telemetry)), (c, _golden(Heartbeat)),
        (m, _golden(HeartbeatReply)), (c, _golden(MapBegin)), (c, _golden(MapChunk)),
        (m, _golden(Telemetry)), (c, _golden(MapEnd)), (m, _golden(MapReject)),
        (c, _golden(MapBegin)), (c, _golden(MapChunk)), (c, _golden(MapEnd)),
        (c, _golden(ReleaseCompensation)), (m, _golden(MapAck)), (m, _golden(Released)),
        (c, Error(ErrorCode.SHUTDOWN, "bye")),
    ]


def _streams() -> dict[Role, list[bytes]]:
    """The literal frames each role sends in the script, in order."""
    out: dict[Role, list[bytes]] = {Role.CENTER: [], Role.MACHINE: []}
    for sender, msg in _script():
        out[sender].append(frame(TYPE_OF[type(msg)], len(out[sender]), encode_payload(msg)))
    return out


@pytest.mark.parametrize("role", [Role.CENTER, Role.MACHINE])
@pytest.mark.parametrize("bytewise", [False, True], ids=["whole", "byte-by-byte"])
def test_conversation_stream(role: Role, bytewise: bool) -> None:
    conn = Connection(role)
    streams = _streams()
    incoming = iter(streams[role.peer])
    outgoing = iter(streams[role])
    if not bytewise:
        conn.receive_data(b"".join(streams[role.peer]))
    for sender, msg in _script():
        if sender is role:
            assert conn.send(msg) == next(outgoing)
            continue
        if bytewise:
            wire = next(incoming)
            for b in wire[:-1]:
                conn.receive_data(bytes([b]))
                assert conn.next_event() is NEED_DATA
            conn.receive_data(wire[-1:])
        assert conn.next_event() == msg
    assert conn.session is State.CLOSED
    assert conn.next_event() is NEED_DATA
    conn.receive_data(b"")
    assert conn.next_event() is CONNECTION_CLOSED


def test_readme_worked_example_is_the_real_frame() -> None:
    readme = (Path(__file__).resolve().parents[1] / "protocol" / "README.md").read_text()
    section = readme.split("## 10.")[1].split("| bytes |")[0]
    dump = [line.split()[1:] for line in section.splitlines()
            if line.startswith("    00")]
    assert bytes.fromhex("".join(b for row in dump for b in row)) == HELLO_FRAME
