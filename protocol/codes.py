"""Numeric codes carried on the wire: message types, controller families, map encodings,
error and rejection reasons. Values are part of protocol version 1 and never change meaning."""

from __future__ import annotations

from enum import IntEnum, IntFlag


class MessageType(IntEnum):
    """Frame header byte 5. 0x0_ handshake, 0x1_ map push, 0x2_ running, 0x7_ closing."""

    HELLO = 0x01
    CHALLENGE = 0x02
    AUTH_RESPONSE = 0x03
    WELCOME = 0x04
    REJECT = 0x05
    MAP_BEGIN = 0x10
    MAP_CHUNK = 0x11
    MAP_END = 0x12
    MAP_ACK = 0x13
    MAP_REJECT = 0x14
    TELEMETRY = 0x20
    HEARTBEAT = 0x21
    HEARTBEAT_REPLY = 0x22
    RELEASE_COMPENSATION = 0x23
    RELEASED = 0x24
    TEMPERATURES = 0x25
    ERROR = 0x7F


class Controller(IntEnum):
    """Controller family of a machine (Hello byte)."""

    FANUC = 1
    SIEMENS = 2

    @property
    def label(self) -> str:
        """The name used in machine descriptions: ``fanuc`` or ``siemens``."""
        return self.name.lower()


class MapEncoding(IntFlag):
    """How error-map values are stored. As a flag set in Hello (formats a machine accepts);
    exactly one in a map payload."""

    INT32_INCREMENTS = 1
    """int32 little-endian, in units of the increment given in the map header (Fanuc)."""
    FLOAT32_MM = 2
    """float32 little-endian IEEE 754, in mm (Siemens)."""
    TABLES = 4
    """Hello only: the machine also evaluates ``tables`` maps (format version 2), whose
    corrections it rounds to one of the value encodings above."""
    THERMAL = 8
    """Hello only: the machine applies the thermal records of grid maps (format version
    3) with its latest temperatures every cycle."""
    FACTORED = 16
    """Hello only: the machine evaluates ``factored`` maps (format version 4: sums of
    products of 1-D tables, rounded rotary-first to int32 increments)."""


class ErrorCode(IntEnum):
    """Reason in Reject and Error."""

    PROTOCOL_ERROR = 1
    """The peer sent a bad frame or a message out of turn."""
    UNKNOWN_MACHINE = 2
    """Hello names a machine the center does not know."""
    ADDRESS_MISMATCH = 3
    """The connection comes from another address than the one registered for the machine."""
    AUTH_FAILED = 4
    """AuthResponse does not match the machine's secret."""
    DUPLICATE_SESSION = 5
    """That machine already has a live session."""
    UNSUPPORTED = 6
    """Hello asks for something the center cannot serve (no common map format, controller)."""
    TIMEOUT = 7
    """A handshake step, heartbeat reply or map verdict did not arrive in time."""
    SHUTDOWN = 8
    """Orderly close: the sender is shutting down."""
    INTERNAL = 9
    """The sender failed internally; the peer did nothing wrong."""


class MapRejectReason(IntEnum):
    """Reason in MapReject: why the machine kept its previous map."""

    MISSING_CHUNK = 1
    """A chunk index was skipped, or MapEnd came before all announced chunks."""
    UNEXPECTED_CHUNK = 2
    """A chunk repeated an index, came out of order, or beyond the announced count."""
    WRONG_SIZE = 3
    """The chunks' bytes add up to another size than MapBegin announced."""
    CHECKSUM_MISMATCH = 4
    """SHA-256 of the assembled payload differs from MapBegin's."""
    WRONG_VERSION = 5
    """A chunk, MapEnd or the payload's own header carries another map version than MapBegin."""
    DECODE_ERROR = 6
    """The assembled payload is not a valid error map (text says which field)."""
    WRONG_MACHINE = 7
    """The payload names another machine."""
    UNSUPPORTED_ENCODING = 8
    """The payload's value encoding is not one the machine accepted in Hello."""
    TOO_LARGE = 9
    """MapBegin announces more bytes than the machine can store."""
    STALE_VERSION = 10
    """The map version is not newer than the map the machine has applied."""
    APPLY_FAILED = 11
    """The map checked out but the controller refused it (text says why)."""
