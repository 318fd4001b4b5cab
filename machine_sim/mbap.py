"""Modbus/TCP application frames (MBAP header + PDU), as far as a relay needs them.

A frame is the 7-byte MBAP header (transaction id, protocol id 0, length of what follows,
unit id) and the PDU (function code and data). Nothing here does I/O: the fault relay
(:mod:`machine_sim.faultrelay`) reads and writes the bytes, these functions say where a
frame ends, what a request touches and what an exception answer to it is.

Reference: MODBUS Messaging on TCP/IP Implementation Guide V1.0b, §3.1.3 (MBAP header);
MODBUS Application Protocol V1.1b3, §6.3, §6.12, §6.17 (03h, 10h, 17h) and §7
(exception responses: function code | 0x80, one exception code byte).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Final

__all__ = ["HEADER", "MAX_FRAME", "MbapError", "Request", "exception_answer", "frame_size",
           "parse_request"]

HEADER: Final = struct.Struct(">HHHB")
"""Transaction id, protocol id, length (unit id + PDU bytes), unit id."""

MAX_FRAME: Final = HEADER.size + 253
"""A PDU is at most 253 bytes (Application Protocol §4.1), so a frame at most 260."""

WRITES: Final = frozenset({0x06, 0x10, 0x17})
"""Function codes that write holding registers (06h single, 10h multiple, 17h read/write)."""


class MbapError(ValueError):
    """Bytes that cannot be a Modbus/TCP frame (a relay closes the connection)."""


def frame_size(head: bytes) -> int:
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
