"""The PLC program of ``plc/`` (IEC 61131-3 Structured Text), compiled by MATIEC's iec2c
and gcc and run scan by scan (machine_sim/iec.py, machine_sim/stplc.py): the compiler
runs loops as IEC 61131-3 says, and the program gives the counts of the test vectors and
of ``ednc lookup`` exactly."""

from __future__ import annotations

import ctypes
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim.iec import StProgram, StVar, build_program
from machine_sim.stplc import StPlc
from protocol.mapfactored import decode_factored
from tests.support.stplc import loaded, status

VECTORS = Path(__file__).parent / "vectors"

LOOPS = """
FUNCTION_BLOCK FB_Count
VAR_INPUT
  a : DINT;
  b : DINT;
  s : DINT;
END_VAR
VAR_OUTPUT
  n : DINT;
END_VAR
VAR
  i : DINT;
END_VAR
n := 0;
FOR i := a TO b BY s DO
  n := n + 1;
END_FOR;
END_FUNCTION_BLOCK

PROGRAM PRG_Loops
VAR
  a : DINT;
  b : DINT;
  s : DINT := 1;
  n : DINT;
  counter : FB_Count;
END_VAR
counter(a := a, b := b, s := s);
n := counter.n;
END_PROGRAM
"""


@pytest.mark.parametrize(("a", "b", "s", "n"), [
    (3, 3, 1, 1),     # one iteration: MATIEC from 8a06b3b runs it zero times
    (-7, -7, 1, 1),
    (3, 2, 1, 0),     # zero iterations
    (0, 9, 1, 10),
    (0, 9, 4, 3),     # 0, 4, 8
    (5, 5, -1, 1),
    (5, 3, -1, 3),
])
def test_for_loops_run_as_iec_61131_3_says(tmp_path: Path, a: int, b: int, s: int,
                                          n: int) -> None:
    src = tmp_path / "loops.st"
    src.write_text(LOOPS)
    names = [StVar(v, ctypes.c_int32) for v in ("a", "b", "s", "n")]
    prog = StProgram(build_program([src], "PRG_Loops", names), names)
    prog.init()
    prog.var("a")[0], prog.var("b")[0], prog.var("s")[0] = a, b, s
    prog.scan()
    assert prog.var("n")[0] == n


def _vector(name: str) -> dict[str, Any]:
    body: dict[str, Any] = json.loads((VECTORS / f"{name}.json").read_text())
    return body


def test_the_program_gives_the_factored_vectors() -> None:
    body = _vector("factored_5axis")
    plc = loaded((VECTORS / body["map"]).read_bytes(), body["temperatures_mC"])
    got = [plc.lookup(p["q_counts"], p["negative"]).tolist() for p in body["points"]]
    want = [p["counts"] for p in body["points"]]
    bad = [i for i, (g, w) in enumerate(zip(got, want, strict=True)) if g != w]
    assert not bad, f"{len(bad)} of {len(want)} differ, first {body['points'][bad[0]]}: " \
                    f"{got[bad[0]]}"
    assert any(any(p["negative"]) for p in body["points"])


@pytest.mark.parametrize("name", ["grid_3axis", "grid_ties"])
def test_the_program_gives_the_grid_vectors(name: str) -> None:
    """int32 grids: format version 3 with thermal records and a reversal, format version
    1 whose interpolation lands on half counts (halves up)."""
    from protocol.mapformat import decode_map

    body = _vector(name)
    data = (VECTORS / body["map"]).read_bytes()
    axes = body["axes"]
    plc = loaded(data, body["temperatures_mC"], axes)
    outs = [axes.index(o.name.upper()) for o in decode_map(data).outputs]
    got = [[int(v) for v in plc.lookup(p["q_counts"], p["negative"])[outs]]
           for p in body["points"]]
    want = [p["counts"] for p in body["points"]]
    bad = [i for i, (g, w) in enumerate(zip(got, want, strict=True)) if g != w]
    assert not bad, f"{len(bad)} of {len(want)} differ, first {body['points'][bad[0]]}: " \
                    f"{got[bad[0]]}"


