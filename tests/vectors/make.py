"""Writes the test vectors of protocol/README.md section 6 (run from the repository root):

    PYTHONPATH=. .venv/bin/python tests/vectors/make.py [NAME ...]   # all, or: tables

Each ``<name>.bin`` is a map payload as the machine receives it; ``<name>.json`` gives the
temperatures, the points (in mm or degrees and in counts), the approach direction of each
axis and the counts the Fanuc-style ladder writes there (``machine_sim/ladder.py``). The
files are committed; this script is how they were made (``README.md`` here says what each
holds). Regenerate only when the format or its arithmetic changes on purpose.
"""

from __future__ import annotations

import json
import struct
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.map_build import TRUNNION, errors  # noqa: E402
from machine_sim import ladder  # noqa: E402
from machine_sim.lookup import FactoredLadder, GridLadder, positions_in_counts  # noqa: E402
from protocol import ErrorMapPayload, GridAxis, MapEncoding, OutputAxis, pack_values  # noqa: E402
from protocol.ctrlmem import (  # noqa: E402
    NO_TEMPERATURE,
    SWITCH_AT,
    BufferHeader,
    Layout,
    encode_buffer_header,
    plan_map_write,
)
from protocol.mapfactored import (  # noqa: E402
    FactoredAxis,
    FactoredPayload,
    FactoredThermal,
    TermTable,
    decode_factored,
    encode_factored,
    milli_celsius,
)
from protocol.mapformat import decode_map, encode_map  # noqa: E402
from server.mapcodec import encode  # noqa: E402
from volumetric.compensate.factoredmap import build_factored_map  # noqa: E402
from volumetric.compensate.gridmap import build_map  # noqa: E402
from volumetric.model.machine import parse_machine  # noqa: E402
from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm  # noqa: E402

HERE = Path(__file__).resolve().parent
VMC = {"name": "vmc-v", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}
THERMAL = (ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 20.0),
           ThermalTerm("thermal_expansion", "x", "T_x_screw_C", 11.5, 20.0, 0.0))
TEMPERATURES = {"spindle": 26.35, "x_screw": 23.8}


def _points(lo: np.ndarray, hi: np.ndarray, rng: np.random.Generator, n: int) -> np.ndarray:
    """Random points in the travel, the travel's corners and centre, and a few just
    outside it (the ladder holds the end values), rounded to whole µm (µ°)."""
    inside = lo + (hi - lo) * rng.random((n, lo.size))
    corners = np.array([lo, hi, 0.5 * (lo + hi)])
    outside = np.array([lo - 5.0, hi + 5.0])
    return np.round(np.vstack([inside, corners, outside]), 3)


def _write(name: str, payload: bytes, axes: list[str], per_unit: int,
           q: np.ndarray, counts_of: object, reversal: np.ndarray, kind: str,
           note: str, travel: dict[str, list[float]],
           temperatures: dict[str, float] | None = None) -> None:
    temps = TEMPERATURES if temperatures is None else temperatures
    rng = np.random.default_rng(7)
    qc = positions_in_counts(q, per_unit)
    positive = counts_of(q)  # type: ignore[operator]
    points = []
    for n in range(q.shape[0]):
        points.append({"q": dict(zip(axes, q[n].tolist(), strict=True)),
                       "q_counts": qc[n].tolist(), "negative": [False] * len(axes),
                       "counts": positive[n].tolist()})
        neg = rng.random(len(axes)) < 0.5
        if neg.any():
            points.append({"q": dict(zip(axes, q[n].tolist(), strict=True)),
                           "q_counts": qc[n].tolist(), "negative": neg.tolist(),
                           "counts": (positive[n] + np.where(neg, reversal, 0)).tolist()})
    (HERE / f"{name}.bin").write_bytes(payload)
    body = {"map": f"{name}.bin", "kind": kind, "note": note, "counts_per_unit": per_unit,
            "axes": axes, "travel": travel, "temperatures_C": temps,
            "temperatures_mC": {k: round(v * 1000) for k, v in temps.items()},
            "points": points}
    (HERE / f"{name}.json").write_text(json.dumps(body, indent=1) + "\n")


