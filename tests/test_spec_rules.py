"""Golden tests of the rules of protocol/README.md sections 6 and 13 that a from-spec PLC
program gets wrong first (issue 30, item 7), on ``tests/vectors/rules.json``:

* §6: the tie rule, temperatures in m°C from the exact double, held readings per sensor
  name (a sensor never read adds 0, an empty slot keeps the held one), ΔT clamped to
  ±2^17 m°C, the thermal constants recomputed at a swap, direction (+ at start-up, the
  sign of the last move) and the reversal added before the final clamp, rotary rounding
  from the nearest count on equal costs, the decode rules, axes matched by name;
* §13: the PLC's side of the window: temperature sequence 0, the slots' map version
  stamp, temp_refused, the sequence forgotten at a swap, WRONG_VERSION, state bits, the
  start-up re-check.

Each rule is checked on the simulated Fanuc PMC (``machine_sim``) and on the integer
implementation written from the README alone (``tests/support/factored_fromspec.py``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import random
import struct
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim import ladder
from machine_sim.fanuc import FanucPMC
from machine_sim.lookup import FactoredLadder
from machine_sim.plcmap import PlcMapProgram
from machine_sim.siemens import SD_ABS_VALUE, SiemensConfig, SiemensNC
from machine_sim.stplc import StPlc
from protocol import MapAck, MapReject, split_into_chunks
from protocol.codes import MapEncoding, MapRejectReason
from protocol.ctrlmem import (
    NO_TEMPERATURE,
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    Layout,
    State,
    decode_status,
    plan_map_write,
    plan_temperatures,
)
from protocol.mapfactored import decode_factored, milli_celsius
from protocol.mapformat import MapFormatError
from protocol.maptables import decode_payload
from server.mapcodec import factored_from_payload
from tests.support import factored_fromspec as spec
from tests.support import window_vector
from tests.support.stplc import write_map as st_write_map
from tests.support.stplc import write_temperatures as st_write_temperatures

VECTORS = Path(__file__).parent / "vectors"
RULES: dict[str, Any] = json.loads((VECTORS / "rules.json").read_text())
MAPS = {k: (VECTORS / v).read_bytes() for k, v in RULES["maps"].items()}
STEPS: list[dict[str, Any]] = RULES["steps"]
VERSIONS = {"A": 1, "B": 2}


# --- the vector itself: the figures the README's rules give by hand -------------------

def test_the_vector_holds_the_hand_computed_cases() -> None:
    """Worked by hand from §6 (so the vector cannot drift with the code that wrote it):
    C is a constant 2.5 counts with sensitivities 0, so every choice costs the same and
    the nearest count, halves up, wins: 3 (the old rule, floor first, gave 2); X is 8
    counts with reversal +5 and limit 10: negative, 13 clamped to 10 (reversal before
    the clamp); coolant at 25 °C against t_ref -150 °C: ΔT 175,000 m°C clamped to
    131,072, drift 2^20 · 131072 · 2^-16 = 2^21 in 2^-16 counts (unclamped it would be
    2,800,000: Z -67 counts, not -57)."""
    first = STEPS[0]
    assert first["direction"] == [1, 1, 1] and first["counts"] == [8, 0, 3]
    assert STEPS[1]["counts"][2] == 3 + 2  # C negative: its reversal 2
    assert STEPS[1]["c0"][1] == -(1 << 24) * 6000 >> 16
    clamp = STEPS[4]
    assert clamp["c0"][1] == STEPS[3]["c0"][1] - (1 << 21)
    assert clamp["counts"][1] == -57  # R(-3631931 + 122070, 16) = -54, reversal -3
    assert STEPS[5]["direction"][0] == -1 and STEPS[5]["counts"][0] == 10
    swap = STEPS[6]
    # B's spindle record (t_ref 21 °C, its slot 1, A's x_screw slot) at the held 26 °C,
    # air never read: 0; no x_screw record
    assert swap["c0"] == [0, (1 << 23) * 5000 >> 16, 0] and swap["c1"] == [0, 0, 0]
    assert swap["direction"] == STEPS[5]["direction"]  # a swap keeps the directions


# --- the simulated PMC against the scenario -------------------------------------------

def _feed(pmc: FanucPMC, data: bytes, version: int, now_s: float) -> MapAck | MapReject:
    reply = None
    for msg in split_into_chunks(data, version):
        reply = pmc.feed_map(msg, now_s)
    assert reply is not None
    return reply


def test_the_fanuc_pmc_runs_the_scenario() -> None:
    """Readings go into the PMC's held readings (a null slot: nothing stored), a swap
    builds the new map's constants from them, and the R shifts reach the vector's
    counts (at the step limit of §13.3, 5 counts per scan)."""
    pmc = FanucPMC("rules", ("X", "Z", "C"))
    now = 0.0
    for k, st in enumerate(STEPS):
        if "map" in st:
            assert isinstance(_feed(pmc, MAPS[st["map"]], VERSIONS[st["map"]], now), MapAck)
        for name, mc in st.get("readings_mC", {}).items():
            if mc is not None:
                assert pmc.temperatures.update(name, mc / 1000.0, now, "center")
        q = np.array(st["q_counts"], dtype=float) / 1000.0
        for _ in range(200):
            now += 0.008
            pmc.scan(now, q, np.array(st["direction"]))
        assert pmc.shifts().tolist() == st["counts"], f"step {k}: {st['note']}"
        assert not pmc.status & State.RAMPING
        m = pmc.store.active
        assert isinstance(m, FactoredLadder)
        assert m.c0.tolist() == st["c0"] and m.c1.tolist() == st["c1"]


def test_the_st_program_runs_the_scenario() -> None:
    """The compiled Structured Text program (``plc/``, written from the README by
    another hand) through its window: the maps switched in, the readings written to the
    slots in each map's record order (null: -2^31) stamped with its version, then scans
    at the step's positions (it tracks directions itself)."""
    plc = StPlc("rules", ("X", "Z", "C"), channel_limit=(1 << 30) - 1)
    plc.scan([0, 0, 0])
    seq = tseq = 0
    key = ""
    for k, st in enumerate(STEPS):
        q = st["q_counts"]
        if "map" in st:
            seq, key = seq + 1, st["map"]
            st_write_map(plc.window, plc.layout, 2 - seq % 2, MAPS[key], VERSIONS[key], seq)
            plc.scan(q)
        if "readings_mC" in st:
            tseq += 1
            sensors = list(dict.fromkeys(r.sensor for r in decode_factored(MAPS[key]).thermal))
            given = st["readings_mC"]
            st_write_temperatures(plc.window, [NO_TEMPERATURE if given.get(s) is None
                                               else given[s] for s in sensors],
                                  tseq, VERSIONS[key])
        for _ in range(200):
            plc.scan(q)
        assert plc.applied.tolist() == st["counts"], f"step {k}: {st['note']}"


