"""Grid maps with thermal records (format version 3, protocol/README.md §6.4): golden
bytes, round trips, every decode error naming its field and offset, the Hello bit and the
assembler's refusal of a version-3 map to a machine that did not declare it."""

from __future__ import annotations

import dataclasses
import struct

import pytest

from protocol import (
    ErrorMapPayload,
    GridAxis,
    Hello,
    MapAccepted,
    MapAssembler,
    MapEncoding,
    MapFormatError,
    MapRejected,
    MapRejectReason,
    MessageType,
    OutputAxis,
    ThermalRecord,
    decode_map,
    decode_payload,
    encode_map,
    encode_payload,
    pack_values,
    split_into_chunks,
)
from protocol.codec import decode_payload as decode_message
from protocol.codec import encode_payload as encode_message
from protocol.codes import Controller
from tests.support.protocol import sample_map

INT32 = MapEncoding.INT32_INCREMENTS
FLOAT32 = MapEncoding.FLOAT32_MM
THERMAL = MapEncoding.THERMAL

RECORDS = (ThermalRecord("spindle", "X", 1, -2.5, 20.0),
           ThermalRecord("T_y_C", "Y", 2, 11.5, 20.0, -150.0))
TINY3 = ErrorMapPayload("m1", 2, INT32, (GridAxis("X", 0.0, 10.0, 2),),
                        (OutputAxis("X", 5), OutputAxis("Y")),
                        pack_values(INT32, [1, -1, 2, -2]), 0.001, 60, RECORDS)
TINY3_BYTES = bytes.fromhex(
    "45444d50 0300 01 01 02 00000000000000"          # EDMP, v3, int32, 1 dim, 2 outputs
    "6d31" + "00" * 30 +                              # machine "m1"
    "02000000 3c000000 fca9f1d24d62503f"              # version 2, valid 60 s, 0.001 mm
    "58000000 02000000 0000000000000000 0000000000002440"  # X: 2 nodes from 0 step 10
    "58000000 01 000000 05000000"                     # output X, reversal 5 counts
    "59000000 00 000000 00000000"                     # output Y, no reversal
    "01000000 ffffffff 02000000 feffffff"             # values (X0: 1, -1), (X1: 2, -2)
    "02000000"                                        # offset 128: 2 thermal records
    "7370696e646c65" + "00" * 9 +                     # 132: sensor "spindle"
    "58000000 01 000000"                              # axis X, kind 1 drift, reserved
    "00000000000004c0 0000000000003440 0000000000000000"  # -2.5 µm/K, 20 °C, q_min 0
    "545f795f43" + "00" * 11 +                        # 180: sensor "T_y_C"
    "59000000 02 000000"                              # axis Y, kind 2 expansion
    "0000000000002740 0000000000003440 0000000000c062c0"  # 11.5 µm/(m·K), 20 °C, -150 mm
)


def _patch(data: bytes, at: int, raw: bytes) -> bytes:
    return data[:at] + raw + data[at + len(raw):]


def test_golden_grid_with_thermal_records_both_ways() -> None:
    assert encode_map(TINY3) == TINY3_BYTES == encode_payload(TINY3)
    assert decode_map(TINY3_BYTES) == TINY3 == decode_payload(TINY3_BYTES)
    assert TINY3.size == len(TINY3_BYTES) == 128 + 4 + 2 * 48
    assert TINY3.format_version == 3
    # exactly the version-1 layout ahead of the trailer
    v1 = encode_map(dataclasses.replace(TINY3, thermal=()))
    assert v1[4:6] == b"\x01\x00" and v1[6:] == TINY3_BYTES[6:128] and len(v1) == 128


@pytest.mark.parametrize("encoding", [INT32, FLOAT32])
def test_round_trip(encoding: MapEncoding) -> None:
    m = dataclasses.replace(sample_map(encoding=encoding),
                            thermal=(ThermalRecord("T_spindle_C", "Z", 1, -1.5, 21.0),
                                     ThermalRecord("x_screw", "X", 2, 11.5, 20.0, 0.0)))
    data = encode_map(m)
    assert data[4:6] == b"\x03\x00"
    back = decode_payload(data)
    assert back == m and encode_map(back) == data