def _travel(m: object) -> dict[str, list[float]]:
    return {a.name.upper(): [float(a.travel[0]), float(a.travel[1])]
            for a in m.axes}  # type: ignore[attr-defined]


def factored() -> None:
    m = parse_machine({**TRUNNION, "name": "trunnion-v", "controller": "fanuc"})
    geo = errors(m, np.random.default_rng(2024), 5.0)
    model = MachineModel(m.name, geo, (*THERMAL, BacklashTerm("x", 6.0),
                                       BacklashTerm("c", 4.0)))
    fm = build_factored_map(m, model, tolerance_um=1.0)
    payload = encode(fm)
    p = decode_factored(payload)
    lad = FactoredLadder(p, TEMPERATURES)
    axes = [a.name for a in p.axes]
    q = _points(m.travel_lo, m.travel_hi, np.random.default_rng(1), 40)
    _write("factored_5axis", payload, axes, p.counts_per_unit, q, lad.counts,
           lad.program.reversal, "factored",
           "a 5-axis trunnion (w C A X Y b Z t), two thermal records, reversal on X and C",
           _travel(m))


def grid() -> None:
    m = parse_machine({**VMC, "controller": "fanuc"})
    geo = errors(m, np.random.default_rng(2031), 5.0)
    model = MachineModel(m.name, geo, (*THERMAL, BacklashTerm("y", 5.0)))
    from server.mapcodec import grid_to_payload
    emap = build_map(m, model, tolerance_um=1.0, controller="fanuc", thermal_in_map=True)
    payload = encode_map(grid_to_payload(emap))
    p = decode_map(payload)
    g = GridLadder.from_payload(p, TEMPERATURES)
    axes = list(g.inputs)
    q = _points(m.travel_lo, m.travel_hi, np.random.default_rng(2), 40)
    _write("grid_3axis", payload, axes, g.per_unit, q, g.counts,
           g.program.reversal if g.program is not None else np.zeros(3, dtype=np.int64),
           "grid", "a 3-axis int32 grid with thermal records (format version 3)", _travel(m))


def grid_ties() -> None:
    """A 2 x 2 grid whose interpolation lands exactly on half counts: the tie rule."""
    values = [0, 1, -1, 0,   # node (0, 0): X 0, Y 1; node (0, 1): X -1, Y 0
              1, 2, 0, -3]   # node (1, 0): X 1, Y 2; node (1, 1): X 0, Y -3
    p = ErrorMapPayload("ties", 1, MapEncoding.INT32_INCREMENTS,
                        (GridAxis("X", 0.0, 0.002, 2), GridAxis("Y", 0.0, 0.002, 2)),
                        (OutputAxis("X", 2), OutputAxis("Y")),
                        pack_values(MapEncoding.INT32_INCREMENTS, values), 0.001)
    payload = encode_map(p)
    g = GridLadder.from_payload(decode_map(payload))
    q = np.array([[0.001, 0.0], [0.0, 0.001], [0.001, 0.001], [0.002, 0.001],
                  [0.001, 0.002], [0.0005, 0.0015], [-1.0, 9.0]])
    _write("grid_ties", payload, ["X", "Y"], 1000, q, g.counts, g.program.reversal
           if g.program is not None else np.zeros(2, dtype=np.int64), "grid",
           "half-count ties: 0.5 -> 1, -0.5 -> 0, 1.5 -> 2, -1.5 -> -1 (halves up)",
           {"X": [0.0, 0.002], "Y": [0.0, 0.002]}, {})


NO_READING = None
"""A step's reading of ``null``: nothing to say for that sensor (slot -2^31): held."""


