"""The error-map payload: golden bytes, round trips, every decode error, chunking, and
every reason MapAssembler rejects a push for."""

from __future__ import annotations

import dataclasses
import hashlib
import struct

import numpy as np
import pytest

from protocol import (
    ErrorMapPayload,
    GridAxis,
    LocalProtocolError,
    MapAccepted,
    MapAssembler,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapEnd,
    MapFormatError,
    MapRejected,
    MapRejectReason,
    OutputAxis,
    decode_map,
    encode_map,
    pack_values,
    split_into_chunks,
)
from tests.support.protocol import sample_map

INT32 = MapEncoding.INT32_INCREMENTS
FLOAT32 = MapEncoding.FLOAT32_MM

TINY = ErrorMapPayload("m1", 2, INT32, (GridAxis("X", 0.0, 10.0, 2),),
                       (OutputAxis("X", 5), OutputAxis("Y")),
                       pack_values(INT32, [1, -1, 2, -2]), 0.001, 60)
TINY_BYTES = bytes.fromhex(
    "45444d50 0100 01 01 02 00000000000000"          # EDMP, v1, int32, 1 dim, 2 outputs
    "6d31" + "00" * 30 +                              # machine "m1"
    "02000000 3c000000 fca9f1d24d62503f"              # version 2, valid 60 s, 0.001 mm
    "58000000 02000000 0000000000000000 0000000000002440"  # X: 2 nodes from 0 step 10
    "58000000 01 000000 05000000"                     # output X, reversal 5 counts
    "59000000 00 000000 00000000"                     # output Y, no reversal
    "01000000 ffffffff 02000000 feffffff"             # values (X0: 1, -1), (X1: 2, -2)
)


def test_golden_map_both_ways() -> None:
    assert encode_map(TINY) == TINY_BYTES
    assert decode_map(TINY_BYTES) == TINY
    assert TINY.size == len(TINY_BYTES) == 128


@pytest.mark.parametrize("encoding", [INT32, FLOAT32])
def test_round_trip_and_numpy_view(encoding: MapEncoding) -> None:
    m = sample_map(encoding=encoding)
    data = encode_map(m)
    back = decode_map(data)
    assert back == m and encode_map(back) == data
    arr = np.frombuffer(back.values, back.dtype).reshape(back.shape)
    assert arr.shape == (21, 11, 3)
    flat = np.arange(21 * 11 * 3)
    expected = (flat * 37) % 201 - 100
    if encoding is FLOAT32:
        np.testing.assert_array_equal(arr.ravel(), (expected * 1e-3).astype("<f4"))
    else:
        np.testing.assert_array_equal(arr.ravel(), expected)
    # row-major, output axis fastest: node (i, j) output k sits at ((i*11)+j)*3+k
    assert arr[2, 5, 1] == arr.ravel()[(2 * 11 + 5) * 3 + 1]
    assert list(back.value_array()) == list(arr.ravel())


def test_float32_reversal_is_rounded_on_construction() -> None:
    m = sample_map(encoding=FLOAT32)
    assert m.outputs[0].reversal == struct.unpack("<f", struct.pack("<f", 0.004))[0]
    assert decode_map(encode_map(m)).outputs == m.outputs


def _patch(data: bytes, offset: int, new: bytes) -> bytes:
    return data[:offset] + new + data[offset + len(new):]


