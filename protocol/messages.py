"""One frozen, slotted dataclass per message; ``Message`` is their closed union.

Each ``__post_init__`` checks every field against the protocol's limits, so a message that
could not be sent or could not have come off the wire cannot exist. Units are in the field
names or docstrings; wire layouts are in ``codec.py`` and README.md.
"""

from __future__ import annotations

import ipaddress
import re
from dataclasses import dataclass
from typing import Final

from . import _check as check
from .codes import Controller, ErrorCode, MapEncoding, MapRejectReason, MessageType
from .limits import (
    MAX_AXES,
    MAX_CHAIN_BYTES,
    MAX_CHUNK_BYTES,
    MAX_LABEL_BYTES,
    MAX_MAP_BYTES,
    MAX_NAME_BYTES,
    MAX_SENSORS,
    MAX_TEXT_BYTES,
)

NONCE_BYTES: Final = 32
MAC_BYTES: Final = 32
SHA256_BYTES: Final = 32
_VALUE_FORMATS: Final = MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM
_ALL_FORMATS: Final = (_VALUE_FORMATS | MapEncoding.TABLES | MapEncoding.THERMAL
                       | MapEncoding.FACTORED)
ABSOLUTE_ZERO_C: Final = -273.15
_AXIS_TOKEN = re.compile(r"[XYZABC][0-9]?")


def clip_text(text: str, max_bytes: int = MAX_TEXT_BYTES) -> str:
    """Shorten ``text`` to at most ``max_bytes`` of UTF-8 (whole characters) and replace
    non-printable characters, so any exception message fits a Reject, MapReject or Error."""
    text = "".join(c if c.isprintable() else " " for c in text)
    raw = text.encode("utf-8")[:max_bytes]
    return raw.decode("utf-8", errors="ignore")


def _check_chain(chain: str) -> None:
    check.text("Hello.chain", chain, MAX_CHAIN_BYTES)
    if not chain:
        return
    tokens = chain.split(" ")
    problem = ""
    if tokens[0] != "w" or tokens[-1] != "t" or tokens.count("b") != 1:
        problem = "must start with 'w', end with 't' and contain one 'b'"
    elif bad := [t for t in tokens[1:-1] if t != "b" and not _AXIS_TOKEN.fullmatch(t)]:
        problem = f"has unknown token {bad[0]!r} (axes are X Y Z A B C, optionally a digit)"
    elif len(set(tokens)) != len(tokens):
        problem = "repeats a token"
    if problem:
        raise ValueError(f"Hello.chain {chain!r} {problem}")


@dataclass(frozen=True, slots=True)
class Hello:
    """Machine → center, first message: who the machine is and what it accepts.

    Either ``chain`` (e.g. ``"w X Y b Z t"``) or ``translational_type`` (with
    ``rotary_type``, 0 for none) describes the kinematics; 0 / ``""`` mean "not given".
    """

    name: str
    ip: str
    controller: Controller
    map_formats: MapEncoding
    software_version: str
    chain: str = ""
    translational_type: int = 0
    rotary_type: int = 0

    def __post_init__(self) -> None:
        check.name("Hello.name", self.name, MAX_NAME_BYTES)
        check.text("Hello.ip", self.ip, 45, empty=False)
        try:
            canonical = str(ipaddress.ip_address(self.ip))
        except ValueError:
            raise ValueError(f"Hello.ip {self.ip!r} is not an IPv4 or IPv6 address") from None
        if canonical != self.ip:
            raise ValueError(f"Hello.ip {self.ip!r} must be written canonically: {canonical!r}")
        check.member("Hello.controller", self.controller, Controller)
        check.member("Hello.map_formats", self.map_formats, MapEncoding)
        if not self.map_formats & _VALUE_FORMATS or self.map_formats & ~_ALL_FORMATS:
            raise ValueError(f"Hello.map_formats must name at least one known format, "
                             f"got {int(self.map_formats)}")
        check.text("Hello.software_version", self.software_version, MAX_LABEL_BYTES, empty=False)
        _check_chain(self.chain)
        check.uint("Hello.translational_type", self.translational_type, 8)
        check.uint("Hello.rotary_type", self.rotary_type, 8)
        if not self.chain and not self.translational_type:
            raise ValueError("Hello needs a chain or a translational_type")