def test_the_ladder_tracks_direction_by_moves() -> None:
    prev = np.zeros(3, dtype=np.int64)
    direction = np.ones(3, dtype=np.int64)  # start-up: positive
    for st in STEPS[1:]:
        q = np.array(st["q_counts"], dtype=np.int64)
        direction = ladder.directions(prev, q, direction)
        prev = q
        assert direction.tolist() == st["direction"]


def test_the_from_spec_implementation_runs_the_scenario() -> None:
    held: dict[str, int] = {}
    prev, direction = [0, 0, 0], [1, 1, 1]
    m = None
    for k, st in enumerate(STEPS):
        if "map" in st:
            m = spec.parse_factored(MAPS[st["map"]])
        held.update({n: v for n, v in st.get("readings_mC", {}).items() if v is not None})
        q = st["q_counts"]
        if k:
            direction = [(1 if b > a else -1) if b != a else d
                         for a, b, d in zip(prev, q, direction, strict=True)]
        prev = q
        assert m is not None
        assert list(spec.thermal_constants(m.records, 3, held)) == [st["c0"], st["c1"]]
        got = spec.factored_counts(m, q, held, [d < 0 for d in direction])
        assert got == st["counts"], f"step {k}: {st['note']}"


def test_the_centers_check_rounds_equal_costs_to_the_nearest_count() -> None:
    center = factored_from_payload(decode_factored(MAPS["A"]))
    assert center.applied_counts(np.zeros((1, 3))).tolist() == [STEPS[0]["counts"]]