@pytest.mark.parametrize(("data", "pattern"), [
    (TINY_BYTES[:63], r"map payload is 63 bytes, shorter than the 64-byte header"),
    (_patch(TINY_BYTES, 0, b"EDMQ"), r"map magic is b'EDMQ', expected b'EDMP'"),
    (_patch(TINY_BYTES, 4, b"\x02\x00"),
     r"map format version 2 at offset 4, a grid map is version 1 or 3"),
    (_patch(TINY_BYTES, 6, b"\x03"), r"map value encoding 3 at offset 6 is unknown"),
    (_patch(TINY_BYTES, 7, b"\x00"), r"map has 0 grid dimensions, 1 to 6 allowed"),
    (_patch(TINY_BYTES, 8, b"\x11"), r"map has 17 output axes, 1 to 16 allowed"),
    (_patch(TINY_BYTES, 12, b"\x01"), r"reserved bytes 9..15 are not zero"),
    (_patch(TINY_BYTES, 20, b"x"), r"machine name at offset 16 has bytes after its NUL"),
    (_patch(TINY_BYTES, 16, b"\xff"), r"machine name at offset 16 is not ASCII"),
    (_patch(TINY_BYTES, 16, b" "), r"map machine must be 1 to 32 ASCII letters"),
    (_patch(TINY_BYTES, 48, bytes(4)), r"map version must be in \[1, "),
    (_patch(TINY_BYTES, 56, struct.pack("<d", 0.0)), r"int32 map increment_mm must be in"),
    (_patch(TINY_BYTES, 68, b"\x01\x00\x00\x00"), r"grid axis X count must be in \[2, "),
    (_patch(TINY_BYTES, 80, struct.pack("<d", -1.0)), r"grid axis X step must be > 0"),
    (_patch(TINY_BYTES, 72, struct.pack("<d", float("nan"))), r"grid axis X start must be "
                                                               r"finite"),
    (_patch(TINY_BYTES, 64, b"1\x00"), r"grid axis name must be 1 to 4 ASCII"),
    (_patch(TINY_BYTES, 100, b"X"), r"map outputs names 'X' twice"),
    (_patch(TINY_BYTES, 92, b"\x03"), r"output axis 0 at offset 88 has unknown flags 0x03"),
    (TINY_BYTES[:-1], r"map payload is 127 bytes, its header describes 128 \(2 nodes x 2 axes"),
    (TINY_BYTES + b"\x00", r"map payload is 129 bytes, its header describes 128"),
    (_patch(TINY_BYTES, 68, b"\xff\xff\xff\xff"), r"its header describes"),
    (TINY_BYTES[:100], r"map payload is 100 bytes, its axis tables need 112"),
])
def test_decode_error_names_the_field(data: bytes, pattern: str) -> None:
    with pytest.raises(MapFormatError, match=pattern):
        decode_map(data)


def test_float_map_with_nan_value_is_refused() -> None:
    m = sample_map(encoding=FLOAT32)
    bad = bytearray(m.values)
    bad[4 * 17:4 * 18] = struct.pack("<f", float("inf"))
    with pytest.raises(ValueError, match=r"map value 17 \(flat index\) is not finite"):
        dataclasses.replace(m, values=bytes(bad))
    data = encode_map(m)
    start = len(data) - len(m.values)
    with pytest.raises(MapFormatError, match=r"map value 17"):
        decode_map(data[:start] + bytes(bad))


