"""Modbus/TCP application frames (MBAP header + PDU): the center's requests and the
answers to them, and what a relay needs to read requests.

A frame is the 7-byte MBAP header (transaction id, protocol id 0, length of what follows,
unit id) and the PDU (function code and data). Nothing here does I/O:

* the center's Modbus link (:mod:`server.links.modbus`) builds its requests with
  :func:`read_request` and :func:`write_request`, cuts the answers out of the bytes it
  received with :func:`take_frame` and reads them with :func:`read_answer` and
  :func:`write_answer`;
* the fault relay (:mod:`machine_sim.faultrelay`) says where a request frame ends, what it
  touches and what an exception answer to it is (:func:`frame_size`,
  :func:`parse_request`, :func:`exception_answer`).

Reference: MODBUS Messaging on TCP/IP Implementation Guide V1.0b, §3.1.3 (MBAP header);
MODBUS Application Protocol V1.1b3, §6.3, §6.12, §6.17 (03h, 10h, 17h) and §7
(exception responses: function code | 0x80, one exception code byte).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Final

__all__ = ["HEADER", "MAX_FRAME", "MAX_READ_REGISTERS", "MAX_WRITE_REGISTERS", "MbapError",
           "ModbusException", "Request", "exception_answer", "frame", "frame_size",
           "parse_request", "read_answer", "read_request", "take_frame", "write_answer",
           "write_request"]

HEADER: Final = struct.Struct(">HHHB")
"""Transaction id, protocol id, length (unit id + PDU bytes), unit id."""

MAX_FRAME: Final = HEADER.size + 253
"""A PDU is at most 253 bytes (Application Protocol §4.1), so a frame at most 260."""

WRITES: Final = frozenset({0x06, 0x10, 0x17})
"""Function codes that write holding registers (06h single, 10h multiple, 17h read/write)."""


class MbapError(ValueError):
    """Bytes that cannot be a Modbus/TCP frame (a relay closes the connection)."""


def frame_size(head: bytes | bytearray) -> int:
    """Size of the whole frame whose first :data:`HEADER` ``.size`` bytes are ``head``.

    Raises
    ------
    MbapError
        Protocol id not 0, or a length no PDU can have (below 2: unit id and function
        code, above 254).
    """
    _tid, protocol, length, _unit = HEADER.unpack(head[:HEADER.size])
    if protocol != 0 or not 2 <= length <= MAX_FRAME - HEADER.size + 1:
        raise MbapError(f"protocol id {protocol}, length {length}: not a Modbus/TCP frame")
    return HEADER.size - 1 + int(length)


@dataclass(frozen=True, slots=True)
class Request:
    """What a request frame asks.

    Attributes
    ----------
    tid : int
        Transaction id.
    unit : int
    function : int
    first, count : int
        Holding registers it reads or writes (0, 0 for a function without a register
        span); for 17h the write span.
    write : bool
    data : bytes
        Register values written, as sent (empty for a read).
    """

    tid: int
    unit: int
    function: int
    first: int
    count: int
    write: bool
    data: bytes

    def touches(self, first: int, end: int) -> bool:
        """Whether it writes any register of ``[first, end)``."""
        return self.write and self.first < end and first < self.first + self.count


def parse_request(frame: bytes) -> Request:
    """Read a whole request frame (a span the PDU does not carry is 0, 0)."""
    tid, _protocol, _length, unit = HEADER.unpack_from(frame)
    pdu = frame[HEADER.size:]
    fc = pdu[0]
    first = count = 0
    data = b""
    if fc in (0x03, 0x04, 0x10) and len(pdu) >= 5:
        first, count = struct.unpack_from(">HH", pdu, 1)
        if fc == 0x10:
            data = pdu[6:]
    elif fc == 0x06 and len(pdu) >= 5:
        (first,) = struct.unpack_from(">H", pdu, 1)
        count, data = 1, pdu[3:5]
    elif fc == 0x17 and len(pdu) >= 10:
        first, count = struct.unpack_from(">HH", pdu, 5)
        data = pdu[10:]
    return Request(tid, unit, fc, first, count, fc in WRITES, data)


def exception_answer(request: bytes, code: int) -> bytes:
    """The exception response to ``request`` (same transaction and unit): function code
    with bit 7 set and the exception ``code`` (02 illegal data address, 05 acknowledge,
    06 server device busy, ...)."""
    tid, protocol, _length, unit = HEADER.unpack_from(request)
    fc = request[HEADER.size]
    return HEADER.pack(tid, protocol, 3, unit) + bytes((fc | 0x80, code))


# -- the client's side: requests the center sends, answers it reads

MAX_READ_REGISTERS: Final = 125
"""Registers one 03h request may read (Application Protocol §6.3)."""
MAX_WRITE_REGISTERS: Final = 123
"""Registers one 10h request may write (Application Protocol §6.12)."""

_SPAN: Final = struct.Struct(">BHH")
_WRITE_HEAD: Final = struct.Struct(">BHHB")


class ModbusException(Exception):
    """An exception response (§7): ``code`` 01 illegal function, 02 illegal data address,
    03 illegal data value, 04 server device failure, 05 acknowledge, 06 server busy, ..."""

    def __init__(self, function: int, code: int) -> None:
        super().__init__(f"function {function:02X}h: exception {code:02d}")
        self.function = function
        self.code = code


def read_request(first: int, count: int) -> bytes:
    """The PDU of a 03h Read Holding Registers request.

    Raises
    ------
    MbapError
        ``count`` outside 1..125 or registers beyond 65535.
    """
    if not 1 <= count <= MAX_READ_REGISTERS or not 0 <= first <= 0x10000 - count:
        raise MbapError(f"read of {count} registers from {first}: 1..125 registers "
                        "within 0..65535")
    return _SPAN.pack(0x03, first, count)


def write_request(first: int, wire: bytes) -> bytes:
    """The PDU of a 10h Write Multiple Registers request writing ``wire``: the registers'
    values as they go on the wire (two bytes each, most significant first).

    Raises
    ------
    MbapError
        An odd length, none or more than 123 registers, or registers beyond 65535.
    """
    count = len(wire) // 2
    if len(wire) % 2 or not 1 <= count <= MAX_WRITE_REGISTERS \
            or not 0 <= first <= 0x10000 - count:
        raise MbapError(f"write of {len(wire)} bytes at register {first}: 1..123 whole "
                        "registers within 0..65535")
    return _WRITE_HEAD.pack(0x10, first, count, len(wire)) + wire


def frame(tid: int, unit: int, pdu: bytes) -> bytes:
    """A whole frame: the MBAP header (protocol id 0) and ``pdu``."""
    return HEADER.pack(tid, 0, len(pdu) + 1, unit) + pdu


def take_frame(buffer: bytearray) -> tuple[int, int, bytes] | None:
    """The first whole frame in ``buffer`` as (transaction id, unit id, PDU), removed from
    it; None while the frame is not complete. Frames follow each other in a stream (a
    server may answer several requests in one TCP segment, or split one).

    Raises
    ------
    MbapError
        The bytes at the front cannot be a frame (protocol id not 0, a length no PDU has):
        there is no telling where the next frame starts, so the connection is useless.
    """
    if len(buffer) < HEADER.size:
        return None
    end = frame_size(buffer)
    if len(buffer) < end:
        return None
    tid, _protocol, _length, unit = HEADER.unpack_from(buffer)
    pdu = bytes(buffer[HEADER.size:end])
    del buffer[:end]
    return tid, unit, pdu


def _check(pdu: bytes, function: int) -> None:
    if not pdu:
        raise MbapError("an empty answer")
    if pdu[0] == function | 0x80:
        if len(pdu) != 2:
            raise MbapError(f"an exception answer of {len(pdu)} bytes, not 2")
        raise ModbusException(function, pdu[1])
    if pdu[0] != function:
        raise MbapError(f"answer to function {pdu[0]:02X}h, not {function:02X}h")


def read_answer(pdu: bytes, count: int) -> bytes:
    """The ``count`` registers' values (two bytes each as on the wire) of a 03h answer.

    Raises
    ------
    ModbusException
        An exception response.
    MbapError
        Not the answer to a read of ``count`` registers.
    """
    _check(pdu, 0x03)
    if len(pdu) != 2 + 2 * count or pdu[1] != 2 * count:
        raise MbapError(f"a read answer of {len(pdu)} bytes (byte count {pdu[1:2].hex()}) "
                        f"for {count} registers")
    return pdu[2:]


def write_answer(pdu: bytes, first: int, count: int) -> None:
    """Check a 10h answer: it echoes the first register and the count written.

    Raises
    ------
    ModbusException
        An exception response.
    MbapError
        Not the answer to that write.
    """
    _check(pdu, 0x10)
    if pdu != _SPAN.pack(0x10, first, count):
        raise MbapError(f"a write answer {pdu.hex()} for {count} registers at {first}")
