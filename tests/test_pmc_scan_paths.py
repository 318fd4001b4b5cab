"""The simulated PMC's per-scan work in Python numbers (issue 30: its CPU was stolen from
the center) writes what the array code wrote, bit for bit.

* :class:`~machine_sim.ladder_point.FactoredPoint` against
  :func:`machine_sim.ladder.factored_counts` on random factored programs (rotary axes,
  constants, basis factors, thermal constants, reversals, positions beyond the tables),
  and the fallback to the array code where an intermediate leaves int64;
* a PMC and its PLC program scanned over a sequence with maps switched in through the
  window (factored with rotary axes, grid, a refused buffer, a map that expires),
  temperature slots written, a release, a jump alarm and its reset, positions and
  directions moving: the window and R memory after every scan equal those of the same
  machine run by the array-form code this work replaced (kept below as the reference);
* the scan clock: scans woken on the grid never run before their deadline, at most one
  grid step after it, and none is skipped.
"""

from __future__ import annotations

import asyncio
import dataclasses
import json
import math
import struct
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

from machine_sim import ladder
from machine_sim.controller import _Release
from machine_sim.fanuc import ALARM_JUMP, FanucConfig, FanucPMC
from machine_sim.ladder_point import FactoredPoint, Wide
from machine_sim.lookup import FactoredLadder
from machine_sim.plcmap import PlcMapProgram
from machine_sim.runtime import Motion
from protocol import MapAck, decode_payload, split_into_chunks
from protocol.ctrlmem import (
    NO_TEMPERATURE,
    STATUS_AT,
    STATUS_SIZE,
    SWITCH_AT,
    TEMP_SEQ_AT,
    AckCode,
    Layout,
    State,
    Status,
    check_buffer,
    decode_command,
    decode_status,
    encode_status,
    plan_delivery,
    plan_temperatures,
    sensor_slots,
    unpack_switch,
)
from protocol.mapfactored import (
    BASIS_ONE,
    BasisTable,
    FactoredAxis,
    FactoredPayload,
    TermTable,
    decode_factored,
    encode_factored,
)
from protocol.mapformat import MapFormatError, decode_map, encode_map

VECTORS = Path(__file__).parent / "vectors"
F64 = np.ndarray


# -- the ladder at one point

def _random_program(rng: np.random.Generator) -> FactoredPayload:
    d = int(rng.integers(1, 6))
    rotary = [bool(rng.random() < 0.4) for _ in range(d)]
    axes = []
    for k in range(d):
        count = int(rng.integers(1, 40))
        shift = int(rng.integers(0, 21))
        axes.append(FactoredAxis(f"A{k}", rotary[k],
                                 int(rng.integers(-300, 300)) if rng.random() < 0.5 else None,
                                 int(rng.integers(1, 1 << 20)), count,
                                 int(rng.integers(-(1 << 20), 1 << 20)), shift))
    bases = []
    for _ in range(int(rng.integers(0, 5))):
        n = int(rng.integers(1, 20))
        bases.append(BasisTable(int(rng.integers(0, d)), int(rng.integers(-(1 << 20), 1 << 20)),
                                int(rng.integers(0, 21)),
                                tuple(int(v) for v in rng.integers(-BASIS_ONE, BASIS_ONE + 1,
                                                                   n))))
    n_rot = sum(rotary)
    n_fields = d + (d - n_rot) * n_rot
    terms = []
    for _ in range(int(rng.integers(1, 26))):
        axis = int(rng.integers(0, d))
        n = 1 if rng.random() < 0.15 else axes[axis].count
        factors = tuple(int(b) for b in rng.integers(0, len(bases), int(rng.integers(0, 3))))\
            if bases else ()
        terms.append(TermTable(int(rng.integers(0, n_fields)), axis, int(rng.integers(-40, 9)),
                               factors,
                               tuple(int(v) for v in rng.integers(-(1 << 15) + 1, 1 << 15, n))))
    return FactoredPayload("m", 1, 0, 1000, tuple(axes), tuple(bases), tuple(terms))