@pytest.mark.parametrize(("data", "pattern"), [
    (TINY3_BYTES[:128], r"version-3 map needs its thermal record count at offset 128"),
    (_patch(TINY3_BYTES, 128, struct.pack("<I", 0)), r"0 thermal records \(offset 128\)"),
    (_patch(TINY3_BYTES, 128, struct.pack("<I", 33)), r"33 thermal records \(offset 128\)"),
    (_patch(TINY3_BYTES, 128, struct.pack("<I", 3)), r"its 3 thermal records need 276"),
    (TINY3_BYTES + b"\0", r"map payload is 229 bytes, its header describes 228"),
    (TINY3_BYTES[:-1], r"its 2 thermal records need 228"),
    (_patch(TINY3_BYTES, 153, b"\x01"), r"thermal record 0 at offset 132 has non-zero reserved"),
    (_patch(TINY3_BYTES, 152, b"\x03"), r"thermal record 0 at offset 132: .*kind must be 1"),
    (_patch(TINY3_BYTES, 148, b"Z"), r"thermal record 0 at offset 148: axis Z is not an output"),
    (_patch(TINY3_BYTES, 148, b"A"), r"thermal record 0 at offset 132: .*linear axis name"),
    (_patch(TINY3_BYTES, 132, b" "), r"thermal record 0 at offset 132: .*printable ASCII"),
    (_patch(TINY3_BYTES, 180 + 24, struct.pack("<d", float("nan"))),
     r"thermal record 1 at offset 180: .*coefficient must be finite"),
    (_patch(TINY3_BYTES, 4, b"\x01\x00"), r"map payload is 228 bytes, its header describes 128"),
    (_patch(TINY3_BYTES, 108, b"\x01"), r"output axis 1 at offset 108: reversal is not 0"),
])
def test_decode_error_names_the_field(data: bytes, pattern: str) -> None:
    with pytest.raises(MapFormatError, match=pattern):
        decode_payload(data)


def test_construction_refuses_a_record_of_no_output() -> None:
    with pytest.raises(ValueError, match="axis Z is not an output axis"):
        dataclasses.replace(TINY3, thermal=(ThermalRecord("s", "Z", 1, 1.0, 20.0),))
    with pytest.raises(ValueError, match="at most 32"):
        dataclasses.replace(TINY3, thermal=RECORDS[:1] * 33)


def _push(payload: ErrorMapPayload, accepted: MapEncoding) -> MapAccepted | MapRejected:
    asm = MapAssembler("m1", accepted)
    verdict = None
    for msg in split_into_chunks(encode_map(payload), payload.version, chunk_size=100):
        verdict = asm.feed(msg)
    assert verdict is not None
    return verdict


def test_a_machine_without_the_thermal_bit_refuses_version_3() -> None:
    refused = _push(TINY3, INT32)
    assert isinstance(refused, MapRejected)
    assert refused.reason is MapRejectReason.UNSUPPORTED_ENCODING
    assert "thermal records" in refused.text
    ok = _push(TINY3, INT32 | THERMAL)
    assert isinstance(ok, MapAccepted) and ok.payload == TINY3
    # the bit is no value encoding: a float32 machine still refuses int32 values
    assert isinstance(_push(TINY3, FLOAT32 | THERMAL), MapRejected)
    # and a version-1 map goes to either
    plain = dataclasses.replace(TINY3, thermal=())
    assert isinstance(_push(plain, INT32), MapAccepted)
    assert isinstance(_push(plain, INT32 | THERMAL), MapAccepted)


def test_hello_carries_the_thermal_bit() -> None:
    hello = Hello("vmc-01", "10.0.0.21", Controller.FANUC, INT32 | THERMAL, "1.0.0",
                  "w X Y b Z t")
    raw = encode_message(hello)
    assert raw[17:19] == b"\x01\x09"  # after name and ip: controller 1, formats 0x09
    assert decode_message(MessageType.HELLO, raw) == hello
    with pytest.raises(ValueError, match="at least one known format"):
        Hello("vmc-01", "10.0.0.21", Controller.FANUC, THERMAL, "1.0.0", "w X Y b Z t")