@dataclass(frozen=True, slots=True)
class Challenge:
    """Center → machine: a fresh random nonce the machine must sign (see auth.py)."""

    nonce: bytes

    def __post_init__(self) -> None:
        check.exact_bytes("Challenge.nonce", self.nonce, NONCE_BYTES)


@dataclass(frozen=True, slots=True)
class AuthResponse:
    """Machine → center: HMAC-SHA256(secret, nonce ‖ machine name)."""

    mac: bytes

    def __post_init__(self) -> None:
        check.exact_bytes("AuthResponse.mac", self.mac, MAC_BYTES)


@dataclass(frozen=True, slots=True)
class Welcome:
    """Center → machine: authenticated; the periods the machine should keep (ms)."""

    heartbeat_period_ms: int
    telemetry_period_ms: int

    def __post_init__(self) -> None:
        check.uint("Welcome.heartbeat_period_ms", self.heartbeat_period_ms, 32, minimum=100)
        check.uint("Welcome.telemetry_period_ms", self.telemetry_period_ms, 32, minimum=10)


@dataclass(frozen=True, slots=True)
class Reject:
    """Center → machine during the handshake: refused; the center closes the connection."""

    code: ErrorCode
    text: str = ""

    def __post_init__(self) -> None:
        check.member("Reject.code", self.code, ErrorCode)
        check.text("Reject.text", self.text, MAX_TEXT_BYTES)