def test_one_point_equals_the_array_code_on_random_programs() -> None:
    rng = np.random.default_rng(30)
    points = 0
    for _ in range(300):
        p = _random_program(rng)
        prog = ladder.factored_program(p)
        point = FactoredPoint(prog)
        d = len(p.axes)
        lo = np.array([a.start for a in p.axes]) - (1 << 21)
        hi = np.array([a.start + ((a.count - 1) << a.shift) for a in p.axes]) + (1 << 21)
        q = rng.integers(lo, hi + 1, size=(12, d)).astype(np.int64)
        c0 = rng.integers(-(1 << 40), 1 << 40, d).astype(np.int64)
        c1 = rng.integers(-(1 << 30), 1 << 30, d).astype(np.int64)
        neg = rng.random((12, d)) < 0.5
        want_fields = ladder.factored_fields(prog, q)
        want = ladder.factored_counts(prog, q, c0, c1, neg)
        want_pos = ladder.factored_counts(prog, q, c0, c1)
        for n in range(q.shape[0]):
            row = q[n].tolist()
            assert point.fields(row) == want_fields[n].tolist()
            assert point.counts(row, c0.tolist(), c1.tolist(), neg[n].tolist()) == \
                want[n].tolist()
            assert point.counts(row, c0.tolist(), c1.tolist()) == want_pos[n].tolist()
            points += 1
    assert points == 3600


def test_the_vector_maps_at_one_point() -> None:
    """The published factored vector (rotary axes, thermal records) through the map
    object's one-point path, positions in mm, both approaches."""
    body = json.loads((VECTORS / "factored_5axis.json").read_text())
    lad = FactoredLadder(decode_factored((VECTORS / body["map"]).read_bytes()),
                         body["temperatures_C"])
    for pt in body["points"]:
        q = [pt["q"][a] for a in body["axes"]]
        got = lad.counts_at(q)
        assert [g + (r if n else 0) for g, r, n in
                zip(got, lad.program.reversal.tolist(), pt["negative"], strict=True)] == \
            pt["counts"]
        assert lad.counts_at(q, pt["negative"]) == \
            lad.counts(np.array([q]), np.array([pt["negative"]]))[0].tolist()


def test_a_point_whose_arithmetic_leaves_int64_goes_to_the_array_code() -> None:
    """A slope so large that ``c1 · q`` overflows int64: the one-point code refuses it
    (Wide) and the map answers what the array code answers (wrapped), not the exact
    product's clamp."""
    body = json.loads((VECTORS / "factored_5axis.json").read_text())
    lad = FactoredLadder(decode_factored((VECTORS / body["map"]).read_bytes()))
    d = len(lad.grid)
    big = np.full(d, 1 << 55, dtype=np.int64)
    lad.c1 = big
    lad._consts = ([0] * d, big.tolist())
    q = [10.0, 5.0, 400.0, 300.0, -200.0]
    qc = [int(v) for v in np.floor(np.array(q) * lad.per_unit + 0.5)]
    with pytest.raises(Wide):
        lad.point.counts(qc, [0] * d, big.tolist())
    with np.errstate(over="ignore"):
        want = lad.counts(np.array([q]))[0].tolist()
    assert lad.counts_at(q) == want
    # NaN positions: the array code decides (as before)
    nan = [float("nan")] * d
    assert lad.counts_at(nan) == lad.counts(np.array([nan]))[0].tolist()


# -- the reference: the array-form scan this work replaced