# --- m°C ---------------------------------------------------------------------------

def _lreal_mc(c: float) -> int:
    """The README's exact method in LREAL (§6, Temperatures), step by step."""
    p = c * 1000.0
    n = math.floor(p + 0.5)
    h = c * 134217729.0
    ch = h - (h - c)
    cl = c - ch
    a, b = ch * 1000.0, cl * 1000.0
    if (a - (n - 0.5)) + b < 0:
        return n - 1
    if (a - (n + 0.5)) + b >= 0:
        return n + 1
    return n


@pytest.mark.parametrize("case", RULES["milli_celsius"], ids=lambda c: repr(c["celsius"]))
def test_milli_celsius_of_the_exact_double(case: dict[str, Any]) -> None:
    c = float.fromhex(case["celsius_hex"])
    assert c == case["celsius"]
    assert milli_celsius(c) == spec.millicelsius(c) == _lreal_mc(c) == case["mC"]
    slots = plan_temperatures([c], 1).data
    assert struct.unpack_from("<i", slots, 0)[0] == case["mC"]


def test_the_lreal_method_is_exact_where_doubles_are_not() -> None:
    """Readings with a 5 in the fourth decimal: the README's LREAL method equals the
    exact rounding on all of them, the naive ``floor(c · 1000 + 0.5)`` misses some."""
    rng = random.Random(30)
    naive_off = 0
    for _ in range(20_000):
        c = rng.randrange(-50_000, 150_000) / 1000.0 + 0.0005 * rng.choice((1, -1))
        exact = (Fraction(c) * 1000 + Fraction(1, 2)).__floor__()
        assert _lreal_mc(c) == exact == milli_celsius(c)
        naive_off += math.floor(c * 1000.0 + 0.5) != exact
    assert naive_off > 1000  # 7,101 of the 20,000 here


# --- decode rules ------------------------------------------------------------------

def _patched(data: bytes, at: int, fmt: str, value: int) -> bytes:
    out = bytearray(data)
    struct.pack_into(fmt, out, at, value)
    return bytes(out)


AXIS0 = 64
TERMS = 64 + 3 * 20  # no basis tables
THERMAL = TERMS + 2 * (8 + 2)


@pytest.mark.parametrize(("what", "at", "fmt", "value", "text"), [
    ("reversal with its flag clear", AXIS0 + 4, "<B", 0, "flagged absent"),
    ("flags bits 2-7", AXIS0 + 4, "<B", 0x06, "unknown flags"),
    ("axis names distinct", AXIS0 + 20, "<4s", int.from_bytes(b"X\0\0\0", "little"),
     "repeats"),
    ("a term's field below D + L x R (5 here)", TERMS, "<B", 5, "field 5"),
    ("a drift's q_min 0", THERMAL + 28, "<i", 7, "q_min 0"),
    ("|start| < 2^30", AXIS0 + 8, "<i", 1 << 30, "start"),
    ("|t_ref| < 2^30", THERMAL + 24, "<i", -(1 << 30), "t_ref"),
    ("expansion coefficient < 2^24", THERMAL + 32 + 20, "<i", 1 << 24, "expansion"),
])
def test_decode_rules_of_a_factored_map(what: str, at: int, fmt: str, value: int,
                                        text: str) -> None:
    data = MAPS["A"]
    assert decode_factored(data).axes[0].reversal == 5  # the unpatched map decodes
    if fmt == "<4s":
        bad = bytearray(data)
        bad[at:at + 4] = value.to_bytes(4, "little")
        patched = bytes(bad)
    else:
        patched = _patched(data, at, fmt, value)
    with pytest.raises(MapFormatError, match=text) as err:
        decode_payload(patched)
    assert "offset" in str(err.value), what


