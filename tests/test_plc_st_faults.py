"""The fault table of protocol/README.md §13 with the compiled Structured Text program
and with the Python PLC (machine_sim/plcmap.py over the Fanuc-style ladder) side by side:
the same window writes reach both, and after every scan both report the same verdict
(ack_seq, ack_code), the same active buffer, the same applied map version and the same
temperature sequence taken. Never a mixed map: the applied version is always one whose
every byte checked out."""

from __future__ import annotations

import struct
import zlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from machine_sim.fanuc import FanucConfig, FanucPMC
from machine_sim.plcmap import PlcMapProgram
from machine_sim.stplc import StPlc
from protocol.codes import MapEncoding
from protocol.ctrlmem import (
    SWITCH_AT,
    BufferHeader,
    Write,
    encode_buffer_header,
    plan_map_write,
    plan_temperatures,
)
from protocol.mapfactored import decode_factored
from tests.support.stplc import status, write_all

VECTORS = Path(__file__).parent / "vectors"
MAP = (VECTORS / "factored_5axis.bin").read_bytes()
P = decode_factored(MAP)
AXES = [a.name for a in P.axes]


def version(payload: bytes, v: int) -> bytes:
    """The payload with map version v (offset 48)."""
    return payload[:48] + struct.pack("<I", v) + payload[52:]


class Pair:
    """The Python PLC and the compiled ST program, each over its own window, fed the same
    writes."""

    def __init__(self) -> None:
        self.st = StPlc(P.machine, AXES, channel_limit=500, max_step=5)
        self.layout = self.st.layout
        self.t = 0.0
        self._boot_python(bytearray(self.layout.size))
        self.scan()

    def _boot_python(self, window: bytearray) -> None:
        self.window = window
        self.ctl = FanucPMC(P.machine, AXES, FanucConfig())
        self.py = PlcMapProgram(window, self.layout, self.ctl,
                                formats=MapEncoding.INT32_INCREMENTS | MapEncoding.FACTORED
                                | MapEncoding.THERMAL)
        self.py.boot(self.t, P.machine)

    def write(self, writes: Sequence[Write]) -> None:
        write_all(self.window, writes)
        write_all(self.st.window, writes)

    def scan(self) -> None:
        self.t += 0.008
        q = np.zeros(len(AXES))
        applied = self.ctl.scan(self.t, q)
        self.py.scan(self.t, q, np.asarray(applied * 0.001, dtype=np.float64))
        self.st.scan([0] * len(AXES))

    def restart(self) -> None:
        """Both PLCs restart; their windows (nonvolatile) keep every byte."""
        self._boot_python(self.window)
        self.st.restart()
        self.scan()

    def verdict(self) -> tuple[int, int, int, int, int]:
        """(ack_seq, ack_code, active, applied version, temp_ack), the same on both."""
        py, st = status(self.window), status(self.st.window)
        a = (py.ack_seq, py.ack_code, py.active, py.applied_version, py.temp_ack)
        b = (st.ack_seq, st.ack_code, st.active, st.applied_version, st.temp_ack)
        assert a == b, f"Python PLC {a}, ST program {b}"
        return a

    def push(self, buffer: int, payload: bytes, v: int, seq: int) -> tuple[int, ...]:
        self.write(plan_map_write(self.layout, buffer, payload, v, seq))
        self.scan()
        return self.verdict()


@pytest.fixture
def pair() -> Pair:
    p = Pair()
    assert p.push(1, MAP, 1, 1) == (1, 0, 1, 1, 0)
    return p


def test_a_center_dropping_after_any_block_leaves_the_last_good_map(pair: Pair) -> None:
    v2 = version(MAP, 2)
    writes = plan_map_write(pair.layout, 2, v2, 2, 2)
    for w in writes[:-1]:   # every write but the switch: nothing changes
        pair.write([w])
        pair.scan()
        assert pair.verdict() == (1, 0, 1, 1, 0)
    pair.write(writes[-1:])
    pair.scan()
    assert pair.verdict() == (2, 0, 2, 2, 0)


