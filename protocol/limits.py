"""Sizes and timing of the protocol, each with the reason for its value.

Every bound a receiver relies on lives here, so the README, the codec and a PLC
programmer's buffers agree on one set of numbers.
"""

from __future__ import annotations

from typing import Final

PROTOCOL_VERSION: Final = 1
"""Frame layout version carried in every frame header; a receiver rejects any other."""

MAGIC: Final = b"EDNC"
"""First four bytes of every frame: lets a receiver spot a stray client (HTTP, telnet) at once."""

HEADER_SIZE: Final = 16
"""magic 4 + version 1 + type 1 + reserved 2 + sequence 4 + payload length 4."""

TRAILER_SIZE: Final = 4
"""CRC-32 over header and payload."""

MAX_CHUNK_BYTES: Final = 8192
"""Largest data part of one MapChunk. A receiver must hold a whole frame before it can check
the CRC, and a PLC does that in a fixed buffer; 8 KiB is a buffer any PLC family we target can
reserve, and still cuts a 1.6 MB map (51 x 51 x 51 nodes x 3 axes x 4 bytes) into only ~200
frames."""

CHUNK_HEADER_BYTES: Final = 8
"""MapChunk fields before its data: map version u32 + chunk index u32."""

MAX_PAYLOAD: Final = CHUNK_HEADER_BYTES + MAX_CHUNK_BYTES
"""Largest payload of any frame: the largest MapChunk. Every other message is bounded by the
field limits below to well under this (tests/test_protocol_messages.py builds the largest of
each and checks). A receiver rejects a frame whose header announces more, as soon as the
header is read and before buffering any payload, so a peer cannot make us hold more than
HEADER_SIZE + MAX_PAYLOAD + TRAILER_SIZE bytes of an incomplete frame."""

MAX_FRAME: Final = HEADER_SIZE + MAX_PAYLOAD + TRAILER_SIZE
"""8220 bytes: the receive buffer a PLC needs for one frame."""

MAX_MAP_BYTES: Final = 16 * 1024 * 1024
"""Largest error-map payload a MapBegin may announce (16 MiB, ten times the 1.6 MB map
above). A machine that cannot store that much rejects with MapRejectReason.TOO_LARGE."""

MAX_TEXT_BYTES: Final = 255
"""Free text (reasons, errors) is a u8 length + UTF-8, like a PLC STRING[255]."""

MAX_NAME_BYTES: Final = 32
"""Machine names: fits the 32-byte name field of the map payload."""

MAX_LABEL_BYTES: Final = 16
"""Axis and sensor names, software version, machine state string."""

MAX_CHAIN_BYTES: Final = 64
"""Kinematic chain string such as ``w X Y b Z t``."""

MAX_AXES: Final = 16
"""Axes in one Telemetry message."""

MAX_SENSORS: Final = 32
"""Temperature sensors in one Telemetry message."""

# --- timing (milliseconds); the center sends the two periods to the machine in Welcome ---

HEARTBEAT_PERIOD_MS: Final = 5000
"""The center sends a Heartbeat every 5 s; the machine answers each with HeartbeatReply."""

MISSED_HEARTBEATS: Final = 3
"""A peer from which nothing arrived for 3 heartbeat periods (15 s) is dead: close."""

TELEMETRY_PERIOD_MS: Final = 1000
"""Default Telemetry period the center asks for in Welcome."""

HANDSHAKE_TIMEOUT_MS: Final = 10_000
"""Hello to Welcome must finish within 10 s, or the center closes the connection."""

MAP_VERDICT_TIMEOUT_MS: Final = 30_000
"""After MapEnd the center waits 30 s for MapAck or MapReject (the machine decodes and
checks the map), then treats the push as failed and closes."""

RELEASE_GRACE_MS: Final = 10_000
"""After ReleaseCompensation the center waits ramp time + 10 s for Released."""