def test_decode_rules_of_a_grid_map() -> None:
    from protocol import ErrorMapPayload, GridAxis, OutputAxis, pack_values
    from protocol.mapformat import ThermalRecord, encode_map
    p = ErrorMapPayload("g", 1, MapEncoding.INT32_INCREMENTS, (GridAxis("X", 0.0, 1.0, 2),),
                        (OutputAxis("X", 3), OutputAxis("Y")),
                        pack_values(MapEncoding.INT32_INCREMENTS, [1, 2, 3, 4]), 0.001)
    data = encode_map(p)
    out0 = 64 + 24
    with pytest.raises(MapFormatError, match="flagged absent"):
        decode_payload(_patched(data, out0 + 4, "<B", 0))  # reversal 3, flag cleared
    twice = bytearray(data)
    twice[out0 + 12:out0 + 16] = b"X\0\0\0"
    with pytest.raises(MapFormatError, match="'X' twice"):
        decode_payload(bytes(twice))
    with pytest.raises(ValueError, match="q_min 0"):
        ThermalRecord("spindle", "Z", 1, -2.5, 20.0, 5.0)
    # the ranges of section 6 after the loader's conversion (int32 grids)
    far = dataclasses.replace(p, grid=(GridAxis("X", 2_000_000.0, 1.0, 2),))
    with pytest.raises(MapFormatError, match="offset 72: start 2000000000"):
        decode_payload(encode_map(far))
    hot = dataclasses.replace(p, thermal=(ThermalRecord("x", "X", 2, 100.0, 20.0, 0.0),))
    with pytest.raises(MapFormatError, match=r"thermal record 0 at offset \d+: .*expansion"):
        decode_payload(encode_map(hot))
    ok = dataclasses.replace(p, thermal=(ThermalRecord("x", "X", 2, 11.5, 20.0, 0.0),))
    assert decode_payload(encode_map(ok)) == ok


# --- axes matched by name ----------------------------------------------------------

def test_axes_are_matched_by_name_not_by_place() -> None:
    """A machine whose axes come in another order, with one more, takes the map (C, X,
    Z found by name) and applies the same counts to the same axes; a map naming an axis
    the machine lacks is APPLY_FAILED naming it."""
    pmc = FanucPMC("rules", ("C", "Y", "Z", "X"))
    assert isinstance(_feed(pmc, MAPS["A"], 1, 0.0), MapAck)
    for t in range(10):
        pmc.scan(0.008 * t, np.zeros(4))
    assert pmc.shifts().tolist() == [3, 0, 0, 8]  # C 3, Y nothing, Z 0, X 8
    other = FanucPMC("rules", ("X", "Y", "Z"))
    reply = _feed(other, MAPS["A"], 1, 0.0)
    assert isinstance(reply, MapReject) and reply.reason == MapRejectReason.APPLY_FAILED
    assert "'C'" in reply.text


# --- the PLC program's side of the window (§13) -------------------------------------