def test_a_switch_to_a_half_written_buffer_is_refused(pair: Pair) -> None:
    v2 = version(MAP, 2)
    writes = plan_map_write(pair.layout, 2, v2, 2, 2)
    pair.write(writes[: len(writes) // 2] + writes[-1:])  # header cleared, half the payload
    pair.scan()
    assert pair.verdict() == (2, 100, 1, 1, 0)


@pytest.mark.parametrize(("what", "code"), [("payload CRC", 4), ("header CRC", 100),
                                            ("too long", 3), ("header format", 6),
                                            ("header version", 5)])
def test_a_corrupted_buffer_is_refused_and_the_old_map_kept(pair: Pair, what: str,
                                                            code: int) -> None:
    v2 = version(MAP, 2)
    writes = plan_map_write(pair.layout, 2, v2, 2, 2)
    at = pair.layout.buffer_at(2)
    crc = zlib.crc32(v2)
    match what:
        case "payload CRC":
            bad = [Write(at + 32 + 100, bytes([v2[100] ^ 0x40, v2[101]]))]
        case "header CRC":
            head = bytearray(encode_buffer_header(BufferHeader(5, 2, len(v2), crc)))
            head[21] ^= 1
            bad = [Write(at, bytes(head))]
        case "too long":
            bad = [Write(at, encode_buffer_header(BufferHeader(5, 2, 20_000, crc)))]
        case "header format":
            bad = [Write(at, encode_buffer_header(BufferHeader(1, 2, len(v2), crc)))]
        case _:
            bad = [Write(at, encode_buffer_header(BufferHeader(5, 3, len(v2), crc)))]
    pair.write(writes[:-1] + bad + writes[-1:])
    pair.scan()
    assert pair.verdict() == (2, code, 1, 1, 0)


def test_a_switch_naming_no_buffer_is_refused(pair: Pair) -> None:
    for seq, buffer in ((2, 3), (3, 0)):
        pair.write([Write(SWITCH_AT, struct.pack("<H", seq << 2 | buffer))])
        pair.scan()
        assert pair.verdict() == (seq, 101, 1, 1, 0)


def test_another_machines_map_and_an_older_version_are_refused(pair: Pair) -> None:
    other = bytearray(version(MAP, 2))
    other[16:48] = b"another-machine".ljust(32, b"\0")
    assert pair.push(2, bytes(other), 2, 2) == (2, 7, 1, 1, 0)
    assert pair.push(2, version(MAP, 5), 5, 3) == (3, 0, 2, 5, 0)
    assert pair.push(1, version(MAP, 4), 4, 4) == (4, 10, 2, 5, 0)   # STALE_VERSION
    assert pair.push(1, version(MAP, 5), 5, 5) == (5, 0, 1, 5, 0)    # the same: taken


def test_a_broken_payload_is_a_decode_error(pair: Pair) -> None:
    bad = bytearray(version(MAP, 2))
    bad[7] = 9   # nine axes
    assert pair.push(2, bytes(bad), 2, 2) == (2, 6, 1, 1, 0)
    short = version(MAP, 2)[:-2]  # a value missing: the length does not match
    assert pair.push(2, short, 2, 3) == (3, 6, 1, 1, 0)


def test_garbage_over_the_active_buffer_changes_nothing_until_a_restart(pair: Pair) -> None:
    at = pair.layout.buffer_at(1)
    rng = np.random.default_rng(5)
    pair.write([Write(at + 200, rng.integers(0, 256, 600, dtype=np.uint8).tobytes())])
    for _ in range(3):
        pair.scan()
        assert pair.verdict() == (1, 0, 1, 1, 0)   # the map in use is the program's copy
    pair.restart()   # the active buffer no longer checks out: none applied
    assert pair.verdict() == (1, 0, 0, 0, 0)
    assert pair.push(2, version(MAP, 2), 2, 2) == (2, 0, 2, 2, 0)


def test_two_writers_interleaved_never_give_a_mixed_map(pair: Pair) -> None:
    a = plan_map_write(pair.layout, 2, version(MAP, 2), 2, 2)
    b = plan_map_write(pair.layout, 2, version(MAP, 3), 3, 3)
    mixed = [w for pair_ in zip(a[:-1], b[:-1], strict=False) for w in pair_]
    pair.write(mixed + a[-1:])
    pair.scan()
    v = pair.verdict()
    # a whole map is in use (b's blocks, written after a's, and b's header make b's map
    # whole in the buffer: the PLC takes it on a's switch), or the old one is kept
    assert v[0] == 2 and (v[1] == 0) == (v[3] in (2, 3)) and v[3] in (1, 2, 3), v
    pair.write(b[-1:])
    pair.scan()
    w = pair.verdict()
    assert w[0] == 3 and w[3] in (1, 2, 3), w


def test_the_sequence_wraps_from_16383_to_1(pair: Pair) -> None:
    assert pair.push(2, version(MAP, 2), 2, 16383) == (16383, 0, 2, 2, 0)
    assert pair.push(1, version(MAP, 3), 3, 1) == (1, 0, 1, 3, 0)
    # the same sequence again is no new switch
    pair.write(plan_map_write(pair.layout, 2, version(MAP, 4), 4, 1))
    pair.scan()
    assert pair.verdict() == (1, 0, 1, 3, 0)


def test_torn_temperature_writes_are_taken_only_whole(pair: Pair) -> None:
    whole = plan_temperatures([30.0, 25.0], 7)
    pair.write([Write(whole.offset, whole.data[:64])])   # half the slots, no sequence
    pair.scan()
    assert pair.verdict()[4] == 0
    pair.write([whole])
    pair.scan()
    assert pair.verdict()[4] == 7
    # the ST program took the readings: the thermal records move the Z and X counts
    cold = StPlc(P.machine, AXES, channel_limit=500, max_step=1 << 20)
    cold.scan([0] * 5)
    write_all(cold.window, plan_map_write(cold.layout, 1, MAP, 1, 1))
    cold.scan([0] * 5)
    assert not np.array_equal(cold.lookup([0, 0, 100_000, 0, -100_000], [False] * 5),
                              pair.st.lookup([0, 0, 100_000, 0, -100_000], [False] * 5))


def test_a_restart_with_the_window_kept_applies_the_active_buffer_again(pair: Pair) -> None:
    assert pair.push(2, version(MAP, 2), 2, 2) == (2, 0, 2, 2, 0)
    pair.write([plan_temperatures([22.0, 21.0], 9)])
    pair.scan()
    assert pair.verdict() == (2, 0, 2, 2, 9)
    pair.restart()
    # the verdict is kept; the map again; the slots the window still holds are taken anew
    assert pair.verdict()[:4] == (2, 0, 2, 2)
    pair.scan()
    assert pair.verdict() == (2, 0, 2, 2, 9)
    # and the next switch is a new one
    assert pair.push(1, version(MAP, 3), 3, 3) == (3, 0, 1, 3, 9)


RULES_A = (VECTORS / "rules_a.bin").read_bytes()
RULES_B = (VECTORS / "rules_b.bin").read_bytes()


class RulesPair(Pair):
    """The pair on the rules maps (machine ``rules``, axes X Z C), the screen of the
    Python PLC's defaults (-20..100 °C)."""

    def __init__(self) -> None:
        self.st = StPlc("rules", ["X", "Z", "C"], channel_limit=500, max_step=5)
        self.layout = self.st.layout
        self.t = 0.0
        self._boot_rules(bytearray(self.layout.size))
        self.scan()

    def _boot_rules(self, window: bytearray) -> None:
        self.window = window
        self.ctl = FanucPMC("rules", ["X", "Z", "C"], FanucConfig())
        self.py = PlcMapProgram(window, self.layout, self.ctl,
                                formats=self.ctl.store.assembler.accepted)
        self.py.boot(self.t, "rules")

    def scan(self) -> None:
        self.t += 0.008
        q = np.zeros(3)
        applied = self.ctl.scan(self.t, q)
        self.py.scan(self.t, q, np.asarray(applied * 0.001, dtype=np.float64))
        self.st.scan([0, 0, 0])

    def refused(self) -> int:
        a, b = status(self.window).temp_refused, status(self.st.window).temp_refused
        assert a == b, f"temp_refused: Python PLC {a:#x}, ST program {b:#x}"
        return a

    def slots(self, celsius: list[float | None], seq: int, version: int = 0) -> None:
        self.write([plan_temperatures(celsius, seq, map_version=version)])
        self.scan()


def test_slots_by_sequence_and_stamp_screen_and_swap_as_the_python_plc() -> None:
    """§13.1 on both PLCs: sequence 0 takes nothing, a stamp of another map version
    is not taken, the screen's refusals in temp_refused, a swap forgets the sequence;
    and the header's map version differing from the payload's is WRONG_VERSION."""
    pair = RulesPair()
    assert pair.push(1, RULES_A, 1, 1) == (1, 0, 1, 1, 0)
    pair.write([plan_temperatures([26.0, 25.0], 1), Write(384, b"\0\0")])  # sequence 0
    pair.scan()
    assert pair.verdict()[4] == 0
    pair.slots([26.0, 25.0], 2, version=7)                  # another map's stamp
    assert pair.verdict()[4] == 0
    pair.slots([26.0, None], 3, version=1)
    assert pair.verdict()[4] == 3 and pair.refused() == 0
    pair.slots([None, 150.0], 4)                            # beyond the screen: bit 1
    assert pair.verdict()[4] == 4 and pair.refused() == 0b10
    pair.slots([None, 25.0], 9, version=1)
    assert pair.refused() == 0
    # a swap keeps temp_ack (the last taken) but forgets the sequence for the next take
    assert pair.push(2, RULES_B, 2, 2) == (2, 0, 2, 2, 9)
    before = pair.st.thermal_constants
    pair.slots([None, 19.0], 9, version=1)                  # A's stamp: not B's slots
    assert "air" not in pair.ctl.temperatures.readings()
    assert pair.st.thermal_constants == before
    pair.slots([None, 19.0], 9, version=2)                  # B's: taken, same sequence
    assert "air" in pair.ctl.temperatures.readings()
    assert pair.st.thermal_constants != before and pair.verdict()[4] == 9
    # a header whose map version is not the payload's
    pair.write(plan_map_write(pair.layout, 1, version(RULES_B, 3), 4, 3))
    pair.scan()
    assert pair.verdict() == (3, 5, 2, 2, 9)


AXIS0, TERMS = 64, 64 + 3 * 20
THERMAL = TERMS + 2 * (8 + 2)


@pytest.mark.parametrize(("what", "at", "fmt", "value"), [
    ("reversal with its flag clear", AXIS0 + 4, "<B", 0),
    ("flags bits 2-7", AXIS0 + 4, "<B", 0x06),
    ("axis names distinct", AXIS0 + 20, "<I", int.from_bytes(b"X\0\0\0", "little")),
    ("a term's field below D + L x R", TERMS, "<B", 5),
    ("a drift's q_min 0", THERMAL + 28, "<i", 7),
    ("|start| < 2^30", AXIS0 + 8, "<i", 1 << 30),
    ("|t_ref| < 2^30", THERMAL + 24, "<i", -(1 << 30)),
    ("expansion coefficient < 2^24", THERMAL + 32 + 20, "<i", 1 << 24),
])
def test_a_map_breaking_a_decode_rule_is_a_decode_error_on_both(what: str, at: int,
                                                                fmt: str, value: int) -> None:
    bad = bytearray(RULES_A)
    struct.pack_into(fmt, bad, at, value)
    pair = RulesPair()
    assert pair.push(1, bytes(bad), 1, 1) == (1, 6, 0, 0, 0), what
    assert pair.push(2, RULES_A, 1, 2) == (2, 0, 2, 1, 0)


def test_corrections_scan_by_scan_equal_the_python_plcs_while_the_axes_move() -> None:
    """The whole output path on both PLCs over 400 scans of random moves (some axes
    standing, reversals, jumps across the map): evaluation, reversal, clamp to the
    channel's 500 counts and the step limit of 5 counts per scan give the same applied
    corrections in the status at every scan."""
    pair = Pair()
    assert pair.push(1, MAP, 1, 1) == (1, 0, 1, 1, 0)
    pair.write([plan_temperatures([31.0, 12.5], 1, map_version=1)])
    rng = np.random.default_rng(11)
    lo = np.array([a.start for a in P.axes])
    hi = np.array([a.start + ((a.count - 1) << a.shift) for a in P.axes])
    q = ((lo + hi) // 2).astype(np.int64)
    last = q.copy()
    direction = np.ones(len(AXES))
    differ = 0

    def scan_both() -> None:
        pair.t += 0.008
        applied = pair.ctl.scan(pair.t, q * 0.001, direction.astype(np.int8))
        pair.py.scan(pair.t, q * 0.001, np.asarray(applied * 0.001, dtype=np.float64))
        pair.st.scan(q.tolist())

    # settle: the Python PLC's ladder uses a new map or reading one scan after its map
    # handling took it, the ST program in the same scan; both then ramp to rest
    for _ in range(200):
        scan_both()
    assert status(pair.window).applied == status(pair.st.window).applied
    for k in range(400):
        if k % 50 == 0:   # a jump across the map
            step = rng.integers(-20_000, 20_000, len(AXES))
        else:
            step = rng.integers(-300, 300, len(AXES)) * (rng.random(len(AXES)) < 0.6)
        q = np.clip(q + step, lo, hi)
        moved = q != last
        direction = np.where(moved, np.sign(q - last), direction)
        last = q.copy()
        scan_both()
        a, b = status(pair.window).applied, status(pair.st.window).applied
        assert a == b, f"scan {k}: Python PLC {a}, ST program {b}"
        differ += int(np.any(pair.st.target != pair.st.applied))
    assert differ > 10   # the step limit was at work, not idle
    assert status(pair.st.window).temp_ack == 1


class AlarmPair(RulesPair):
    """The rules pair with the step alarm instead of the ramp on both PLCs."""

    def __init__(self) -> None:
        self.st = StPlc("rules", ["X", "Z", "C"], channel_limit=500, max_step=5,
                        alarm_on_jump=True)
        self.layout = self.st.layout
        self.t = 0.0
        self.window = bytearray(self.layout.size)
        self.ctl = FanucPMC("rules", ["X", "Z", "C"], FanucConfig(on_jump="alarm"))
        self.py = PlcMapProgram(self.window, self.layout, self.ctl,
                                formats=self.ctl.store.assembler.accepted)
        self.py.boot(self.t, "rules")
        self.scan()

    def state(self) -> tuple[int, tuple[int, ...]]:
        a, b = status(self.window), status(self.st.window)
        assert (a.state, a.applied) == (b.state, b.applied), \
            f"Python PLC {a.state:#x} {a.applied}, ST program {b.state:#x} {b.applied}"
        return a.state, a.applied[:3]


def test_the_step_alarm_holds_the_corrections_until_reset_as_the_python_plc() -> None:
    """§13.3 step 4's alternative: a target more than max_step away raises the alarm
    (state bit 3) and holds the corrections; the operator's reset lets the next scan
    decide again (the same jump: the alarm again)."""
    pair = AlarmPair()
    pair.push(1, RULES_A, 1, 1)   # X wants 8 counts at once: more than 5
    pair.scan()
    state, applied = pair.state()
    assert state & 8 and applied == (0, 0, 0)
    pair.ctl.reset_alarm()
    pair.st.reset_alarm()
    pair.scan()
    state, applied = pair.state()
    assert state & 8 and applied == (0, 0, 0)