class ArrayPMC(FanucPMC):
    """The Fanuc-style PMC as its scan was written before (arrays throughout)."""

    def wanted_mm(self, now_s: float, positions: Mapping[str, float] | F64,
                  directions: Mapping[str, int] | np.ndarray | None = None) -> F64:
        self.now_s = now_s
        pos = self._vector(positions, float)
        if self.store.expired(now_s) and self._release is None:
            self._release = _Release(now_s, self.expiry_ramp_s, self.applied_mm().copy(),
                                     False)
        if self._release is not None:
            r = self._release
            frac = 1.0 if r.ramp_s <= 0 else (now_s - r.start_s) / r.ramp_s
            if frac >= 1.0:
                self.store.drop(now_s, "released" if r.asked else "expired")
                if r.asked:
                    self.released_owed += 1
                self._release = None
                return np.zeros(len(self.axes))
            out: F64 = r.snapshot * (1.0 - frac)
            return out
        if self.temperatures.updated_s != self._folded_s:
            self._folded_s = self.temperatures.updated_s
            self.store.set_temperatures(self.temperatures.values(now_s))
        m = self.store.active
        wanted = np.zeros(len(self.axes))
        if m is None:
            return wanted
        q = np.array([pos[self.axes.index(g)] for g in m.inputs])
        dirs = (np.zeros(len(self.axes)) if directions is None
                else self._vector(directions, float))
        negative = np.array([dirs[self.axes.index(name)] < 0 for name in m.outputs])
        directed = getattr(m, "lookup_directed", None)
        if directed is not None:
            values = directed(q[None, :], negative[None, :])[0]
            for k, name in enumerate(m.outputs):
                wanted[self.axes.index(name)] = values[k]
            return wanted
        values = m.lookup(q[None, :])[0]
        for k, name in enumerate(m.outputs):
            wanted[self.axes.index(name)] = values[k] + (m.reversal[k] if negative[k]
                                                         else 0.0)
        return wanted

    def scan(self, now_s: float, positions: Mapping[str, float] | F64,
             directions: Mapping[str, int] | np.ndarray | None = None) -> np.ndarray:
        c, lay = self.config, self.config.layout
        pos = self._vector(positions, float)
        wanted = self.wanted_mm(now_s, pos, directions)
        if self.store.active is None and not self.releasing and self.store.events and \
                self.store.events[-1].kind == "expired":
            self._expired_seen = True
        if self.store.active is not None:
            self._expired_seen = False
        target = np.floor(wanted / c.increment_mm + 0.5).astype(np.int64)
        clamped = bool(np.any(np.abs(target) > c.limit_counts))
        target = np.clip(target, -c.limit_counts, c.limit_counts)
        current = np.array([self.read_i32(self._addr(lay.shift, k))
                            for k in range(len(self.axes))], dtype=np.int64)
        delta = target - current
        jump = np.abs(delta) > c.max_step_counts
        if self.alarm:
            new = current
        elif np.any(jump) and c.on_jump == "alarm" and not self.releasing:
            self.r[self._addr(lay.alarm)] = ALARM_JUMP
            new = current
        else:
            new = current + np.clip(delta, -c.max_step_counts, c.max_step_counts)
        for k in range(len(self.axes)):
            struct.pack_into("<i", self.r, self._addr(lay.shift, k), int(new[k]))
            struct.pack_into("<i", self.r, self._addr(lay.target, k), int(target[k]))
            struct.pack_into("<i", self.r, self._addr(lay.position, k),
                             int(np.floor(pos[k] / c.increment_mm + 0.5)))
        status = (1 if self.store.active is not None else 0)
        status |= 2 if np.any(new != target) else 0
        status |= 4 if self.releasing else 0
        status |= 8 if self.alarm else 0
        status |= 16 if clamped else 0
        status |= 32 if self._expired_seen else 0
        self.r[self._addr(lay.status)] = status
        struct.pack_into("<I", self.r, self._addr(lay.version), self.store.version)
        self.scans += 1
        struct.pack_into("<I", self.r, self._addr(lay.counter), self.scans & 0xFFFFFFFF)
        return new