def _rules_map(version: int, thermal: tuple[FactoredThermal, ...]) -> FactoredPayload:
    """Axes X, Z (linear) and C (rotary): constant terms X = 8 counts (limit 10, reversal
    +5: the clamp order), C = 2.5 counts (sensitivities 0: equal costs, the nearest count
    3); Z only thermal (limit 400, reversal -3)."""
    axes = (FactoredAxis("X", False, 5, 10, 1, 0, 0),
            FactoredAxis("Z", False, -3, 400, 1, 0, 0),
            FactoredAxis("C", True, 2, 400, 1, 0, 0))
    terms = (TermTable(0, 0, 0, (), (8,)),     # 8 · 2^15 · 2^1 = 8 counts in 2^-16
             TermTable(2, 2, -1, (), (5,)))    # 5 · 2^15 · 2^0 = 2.5 counts
    return FactoredPayload("rules", version, 0, 1000, axes, (), terms, thermal)


RULES_A = (FactoredThermal("spindle", 1, 1, 1 << 24, 20000),          # drift of Z
           FactoredThermal("x_screw", 1, 2, 1 << 20, 20000, 1000),    # expansion of Z
           # t_ref -150 °C: a reading in any plausible range is beyond ΔT's clamp
           FactoredThermal("coolant", 1, 1, 1 << 20, -150000))
# B names air first: its slot 0 is air, slot 1 spindle (A's slot 1 was x_screw): held
# readings belong to sensor names, not to slots
RULES_B = (FactoredThermal("air", 0, 1, 1 << 26, 20000),              # never read yet
           FactoredThermal("spindle", 1, 1, -(1 << 23), 21000))


def rules() -> None:
    """``rules.json``: one scenario through two factored maps that pins the rules of
    section 6 a PLC program gets wrong first: held readings per sensor name, a sensor
    never read adding 0, ΔT clamped to ±2^17 m°C, the thermal constants recomputed at a
    swap, direction (+ at start-up, the sign of the last move, kept by a scan without a
    move and across a swap), the reversal before the final clamp, and rotary rounding
    from the nearest count on equal costs; then temperatures in m°C from the exact
    double."""
    maps = {"A": _rules_map(1, RULES_A), "B": _rules_map(2, RULES_B)}
    for key, p in maps.items():
        (HERE / f"rules_{key.lower()}.bin").write_bytes(encode_factored(p))
    steps: list[dict[str, object]] = [
        {"note": "start-up: no reading yet, every direction positive", "map": "A",
         "q_counts": [0, 0, 0]},
        {"note": "spindle read (ΔT 6 K); x_screw never read adds 0; C moved negative",
         "readings_mC": {"spindle": 26000}, "q_counts": [0, 0, -1000]},
        {"note": "x_screw read, spindle's slot empty (-2^31): spindle's reading is held; "
                 "Z moved negative",
         "readings_mC": {"spindle": NO_READING, "x_screw": 25000},
         "q_counts": [0, -100000, -1000]},
        {"note": "no move: directions kept; X moves positive", "q_counts": [5, -100000, -1000]},
        {"note": "coolant read, 25 °C against t_ref -150 °C: ΔT 175 K clamped to "
                 "131.072 K", "readings_mC": {"coolant": 25000},
         "q_counts": [5, -100000, -1000]},
        {"note": "X moved negative: 8 + 5 = 13 counts clamped to its limit 10",
         "q_counts": [-7, -100000, -1000]},
        {"note": "swap to B: constants from B's records and the held readings (spindle "
                 "26000; air never read: 0); directions kept", "map": "B",
         "q_counts": [-7, -100000, -1000]},
        {"note": "air read; C moves positive again", "readings_mC": {"air": 19000},
         "q_counts": [-7, -100000, 2000]},
    ]
    held: dict[str, int] = {}
    prog = None
    prev = np.zeros(3, dtype=np.int64)
    direction = np.ones(3, dtype=np.int64)
    for k, st in enumerate(steps):
        if "map" in st:
            prog = ladder.factored_program(maps[str(st["map"])])
        for name, v in dict(st.get("readings_mC", {})).items():  # type: ignore[call-overload]
            if v is not NO_READING:
                held[name] = int(v)
        assert prog is not None
        q = np.array(st["q_counts"], dtype=np.int64)
        if k:
            direction = ladder.directions(prev, q, direction)
        prev = q
        c0, c1 = ladder.thermal_constants(prog.thermal, 3, held)
        st["direction"] = direction.tolist()
        st["c0"], st["c1"] = c0.tolist(), c1.tolist()
        st["counts"] = ladder.factored_counts(prog, q[None, :], c0, c1,
                                              (direction < 0)[None, :])[0].tolist()
    celsius = [20.0005, -0.0015, 21.2345, 26.35, 0.0005, -0.0005, 99.9995, 23.8,
               12.3455, -273.15]
    body = {
        "note": "a scenario a PLC program runs scan by scan (see README.md); each step's "
                "readings are what the slots carry (null: -2^31, nothing to say), then "
                "the commanded positions; expected: direction (+1/-1), the thermal "
                "constants c0 (2^-16 counts) and c1 (2^-32 counts per count) per axis, "
                "and the counts written",
        "maps": {k: f"rules_{k.lower()}.bin" for k in maps}, "axes": ["X", "Z", "C"],
        "steps": steps,
        "milli_celsius": [{"celsius": c, "celsius_hex": c.hex(), "mC": milli_celsius(c)}
                          for c in celsius],
    }
    (HERE / "rules.json").write_text(json.dumps(body, indent=1) + "\n")


