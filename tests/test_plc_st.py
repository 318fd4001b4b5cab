"""The PLC program of ``plc/`` (IEC 61131-3 Structured Text), compiled by MATIEC's iec2c
and gcc and run scan by scan (machine_sim/iec.py, machine_sim/stplc.py): the compiler
runs loops as IEC 61131-3 says, and the program gives the counts of the test vectors and
of ``ednc lookup`` exactly."""

from __future__ import annotations

import ctypes
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim.iec import StProgram, StVar, build_program
from protocol.mapfactored import decode_factored
from tests.support.stplc import loaded

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