class ArrayProgram(PlcMapProgram):
    """The PLC program's map handling as written before (IntFlag state, arrays, the
    status and the command area decoded whole every scan, the payload decoded again)."""

    def scan(self, now_s: float, positions: F64, applied_mm: F64) -> None:
        (word,) = struct.unpack_from("<H", self.window, SWITCH_AT)
        seq, buffer = unpack_switch(word)
        st = decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        active, ack_code = st.active, st.ack_code
        if seq != 0 and seq != self._handled_seq:
            self._handled_seq = seq
            checked = check_buffer(self.window, self.layout, buffer)
            if isinstance(checked[0], bytes):
                code, _why = self._apply(checked[0], checked[1].map_version, now_s)
            else:
                code = int(checked[0])
            ack_code = code
            if code == 0:
                active = buffer
                self.applied_switches += 1
            else:
                self.rejected_switches += 1
        self._take_temperatures(now_s)
        self.heartbeat = (self.heartbeat + 1) & 0xFFFFFFFF
        self._write_status(active=active, ack_code=ack_code, positions=positions,
                           applied_mm=applied_mm)

    def _apply(self, payload: bytes, version: int, now_s: float) -> tuple[int, str]:
        reply = None
        for msg in split_into_chunks(payload, version):
            reply = self.controller.feed_map(msg, now_s)
        if isinstance(reply, MapAck):
            try:
                records = decode_payload(payload).thermal
            except MapFormatError:
                records = ()
            slots = sensor_slots([r.sensor for r in records])
            self._slots = {i: s for s, i in slots.items()}
            self._temp_seq = None
            self._temp_ack = 0
            return 0, ""
        if reply is None:
            return int(AckCode.BAD_HEADER), "no verdict"
        return int(reply.reason), reply.text

    def _take_temperatures(self, now_s: float) -> None:
        cmd = decode_command(self.window)
        seq = cmd.temp_seq
        if seq == 0 or seq == self._temp_seq:
            return
        if cmd.slots_version not in (0, self.controller.store.version):
            return
        (again,) = struct.unpack_from("<H", self.window, TEMP_SEQ_AT)
        if again != seq:
            return
        self._temp_seq = self._temp_ack = seq
        store = self.controller.temperatures
        refused = 0
        for i, sensor in self._slots.items():
            value = cmd.slots[i]
            if value == NO_TEMPERATURE:
                continue
            if not store.update(sensor, value / 1000.0, now_s, "center"):
                refused |= 1 << i
        self._temp_refused = refused

    def _write_status(self, *, active: int, ack_code: int | None = None,
                      positions: F64 | None = None, applied_mm: F64 | None = None,
                      old: Status | None = None) -> None:
        old = decode_status(self.window[STATUS_AT:STATUS_AT + STATUS_SIZE])
        c = self.controller
        state = self._state_bits()
        pos = old.positions if positions is None else tuple(
            int(v) for v in np.floor(positions / self.increment_mm + 0.5))
        app = old.applied if applied_mm is None else tuple(
            int(v) for v in np.floor(applied_mm / self.increment_mm + 0.5))
        st = Status(self.heartbeat, self._handled_seq,
                    old.ack_code if ack_code is None else ack_code, active, state,
                    c.store.version, self._temp_ack, pos, app, self._temp_refused)
        self.window[STATUS_AT:STATUS_AT + STATUS_SIZE] = encode_status(st)

    def _state_bits(self) -> int:
        c = self.controller
        state = State(0)
        if c.store.active is not None:
            state |= State.MAP_IN_USE
        if c.releasing:
            state |= State.RELEASING
        r_status = getattr(c, "status", None)
        if isinstance(r_status, int):
            keep = State.RAMPING | State.ALARM | State.CLAMPED | State.EXPIRED
            return int(state | (State(r_status & 0x3F) & keep))
        return int(state)


# -- a PMC and its program, twice, over one sequence

def _machine(pmc_type: type[FanucPMC], prog_type: type[PlcMapProgram], name: str,
             axes: list[str], config: FanucConfig) -> tuple[FanucPMC, PlcMapProgram]:
    pmc = pmc_type(name, axes, config)
    layout = Layout(16_384)
    program = prog_type(bytearray(layout.size), layout, pmc,
                        formats=pmc.store.assembler.accepted, increment_mm=0.001)
    program.boot(0.0, name)
    return pmc, program


