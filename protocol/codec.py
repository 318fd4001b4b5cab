"""Payload encode/decode for every message: network byte order (big-endian), fixed-width
integers, IEEE 754 binary64 reals, text as a u8 byte count followed by UTF-8.

``encode_payload`` and ``decode_payload`` dispatch with ``match``; the field order of each
layout is the dataclass field order, and README.md lists the same layouts with offsets.
"""

from __future__ import annotations

import struct
from enum import IntEnum
from typing import TypeVar, assert_never

from .codes import Controller, ErrorCode, MapEncoding, MapRejectReason, MessageType
from .errors import RemoteProtocolError
from .messages import (
    MAC_BYTES,
    NONCE_BYTES,
    SHA256_BYTES,
    AuthResponse,
    AxisReading,
    Challenge,
    Error,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    Message,
    Reject,
    ReleaseCompensation,
    Released,
    SensorReading,
    Telemetry,
    TemperatureReading,
    Temperatures,
    Welcome,
)

_E = TypeVar("_E", bound=IntEnum)


class _Writer:
    """Appends big-endian fields to one growing buffer."""

    def __init__(self) -> None:
        self.out = bytearray()

    def u8(self, v: int) -> None:
        self.out += struct.pack(">B", v)

    def u16(self, v: int) -> None:
        self.out += struct.pack(">H", v)

    def u32(self, v: int) -> None:
        self.out += struct.pack(">I", v)

    def u64(self, v: int) -> None:
        self.out += struct.pack(">Q", v)

    def f64(self, v: float) -> None:
        self.out += struct.pack(">d", v)

    def raw(self, b: bytes) -> None:
        self.out += b

    def text(self, s: str) -> None:
        b = s.encode("utf-8")
        self.u8(len(b))  # the dataclasses cap every text at 255 bytes
        self.out += b


class _DecodeError(ValueError):
    pass


class _Reader:
    """Reads big-endian fields from a payload, naming the field and offset when short."""

    def __init__(self, data: bytes) -> None:
        self.data = data
        self.pos = 0

    def take(self, n: int, field: str) -> bytes:
        if self.pos + n > len(self.data):
            raise _DecodeError(f"{field} needs {n} bytes at offset {self.pos}, "
                               f"only {len(self.data) - self.pos} left")
        b = self.data[self.pos:self.pos + n]
        self.pos += n
        return b

    def u8(self, field: str) -> int:
        return int(self.take(1, field)[0])

    def u16(self, field: str) -> int:
        return int.from_bytes(self.take(2, field), "big")

    def u32(self, field: str) -> int:
        return int.from_bytes(self.take(4, field), "big")

    def u64(self, field: str) -> int:
        return int.from_bytes(self.take(8, field), "big")

    def f64(self, field: str) -> float:
        value: float = struct.unpack(">d", self.take(8, field))[0]
        return value

    def text(self, field: str) -> str:
        n = self.u8(field + " length")
        raw = self.take(n, field)
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise _DecodeError(f"{field} is not valid UTF-8 ({exc.reason} at byte "
                               f"{exc.start})") from None

    def code(self, field: str, enum: type[_E], width: int) -> _E:
        value = self.u8(field) if width == 1 else self.u16(field)
        try:
            return enum(value)
        except ValueError:
            raise _DecodeError(f"{field} {value} is not a known {enum.__name__}") from None

    def rest(self) -> bytes:
        b = self.data[self.pos:]
        self.pos = len(self.data)
        return b

    def end(self) -> None:
        if self.pos != len(self.data):
            raise _DecodeError(f"{len(self.data) - self.pos} unexpected bytes after the "
                               f"last field (offset {self.pos})")