class _Plc:
    """A Fanuc PMC and its map handling over one window, driven scan by scan."""

    def __init__(self) -> None:
        self.layout = Layout(1024)
        self.window = bytearray(self.layout.size)
        self.pmc = FanucPMC("rules", ("X", "Z", "C"))
        self.plc = PlcMapProgram(self.window, self.layout, self.pmc,
                                 formats=self.pmc.store.assembler.accepted)
        self.plc.boot(0.0, "rules")
        self.now = 0.0
        self.seq = 0

    def scan(self, n: int = 1) -> None:
        for _ in range(n):
            self.now += 0.008
            applied = self.pmc.scan(self.now, np.zeros(3))
            self.plc.scan(self.now, np.zeros(3), np.asarray(applied, dtype=np.float64) * 0.001)

    def push(self, key: str, version: int, buffer: int, *,
             header_version: int | None = None) -> None:
        self.seq += 1
        for w in plan_map_write(self.layout, buffer, MAPS[key],
                                version if header_version is None else header_version,
                                self.seq):
            self.window[w.offset:w.offset + len(w.data)] = w.data
        self.scan()

    def slots(self, celsius: list[float | None], seq: int, version: int = 0) -> None:
        w = plan_temperatures(celsius, seq, map_version=version)
        self.window[w.offset:w.offset + len(w.data)] = w.data
        self.scan()

    def status(self) -> Any:
        return decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE], 3)

    def held(self) -> dict[str, float]:
        return {k: r.celsius for k, r in self.pmc.temperatures.readings().items()}


def test_the_plc_takes_slots_by_sequence_and_stamp_and_holds_readings() -> None:
    plc = _Plc()
    plc.push("A", 1, 1)
    st = plc.status()
    assert (st.ack_code, st.active, st.applied_version) == (0, 1, 1)
    assert st.state & State.MAP_IN_USE
    # A's slots: 0 spindle, 1 x_screw. Sequence 0: nothing written yet, nothing taken
    w = plan_temperatures([26.0, 25.0], 1)
    plc.window[w.offset:w.offset + len(w.data)] = w.data
    struct.pack_into("<H", plc.window, 384, 0)
    plc.scan()
    assert plc.held() == {} and plc.status().temp_ack == 0
    # stamped for map version 7, not the one in use: not taken
    plc.slots([26.0, 25.0], 2, version=7)
    assert plc.held() == {} and plc.status().temp_ack == 0
    plc.slots([26.0, None], 3, version=1)
    assert plc.held() == {"spindle": 26.0} and plc.status().temp_ack == 3
    # -2^31 keeps spindle's reading; 150 °C is refused by the screen: bit 1, held stays
    plc.slots([None, 150.0], 4)
    st = plc.status()
    assert plc.held() == {"spindle": 26.0} and (st.temp_ack, st.temp_refused) == (4, 0b10)
    plc.slots([None, 25.0], 5)
    assert plc.held() == {"spindle": 26.0, "x_screw": 25.0}
    assert plc.status().temp_refused == 0
    # the same sequence again is not taken again
    struct.pack_into("<i", plc.window, 256, 30000)
    plc.scan()
    assert plc.held()["spindle"] == 26.0


def test_a_swap_keeps_held_readings_and_forgets_the_sequence() -> None:
    plc = _Plc()
    plc.push("A", 1, 1)
    plc.slots([26.0, 25.0], 9, version=1)
    plc.push("B", 2, 2)
    st = plc.status()
    assert (st.ack_code, st.active, st.applied_version) == (0, 2, 2)
    m = plc.pmc.store.active
    # B's spindle record (t_ref 21 °C) at the held 26 °C
    assert isinstance(m, FactoredLadder) and m.c0.tolist()[1] == (1 << 23) * 5000 >> 16
    assert plc.status().temp_ack == 0  # none taken for B yet
    # B's slots (0 air, 1 spindle) with the sequence A's last had, stamped for B: taken,
    # since the swap forgot the sequence; A's stamp would not be
    plc.slots([19.0, None], 9, version=1)
    assert "air" not in plc.held() and plc.status().temp_ack == 0
    plc.slots([19.0, None], 9, version=2)
    assert plc.held()["air"] == 19.0 and plc.status().temp_ack == 9
    assert plc.held()["spindle"] == 26.0


def test_header_map_version_differing_from_the_payloads_is_wrong_version() -> None:
    plc = _Plc()
    plc.push("A", 1, 1, header_version=3)
    st = plc.status()
    assert (st.ack_seq, st.ack_code, st.active) == (1, MapRejectReason.WRONG_VERSION, 0)