def _maps(kind: str) -> tuple[str, list[str], list[bytes], list[str], np.ndarray]:
    """Machine name, axes, three map versions' bytes (the third expires after 3 s),
    the sensors, and each axis's travel (2, D)."""
    if kind == "factored":
        body = json.loads((VECTORS / "factored_5axis.json").read_text())
        p = decode_factored((VECTORS / body["map"]).read_bytes())
        maps = [encode_factored(dataclasses.replace(p, version=v, valid_s=3 if v == 3 else 0))
                for v in (1, 2, 3)]
        axes = [a.name for a in p.axes]
        sensors = list(dict.fromkeys(t.sensor for t in p.thermal))
    else:
        body = json.loads((VECTORS / "grid_3axis.json").read_text())
        g = decode_map((VECTORS / body["map"]).read_bytes())
        maps = [encode_map(dataclasses.replace(g, version=v, valid_s=3 if v == 3 else 0))
                for v in (1, 2, 3)]
        axes = [a.name for a in g.grid]
        sensors = list(dict.fromkeys(t.sensor for t in g.thermal))
        p = g  # type: ignore[assignment]
    travel = np.array([body["travel"][a] for a in axes], dtype=float).T
    return p.machine, axes, maps, sensors, travel


@pytest.mark.parametrize(("kind", "on_jump"), [("factored", "ramp"), ("factored", "alarm"),
                                               ("grid", "ramp")])
def test_a_scan_sequence_writes_what_the_array_code_wrote(kind: str, on_jump: str) -> None:
    name, axes, maps, sensors, travel = _maps(kind)
    config = FanucConfig(max_step_counts=7, on_jump=on_jump)  # type: ignore[arg-type]
    new = _machine(FanucPMC, PlcMapProgram, name, axes, config)
    ref = _machine(ArrayPMC, ArrayProgram, name, axes, config)
    rng = np.random.default_rng(300)
    d = len(axes)
    q = travel.mean(axis=0)
    direction = np.ones(d)
    t = 0.0
    temp_seq = 0
    layout = Layout(16_384)
    pushes = {5: maps[0], 60: maps[1], 200: maps[2]}
    seen_states: set[int] = set()
    for k in range(320):
        writes = []
        if k in pushes:
            st = decode_status(new[1].window[STATUS_AT:STATUS_AT + STATUS_SIZE])
            (word,) = struct.unpack_from("<H", new[1].window, SWITCH_AT)
            version = struct.unpack_from("<I", pushes[k], 48)[0] if kind == "factored" \
                else decode_map(pushes[k]).version
            plan = plan_delivery(layout, st, unpack_switch(word)[0], pushes[k], version)
            assert plan is not None
            writes += plan
        if k == 120:  # a switch to a buffer whose CRC does not check: refused
            st = decode_status(new[1].window[STATUS_AT:STATUS_AT + STATUS_SIZE])
            plan = plan_delivery(layout, st, st.ack_seq, maps[0], 9)
            assert plan is not None
            bad = bytearray(plan[1].data)
            bad[0] ^= 0xFF
            writes += [plan[0], dataclasses.replace(plan[1], data=bytes(bad)), *plan[2:]]
        if k % 7 == 3:  # the center's temperatures, now and then far off (refused)
            temp_seq = temp_seq % 0xFFFF + 1
            values = [float(v) for v in 22.0 + 6.0 * rng.random(len(sensors))]
            if k % 35 == 3:
                values[0] += 50.0
            writes.append(plan_temperatures(values, temp_seq))
        for w in writes:
            for _, prog in (new, ref):
                prog.window[w.offset:w.offset + len(w.data)] = w.data
        if k == 150:
            for pmc, _ in (new, ref):
                pmc.release(t, 0.5)
        if k == 90 or k == 250:
            for pmc, _ in (new, ref):
                pmc.reset_alarm()
        # motion: steps of all sizes (a jump now and then), reversals, a standstill
        step = rng.normal(0.0, 2.0 if k % 40 else 60.0, d) * (k % 13 != 0)
        q = np.clip(q + step, travel[0], travel[1])
        direction = np.where(step > 0, 1.0, np.where(step < 0, -1.0, direction))
        t += float(rng.choice([0.008, 0.05, 0.3, 1.0]))
        for pmc, prog in (new, ref):
            shifts = pmc.scan(t, q.copy(), direction.astype(np.int8))
            prog.scan(t, q.copy(), pmc.applied_mm())
        assert new[0].r == ref[0].r, f"R memory differs after scan {k}"
        assert new[1].window == ref[1].window, f"window differs after scan {k}"
        assert shifts.tolist() == new[0].shifts().tolist()
        seen_states.add(decode_status(new[1].window[STATUS_AT:STATUS_AT + STATUS_SIZE]).state)
    # the sequence went through what it is meant to: maps in use, ramping, releasing,
    # expired (and the alarm where the ladder latches one), applied and refused switches
    bits = 0
    for s in seen_states:
        bits |= s
    want = State.MAP_IN_USE | State.RAMPING | State.RELEASING | State.EXPIRED
    if on_jump == "alarm":
        want |= State.ALARM
    assert bits & want == want, State(bits)
    assert new[1].applied_switches == 3 and new[1].rejected_switches == 1
    assert new[1]._temp_refused or new[0].temperatures.refused