@dataclass(frozen=True, slots=True)
class MapBegin:
    """Center → machine: a map of ``total_size`` bytes follows in ``chunk_count`` chunks."""

    version: int
    total_size: int
    chunk_count: int
    sha256: bytes

    def __post_init__(self) -> None:
        check.uint("MapBegin.version", self.version, 32, minimum=1)
        check.uint("MapBegin.total_size", self.total_size, 32, minimum=1)
        if self.total_size > MAX_MAP_BYTES:
            raise ValueError(f"MapBegin.total_size {self.total_size} exceeds {MAX_MAP_BYTES}")
        check.uint("MapBegin.chunk_count", self.chunk_count, 32, minimum=1)
        lo = -(-self.total_size // MAX_CHUNK_BYTES)
        if not lo <= self.chunk_count <= self.total_size:
            raise ValueError(f"MapBegin.chunk_count {self.chunk_count} cannot carry "
                             f"{self.total_size} bytes (needs {lo} to {self.total_size})")
        check.exact_bytes("MapBegin.sha256", self.sha256, SHA256_BYTES)


@dataclass(frozen=True, slots=True)
class MapChunk:
    """Center → machine: chunk ``index`` (0-based) of map ``version``."""

    version: int
    index: int
    data: bytes

    def __post_init__(self) -> None:
        check.uint("MapChunk.version", self.version, 32, minimum=1)
        check.uint("MapChunk.index", self.index, 32)
        if not isinstance(self.data, bytes):
            raise ValueError(f"MapChunk.data must be bytes, got {type(self.data).__name__}")
        if not 1 <= len(self.data) <= MAX_CHUNK_BYTES:
            raise ValueError(f"MapChunk.data must be 1 to {MAX_CHUNK_BYTES} bytes, "
                             f"got {len(self.data)}")


@dataclass(frozen=True, slots=True)
class MapEnd:
    """Center → machine: all chunks of map ``version`` are sent; check and swap."""

    version: int

    def __post_init__(self) -> None:
        check.uint("MapEnd.version", self.version, 32, minimum=1)


@dataclass(frozen=True, slots=True)
class MapAck:
    """Machine → center: map ``version`` arrived whole, checked out and is now applied."""

    version: int

    def __post_init__(self) -> None:
        check.uint("MapAck.version", self.version, 32, minimum=1)


@dataclass(frozen=True, slots=True)
class MapReject:
    """Machine → center: map ``version`` was not applied; the previous map stays."""

    version: int
    reason: MapRejectReason
    text: str = ""

    def __post_init__(self) -> None:
        check.uint("MapReject.version", self.version, 32, minimum=1)
        check.member("MapReject.reason", self.reason, MapRejectReason)
        check.text("MapReject.text", self.text, MAX_TEXT_BYTES)


@dataclass(frozen=True, slots=True)
class AxisReading:
    """One axis in Telemetry: machine coordinate and the compensation applied to it.

    Units: mm for linear axes, degrees for rotary axes (both fields).
    """

    name: str
    position: float
    compensation: float

    def __post_init__(self) -> None:
        check.text("AxisReading.name", self.name, MAX_LABEL_BYTES, empty=False)
        check.finite(f"axis {self.name} position", self.position)
        check.finite(f"axis {self.name} compensation", self.compensation)


@dataclass(frozen=True, slots=True)
class SensorReading:
    """One temperature sensor in Telemetry, °C."""

    name: str
    celsius: float

    def __post_init__(self) -> None:
        check.text("SensorReading.name", self.name, MAX_LABEL_BYTES, empty=False)
        check.finite(f"sensor {self.name} temperature", self.celsius)


@dataclass(frozen=True, slots=True)
class Telemetry:
    """Machine → center, every telemetry period.

    ``timestamp_ms`` is the machine's clock in ms since the Unix epoch (UTC);
    ``map_version`` is the applied map, 0 when none is applied (released or never pushed).
    """

    timestamp_ms: int
    state: str
    map_version: int
    axes: tuple[AxisReading, ...] = ()
    temperatures: tuple[SensorReading, ...] = ()

    def __post_init__(self) -> None:
        check.uint("Telemetry.timestamp_ms", self.timestamp_ms, 64)
        check.text("Telemetry.state", self.state, MAX_LABEL_BYTES, empty=False)
        check.uint("Telemetry.map_version", self.map_version, 32)
        if not isinstance(self.axes, tuple) or not isinstance(self.temperatures, tuple):
            raise ValueError("Telemetry.axes and Telemetry.temperatures must be tuples")
        if len(self.axes) > MAX_AXES:
            raise ValueError(f"Telemetry has {len(self.axes)} axes, at most {MAX_AXES}")
        if len(self.temperatures) > MAX_SENSORS:
            raise ValueError(f"Telemetry has {len(self.temperatures)} sensors, "
                             f"at most {MAX_SENSORS}")
        for a in self.axes:
            if not isinstance(a, AxisReading):
                raise ValueError(f"Telemetry.axes holds a {type(a).__name__}, not AxisReading")
        for s in self.temperatures:
            if not isinstance(s, SensorReading):
                raise ValueError(f"Telemetry.temperatures holds a {type(s).__name__}, "
                                 "not SensorReading")
        check.unique("Telemetry.axes", [a.name for a in self.axes])
        check.unique("Telemetry.temperatures", [s.name for s in self.temperatures])


@dataclass(frozen=True, slots=True)
class TemperatureReading:
    """One sensor in Temperatures: its name, °C, and how old the reading was when sent.

    ``age_ms`` (u32) lets a machine judge staleness from its own receive time, without a
    clock synchronised with the center's: the reading was taken ``age_ms`` before the
    message left the center.
    """

    name: str
    celsius: float
    age_ms: int = 0

    def __post_init__(self) -> None:
        check.text("TemperatureReading.name", self.name, MAX_LABEL_BYTES, empty=False)
        check.finite(f"sensor {self.name} temperature", self.celsius)
        if self.celsius < ABSOLUTE_ZERO_C:
            raise ValueError(f"sensor {self.name} temperature {self.celsius} °C is below "
                             f"absolute zero")
        check.uint(f"sensor {self.name} age_ms", self.age_ms, 32)


@dataclass(frozen=True, slots=True)
class Temperatures:
    """Center → machine: the latest temperatures the center has for this machine.

    ``timestamp_ms`` is the center's clock when it sent the message (ms since the Unix
    epoch, UTC); each reading carries its own age. 1 to 32 sensors, each named once; a
    sensor not in the message keeps its previous value on the machine.
    """

    timestamp_ms: int
    readings: tuple[TemperatureReading, ...]

    def __post_init__(self) -> None:
        check.uint("Temperatures.timestamp_ms", self.timestamp_ms, 64)
        if not isinstance(self.readings, tuple):
            raise ValueError("Temperatures.readings must be a tuple")
        if not 1 <= len(self.readings) <= MAX_SENSORS:
            raise ValueError(f"Temperatures has {len(self.readings)} sensors, "
                             f"1 to {MAX_SENSORS} allowed")
        for r in self.readings:
            if not isinstance(r, TemperatureReading):
                raise ValueError(f"Temperatures.readings holds a {type(r).__name__}, "
                                 "not TemperatureReading")
        check.unique("Temperatures.readings", [r.name for r in self.readings])


@dataclass(frozen=True, slots=True)
class Heartbeat:
    """Center → machine every heartbeat period; the machine echoes ``token``."""

    token: int

    def __post_init__(self) -> None:
        check.uint("Heartbeat.token", self.token, 32)


@dataclass(frozen=True, slots=True)
class HeartbeatReply:
    """Machine → center: answer to the Heartbeat with the same ``token``."""

    token: int

    def __post_init__(self) -> None:
        check.uint("HeartbeatReply.token", self.token, 32)


@dataclass(frozen=True, slots=True)
class ReleaseCompensation:
    """Center → machine: ramp the applied compensation linearly to zero over ``ramp_ms``."""

    ramp_ms: int
    text: str = ""

    def __post_init__(self) -> None:
        check.uint("ReleaseCompensation.ramp_ms", self.ramp_ms, 32)
        check.text("ReleaseCompensation.text", self.text, MAX_TEXT_BYTES)


@dataclass(frozen=True, slots=True)
class Released:
    """Machine → center: the release ramp has finished; no compensation is applied."""


@dataclass(frozen=True, slots=True)
class Error:
    """Either side: a fatal error; the sender closes the connection after it."""

    code: ErrorCode
    text: str = ""

    def __post_init__(self) -> None:
        check.member("Error.code", self.code, ErrorCode)
        check.text("Error.text", self.text, MAX_TEXT_BYTES)


Message = (
    Hello | Challenge | AuthResponse | Welcome | Reject
    | MapBegin | MapChunk | MapEnd | MapAck | MapReject
    | Telemetry | Heartbeat | HeartbeatReply | ReleaseCompensation | Released | Temperatures
    | Error
)
"""Every message of protocol version 1."""

TYPE_OF: Final[dict[type[Message], MessageType]] = {
    Hello: MessageType.HELLO,
    Challenge: MessageType.CHALLENGE,
    AuthResponse: MessageType.AUTH_RESPONSE,
    Welcome: MessageType.WELCOME,
    Reject: MessageType.REJECT,
    MapBegin: MessageType.MAP_BEGIN,
    MapChunk: MessageType.MAP_CHUNK,
    MapEnd: MessageType.MAP_END,
    MapAck: MessageType.MAP_ACK,
    MapReject: MessageType.MAP_REJECT,
    Telemetry: MessageType.TELEMETRY,
    Heartbeat: MessageType.HEARTBEAT,
    HeartbeatReply: MessageType.HEARTBEAT_REPLY,
    ReleaseCompensation: MessageType.RELEASE_COMPENSATION,
    Released: MessageType.RELEASED,
    Temperatures: MessageType.TEMPERATURES,
    Error: MessageType.ERROR,
}
"""The frame type code of each message class."""
