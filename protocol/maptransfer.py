"""Pushing an error map: cut a payload into MapBegin / MapChunk... / MapEnd, and put it
back together on the machine with every check the swap rule needs.

Swap rule: the machine applies a new map only when all announced chunks arrived in order,
their bytes add up to the announced size, their SHA-256 matches MapBegin's, the payload
decodes (mapformat.decode_map), and it names this machine, the announced version and an
encoding the machine accepts. Otherwise it keeps its current map and answers MapReject
with the first reason found.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

from .codes import MapEncoding, MapRejectReason
from .errors import LocalProtocolError
from .limits import MAX_CHUNK_BYTES, MAX_MAP_BYTES
from .mapfactored import FactoredPayload
from .mapformat import ErrorMapPayload, MapFormatError
from .maptables import TablesPayload, decode_payload
from .messages import MapAck, MapBegin, MapChunk, MapEnd, MapReject, clip_text

_ALL: MapEncoding = MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM


def split_into_chunks(payload: bytes, version: int,
                      chunk_size: int = MAX_CHUNK_BYTES) -> list[MapBegin | MapChunk | MapEnd]:
    """``[MapBegin, MapChunk 0, ..., MapChunk n-1, MapEnd]`` carrying ``payload``.

    Every chunk but the last holds exactly ``chunk_size`` bytes.
    """
    if not 1 <= chunk_size <= MAX_CHUNK_BYTES:
        raise ValueError(f"chunk_size must be 1 to {MAX_CHUNK_BYTES}, got {chunk_size}")
    if not payload:
        raise ValueError("cannot push an empty map payload")
    pieces = [payload[i:i + chunk_size] for i in range(0, len(payload), chunk_size)]
    begin = MapBegin(version, len(payload), len(pieces), hashlib.sha256(payload).digest())
    chunks = [MapChunk(version, i, bytes(p)) for i, p in enumerate(pieces)]
    return [begin, *chunks, MapEnd(version)]


@dataclass(frozen=True, slots=True)
class MapAccepted:
    """A whole, verified map: swap to ``payload``, then send ``ack()``."""

    version: int
    payload: ErrorMapPayload | TablesPayload | FactoredPayload
    data: bytes

    def ack(self) -> MapAck:
        """The MapAck to send once the map is applied."""
        return MapAck(self.version)


@dataclass(frozen=True, slots=True)
class MapRejected:
    """The push failed; keep the current map and send ``message()``."""

    version: int
    reason: MapRejectReason
    text: str

    def message(self) -> MapReject:
        """The MapReject to send."""
        return MapReject(self.version, self.reason, clip_text(self.text))


@dataclass(slots=True)
class _Transfer:
    begin: MapBegin
    data: bytearray = field(default_factory=bytearray)
    next_index: int = 0
    failure: MapRejected | None = None


class MapAssembler:
    """Machine side of a map push: feed it the map messages in the order received.

    Parameters
    ----------
    machine
        This machine's name; a payload naming another is rejected (WRONG_MACHINE).
    accepted
        The encodings this machine announced in Hello.
    max_bytes
        Most payload bytes this machine can store (TOO_LARGE above it).
    applied_version
        The version now applied (0 = none); older versions are STALE_VERSION. The
        caller updates it after applying an accepted map or releasing compensation.
    """

    def __init__(self, machine: str, accepted: MapEncoding = _ALL,
                 max_bytes: int = MAX_MAP_BYTES, applied_version: int = 0) -> None:
        self.machine = machine
        self.accepted = accepted
        self.max_bytes = max_bytes
        self.applied_version = applied_version
        self._transfer: _Transfer | None = None

    @property
    def in_progress(self) -> bool:
        """A MapBegin was fed and its MapEnd not yet."""
        return self._transfer is not None

    def feed(self, msg: MapBegin | MapChunk | MapEnd) -> MapAccepted | MapRejected | None:
        """Take one map message; on MapEnd return the verdict, else None.

        Raises
        ------
        LocalProtocolError
            MapBegin during a transfer, or MapChunk/MapEnd outside one: the Connection's
            state machine never lets that through, so it means the caller skipped it.
        """
        match msg:
            case MapBegin():
                if self._transfer is not None:
                    raise LocalProtocolError("MapBegin while another map transfer is open")
                t = self._transfer = _Transfer(msg)
                if msg.total_size > self.max_bytes:
                    self._fail(t, MapRejectReason.TOO_LARGE,
                               f"map of {msg.total_size} bytes, this machine stores at most "
                               f"{self.max_bytes}")
                elif msg.version < self.applied_version:
                    self._fail(t, MapRejectReason.STALE_VERSION,
                               f"map version {msg.version} is older than the applied "
                               f"version {self.applied_version}")
                return None
            case MapChunk():
                t = self._open(msg)
                if t.failure is None:
                    self._chunk(t, msg)
                return None
            case MapEnd():
                t = self._open(msg)
                self._transfer = None
                return self._finish(t, msg)

    def _open(self, msg: MapChunk | MapEnd) -> _Transfer:
        if self._transfer is None:
            raise LocalProtocolError(f"{type(msg).__name__} without MapBegin")
        return self._transfer

    @staticmethod
    def _fail(t: _Transfer, reason: MapRejectReason, text: str) -> None:
        if t.failure is None:  # the first problem is the one reported
            t.failure = MapRejected(t.begin.version, reason, text)
        t.data.clear()

    def _chunk(self, t: _Transfer, c: MapChunk) -> None:
        b = t.begin
        if c.version != b.version:
            self._fail(t, MapRejectReason.WRONG_VERSION,
                       f"chunk {c.index} carries version {c.version}, MapBegin {b.version}")
        elif c.index >= b.chunk_count:
            self._fail(t, MapRejectReason.UNEXPECTED_CHUNK,
                       f"chunk {c.index} is beyond the {b.chunk_count} announced")
        elif c.index < t.next_index:
            self._fail(t, MapRejectReason.UNEXPECTED_CHUNK,
                       f"chunk {c.index} arrived again (expected chunk {t.next_index})")
        elif c.index > t.next_index:
            self._fail(t, MapRejectReason.MISSING_CHUNK,
                       f"chunk {t.next_index} is missing (got chunk {c.index} next)")
        elif len(t.data) + len(c.data) > b.total_size:
            self._fail(t, MapRejectReason.WRONG_SIZE,
                       f"chunks 0..{c.index} hold {len(t.data) + len(c.data)} bytes, more "
                       f"than the {b.total_size} announced")
        else:
            t.data += c.data
            t.next_index += 1

    def _finish(self, t: _Transfer, end: MapEnd) -> MapAccepted | MapRejected:
        b = t.begin
        if t.failure is None:
            if end.version != b.version:
                self._fail(t, MapRejectReason.WRONG_VERSION,
                           f"MapEnd carries version {end.version}, MapBegin {b.version}")
            elif t.next_index < b.chunk_count:
                self._fail(t, MapRejectReason.MISSING_CHUNK,
                           f"got {t.next_index} of {b.chunk_count} chunks; chunk "
                           f"{t.next_index} is missing")
            elif len(t.data) != b.total_size:
                self._fail(t, MapRejectReason.WRONG_SIZE,
                           f"chunks hold {len(t.data)} bytes, MapBegin announced "
                           f"{b.total_size}")
            elif (digest := hashlib.sha256(t.data).digest()) != b.sha256:
                self._fail(t, MapRejectReason.CHECKSUM_MISMATCH,
                           f"SHA-256 of the payload is {digest.hex()[:16]}..., MapBegin "
                           f"announced {b.sha256.hex()[:16]}...")
        if t.failure is not None:
            return t.failure
        data = bytes(t.data)
        payload: ErrorMapPayload | TablesPayload | FactoredPayload
        try:
            payload = decode_payload(data)
        except MapFormatError as exc:
            return MapRejected(b.version, MapRejectReason.DECODE_ERROR, str(exc))
        if payload.version != b.version:
            return MapRejected(b.version, MapRejectReason.WRONG_VERSION,
                               f"payload says version {payload.version}, MapBegin "
                               f"{b.version}")
        if payload.machine != self.machine:
            return MapRejected(b.version, MapRejectReason.WRONG_MACHINE,
                               f"map is for {payload.machine!r}, this is {self.machine!r}")
        if isinstance(payload, TablesPayload) and not self.accepted & MapEncoding.TABLES:
            return MapRejected(b.version, MapRejectReason.UNSUPPORTED_ENCODING,
                               "a tables map, and this machine evaluates only grid maps")
        if isinstance(payload, FactoredPayload) and not self.accepted & MapEncoding.FACTORED:
            return MapRejected(b.version, MapRejectReason.UNSUPPORTED_ENCODING,
                               "a factored map (format version 4), and this machine does not "
                               "evaluate them")
        if (isinstance(payload, ErrorMapPayload) and payload.thermal
                and not self.accepted & MapEncoding.THERMAL):
            return MapRejected(b.version, MapRejectReason.UNSUPPORTED_ENCODING,
                               "a grid map with thermal records (format version 3), and this "
                               "machine does not apply them")
        if not payload.encoding & self.accepted:
            return MapRejected(b.version, MapRejectReason.UNSUPPORTED_ENCODING,
                               f"map encoding {payload.encoding.name} is not one this "
                               f"machine accepts")
        return MapAccepted(b.version, payload, data)
