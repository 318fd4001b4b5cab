"""Frame layer: header, CRC and the receive buffer that cuts a byte stream into frames.

Frame layout (all integers big-endian, "network byte order")::

    offset size field
         0    4 magic        b"EDNC"
         4    1 version      PROTOCOL_VERSION (1)
         5    1 type         MessageType
         6    2 reserved     0
         8    4 sequence     per direction: 0 for the first frame, then +1 (mod 2**32)
        12    4 length       payload bytes, at most MAX_PAYLOAD
        16    n payload
    16 + n    4 crc          CRC-32 (zlib.crc32: IEEE 802.3, reflected poly 0xEDB88320,
                             init and final XOR 0xFFFFFFFF) of bytes 0 .. 16+n-1
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass

from .codes import MessageType
from .errors import LocalProtocolError, RemoteProtocolError
from .limits import HEADER_SIZE, MAGIC, MAX_PAYLOAD, PROTOCOL_VERSION, TRAILER_SIZE

_HEADER = struct.Struct(">4sBBHII")
_CRC = struct.Struct(">I")


@dataclass(frozen=True, slots=True)
class Frame:
    """One checked frame off the wire: its type, sequence number and raw payload."""

    kind: MessageType
    seq: int
    payload: bytes


def encode_frame(kind: MessageType, seq: int, payload: bytes) -> bytes:
    """Header + ``payload`` + CRC, ready to write to the socket."""
    if len(payload) > MAX_PAYLOAD:
        raise LocalProtocolError(f"{kind.name} payload of {len(payload)} bytes exceeds the "
                                 f"{MAX_PAYLOAD}-byte frame limit")
    if not 0 <= seq < 1 << 32:
        raise LocalProtocolError(f"sequence number {seq} does not fit 32 bits")
    head = _HEADER.pack(MAGIC, PROTOCOL_VERSION, kind, 0, seq, len(payload))
    return head + payload + _CRC.pack(zlib.crc32(payload, zlib.crc32(head)))


class FrameBuffer:
    """Receive buffer: append bytes as they arrive, take whole checked frames out.

    The header is checked as soon as its 16 bytes are in, before any payload is kept
    waiting, so an oversize or foreign frame is refused at once and an incomplete frame
    never holds more than ``MAX_FRAME`` bytes. Bytes are kept in one ``bytearray`` with a
    read offset (compacted when consumed bytes dominate), so feeding a frame one byte at a
    time costs linear, not quadratic, time.
    """

    __slots__ = ("_buf", "_offset", "_pos")

    def __init__(self) -> None:
        self._buf = bytearray()
        self._pos = 0
        self._offset = 0  # stream offset of self._buf[0], for error messages

    def feed(self, data: bytes) -> None:
        """Append received bytes."""
        if self._pos and self._pos * 2 >= len(self._buf):
            del self._buf[:self._pos]
            self._offset += self._pos
            self._pos = 0
        self._buf += data

    @property
    def pending(self) -> int:
        """Bytes received but not yet returned as a frame."""
        return len(self._buf) - self._pos

    def next_frame(self) -> Frame | None:
        """The next whole frame, or None while more bytes are needed.

        Raises
        ------
        RemoteProtocolError
            Bad magic, unknown version or type, non-zero reserved field, a length over
            ``MAX_PAYLOAD``, or a CRC mismatch; the text gives the stream offset.
        """
        head = bytes(self._buf[self._pos:self._pos + HEADER_SIZE])
        # Magic, version and type are checked on a partial header too: a stray client
        # (HTTP, telnet) or a peer of another version fails at its first bytes.
        kind = self._check_start(head[:6])
        if kind is None or len(head) < HEADER_SIZE:
            return None
        _, _, _, reserved, seq, length = _HEADER.unpack(head)
        if reserved:
            raise self._bad(f"reserved header field is 0x{reserved:04x}, must be 0")
        if length > MAX_PAYLOAD:
            raise self._bad(f"{kind.name} frame announces {length} payload bytes, "
                            f"limit {MAX_PAYLOAD}")
        end = self._pos + HEADER_SIZE + length
        if len(self._buf) < end + TRAILER_SIZE:
            return None
        (crc,) = _CRC.unpack_from(self._buf, end)
        actual = zlib.crc32(memoryview(self._buf)[self._pos:end])
        if crc != actual:
            raise self._bad(f"CRC mismatch in {kind.name} frame seq {seq}: "
                            f"computed 0x{actual:08x}, frame says 0x{crc:08x}")
        payload = bytes(self._buf[self._pos + HEADER_SIZE:end])
        self._pos = end + TRAILER_SIZE
        return Frame(kind, seq, payload)

    def _check_start(self, head: bytes) -> MessageType | None:
        """Check magic, version and type, as far as ``head`` (up to 6 bytes) reaches."""
        got = head[:len(MAGIC)]
        if not MAGIC.startswith(got):
            raise self._bad(f"bad magic {got!r}, expected {MAGIC!r}")
        if len(head) > 4 and head[4] != PROTOCOL_VERSION:
            raise self._bad(f"protocol version {head[4]}, this end speaks {PROTOCOL_VERSION}")
        if len(head) < 6:
            return None
        try:
            return MessageType(head[5])
        except ValueError:
            raise self._bad(f"unknown message type 0x{head[5]:02x}") from None

    def _bad(self, what: str) -> RemoteProtocolError:
        return RemoteProtocolError(f"{what} (frame at stream offset {self._offset + self._pos})")