def encode_payload(msg: Message) -> bytes:
    """The payload bytes of ``msg`` (no frame header or CRC)."""
    w = _Writer()
    match msg:
        case Hello():
            w.text(msg.name)
            w.text(msg.ip)
            w.u8(msg.controller)
            w.u8(msg.map_formats)
            w.text(msg.software_version)
            w.text(msg.chain)
            w.u8(msg.translational_type)
            w.u8(msg.rotary_type)
        case Challenge():
            w.raw(msg.nonce)
        case AuthResponse():
            w.raw(msg.mac)
        case Welcome():
            w.u32(msg.heartbeat_period_ms)
            w.u32(msg.telemetry_period_ms)
        case Reject() | Error():
            w.u16(msg.code)
            w.text(msg.text)
        case MapBegin():
            w.u32(msg.version)
            w.u32(msg.total_size)
            w.u32(msg.chunk_count)
            w.raw(msg.sha256)
        case MapChunk():
            w.u32(msg.version)
            w.u32(msg.index)
            w.raw(msg.data)
        case MapEnd() | MapAck():
            w.u32(msg.version)
        case MapReject():
            w.u32(msg.version)
            w.u16(msg.reason)
            w.text(msg.text)
        case Telemetry():
            w.u64(msg.timestamp_ms)
            w.u32(msg.map_version)
            w.text(msg.state)
            w.u8(len(msg.axes))
            for a in msg.axes:
                w.text(a.name)
                w.f64(a.position)
                w.f64(a.compensation)
            w.u8(len(msg.temperatures))
            for s in msg.temperatures:
                w.text(s.name)
                w.f64(s.celsius)
        case Heartbeat() | HeartbeatReply():
            w.u32(msg.token)
        case ReleaseCompensation():
            w.u32(msg.ramp_ms)
            w.text(msg.text)
        case Released():
            pass
        case Temperatures():
            w.u64(msg.timestamp_ms)
            w.u8(len(msg.readings))
            for t in msg.readings:
                w.text(t.name)
                w.f64(t.celsius)
                w.u32(t.age_ms)
        case _:
            assert_never(msg)
    return bytes(w.out)


def _decode(kind: MessageType, r: _Reader) -> Message:
    match kind:
        case MessageType.HELLO:
            return Hello(
                name=r.text("name"),
                ip=r.text("ip"),
                controller=r.code("controller", Controller, 1),
                map_formats=MapEncoding(r.u8("map_formats")),
                software_version=r.text("software_version"),
                chain=r.text("chain"),
                translational_type=r.u8("translational_type"),
                rotary_type=r.u8("rotary_type"),
            )
        case MessageType.CHALLENGE:
            return Challenge(r.take(NONCE_BYTES, "nonce"))
        case MessageType.AUTH_RESPONSE:
            return AuthResponse(r.take(MAC_BYTES, "mac"))
        case MessageType.WELCOME:
            return Welcome(r.u32("heartbeat_period_ms"), r.u32("telemetry_period_ms"))
        case MessageType.REJECT:
            return Reject(r.code("code", ErrorCode, 2), r.text("text"))
        case MessageType.ERROR:
            return Error(r.code("code", ErrorCode, 2), r.text("text"))
        case MessageType.MAP_BEGIN:
            return MapBegin(r.u32("version"), r.u32("total_size"), r.u32("chunk_count"),
                            r.take(SHA256_BYTES, "sha256"))
        case MessageType.MAP_CHUNK:
            return MapChunk(r.u32("version"), r.u32("index"), r.rest())
        case MessageType.MAP_END:
            return MapEnd(r.u32("version"))
        case MessageType.MAP_ACK:
            return MapAck(r.u32("version"))
        case MessageType.MAP_REJECT:
            return MapReject(r.u32("version"), r.code("reason", MapRejectReason, 2),
                             r.text("text"))
        case MessageType.TELEMETRY:
            timestamp, version, state = r.u64("timestamp_ms"), r.u32("map_version"), r.text("state")
            axes = tuple(
                AxisReading(r.text(f"axis {i} name"), r.f64(f"axis {i} position"),
                            r.f64(f"axis {i} compensation"))
                for i in range(r.u8("axis count"))
            )
            sensors = tuple(
                SensorReading(r.text(f"sensor {i} name"), r.f64(f"sensor {i} celsius"))
                for i in range(r.u8("sensor count"))
            )
            return Telemetry(timestamp, state, version, axes, sensors)
        case MessageType.HEARTBEAT:
            return Heartbeat(r.u32("token"))
        case MessageType.HEARTBEAT_REPLY:
            return HeartbeatReply(r.u32("token"))
        case MessageType.RELEASE_COMPENSATION:
            return ReleaseCompensation(r.u32("ramp_ms"), r.text("text"))
        case MessageType.RELEASED:
            return Released()
        case MessageType.TEMPERATURES:
            stamp = r.u64("timestamp_ms")
            readings = tuple(
                TemperatureReading(r.text(f"sensor {i} name"), r.f64(f"sensor {i} celsius"),
                                   r.u32(f"sensor {i} age_ms"))
                for i in range(r.u8("sensor count"))
            )
            return Temperatures(stamp, readings)
        case _:
            assert_never(kind)


def decode_payload(kind: MessageType, payload: bytes) -> Message:
    """The message of type ``kind`` whose payload is ``payload``.

    Raises
    ------
    RemoteProtocolError
        The payload is short, long, or holds a value the message does not allow; the text
        names the message and the field.
    """
    r = _Reader(payload)
    try:
        msg = _decode(kind, r)
        r.end()
    except ValueError as exc:  # _DecodeError from the reader, ValueError from __post_init__
        raise RemoteProtocolError(f"bad {kind.name} payload: {exc}") from None
    return msg