def window() -> None:
    """``window.json``: the PLC's side of the window (§13.3), step by step: the center's
    writes (byte offset and hex, the window's own byte order), then scans, then what the
    status must say. Every ack code a switch can get, the temperature take rules, and a
    start-up with the active buffer intact and torn. Each expectation is written here by
    hand and checked against the Python PLC before the file is written."""
    from tests.support.window_vector import run_python

    cap = 16_384
    layout = Layout(cap)
    a, b = (HERE / "rules_a.bin").read_bytes(), (HERE / "rules_b.bin").read_bytes()
    seq = 0
    steps: list[dict[str, object]] = []

    def w(offset: int, data: bytes) -> dict[str, object]:
        return {"offset": offset, "hex": data.hex()}

    def patched(data: bytes, at: int, raw: bytes) -> bytes:
        return data[:at] + raw + data[at + len(raw):]

    def switch(payload: bytes, version: int, buffer: int, note: str, code: int,
               after: list[dict[str, object]] | None = None) -> dict[str, object]:
        nonlocal seq
        seq += 1
        writes = [w(x.offset, x.data) for x in plan_map_write(layout, buffer, payload,
                                                               version, seq)]
        if after:  # changed after the header, before the switch word
            writes[-1:-1] = after
        return {"note": note, "writes": writes, "code": code, "seq": seq}

    def expect(step: dict[str, object], active: int, version: int, temp_ack: int = 0,
               refused: int = 0) -> dict[str, object]:
        code = int(step.pop("code"))  # type: ignore[call-overload]
        step["expect"] = {"ack_seq": step.pop("seq"), "ack_code": code, "active": active,
                          "applied_version": version, "temp_ack": temp_ack,
                          "temp_refused": refused, "map_in_use": int(version > 0)}
        return step

    steps.append({"note": "start-up, an empty window: nothing handled, no map",
                  "expect": {"ack_seq": 0, "ack_code": 0, "active": 0, "applied_version": 0,
                             "temp_ack": 0, "temp_refused": 0, "map_in_use": 0}})
    steps.append(expect(switch(a, 1, 1, "map A (version 1) into buffer 1: applied", 0), 1, 1))
    b2 = layout.buffer_at(2)
    steps.append(expect(switch(b, 2, 2, "B with a payload byte changed after its header: "
                               "CHECKSUM_MISMATCH", 4,
                               [w(b2 + 32 + 100, bytes([b[100] ^ 0xFF, b[101]]))]), 1, 1))
    steps.append(expect(switch(b, 2, 2, "B's header torn (its map version changed, the "
                               "header CRC not): code 100", 100,
                               [w(b2 + 8, b"\x09\x00")]), 1, 1))
    steps.append(expect(switch(b, 3, 2, "B under a header saying map version 3, the "
                               "payload 2: WRONG_VERSION", 5), 1, 1))
    big = encode_buffer_header(BufferHeader(5, 2, cap + 2, 0))
    st = switch(b, 2, 2, "a header whose length exceeds the capacity: WRONG_SIZE", 3,
                [w(b2, big)])
    steps.append(expect(st, 1, 1))
    seq += 1
    steps.append({"note": "a switch word naming buffer 3: code 101",
                  "writes": [w(SWITCH_AT, struct.pack("<H", seq << 2 | 3))],
                  "expect": {"ack_seq": seq, "ack_code": 101, "active": 1,
                             "applied_version": 1, "temp_ack": 0, "temp_refused": 0,
                             "map_in_use": 1}})
    for what, at, raw in (
            ("an axis with its reversal flag clear and a reversal", 68, b"\x00"),
            ("a drift record with q_min 7", 144 + 28, struct.pack("<i", 7)),
            ("two axes named X", 84, b"X\0\0\0"),
            ("a term adding to field 5 of 5 (D + L x R)", 124, b"\x05"),
            ("an axis start of 2^30 counts", 72, struct.pack("<i", 1 << 30))):
        steps.append(expect(switch(patched(b, at, raw), 2, 2,
                                   f"B with {what}: DECODE_ERROR", 6), 1, 1))
    other = patched(b, 16, b"other".ljust(32, b"\0"))
    steps.append(expect(switch(other, 2, 2, "B naming machine 'other': WRONG_MACHINE", 7),
                        1, 1))
    y_axis = patched(b, 84, b"Y\0\0\0")
    steps.append(expect(switch(y_axis, 2, 2, "B with axis Y, which the machine lacks (axes "
                               "are matched by name): APPLY_FAILED", 11), 1, 1))
    f32 = encode_map(ErrorMapPayload("rules", 2, MapEncoding.FLOAT32_MM,
                                     (GridAxis("X", 0.0, 1.0, 2),), (OutputAxis("X"),),
                                     pack_values(MapEncoding.FLOAT32_MM, [0.0, 0.001]), 0.0))
    steps.append(expect(switch(f32, 2, 2, "a float32 grid map: UNSUPPORTED_ENCODING", 8),
                        1, 1))
    steps.append(expect(switch(b, 2, 2, "map B (version 2) into buffer 2: applied", 0), 2, 2))
    steps.append(expect(switch(a, 1, 1, "map A (version 1) again: STALE_VERSION", 10), 2, 2))
    slot_at = 256

    def slots(values: list[int | None], tseq: int, version: int) -> list[dict[str, object]]:
        raw = [NO_TEMPERATURE if v is None else v for v in values]
        raw += [NO_TEMPERATURE] * (32 - len(raw))
        return [w(slot_at, struct.pack("<32i", *raw)), w(388, struct.pack("<I", version)),
                w(384, struct.pack("<H", tseq))]

    base = {"ack_seq": seq, "ack_code": 10, "active": 2, "applied_version": 2,
            "map_in_use": 1}
    steps.append({"note": "slots with sequence 0: not taken", "writes": slots([19000], 0, 2),
                  "expect": {**base, "temp_ack": 0, "temp_refused": 0}})
    steps.append({"note": "slots stamped with map version 1, not the one in use: not taken",
                  "writes": slots([19000, 26000], 1, 1),
                  "expect": {**base, "temp_ack": 0, "temp_refused": 0}})
    steps.append({"note": "slots stamped 2 (B: slot 0 air, 1 spindle): taken",
                  "writes": slots([19000, 26000], 2, 2),
                  "expect": {**base, "temp_ack": 2, "temp_refused": 0}})
    steps.append({"note": "stamp 0 (the map in use); slot 0 -2^31 (air's reading held), "
                          "slot 1 150 °C: refused by a screen whose plausible range ends "
                          "at 100 °C (spindle's reading held)",
                  "writes": slots([None, 150000], 3, 0),
                  "expect": {**base, "temp_ack": 3, "temp_refused": 2}})
    steps.append({"note": "a power cycle: the window is nonvolatile; the program takes "
                          "ack_seq from the status, checks the active buffer again and "
                          "applies it, and takes the slots the window holds (sequence 3, "
                          "forgotten at start-up)", "restart": True,
                  "expect": {**base, "temp_ack": 3, "temp_refused": 2}})
    torn = layout.buffer_at(2) + 32 + 100
    steps.append({"note": "a power cycle with the active buffer's payload changed: it no "
                          "longer checks out, so no map (active 0) until the center "
                          "switches; the slots (stamp 0: the map in use, none) are taken "
                          "with nothing to apply them to", "restart": True,
                  "writes": [w(torn, bytes([b[100] ^ 0xFF, b[101]]))],
                  "expect": {**base, "active": 0, "applied_version": 0, "map_in_use": 0,
                             "temp_ack": 3, "temp_refused": 0}})
    body: dict[str, object] = {
        "note": "the PLC side of section 13.3 (see README.md): apply each step's writes "
                "(offset: window byte, hex: the bytes), restart the program if the "
                "step says restart (the window keeps its bytes), scan twice, compare the "
                "status",
        "machine": "rules", "axes": ["X", "Z", "C"], "capacity": cap,
        "maps": {"A": "rules_a.bin", "B": "rules_b.bin"}, "steps": steps}
    got = run_python(body)
    for k, (step, status) in enumerate(zip(steps, got, strict=True)):
        assert status == step["expect"], (k, step["note"], status, step["expect"])
    (HERE / "window.json").write_text(json.dumps(body, indent=1) + "\n")