def test_start_up_checks_the_active_buffer_again() -> None:
    plc = _Plc()
    plc.push("A", 1, 1)
    plc.scan()
    st = plc.status()  # the step limit: 5 counts per scan, X short of its 8
    assert st.state & State.RAMPING and st.applied == (5, 0, 3)
    plc.scan(5)
    st = plc.status()
    assert not st.state & State.RAMPING and st.applied == (8, 0, 3)
    # a restart: the window stays, the program's state is gone; the buffer still checks
    pmc = FanucPMC("rules", ("X", "Z", "C"))
    again = PlcMapProgram(plc.window, plc.layout, pmc, formats=pmc.store.assembler.accepted)
    again.boot(1.0, "rules")
    assert pmc.store.version == 1 and plc.status().active == 1
    assert pmc.shifts().tolist() == [0, 0, 0]  # applied corrections start at 0
    # the buffer torn meanwhile: applied again it is not, active 0
    at = plc.layout.buffer_at(1) + 32 + 70
    plc.window[at] ^= 0xFF
    pmc2 = FanucPMC("rules", ("X", "Z", "C"))
    third = PlcMapProgram(plc.window, plc.layout, pmc2, formats=pmc2.store.assembler.accepted)
    third.boot(2.0, "rules")
    assert pmc2.store.version == 0 and plc.status().active == 0
    (word,) = struct.unpack_from("<H", plc.window, SWITCH_AT)
    assert plc.status().ack_seq == word >> 2  # ack_seq taken from the status


def test_slot_values_are_milli_celsius_and_empty_slots_no_reading() -> None:
    w = plan_temperatures([None, 20.0005], 1)
    assert struct.unpack_from("<2i", w.data, 0) == (NO_TEMPERATURE, 20000)


# --- the window vector: every ack code, the take rules, start-up -------------------

@pytest.mark.parametrize("run", [window_vector.run_python, window_vector.run_st],
                         ids=["python-plc", "st-program"])
def test_the_window_vector(run: Any) -> None:
    """``tests/vectors/window.json`` on the Python PLC and on the compiled Structured
    Text program: 23 steps, each ack code of §13.1 (0, 3, 4, 5, 6 five ways, 7, 8, 10, 11,
    100, 101), the temperature take rules and two power cycles."""
    vector = window_vector.load()
    got = run(vector)
    want = [s["expect"] for s in vector["steps"]]
    for k, (g, w) in enumerate(zip(got, want, strict=True)):
        assert g == w, f"step {k}: {vector['steps'][k]['note']}"
    codes = {s["expect"]["ack_code"] for s in vector["steps"]}
    assert codes == {0, 3, 4, 5, 6, 7, 8, 10, 11, 100, 101}


def test_a_siemens_nc_clamps_after_the_reversal() -> None:
    """A float32 grid (Siemens-style) of 0.3 mm with a reversal of 0.3 mm on a channel
    of ±0.5 mm: while X's direction is negative the PLC writes 0.5 to SD43900 (0.6
    clamped), no range alarm; positive again, 0.3."""
    from protocol import ErrorMapPayload, GridAxis, OutputAxis, encode_payload, pack_values
    nc = SiemensNC("s", ("X",), SiemensConfig(limit_mm=0.5))
    p = ErrorMapPayload("s", 1, MapEncoding.FLOAT32_MM, (GridAxis("X", 0.0, 1.0, 2),),
                        (OutputAxis("X", 0.3),),
                        pack_values(MapEncoding.FLOAT32_MM, [0.3, 0.3]), 0.0)
    for msg in split_into_chunks(encode_payload(p), 1):
        reply = nc.feed_map(msg, 0.0)
    assert isinstance(reply, MapAck)
    for direction, want in ((-1, 0.5), (1, 0.3)):
        for k in range(4):
            nc.ipo_cycle(0.004 * k, np.zeros(1), np.array([direction]))
        assert nc.read_sd(SD_ABS_VALUE, "X") == pytest.approx(want, abs=1e-7)
        assert not nc.alarms