@pytest.mark.parametrize(("change", "pattern"), [
    ({"values": b"\x00" * 3}, r"map values are 3 bytes, shape \(2, 2\) needs 16"),
    ({"encoding": INT32 | FLOAT32}, r"map encoding must be exactly one MapEncoding"),
    ({"encoding": 1}, r"map encoding must be a MapEncoding, got 1"),
    ({"encoding": FLOAT32}, r"float32 map increment_mm must be 0"),
    ({"outputs": (OutputAxis("X", 1.5),)}, r"output axis X reversal must be an int32 count"),
    ({"grid": ()}, r"map grid must be a tuple of 1 to 6 GridAxis"),
    ({"valid_s": -1}, r"map valid_s must be in \[0, "),
])
def test_invalid_map_cannot_be_built(change: dict[str, object], pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        dataclasses.replace(TINY, **change)  # type: ignore[arg-type]


def test_pack_values_refuses_fractional_or_oversize_counts() -> None:
    with pytest.raises(ValueError, match=r"int32 map values must be whole counts, got 0\.5"):
        pack_values(INT32, [1, 0.5])
    with pytest.raises(ValueError, match=r"int32 map values must lie in \[-2\*\*31, "):
        pack_values(INT32, [2**31])


def test_float_values_beyond_float32_become_inf_and_are_refused() -> None:
    with pytest.raises(ValueError, match=r"map value 0 \(flat index\) is not finite"):
        dataclasses.replace(TINY, encoding=FLOAT32, increment_mm=0.0,
                            outputs=(OutputAxis("X"), OutputAxis("Y")),
                            values=pack_values(FLOAT32, [1e39, 0, 0, 0]))


# --- chunking and assembly ---------------------------------------------------------------

PAYLOAD = encode_map(sample_map())


def test_split_into_chunks() -> None:
    msgs = split_into_chunks(PAYLOAD, 7, 1000)
    begin, *chunks, end = msgs
    assert isinstance(begin, MapBegin) and isinstance(end, MapEnd)
    assert begin == MapBegin(7, len(PAYLOAD), -(-len(PAYLOAD) // 1000),
                             hashlib.sha256(PAYLOAD).digest())
    assert all(isinstance(c, MapChunk) for c in chunks)
    assert [c.index for c in chunks if isinstance(c, MapChunk)] == list(range(len(chunks)))
    assert b"".join(c.data for c in chunks if isinstance(c, MapChunk)) == PAYLOAD
    assert {len(c.data) for c in chunks[:-1] if isinstance(c, MapChunk)} == {1000}
    with pytest.raises(ValueError, match="chunk_size must be 1 to 8192, got 8193"):
        split_into_chunks(PAYLOAD, 7, 8193)


def feed_all(asm: MapAssembler, msgs: list[MapBegin | MapChunk | MapEnd]
             ) -> MapAccepted | MapRejected:
    results = [asm.feed(m) for m in msgs]
    assert results[:-1] == [None] * (len(msgs) - 1)
    last = results[-1]
    assert last is not None
    assert not asm.in_progress
    return last


def test_assembler_accepts_a_whole_map() -> None:
    asm = MapAssembler("vmc-01", INT32)
    result = feed_all(asm, split_into_chunks(PAYLOAD, 7, 1000))
    assert isinstance(result, MapAccepted)
    assert result.payload == sample_map() and result.data == PAYLOAD
    assert result.ack().version == 7


def _chunks(version: int = 7, size: int = 1000, payload: bytes = PAYLOAD
            ) -> list[MapBegin | MapChunk | MapEnd]:
    return split_into_chunks(payload, version, size)


def _with(msgs: list[MapBegin | MapChunk | MapEnd], i: int, new: MapBegin | MapChunk | MapEnd
          ) -> list[MapBegin | MapChunk | MapEnd]:
    return [*msgs[:i], new, *msgs[i + 1:]]


def _tampered_payload(offset: int, new: bytes) -> bytes:
    return PAYLOAD[:offset] + new + PAYLOAD[offset + len(new):]


_M = _chunks()
_N = len(_M)
_OTHER = encode_map(sample_map(machine="vmc-02"))
_FLOAT = encode_map(sample_map(encoding=FLOAT32))
_V8 = encode_map(sample_map(version=8))

REJECTIONS: list[tuple[str, list[MapBegin | MapChunk | MapEnd], MapRejectReason, str]] = [
    ("skipped chunk", [*_M[:2], *_M[3:]], MapRejectReason.MISSING_CHUNK,
     "chunk 1 is missing (got chunk 2 next)"),
    ("end too early", [*_M[:3], _M[-1]], MapRejectReason.MISSING_CHUNK,
     f"got 2 of {_N - 2} chunks; chunk 2 is missing"),
    ("repeated chunk", [*_M[:3], _M[2], *_M[3:]], MapRejectReason.UNEXPECTED_CHUNK,
     "chunk 1 arrived again (expected chunk 2)"),
    ("chunk beyond count", [*_M[:-1], MapChunk(7, _N - 2, b"x"), _M[-1]],
     MapRejectReason.UNEXPECTED_CHUNK, f"chunk {_N - 2} is beyond the {_N - 2} announced"),
    ("too many bytes", _with(_M, _N - 2, MapChunk(7, _N - 3, b"x" * 1000)),
     MapRejectReason.WRONG_SIZE, "more than the"),
    ("too few bytes", _with(_M, _N - 2, MapChunk(7, _N - 3, b"x")),
     MapRejectReason.WRONG_SIZE, f"chunks hold {1000 * (_N - 3) + 1} bytes"),
    ("checksum", _with(_M, 2, MapChunk(7, 1, b"\x00" * 1000)),
     MapRejectReason.CHECKSUM_MISMATCH, "SHA-256 of the payload is"),
    ("chunk version", _with(_M, 2, MapChunk(8, 1, _M[2].data)),  # type: ignore[union-attr]
     MapRejectReason.WRONG_VERSION, "chunk 1 carries version 8, MapBegin 7"),
    ("end version", _with(_M, _N - 1, MapEnd(8)), MapRejectReason.WRONG_VERSION,
     "MapEnd carries version 8, MapBegin 7"),
    ("payload version", _chunks(7, 1000, _V8), MapRejectReason.WRONG_VERSION,
     "payload says version 8, MapBegin 7"),
    ("decode", _chunks(7, 1000, _tampered_payload(0, b"XXXX")), MapRejectReason.DECODE_ERROR,
     "map magic is b'XXXX'"),
    ("machine", _chunks(7, 1000, _OTHER), MapRejectReason.WRONG_MACHINE,
     "map is for 'vmc-02', this is 'vmc-01'"),
    ("encoding", _chunks(7, 1000, _FLOAT), MapRejectReason.UNSUPPORTED_ENCODING,
     "map encoding FLOAT32_MM is not one this machine accepts"),
]


@pytest.mark.parametrize(("name", "msgs", "reason", "text"), REJECTIONS,
                         ids=[r[0] for r in REJECTIONS])
def test_assembler_rejects(name: str, msgs: list[MapBegin | MapChunk | MapEnd],
                           reason: MapRejectReason, text: str) -> None:
    asm = MapAssembler("vmc-01", INT32)
    result = feed_all(asm, msgs)
    assert isinstance(result, MapRejected), name
    assert (result.version, result.reason) == (7, reason)
    assert text in result.text
    reply = result.message()
    assert (reply.version, reply.reason) == (7, reason)
    # the assembler is ready for the next push, which goes through
    assert isinstance(feed_all(asm, _chunks(9, 1000, encode_map(sample_map(version=9)))),
                      MapAccepted)


def test_assembler_too_large_and_stale() -> None:
    asm = MapAssembler("vmc-01", INT32, max_bytes=len(PAYLOAD) - 1)
    r = feed_all(asm, _M)
    assert isinstance(r, MapRejected) and r.reason is MapRejectReason.TOO_LARGE
    assert f"map of {len(PAYLOAD)} bytes, this machine stores at most" in r.text
    asm = MapAssembler("vmc-01", INT32, applied_version=8)
    r = feed_all(asm, _M)
    assert isinstance(r, MapRejected) and r.reason is MapRejectReason.STALE_VERSION
    assert "older than the applied version 8" in r.text


def test_decode_error_text_is_clipped_for_the_wire() -> None:
    long = MapRejected(7, MapRejectReason.DECODE_ERROR, "é" * 300)
    assert len(long.message().text.encode()) <= 255


def test_assembler_misuse_is_a_local_error() -> None:
    asm = MapAssembler("vmc-01")
    with pytest.raises(LocalProtocolError, match="MapChunk without MapBegin"):
        asm.feed(_M[1])
    asm.feed(_M[0])
    with pytest.raises(LocalProtocolError, match="MapBegin while another map transfer"):
        asm.feed(_M[0])
