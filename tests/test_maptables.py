"""The tables map (format version 2): golden bytes, round trips, version dispatch, every
truncation and corruption refused with a message naming the field, construction checks."""

from __future__ import annotations

import dataclasses
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from protocol import (
    ChainAxis,
    ComponentTable,
    ErrorMapPayload,
    GridAxis,
    MapAccepted,
    MapAssembler,
    MapEncoding,
    MapFormatError,
    MapRejected,
    MapRejectReason,
    OutputAxis,
    Spindle,
    TablesPayload,
    ThermalRecord,
    decode_map,
    decode_payload,
    encode_map,
    encode_payload,
    pack_values,
    payload_kind,
    split_into_chunks,
)
from protocol.limits import MAX_MAP_BYTES

FLOAT32 = MapEncoding.FLOAT32_MM
INT32 = MapEncoding.INT32_INCREMENTS

X_AXIS = ChainAxis("X", False, False, (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 100.0))
TINY = TablesPayload(
    "m1", 3, FLOAT32, 0, 0.0, (X_AXIS,),
    (Spindle("S", ("X",), 10.0, (0.0, 0.0, -1.0), (1.0, 1.0, 1.0, 0.0, 0.0, 0.0)),),
    (OutputAxis("X", 0.5),),
    (ComponentTable("EXX", 0.0, 50.0, (1.0, -2.5, 4.0)),),
    (("EC0X", 12.5),),
    (ThermalRecord("x_screw", "X", 2, 11.5, 20.0, 0.0),),
    0.5, 0.25)
TINY_BYTES = bytes.fromhex(
    "45444d50 0200 02 02 01 01 01 01 0100 0100"      # EDMP, v2, float32, tables; K A S H T L
    "6d31" + "00" * 30 +                              # machine "m1"
    "03000000 00000000 0000000000000000"              # version 3, valid_s 0, increment 0
    "000000000000e03f 000000000000d03f"               # limit_mm 0.5, limit_deg 0.25
    # chain axis X: flags 0 (linear, workpiece side), direction, pivot, travel 0..100
    "58000000 00 000000"
    "000000000000f03f 0000000000000000 0000000000000000"
    "0000000000000000 0000000000000000 0000000000000000"
    "0000000000000000 0000000000005940"
    # spindle S: links mask 0x0001, tool 10 mm along -z, weights 1 1 1 0 0 0
    "53" + "00" * 15 + "0100 000000000000"
    "0000000000002440"
    "0000000000000000 0000000000000000 000000000000f0bf"
    "000000000000f03f 000000000000f03f 000000000000f03f"
    "0000000000000000 0000000000000000 0000000000000000"
    "58000000 01 000000 0000003f"                     # output X, reversal 0.5 (float32)
    "45585800 00000000 03000000 00000000"             # table EXX: 3 values from index 0,
    "0000000000000000 0000000000004940"               # start 0, step 50
    "45433058 00000000 0000000000002940"              # location EC0X = 12.5 µrad
    "785f7363726577" + "00" * 9 +                     # thermal: sensor "x_screw",
    "58000000 02 000000"                              # axis X, kind 2 (expansion)
    "0000000000002740 0000000000003440 0000000000000000"  # 11.5 µm/(m·K), 20 °C, q_min 0
    "0000803f 000020c0 00008040"                      # values 1.0, -2.5, 4.0 (float32)
)


def test_golden_tables_both_ways() -> None:
    assert encode_payload(TINY) == TINY_BYTES
    assert decode_payload(TINY_BYTES) == TINY
    assert TINY.size == len(TINY_BYTES) == 376
    assert payload_kind(TINY) == "tables"


def test_version_1_grid_payloads_still_decode_through_the_dispatch() -> None:
    grid = ErrorMapPayload("m1", 2, INT32, (GridAxis("X", 0.0, 10.0, 2),),
                           (OutputAxis("X", 5), OutputAxis("Y")),
                           pack_values(INT32, [1, -1, 2, -2]), 0.001, 60)
    data = encode_map(grid)
    assert decode_payload(data) == decode_map(data) == grid
    assert encode_payload(grid) == data and payload_kind(grid) == "grid"


