"""A map in controller memory: the layout a PLC program reads (protocol/README.md §13).

For controllers that cannot open a connection of their own (a Fanuc PMC behind the
Modbus/TCP Server function, a SINUMERIK PLC behind its OPC UA server) the center writes
the map into a window of the controller's memory and reads back what the PLC program
acknowledges and applies. This module is the window's byte layout and the rules both
sides follow, with no I/O: the center plans its writes (:func:`plan_delivery`, §13.2
steps 0-5, and :func:`plan_map_write`), the PLC
side checks a buffer (:func:`check_buffer`) and writes its status (:func:`encode_status`).

Every area has one writer, so no word is ever written by both sides:

* **identity** (PLC, bytes 0-63): what the PLC program is and can take;
* **status** (PLC, 64-191): heartbeat, the last switch it handled and its verdict, the
  active buffer, state bits, the applied map version, the temperature sequence taken and
  what its screen refused, positions and applied corrections;
* **command** (center, 192-511): the switch word, the temperature slots, their sequence
  and the map version whose sensor order they follow;
* **buffers 1 and 2** (center, from 512): each a 32-byte header and ``capacity`` bytes of
  payload (protocol/README.md §6).

All multi-byte fields are little-endian, like the payload; sizes and offsets are in bytes
(a Modbus register is two of them, see :func:`to_registers`).
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from enum import IntEnum, IntFlag
from typing import Final, Literal

from .codes import MapEncoding, MapRejectReason
from .mapfactored import milli_celsius

__all__ = [
    "BUFFERS_AT",
    "BUFFER_HEADER_SIZE",
    "COMMAND_AT",
    "COMMAND_END",
    "IDENTITY_MAGIC",
    "IDENTITY_SIZE",
    "LAYOUT_VERSION",
    "MAX_AXES",
    "MAX_SENSORS",
    "MODBUS_BLOCK",
    "NO_TEMPERATURE",
    "S7_300_BLOCK",
    "S7_1500_BLOCK",
    "SLOTS_VERSION_AT",
    "STATUS_AT",
    "STATUS_SIZE",
    "SWITCH_AT",
    "TEMPERATURES_AT",
    "TEMP_SEQ_AT",
    "AckCode",
    "BufferHeader",
    "ByteOrder",
    "Command",
    "ControllerMemoryError",
    "Identity",
    "Layout",
    "State",
    "Status",
    "Write",
    "ack_is_verdict",
    "check_buffer",
    "decode_command",
    "decode_identity",
    "decode_status",
    "encode_buffer_header",
    "encode_identity",
    "encode_status",
    "from_registers",
    "needs_push",
    "next_sequence",
    "next_switch_sequence",
    "next_temperature_sequence",
    "pack_switch",
    "plan_delivery",
    "plan_map_write",
    "plan_temperatures",
    "sensor_slots",
    "to_registers",
    "unpack_switch",
]

IDENTITY_MAGIC: Final = b"EDCM"
BUFFER_MAGIC: Final = b"EDBF"
LAYOUT_VERSION: Final = 1
MAX_AXES: Final = 8
MAX_SENSORS: Final = 32

IDENTITY_SIZE: Final = 64
STATUS_AT: Final = 64
STATUS_SIZE: Final = 128
COMMAND_AT: Final = 192
SWITCH_AT: Final = 192
TEMPERATURES_AT: Final = 256
"""32 temperature slots, int32 milli-°C each (bytes 256-383)."""
TEMP_SEQ_AT: Final = 384
"""u16 sequence the center writes after (above) the slots, in the same write: 1..65535,
then 1 again; 0 = no slots written yet."""
SLOTS_VERSION_AT: Final = 388
"""u32 map version whose thermal records the slot order follows (0: the map in use)."""
COMMAND_END: Final = 392
"""End of the temperature write (slots, sequence, reserved, slots' map version)."""
BUFFERS_AT: Final = 512
BUFFER_HEADER_SIZE: Final = 32
NO_TEMPERATURE: Final = -0x80000000
"""Slot value with nothing to say: the PLC keeps the reading it holds for that sensor (a
sensor never read adds 0, protocol/README.md §6 "Readings")."""


class ControllerMemoryError(ValueError):
    """The window does not hold what the layout says (text names the field)."""


class AckCode(IntEnum):
    """The PLC's verdict on a switch (status ``ack_code``): 0 applied, else the MapReject
    reason of protocol/README.md §7 (the same numbers), or one of the memory's own."""

    APPLIED = 0
    BAD_HEADER = 100
    """The buffer header's magic or its own CRC is wrong (a header torn or never written)."""
    BAD_BUFFER = 101
    """The switch word names no buffer (not 1 or 2)."""


def ack_is_verdict(code: int) -> bool:
    """Whether an ack code is the PLC's verdict on the map (§13.2 step 6). Code 100 is
    not: a header torn or never written says nothing of the map, and the center writes
    the map again, once. Every other code (0 applied, a MapReject reason, 101) is final
    for that map: it is not written again."""
    return code != AckCode.BAD_HEADER


class State(IntFlag):
    """Bits of the status ``state`` word (§13.1)."""

    MAP_IN_USE = 1
    RAMPING = 2
    """An applied correction is short of its target (the step limit of §13.3 step 4)."""
    RELEASING = 4
    ALARM = 8
    CLAMPED = 16
    """A target exceeded the limit."""
    EXPIRED = 32
    """The map's validity ran out."""


ByteOrder = Literal["little", "big"]
"""How the controller places a register's two bytes in its memory: ``little``: the low
byte at the lower (even) address, as a Fanuc PMC stores words; ``big``: the high byte
first (Modbus' own order on the wire, an S7 data block)."""


@dataclass(frozen=True, slots=True)
class Layout:
    """A window's size: the payload capacity of each buffer, bytes (even)."""

    capacity: int

    def __post_init__(self) -> None:
        if self.capacity <= 0 or self.capacity % 2 or self.capacity > 60_000:
            raise ControllerMemoryError(
                f"capacity {self.capacity}: an even number of bytes, 2..60000 (two buffers "
                "and the control areas fit the 64 K-word Modbus area)")

    def buffer_at(self, buffer: int) -> int:
        """Byte offset of buffer 1 or 2's header."""
        if buffer not in (1, 2):
            raise ControllerMemoryError(f"buffer {buffer}: 1 or 2")
        return BUFFERS_AT + (buffer - 1) * (BUFFER_HEADER_SIZE + self.capacity)

    @property
    def size(self) -> int:
        """Bytes of the whole window."""
        return BUFFERS_AT + 2 * (BUFFER_HEADER_SIZE + self.capacity)


# -- identity (PLC-written)

@dataclass(frozen=True, slots=True)
class Identity:
    """What the PLC program declares at start-up (bytes 0-63).

    Attributes
    ----------
    formats : MapEncoding
        The map kinds it evaluates (the bits of Hello's map_formats).
    capacity : int
        Payload bytes per buffer.
    axes : int
        Controlled axes reported in the status, 1..8.
    increment_nm : int
        The controller's least increment in nm (1000 = 0.001 mm), the unit of positions
        and corrections in the status.
    name : str
        The machine's name as its maps carry it.
    """

    formats: MapEncoding
    capacity: int
    axes: int
    increment_nm: int
    name: str


_IDENTITY: Final = struct.Struct("<4sHHIBBHI32s12x")


def encode_identity(ident: Identity) -> bytes:
    """The identity block's 64 bytes."""
    name = ident.name.encode("ascii")
    if not 1 <= len(name) <= 32:
        raise ControllerMemoryError(f"machine name {ident.name!r}: 1..32 ASCII bytes")
    if not 1 <= ident.axes <= MAX_AXES:
        raise ControllerMemoryError(f"axes {ident.axes}: 1..{MAX_AXES}")
    return _IDENTITY.pack(IDENTITY_MAGIC, LAYOUT_VERSION, int(ident.formats), ident.capacity,
                          ident.axes, MAX_SENSORS, 0, ident.increment_nm, name)


def decode_identity(data: bytes | bytearray | memoryview) -> Identity:
    """Read the identity block (the window's first 64 bytes).

    Raises
    ------
    ControllerMemoryError
        No PLC program of this layout declared itself there.
    """
    if len(data) < IDENTITY_SIZE:
        raise ControllerMemoryError(f"identity: {len(data)} bytes, 64 needed")
    magic, version, formats, capacity, axes, _sensors, _r, inc, name = _IDENTITY.unpack(
        bytes(data[:IDENTITY_SIZE]))
    if magic != IDENTITY_MAGIC:
        raise ControllerMemoryError(
            f"identity at byte 0: magic {magic!r}, not {IDENTITY_MAGIC!r} (no EDNC PLC "
            "program serves this window, or the window's address or byte order is wrong)")
    if version != LAYOUT_VERSION:
        raise ControllerMemoryError(f"identity at byte 4: layout version {version}, this "
                                    f"center speaks {LAYOUT_VERSION}")
    Layout(capacity)
    if not 1 <= axes <= MAX_AXES:
        raise ControllerMemoryError(f"identity at byte 12: axes {axes}, 1..{MAX_AXES}")
    text = name.rstrip(b"\0")
    try:
        decoded = text.decode("ascii")
    except UnicodeDecodeError:
        raise ControllerMemoryError("identity at byte 20: machine name not ASCII") from None
    return Identity(MapEncoding(formats), capacity, axes, inc, decoded)


# -- status (PLC-written)

@dataclass(frozen=True, slots=True)
class Status:
    """The PLC's status block (bytes 64-191).

    Attributes
    ----------
    heartbeat : int
        Scan counter (u32), moves while the PLC program runs.
    ack_seq : int
        Sequence of the last switch word handled (0: none since the window was cleared).
    ack_code : int
        Its verdict: :class:`AckCode` (0 applied) or a MapReject reason.
    active : int
        The buffer in use, 1 or 2, or 0.
    state : int
        Bits: 0 map in use, 1 ramping, 2 releasing, 3 alarm, 4 clamped, 5 expired.
    applied_version : int
        Version of the map in use (0: none).
    temp_ack : int
        The last temperature sequence taken.
    positions, applied : tuple of int
        Per controlled axis: machine coordinate and the applied correction, counts of
        the increment.
    temp_refused : int
        Bit i set when the program's screen refused slot i's value at the last take
        (u32); that sensor keeps its held reading.
    """

    heartbeat: int
    ack_seq: int
    ack_code: int
    active: int
    state: int
    applied_version: int
    temp_ack: int
    positions: tuple[int, ...]
    applied: tuple[int, ...]
    temp_refused: int = 0


_STATUS: Final = struct.Struct("<IHHHHIHH8i8iI40x")


def encode_status(s: Status) -> bytes:
    """The status block's 128 bytes (positions and corrections padded to 8 axes)."""
    pos = (tuple(s.positions) + (0,) * MAX_AXES)[:MAX_AXES]
    app = (tuple(s.applied) + (0,) * MAX_AXES)[:MAX_AXES]
    return _STATUS.pack(s.heartbeat & 0xFFFFFFFF, s.ack_seq, s.ack_code, s.active, s.state,
                        s.applied_version, s.temp_ack, 0, *pos, *app,
                        s.temp_refused & 0xFFFFFFFF)


def decode_status(data: bytes | bytearray | memoryview, axes: int = MAX_AXES) -> Status:
    """Read the status block from the window's bytes 64-191 (``data`` is that block)."""
    if len(data) < STATUS_SIZE:
        raise ControllerMemoryError(f"status: {len(data)} bytes, {STATUS_SIZE} needed")
    v = _STATUS.unpack(bytes(data[:STATUS_SIZE]))
    if v[3] not in (0, 1, 2):
        raise ControllerMemoryError(f"status at byte 72: active buffer {v[3]}, 0..2")
    return Status(v[0], v[1], v[2], v[3], v[4], v[5], v[6], tuple(v[8:8 + axes]),
                  tuple(v[16:16 + axes]), v[24])


# -- command (center-written)

@dataclass(frozen=True, slots=True)
class Command:
    """The center's command area (bytes 192-391), as the PLC reads it.

    Attributes
    ----------
    switch_seq, switch_buffer : int
        The switch word's sequence (0: none) and buffer.
    temp_seq : int
        Temperature sequence, 0 = no slots written yet.
    slots : tuple of int
        32 slots, m°C, :data:`NO_TEMPERATURE` = nothing to say.
    slots_version : int
        The map version whose records the slot order follows; 0 = the map in use.
    """

    switch_seq: int
    switch_buffer: int
    temp_seq: int
    slots: tuple[int, ...]
    slots_version: int


def decode_command(window: bytes | bytearray | memoryview) -> Command:
    """Read the command area out of the window's bytes (at least 392 of them)."""
    if len(window) < COMMAND_END:
        raise ControllerMemoryError(f"command: {len(window)} bytes, {COMMAND_END} needed")
    (word,) = struct.unpack_from("<H", window, SWITCH_AT)
    seq, buffer = unpack_switch(word)
    slots = struct.unpack_from(f"<{MAX_SENSORS}i", window, TEMPERATURES_AT)
    (tseq,) = struct.unpack_from("<H", window, TEMP_SEQ_AT)
    (version,) = struct.unpack_from("<I", window, SLOTS_VERSION_AT)
    return Command(seq, buffer, tseq, tuple(slots), version)


# -- the switch word and sequences

def pack_switch(seq: int, buffer: int) -> int:
    """The switch word (u16): bits 0-1 the buffer (1 or 2), bits 2-15 the sequence
    (1..16383). One register, so one write sets both at once on any server."""
    if buffer not in (1, 2) or not 1 <= seq <= 0x3FFF:
        raise ControllerMemoryError(f"switch: buffer {buffer} (1 or 2), sequence {seq} "
                                    "(1..16383)")
    return (seq << 2) | buffer


def unpack_switch(word: int) -> tuple[int, int]:
    """(sequence, buffer) of a switch word; (0, 0) for a cleared one."""
    return (word >> 2) & 0x3FFF, word & 0x3


def next_sequence(seq: int) -> int:
    """The sequence after ``seq``: 1..16383, wrapping to 1 (0 means none)."""
    return seq % 0x3FFF + 1


def next_switch_sequence(switch_seq: int, ack_seq: int) -> int:
    """The sequence of the next switch (§13.2 step 5): one that differs from both the
    switch word's and ack_seq's, ``next(switch_seq)``, or the one after it when that
    equals ``ack_seq`` (a PLC that handled a switch this center does not know of, or the
    same sequence after a wrap, would otherwise take the new switch for an old one)."""
    s = next_sequence(switch_seq)
    return next_sequence(s) if s == ack_seq else s


def next_temperature_sequence(seq: int) -> int:
    """The temperature sequence after ``seq``: 1..65535, then 1 again (0: none yet)."""
    return seq % 0xFFFF + 1


def needs_push(status: Status, version: int) -> bool:
    """§13.2 step 0: a map is written unless the PLC reports that version applied (a
    center that starts, or a session that opens, does not re-send it)."""
    return not (status.applied_version == version and status.active in (1, 2))


# -- buffers

@dataclass(frozen=True, slots=True)
class BufferHeader:
    """A buffer's 32-byte header, written after its payload.

    Attributes
    ----------
    format_version : int
        The payload's format version (protocol/README.md §6: 1 grid, 2 tables, ...).
    map_version : int
    length : int
        Payload bytes.
    crc : int
        CRC-32 (ISO-HDLC, zlib's) of the payload.
    """

    format_version: int
    map_version: int
    length: int
    crc: int


_HEADER: Final = struct.Struct("<4sHHIII")  # 20 bytes; header CRC at 20, 8 reserved


def encode_buffer_header(h: BufferHeader) -> bytes:
    """32 bytes: magic, format version, reserved, map version, length, payload CRC, then
    the CRC-32 of those 20 bytes (a torn header never passes) and 8 zero bytes."""
    head = _HEADER.pack(BUFFER_MAGIC, h.format_version, 0, h.map_version, h.length, h.crc)
    return head + struct.pack("<I", zlib.crc32(head)) + bytes(8)


def decode_buffer_header(data: bytes | bytearray | memoryview) -> BufferHeader | None:
    """The header, or None when its magic or its own CRC is wrong."""
    raw = bytes(data[:BUFFER_HEADER_SIZE])
    if len(raw) < BUFFER_HEADER_SIZE or raw[:4] != BUFFER_MAGIC:
        return None
    (own,) = struct.unpack_from("<I", raw, 20)
    if zlib.crc32(raw[:20]) != own:
        return None
    _m, fmt, _r, version, length, crc = _HEADER.unpack(raw[:20])
    return BufferHeader(fmt, version, length, crc)


def check_buffer(window: bytes | bytearray | memoryview, layout: Layout, buffer: int
                 ) -> tuple[bytes, BufferHeader] | tuple[int, str]:
    """What the PLC does with a switch to ``buffer``, before it decodes the payload.

    The PLC first copies the buffer out of the window into its own working area and
    checks that copy (so a center writing meanwhile can change the window, never the map
    in use), in the order of §13.3 step 2: the buffer named (101), the header's magic and
    CRC (100), the length (WRONG_SIZE), the payload's CRC-32 (CHECKSUM_MISMATCH), the
    payload's magic and format version against the header's (DECODE_ERROR), the payload's
    map version (offset 48) against the header's (WRONG_VERSION). Returns (payload,
    header) when all pass, else (ack code, why).
    """
    if buffer not in (1, 2):
        return AckCode.BAD_BUFFER, f"switch names buffer {buffer}, not 1 or 2"
    at = layout.buffer_at(buffer)
    copy = bytes(window[at:at + BUFFER_HEADER_SIZE + layout.capacity])
    header = decode_buffer_header(copy)
    if header is None:
        return AckCode.BAD_HEADER, f"buffer {buffer}: header magic or header CRC wrong"
    if not 16 <= header.length <= layout.capacity:
        return (MapRejectReason.WRONG_SIZE,
                f"buffer {buffer}: length {header.length}, 16..{layout.capacity}")
    payload = copy[BUFFER_HEADER_SIZE:BUFFER_HEADER_SIZE + header.length]
    if zlib.crc32(payload) != header.crc:
        return (MapRejectReason.CHECKSUM_MISMATCH,
                f"buffer {buffer}: CRC-32 of the payload differs from the header's")
    if payload[:4] != b"EDMP" or struct.unpack_from("<H", payload, 4)[0] != \
            header.format_version:
        return (MapRejectReason.DECODE_ERROR,
                f"buffer {buffer}: payload magic or format version differs from the header")
    (payload_version,) = struct.unpack_from("<I", payload, 48) if len(payload) >= 52 else (0,)
    if payload_version != header.map_version:
        return (MapRejectReason.WRONG_VERSION,
                f"buffer {buffer}: the payload's map version {payload_version} differs "
                f"from the header's {header.map_version}")
    return payload, header


# -- the center's writes

@dataclass(frozen=True, slots=True)
class Write:
    """``data`` written at byte ``offset`` of the window (even, like the data's length)."""

    offset: int
    data: bytes


def plan_map_write(layout: Layout, buffer: int, payload: bytes, map_version: int,
                   seq: int, *, block: int = 246) -> list[Write]:
    """The writes that deliver ``payload`` into ``buffer`` and switch to it, in order.

    1. the buffer's header cleared (a buffer being written never looks complete);
    2. the payload in blocks of at most ``block`` bytes (246: the 123 registers of one
       Modbus write), zero-padded to an even length;
    3. the header (magic, format version, map version, length, CRC-32s);
    4. the switch word: this sequence and this buffer.

    A write lost, repeated or reordered before step 4 changes nothing the PLC uses; the
    PLC acts only on a new switch word, and then checks header and CRC over its own copy.
    """
    if not 16 <= len(payload) <= layout.capacity:
        raise ControllerMemoryError(
            f"a {len(payload)}-byte map does not fit the window's {layout.capacity}-byte "
            "buffers")
    if block < 2 or block % 2:
        raise ControllerMemoryError(f"block {block}: an even number of bytes >= 2")
    at = layout.buffer_at(buffer)
    (fmt,) = struct.unpack_from("<H", payload, 4)
    writes = [Write(at, bytes(BUFFER_HEADER_SIZE))]
    body = payload + bytes(len(payload) % 2)
    base = at + BUFFER_HEADER_SIZE
    writes += [Write(base + k, body[k:k + block]) for k in range(0, len(body), block)]
    header = BufferHeader(fmt, map_version, len(payload), zlib.crc32(payload))
    writes.append(Write(at, encode_buffer_header(header)))
    writes.append(Write(SWITCH_AT, struct.pack("<H", pack_switch(seq, buffer))))
    return writes


MODBUS_BLOCK: Final = 246
"""Bytes per payload write on Modbus/TCP: the 123 registers of one 10h request."""
S7_300_BLOCK: Final = 240
"""Bytes per OPC UA write into an S7-300-class PLC's data block (an 840D sl's PLC)."""
S7_1500_BLOCK: Final = 960
"""Bytes per OPC UA write into an S7-1500's data block (its PDU)."""


def plan_delivery(layout: Layout, status: Status, switch_seq: int, payload: bytes,
                  map_version: int, *, block: int = MODBUS_BLOCK) -> list[Write] | None:
    """§13.2 steps 0-5 from what the center read (the status and the switch word's
    sequence): None when the PLC reports ``map_version`` applied (nothing is written);
    else the writes into the buffer that is not active (1 when none is), switched with a
    sequence that differs from both the switch word's and ack_seq's."""
    if not needs_push(status, map_version):
        return None
    target = 2 if status.active == 1 else 1
    seq = next_switch_sequence(switch_seq, status.ack_seq)
    return plan_map_write(layout, target, payload, map_version, seq, block=block)


def sensor_slots(sensors: Sequence[str]) -> dict[str, int]:
    """Slot of each sensor: the order of first appearance in the map's thermal records
    (what the PLC numbers them by when it loads the map)."""
    slots: dict[str, int] = {}
    for s in sensors:
        if s not in slots:
            if len(slots) == MAX_SENSORS:
                raise ControllerMemoryError(f"more than {MAX_SENSORS} sensors")
            slots[s] = len(slots)
    return slots


def plan_temperatures(celsius: Sequence[float | None], seq: int, *,
                      map_version: int = 0) -> Write:
    """One write (bytes 256-391) of the temperature slots, their sequence (u16) and the
    map version whose records the slot order follows (§13.1).

    ``celsius[i]`` is slot i's reading (None: nothing to say, the PLC keeps what it holds
    for that sensor); sent as int32 m°C, ``round_half_up(c · 1000)`` of the exact value
    (:func:`protocol.mapfactored.milli_celsius`, protocol/README.md §6; a value not finite
    or outside int32 is sent as nothing to say). ``seq`` is 1..65535
    (:func:`next_temperature_sequence`); ``map_version`` 0 means the map in use. The PLC
    takes the slots when the sequence is new and reads it again after them (a torn read
    shows two sequences and is read again in the next scan).
    """
    if len(celsius) > MAX_SENSORS:
        raise ControllerMemoryError(f"{len(celsius)} temperatures, at most {MAX_SENSORS}")
    if not 1 <= seq <= 0xFFFF:
        raise ControllerMemoryError(f"temperature sequence {seq}: 1..65535 (0 is none)")
    if not 0 <= map_version <= 0xFFFFFFFF:
        raise ControllerMemoryError(f"slots' map version {map_version}: a u32")
    slots = [NO_TEMPERATURE] * MAX_SENSORS
    for i, c in enumerate(celsius):
        if c is None:
            continue
        try:
            mc = milli_celsius(c)
        except ValueError:
            continue
        if -0x7FFFFFFF <= mc <= 0x7FFFFFFF:
            slots[i] = mc
    data = (struct.pack(f"<{MAX_SENSORS}i", *slots) + struct.pack("<HHI", seq, 0, map_version))
    return Write(TEMPERATURES_AT, data)


# -- registers

def to_registers(data: bytes, order: ByteOrder) -> list[int]:
    """16-bit register values that put ``data`` (even length) into controller memory as
    these bytes, given how the controller maps a register onto two bytes."""
    if len(data) % 2:
        raise ControllerMemoryError("register data must have an even length")
    fmt = f"{'<' if order == 'little' else '>'}{len(data) // 2}H"
    return list(struct.unpack(fmt, data))


def from_registers(registers: Sequence[int], order: ByteOrder) -> bytes:
    """The controller-memory bytes that ``registers`` stand for (inverse of
    :func:`to_registers`)."""
    fmt = f"{'<' if order == 'little' else '>'}{len(registers)}H"
    return struct.pack(fmt, *registers)
