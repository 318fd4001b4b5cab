"""Hypothesis fuzzing of the decoders: arbitrary bytes, valid frames with a flipped bit or
cut short, arbitrary payloads, arbitrary map bytes. Nothing may escape but the documented
RemoteProtocolError (frames) or MapFormatError (maps), and what decodes re-encodes to the
same bytes."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from protocol import (
    NEED_DATA,
    AuthResponse,
    AxisReading,
    Challenge,
    Connection,
    Controller,
    Error,
    ErrorCode,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAck,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapEnd,
    MapFormatError,
    MapReject,
    MapRejectReason,
    Message,
    MessageType,
    Reject,
    ReleaseCompensation,
    Released,
    RemoteProtocolError,
    Role,
    SensorReading,
    Telemetry,
    TemperatureReading,
    Temperatures,
    Welcome,
    clip_text,
    decode_map,
    encode_map,
)
from protocol.codec import decode_payload, encode_payload
from protocol.frames import FrameBuffer, encode_frame
from protocol.limits import MAX_MAP_BYTES
from protocol.messages import TYPE_OF
from tests.support.protocol import sample_map

FUZZ = settings(deadline=None, max_examples=300,
                suppress_health_check=[HealthCheck.too_slow])

u32 = st.integers(0, 2**32 - 1)
version = st.integers(1, 2**32 - 1)
reals = st.floats(allow_nan=False, allow_infinity=False)
texts = st.text(max_size=120).map(clip_text)
labels = st.text(min_size=1, max_size=16).map(lambda s: clip_text(s, 16)).filter(bool)
names = st.from_regex(r"[A-Za-z0-9._-]{1,32}", fullmatch=True)
formats = st.sampled_from([MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM,
                           MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM])


@st.composite
def telemetry(draw: st.DrawFn) -> Telemetry:
    axes = draw(st.lists(labels, max_size=16, unique=True))
    sensors = draw(st.lists(labels, max_size=32, unique=True))
    return Telemetry(draw(st.integers(0, 2**64 - 1)), draw(labels), draw(u32),
                     tuple(AxisReading(a, draw(reals), draw(reals)) for a in axes),
                     tuple(SensorReading(s, draw(reals)) for s in sensors))


@st.composite
def map_begin(draw: st.DrawFn) -> MapBegin:
    size = draw(st.integers(1, MAX_MAP_BYTES))
    count = draw(st.integers(-(-size // 8192), min(size, 10**6)))
    return MapBegin(draw(version), size, count, draw(st.binary(min_size=32, max_size=32)))


messages: st.SearchStrategy[Message] = st.one_of(
    st.builds(Hello, names, st.ip_addresses().map(str), st.sampled_from(Controller), formats,
              labels, st.sampled_from(["w X Y b Z t", "w b Y X Z t", "w C B X b Y Z t"]),
              st.integers(0, 255), st.integers(0, 255)),
    st.builds(Challenge, st.binary(min_size=32, max_size=32)),
    st.builds(AuthResponse, st.binary(min_size=32, max_size=32)),
    st.builds(Welcome, st.integers(100, 2**32 - 1), st.integers(10, 2**32 - 1)),
    st.builds(Reject, st.sampled_from(ErrorCode), texts),
    map_begin(),
    st.builds(MapChunk, version, u32, st.binary(min_size=1, max_size=8192)),
    st.builds(MapEnd, version),
    st.builds(MapAck, version),
    st.builds(MapReject, version, st.sampled_from(MapRejectReason), texts),
    telemetry(),
    st.builds(Heartbeat, u32),
    st.builds(HeartbeatReply, u32),
    st.builds(ReleaseCompensation, u32, texts),
    st.just(Released()),
    st.builds(Temperatures, st.integers(0, 2**64 - 1),
              st.lists(labels, min_size=1, max_size=32, unique=True).flatmap(
                  lambda names: st.tuples(*[st.builds(
                      TemperatureReading, st.just(n), st.floats(-273.15, 1e300), u32)
                      for n in names]))),
    st.builds(Error, st.sampled_from(ErrorCode), texts),
)


def wire(msg: Message, seq: int = 0) -> bytes:
    return encode_frame(TYPE_OF[type(msg)], seq, encode_payload(msg))


@FUZZ
@given(messages, u32)
def test_every_valid_message_round_trips(msg: Message, seq: int) -> None:
    buf = FrameBuffer()
    buf.feed(wire(msg, seq))
    got = buf.next_frame()
    assert got is not None and got.seq == seq
    assert decode_payload(got.kind, got.payload) == msg


@FUZZ
@given(messages, st.data())
def test_flipped_bit_never_yields_a_frame(msg: Message, data: st.DataObject) -> None:
    raw = bytearray(wire(msg))
    bit = data.draw(st.integers(0, len(raw) * 8 - 1))
    raw[bit // 8] ^= 1 << (bit % 8)
    buf = FrameBuffer()
    buf.feed(bytes(raw))
    try:
        assert buf.next_frame() is None  # only if the length field grew: waits for more
    except RemoteProtocolError as exc:
        assert str(exc)


@FUZZ
@given(messages, st.data())
def test_truncated_frame_waits_then_fails_at_eof(msg: Message, data: st.DataObject) -> None:
    raw = wire(msg)
    cut = data.draw(st.integers(1, len(raw) - 1))
    conn = Connection(Role.MACHINE if TYPE_OF[type(msg)] in {2, 4, 5} else Role.CENTER)
    conn.receive_data(raw[:cut])
    assert conn.next_event() is NEED_DATA
    conn.receive_data(b"")
    with pytest.raises(RemoteProtocolError, match="stream closed inside a frame"):
        conn.next_event()


@FUZZ
@given(st.binary(max_size=600), st.sampled_from(Role), st.booleans())
def test_arbitrary_bytes_only_raise_remote_protocol_error(data: bytes, role: Role,
                                                          eof: bool) -> None:
    conn = Connection(role)
    if data:  # b"" would mean end of stream
        conn.receive_data(data)
    if eof:
        conn.receive_data(b"")
    try:
        for _ in range(len(data) + 2):
            event = conn.next_event()
            if not isinstance(event, Message):
                break
    except RemoteProtocolError as exc:
        assert str(exc)


@FUZZ
@given(st.sampled_from(MessageType), st.binary(max_size=300))
def test_arbitrary_payload_decodes_canonically_or_fails_cleanly(kind: MessageType,
                                                                payload: bytes) -> None:
    try:
        msg = decode_payload(kind, payload)
    except RemoteProtocolError as exc:
        assert str(exc).startswith(f"bad {kind.name} payload: ")
        return
    assert encode_payload(msg) == payload


@FUZZ
@given(st.binary(max_size=400))
def test_arbitrary_map_bytes_only_raise_map_format_error(data: bytes) -> None:
    try:
        payload = decode_map(b"EDMP\x01\x00" + data)
    except MapFormatError as exc:
        assert str(exc)
        return
    assert encode_map(payload) == b"EDMP\x01\x00" + data


_MAP = encode_map(sample_map())
_FLOAT_MAP = encode_map(sample_map(encoding=MapEncoding.FLOAT32_MM))


@FUZZ
@given(st.sampled_from([_MAP, _FLOAT_MAP]), st.data())
def test_mutated_map_decodes_canonically_or_fails_cleanly(base: bytes,
                                                          data: st.DataObject) -> None:
    raw = bytearray(base)
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, 200))  # header and axis tables, where the structure is
        raw[i] = data.draw(st.integers(0, 255))
    cut = data.draw(st.integers(0, len(raw)))
    try:
        payload = decode_map(bytes(raw[:cut]))
    except MapFormatError:
        return
    assert encode_map(payload) == bytes(raw[:cut])


@FUZZ
@given(st.lists(messages, max_size=8), st.sampled_from(Role), st.booleans())
def test_random_valid_frames_in_any_order(msgs: list[Message], role: Role,
                                          right_seq: bool) -> None:
    """Well-formed frames in an arbitrary order: each is accepted or refused by the state
    machine with a RemoteProtocolError that names the rule; nothing else escapes."""
    conn = Connection(role)
    conn.receive_data(b"".join(wire(m, i if right_seq else 7) for i, m in enumerate(msgs)))
    got: list[Message] = []
    try:
        while isinstance(event := conn.next_event(), Message):
            got.append(event)
    except RemoteProtocolError as exc:
        assert "may not send" in str(exc) or "sequence number" in str(exc)
    assert got == msgs[:len(got)]