def five_axis(encoding: MapEncoding = FLOAT32) -> TablesPayload:
    """A trunnion (C on A on the table, X Y, Z on the tool side) with thermal records."""
    def ax(name: str, tool: bool, travel: tuple[float, float],
           pivot: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> ChainAxis:
        unit = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
        d = unit[{"A": "X", "B": "Y", "C": "Z"}.get(name, name)]
        return ChainAxis(name, name in "ABC", tool, d, pivot, travel)
    axes = (ax("C", False, (-180.0, 180.0), (1.0, 2.0, 3.0)), ax("A", False, (-90.0, 30.0)),
            ax("X", False, (0.0, 500.0)), ax("Y", False, (0.0, 300.0)),
            ax("Z", True, (-300.0, 0.0)))
    tables = tuple(ComponentTable(f"E{c}{a.name}", a.travel[0], 10.0,
                                  tuple(0.25 * i - 1.0 for i in range(7)))
                   for a in axes for c in "XYZABC")
    inc = 0.001 if encoding is INT32 else 0.0
    rev = 3 if encoding is INT32 else 0.003
    return TablesPayload(
        "5ax-04", 7, encoding, 3600, inc, axes,
        (Spindle("main", tuple(a.name for a in axes), 100.0, (0.0, 0.0, -1.0),
                 (1.0, 1.0, 1.0, 1.0, 1.0, 1.0)),),
        tuple(OutputAxis(a.name, rev if a.name == "X" else None) for a in axes), tables,
        (("EX0C", 5.0), ("EB0C", -3.0), ("EC0Y", 7.5), ("EA0Z", 1.0)),
        (ThermalRecord("T_spindle_C", "Z", 1, -1.5, 21.0),
         ThermalRecord("x_screw", "X", 2, 11.5, 20.0, 0.0)),
        0.2, 0.05)


@pytest.mark.parametrize("encoding", [FLOAT32, INT32])
def test_round_trip_of_a_five_axis_map(encoding: MapEncoding) -> None:
    p = five_axis(encoding)
    data = encode_payload(p)
    assert len(data) == p.size
    assert decode_payload(data) == p
    assert encode_payload(decode_payload(data)) == data


def test_every_truncation_is_refused_with_a_reason() -> None:
    data = encode_payload(five_axis())
    for n in range(len(data)):
        with pytest.raises(MapFormatError) as err:
            decode_payload(data[:n])
        assert "bytes" in str(err.value) or "offset" in str(err.value)
    with pytest.raises(MapFormatError, match=r"header and table directory describe"):
        decode_payload(data + b"\0\0\0\0")


def _patch(data: bytes, at: int, raw: bytes) -> bytes:
    return data[:at] + raw + data[at + len(raw):]


AXES_AT, SPINDLE_AT = 80, 80 + 72
OUT_AT = SPINDLE_AT + 104
TABLE_AT = OUT_AT + 12
LOC_AT = TABLE_AT + 32
THERMAL_AT = LOC_AT + 16
VALUES_AT = THERMAL_AT + 48


@pytest.mark.parametrize(("at", "raw", "pattern"), [
    (0, b"EDMQ", r"map magic is b'EDMQ'"),
    (4, struct.pack("<H", 6),
     r"map format version 6 at offset 4, this end reads 1 .* 2 .* 3 .* and 5"),
    (6, b"\x03", r"value encoding 3 at offset 6"),
    (7, b"\x03", r"map kind 3 at offset 7"),
    (8, b"\x00", r"0 output axes \(offset 8\)"),
    (9, b"\x11", r"17 chain axes \(offset 9\)"),
    (10, b"\x00", r"0 spindles \(offset 10\)"),
    (11, b"\x21", r"33 thermal records \(offset 11\)"),
    (12, struct.pack("<H", 7), r"7 component tables \(offset 12\), at most 6"),
    (14, struct.pack("<H", 7), r"7 location errors \(offset 14\)"),
    (16, b"m\x001", r"machine name at offset 16 has bytes after its NUL"),
    (48, struct.pack("<I", 0), r"map version must be in \[1"),
    (56, struct.pack("<d", 0.5), r"float32 map increment_mm must be 0"),
    (64, struct.pack("<d", -1.0), r"limit_mm must be > 0"),
    (72, struct.pack("<d", float("nan")), r"limit_deg must be finite"),
    (AXES_AT, b"Q\0\0\0", r"chain axis 0 at offset 80: chain axis name must be"),
    (AXES_AT + 4, b"\x04", r"chain axis 0 at offset 80 has unknown flags 0x04"),
    (AXES_AT + 4, b"\x01", r"chain axis 0 at offset 80: chain axis X must be linear"),
    (AXES_AT + 5, b"\x01", r"chain axis 0 at offset 80 has unknown flags 0x00 or non-zero"),
    (AXES_AT + 8, struct.pack("<d", 0.5), r"chain axis X direction must be a unit vector"),
    (AXES_AT + 56, struct.pack("<d", 200.0), r"chain axis X travel must have lower < upper"),
    (SPINDLE_AT + 16, b"\x00\x00", r"spindle 0 \(S\) at offset 168: axis mask 0x0000"),
    (SPINDLE_AT + 16, b"\x00\x01", r"spindle 0 \(S\) at offset 168: axis mask 0x0100"),
    (SPINDLE_AT + 18, b"\x01", r"spindle 0 \(S\) at offset 152 has non-zero reserved"),
    (SPINDLE_AT + 32, struct.pack("<d", 2.0), r"spindle 0 at offset 152: .*tool_direction"),
    (SPINDLE_AT + 56, struct.pack("<d", -1.0), r"spindle S weights must be >= 0"),
    (OUT_AT, b"W\0\0\0", r"output axis W is not a chain axis"),
    (OUT_AT + 4, b"\x02", r"output axis 0 at offset 256 has unknown flags 0x02"),
    (TABLE_AT, b"EQX\0", r"table record at offset 268: component table name must be"),
    (TABLE_AT, b"EXY\0", r"table EXY: Y is not a chain axis"),
    (TABLE_AT + 8, struct.pack("<I", 0), r"table 0 \(EXX\) at offset 268: count is 0"),
    (TABLE_AT + 12, struct.pack("<I", 1), r"first value index 1, expected 0"),
    (TABLE_AT + 24, struct.pack("<d", 0.0), r"table EXX step must be > 0"),
    (TABLE_AT + 8, struct.pack("<I", 2), r"tables map is 376 bytes, its header and table "
                                         r"directory describe 372 \(2 values at offset 364"),
    (LOC_AT, b"EC1Y", r"location error name must be E<c>0<axis>"),
    (LOC_AT, b"EX0X", r"a linear axis has only angular location errors"),
    (LOC_AT + 8, struct.pack("<d", float("inf")), r"location error EC0X must be finite"),
    (THERMAL_AT, b" ", r"thermal sensor must be 1 to 16 printable ASCII"),
    (THERMAL_AT + 16, b"C\0\0\0", r"thermal record axis must be a linear axis name"),
    (THERMAL_AT + 16, b"Y\0\0\0", r"thermal record x_screw: axis Y is not a chain axis"),
    (THERMAL_AT + 20, b"\x03", r"thermal record kind must be 1 \(drift\) or 2"),
    (THERMAL_AT + 21, b"\x01", r"thermal record 0 at offset 316 has non-zero reserved"),
    (VALUES_AT + 4, struct.pack("<f", float("nan")), r"table EXX: value 1 at offset 368 is "
                                                     r"not finite"),
])
def test_corruption_is_refused_naming_the_field(at: int, raw: bytes, pattern: str) -> None:
    with pytest.raises(MapFormatError, match=pattern):
        decode_payload(_patch(TINY_BYTES, at, raw))


def test_assembler_takes_tables_maps_only_from_machines_that_announce_them() -> None:
    p = five_axis()
    data = encode_payload(p)
    verdicts = []
    for accepted in (FLOAT32 | MapEncoding.TABLES, FLOAT32, INT32 | MapEncoding.TABLES):
        asm = MapAssembler("5ax-04", accepted)
        for msg in split_into_chunks(data, 7, 1000):
            verdict = asm.feed(msg)
        verdicts.append(verdict)
    ok, no_tables, wrong_encoding = verdicts
    assert isinstance(ok, MapAccepted) and ok.payload == p
    assert isinstance(no_tables, MapRejected)
    assert no_tables.reason is MapRejectReason.UNSUPPORTED_ENCODING
    assert "tables map" in no_tables.text
    assert isinstance(wrong_encoding, MapRejected)
    assert wrong_encoding.reason is MapRejectReason.UNSUPPORTED_ENCODING


@pytest.mark.parametrize(("change", "pattern"), [
    ({"encoding": MapEncoding.TABLES}, r"must be INT32_INCREMENTS or FLOAT32_MM"),
    ({"encoding": INT32}, r"int32 map increment_mm must be in \(0, 1\]"),
    ({"axes": ()}, r"map axes must be a tuple of 1 to 16"),
    ({"axes": (X_AXIS, X_AXIS)}, r"map axes names 'X' twice"),
    ({"spindles": (Spindle("S", ("Y",), 0.0, (0.0, 0.0, 1.0)),)},
     r"spindle S names axis 'Y', not a chain axis"),
    ({"spindles": (Spindle("S", ("X",), 0.0, (0.0, 0.0, 1.0), (0.0,) * 6),)},
     r"weights are all zero"),
    ({"outputs": (OutputAxis("X"), OutputAxis("X"))}, r"map outputs names 'X' twice"),
    ({"tables": (ComponentTable("EXY", 0.0, 1.0, (1.0,)),)}, r"table EXY: Y is not a chain"),
    ({"locations": (("EC0X", 1.0), ("EC0X", 2.0))}, r"map locations names 'EC0X' twice"),
    ({"locations": (("EC0X", "1"),)}, r"location error EC0X must be a number"),
    ({"thermal": (ThermalRecord("s", "Z", 1, 1.0, 20.0),)}, r"axis Z is not a chain axis"),
    ({"limit_mm": 0.0}, r"map limit_mm must be > 0"),
    ({"tables": (ComponentTable("EXX", 0.0, 1e-3, (0.0,) * (MAX_MAP_BYTES // 4)),)},
     r"tables map needs \d+ bytes, limit 16777216"),
])
def test_construction_refuses_bad_fields(change: dict[str, object], pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        dataclasses.replace(TINY, **change)  # type: ignore[arg-type]


@pytest.mark.parametrize(("build", "pattern"), [
    (lambda: ChainAxis("C", True, False, (1.0, 0.0, 0.0)), r"direction must be \(0.0, 0.0, 1"),
    (lambda: ChainAxis("Z1", True, True, (0.0, 0.0, 1.0)), r"Z1 must be linear"),
    (lambda: ComponentTable("EXX", 0.0, 1.0, (1e39,)), r"does not fit a float32"),
    (lambda: ComponentTable("EXX", 0.0, -1.0, (1.0, 2.0)), r"step must be > 0"),
    (lambda: ComponentTable("EX0X", 0.0, 1.0, (1.0,)), r"ISO 230-1 component error"),
    (lambda: Spindle("two words", ("X",), 0.0, (0.0, 0.0, 1.0)), r"printable ASCII"),
    (lambda: ThermalRecord("s", "X", True, 1.0, 20.0), r"kind must be 1"),
])
def test_records_refuse_bad_fields(build: object, pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        build()  # type: ignore[operator]


def test_a_single_value_table_is_a_constant_with_any_step() -> None:
    t = ComponentTable("EXX", 5.0, 0.0, (2.0,))
    p = dataclasses.replace(TINY, tables=(t,))
    assert decode_payload(encode_payload(p)).tables == (t,)


values = st.floats(-1e4, 1e4, allow_nan=False, width=32)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("XYZABC"), st.floats(-500, 500),
                          st.floats(0.01, 100), st.lists(values, min_size=1, max_size=40)),
                max_size=6, unique_by=lambda t: t[0]),
       st.lists(st.floats(-1e3, 1e3), min_size=0, max_size=3))
def test_random_tables_round_trip(tables: list[tuple[str, float, float, list[float]]],
                                  locs: list[float]) -> None:
    p = dataclasses.replace(
        TINY, tables=tuple(ComponentTable(f"E{c}X", s, st_, tuple(v))
                           for c, s, st_, v in tables),
        locations=tuple((f"E{'ABC'[i]}0X", v) for i, v in enumerate(locs)))
    assert decode_payload(encode_payload(p)) == p