def tables() -> None:
    """The factored vector's machine and errors as a tables map (format version 2), the
    center's build re-encoded in int32 counts of 0.001 mm (the center sends tables maps
    as float32; a PLC writing counts to its NC takes them as int32): the counts are
    ``ednc lookup``'s (machine_sim/chaineval.py), rounded half up."""
    from dataclasses import replace

    from machine_sim.lookup import TablesMap
    from protocol import OutputAxis as Out
    from protocol.maptables import decode_tables, encode_tables
    from server.mapcodec import build_for
    m = parse_machine({**TRUNNION, "name": "trunnion-t", "controller": "fanuc"})
    geo = errors(m, np.random.default_rng(2024), 5.0)
    model = MachineModel(m.name, geo, (*THERMAL, BacklashTerm("x", 6.0),
                                       BacklashTerm("y", 4.0)))  # rotary: not in tables
    built = decode_tables(encode(build_for(m, model, None, kind="tables", tolerance_um=0.5,
                                           formats=MapEncoding.FLOAT32_MM
                                           | MapEncoding.TABLES)))
    p = replace(built, encoding=MapEncoding.INT32_INCREMENTS, increment_mm=0.001,
                outputs=tuple(Out(o.name, None if o.reversal is None
                                  else round(o.reversal / 0.001)) for o in built.outputs))
    payload = encode_tables(p)
    tm = TablesMap.from_payload(decode_tables(payload), TEMPERATURES)
    axes = list(tm.grid)
    reversal = np.array([0 if o.reversal is None else o.reversal for o in p.outputs])
    q = _points(m.travel_lo, m.travel_hi, np.random.default_rng(3), 40)
    order = [m.axis_names.index(a.lower()) if a.lower() in m.axis_names
             else m.axis_names.index(a) for a in axes]
    q = q[:, order]
    _write("tables_5axis", payload, axes, 1000, q,
           lambda x: np.rint(tm.lookup(x) / 0.001).astype(np.int64), reversal, "tables",
           "the factored vector's 5-axis trunnion as an int32 tables map, two thermal "
           "records, reversal on X and Y", {a: _travel(m)[a] for a in axes})


def main() -> None:
    makers = {"factored": factored, "grid": grid, "grid_ties": grid_ties, "rules": rules,
              "window": window, "tables": tables}
    for name in sys.argv[1:] or list(makers):
        makers[name]()


if __name__ == "__main__":
    main()