def test_motion_is_what_it_was() -> None:
    """Positions and directions with 2π/period computed once equal the formula's."""
    rng = np.random.default_rng(5)
    m = Motion(rng.uniform(0, 500, 5), rng.uniform(10, 200, 5), rng.uniform(20, 120, 5),
               rng.uniform(0, 6.3, 5))
    for t in rng.uniform(0, 1e6, 200):
        arg = 2 * np.pi / m.period_s * t + m.phase
        q, d = m.at(float(t))
        assert q.tolist() == (m.centre + m.amplitude * np.sin(arg)).tolist()
        assert d.tolist() == np.sign(np.cos(arg)).astype(np.int8).tolist()


# -- the scan clock

def test_scans_on_the_wake_grid_are_never_early_never_skipped() -> None:
    """Three machines of one process scanned at 40 ms with a 10 ms grid: the n-th scan
    after the first runs at the first grid point at or after its deadline (the first
    scan's time plus n cycles), so none is early, none is skipped and the period is
    kept; late only by the loop's own lateness beyond that point."""
    from machine_sim.windowcnc import WindowCNC
    from tests.support.integration import FANUC_5AX

    times: dict[int, list[tuple[float, float]]] = {}

    class Null:
        port = 0

        async def start(self) -> None: ...

        async def stop(self) -> None: ...

    class Timed(WindowCNC):
        def cycle(self) -> None:
            loop = asyncio.get_running_loop()
            times.setdefault(id(self), []).append((loop.time(), self.wake_grid_s))

    async def run() -> None:
        cncs = [Timed(FANUC_5AX.machine, lambda _c: Null(), cycle_s=0.04, wake_grid_s=0.01)
                for _ in range(3)]
        for c in cncs:
            await c.__aenter__()
            await asyncio.sleep(0.003)
        await asyncio.sleep(1.0)
        for c in cncs:
            await c.__aexit__(None, None, None)

    asyncio.run(run())
    assert len(times) == 3
    for runs in times.values():
        start = runs[0][0]
        assert len(runs) >= 20
        for n, (at, grid) in enumerate(runs[1:], start=1):
            deadline = start + n * 0.04  # none skipped: the n-th scan's deadline
            point = math.ceil(deadline / grid) * grid
            assert at >= deadline - 1e-6, (n, at, deadline)  # never early
            assert at >= point - 1e-6, (n, at, point)  # woken on the grid
            assert at < point + 0.05, (n, at, point)  # 50 ms: the loop's own lateness