def test_without_readings_the_records_add_nothing() -> None:
    """A record whose sensor never had a reading adds 0 (section 6)."""
    from machine_sim.lookup import FactoredLadder

    body = _vector("factored_5axis")
    data = (VECTORS / body["map"]).read_bytes()
    plc = loaded(data)
    ladder = FactoredLadder(decode_factored(data))
    rng = np.random.default_rng(3)
    for p in rng.choice(body["points"], 20):
        q = np.array([p["q"][a] for a in body["axes"]])
        assert plc.lookup(p["q_counts"], [False] * 5).tolist() == \
            ladder.counts(q[None, :])[0].tolist()


CONVERT = """
PROGRAM PRG_Convert
VAR
  x : LREAL;
  y : LREAL;
  d : LREAL;
  n : LINT;
  ok : BOOL;
END_VAR
ok := TRUE;
n := F_RoundProd(ok, x, y, d);
END_PROGRAM
"""


def test_the_loaders_f64_conversion_is_exact(tmp_path: Path) -> None:
    """round_half_up(x · y / d) of the exact f64 values (section 6), as the program
    converts a grid's start and step, t_ref and thermal coefficients, against rational
    arithmetic: random values, decimal-looking ones (20.0005 °C) and exact half-count
    ties."""
    from fractions import Fraction

    from machine_sim.stplc import PLC_DIR

    src = tmp_path / "convert.st"
    src.write_text(CONVERT)
    names = [StVar("x", ctypes.c_double), StVar("y", ctypes.c_double),
             StVar("d", ctypes.c_double), StVar("n", ctypes.c_int64), StVar("ok", ctypes.c_uint8)]
    sources = [PLC_DIR / f for f in ("ednc_types.st", "ednc_bytes.st", "ednc_f64.st")]
    prog = StProgram(build_program([*sources, src], "PRG_Convert", names), names)
    prog.init()
    rng = np.random.default_rng(6)
    cases = [(float(v), 1000.0, 1.0) for v in np.round(rng.uniform(-50, 150, 4000), 4)]
    cases += [(float(v), 1000.0 * 67108864.0, 15625.0) for v in rng.normal(0, 5, 3000)]
    cases += [(float(v), 549755813888.0, 1953125.0) for v in rng.normal(0, 15, 3000)]
    cases += [(k + 0.5, 1.0, 1.0) for k in range(-20, 20)]          # ties: halves up
    cases += [(k * 0.0005, 1000.0, 1.0) for k in range(-2000, 2000)]  # 20.0005-like
    wrong = []
    for x, y, d in cases:
        prog.var("x")[0], prog.var("y")[0], prog.var("d")[0] = x, y, d
        prog.scan()
        want = (Fraction(x) * Fraction(y) / Fraction(d) + Fraction(1, 2)).__floor__()
        if prog.var("n")[0] != want or not prog.var("ok")[0]:
            wrong.append((x, y, d, prog.var("n")[0], want))
    assert not wrong, f"{len(wrong)} of {len(cases)} differ, first {wrong[0]}"
    # the double-precision shortcut is not exact: the test can tell them apart
    assert any(math.floor(x * y / d + 0.5) != (Fraction(x) * Fraction(y) / Fraction(d)
                                               + Fraction(1, 2)).__floor__()
               for x, y, d in cases)


def test_the_program_runs_the_rules_scenario() -> None:
    """tests/vectors/rules.json scan by scan through the window: maps A then B switched
    in, readings through the slots (null: -2^31, the held reading stays), positions;
    each step's directions, thermal constants and counts."""
    from protocol.ctrlmem import sensor_slots
    from protocol.mapfactored import decode_factored
    from tests.support.stplc import write_map, write_temperatures

    rules = _vector("rules")
    maps = {k: (VECTORS / v).read_bytes() for k, v in rules["maps"].items()}
    plc = StPlc("rules", rules["axes"], channel_limit=(1 << 30) - 1, max_step=1 << 30,
                temperature_screen=(-300_000, 300_000, 1 << 30, 1 << 30))
    plc.scan([0, 0, 0])
    seq = tseq = 0
    current = None
    for k, st in enumerate(rules["steps"]):
        if "map" in st:
            seq += 1
            current = decode_factored(maps[st["map"]])
            write_map(plc.window, plc.layout, 1 + seq % 2, maps[st["map"]], current.version,
                      seq)
        if "readings_mC" in st:
            assert current is not None
            slots = sensor_slots([r.sensor for r in current.thermal])
            values = [-(1 << 31)] * len(slots)
            for name, mc in st["readings_mC"].items():
                if name in slots and mc is not None:
                    values[slots[name]] = mc
            tseq += 1
            write_temperatures(plc.window, values, tseq, current.version)
        plc.scan(st["q_counts"], 0)
        assert status(plc.window).ack_code == 0
        where = f"step {k}: {st['note']}"
        assert plc.directions == st["direction"], where
        assert list(plc.thermal_constants) == [st["c0"], st["c1"]], where
        assert plc.target.tolist() == st["counts"], where


def test_axes_are_matched_by_name_not_by_place() -> None:
    """§6.6: a machine whose axes come in another order, with one more, takes the map
    (C, X, Z found by name) and drives the same axes; a map naming an axis the machine
    lacks is APPLY_FAILED."""
    from tests.support.stplc import write_map

    data = (VECTORS / "rules_a.bin").read_bytes()
    plc = StPlc("rules", ["C", "Y", "Z", "X"], max_step=1 << 20)
    plc.scan([0] * 4)
    write_map(plc.window, plc.layout, 1, data, 1, 1)
    plc.scan([0] * 4)
    assert status(plc.window).ack_code == 0
    assert plc.applied.tolist() == [3, 0, 0, 8]   # C 3, Y nothing, Z 0, X 8
    other = StPlc("rules", ["X", "Y", "Z"])
    other.scan([0] * 3)
    write_map(other.window, other.layout, 1, data, 1, 1)
    other.scan([0] * 3)
    assert (status(other.window).ack_code, status(other.window).active) == (11, 0)


def test_the_step_limit_ramps_and_a_map_expires() -> None:
    """§13.3 step 4: at most maxStep counts per scan per axis, state bit 1 while short;
    the status carries positions and applied corrections; §8: a map with valid_s > 0
    expires, the corrections ramp to zero, version 0 and state bit 5."""
    import struct as st_

    from protocol.ctrlmem import State
    from tests.support.stplc import write_map

    data = bytearray((VECTORS / "rules_a.bin").read_bytes())
    st_.pack_into("<I", data, 52, 2)   # valid_s: 2 s
    plc = StPlc("rules", ["X", "Z", "C"], max_step=5)
    plc.scan([0, 0, 0])
    write_map(plc.window, plc.layout, 1, bytes(data), 1, 1)
    plc.scan([10, 20, 30])
    s = status(plc.window)
    assert s.ack_code == 0 and s.applied[:3] == (5, 0, 3) and s.positions[:3] == (10, 20, 30)
    assert s.state & State.RAMPING and s.state & State.MAP_IN_USE
    plc.scan([10, 20, 30])
    s = status(plc.window)
    assert s.applied[:3] == (8, 0, 3) and not s.state & State.RAMPING
    plc.scan([10, 20, 30], 2000)   # the validity runs out
    s = status(plc.window)
    assert s.applied_version == 0 and s.active == 0
    assert s.state & State.EXPIRED and not s.state & State.MAP_IN_USE
    assert s.applied[:3] == (3, 0, 0) and s.state & State.RAMPING
    plc.scan([10, 20, 30])
    assert status(plc.window).applied[:3] == (0, 0, 0)
