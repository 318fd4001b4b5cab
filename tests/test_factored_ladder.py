"""The Fanuc-style ladder's map arithmetic is integer only (issue 24): no float enters
``machine_sim/ladder.py`` (its source has no float literal, no true division, no float
conversion or floating-point function), its per-scan evaluation runs on int64 and
refuses anything else, and int32 grids round half counts up in the simulated PMC as the
README says (they were rounded half to even before)."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from machine_sim import ladder
from machine_sim.fanuc import FanucConfig, FanucPMC
from machine_sim.lookup import FactoredLadder, GridLadder
from protocol import ErrorMapPayload, GridAxis, MapEncoding, OutputAxis, pack_values
from protocol.mapfactored import decode_factored
from protocol.mapformat import decode_map, encode_map
from protocol.maptransfer import split_into_chunks
from protocol.messages import MapAck, MapReject

VECTORS = Path(__file__).parent / "vectors"
_FLOAT_NAMES = {"float", "float16", "float32", "float64", "floating", "longdouble", "double",
                "true_divide", "divide", "sqrt", "exp", "log", "sin", "cos", "tan", "rint",
                "round", "around", "floor", "ceil", "ldexp", "frexp", "interp", "mean",
                "average", "astype", "math"}


def test_the_ladder_module_has_no_float_in_it() -> None:
    """Every literal is an int (or a str/bool/None), no ``/`` or ``/=``, no name that
    makes or takes floats (``float``, ``np.float64``, ``np.floor``, ``math``, ...)."""
    tree = ast.parse(inspect.getsource(ladder))
    bad = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, float | complex):
            bad.append(f"line {node.lineno}: literal {node.value!r}")
        if isinstance(node, ast.BinOp | ast.AugAssign) and isinstance(node.op, ast.Div):
            bad.append(f"line {node.lineno}: true division")
        if isinstance(node, ast.Name) and node.id in _FLOAT_NAMES:
            bad.append(f"line {node.lineno}: name {node.id}")
        if isinstance(node, ast.Attribute) and node.attr in _FLOAT_NAMES:
            bad.append(f"line {node.lineno}: attribute {node.attr}")
        if isinstance(node, ast.Import | ast.ImportFrom):
            names = [a.name for a in node.names] + [getattr(node, "module", "") or ""]
            if any(n in ("math", "cmath", "decimal") for n in names):
                bad.append(f"line {node.lineno}: imports {names}")
    assert not bad, bad


class _NoFloat(np.ndarray):
    """An int64 array that fails the moment any operation produces a float from it."""

    def __array_wrap__(self, out: np.ndarray, context: Any = None,
                       return_scalar: bool = False) -> Any:
        if out.dtype.kind not in "iub":
            raise AssertionError(f"a float entered the ladder: {out.dtype} from {context}")
        return super().__array_wrap__(out, context, return_scalar)


def test_the_per_scan_evaluation_stays_int64() -> None:
    """The factored and grid evaluations on the test vectors with positions and
    constants as int64 arrays that raise if any operation on them yields a float: the
    counts come out int64 and equal the vectors'."""
    import json
    for name in ("factored_5axis", "grid_3axis"):
        body = json.loads((VECTORS / f"{name}.json").read_text())
        data = (VECTORS / body["map"]).read_bytes()
        q = np.array([p["q_counts"] for p in body["points"]], dtype=np.int64).view(_NoFloat)
        want = [p["counts"] for p in body["points"] if not any(p["negative"])]
        keep = [not any(p["negative"]) for p in body["points"]]
        readings = {k: int(v) for k, v in body["temperatures_mC"].items()}
        if name.startswith("factored"):
            prog = ladder.factored_program(decode_factored(data))
            c0, c1 = ladder.thermal_constants(prog.thermal, len(prog.axes), readings)
            got = ladder.factored_counts(prog, q, c0.view(_NoFloat), c1.view(_NoFloat))
        else:
            gprog = GridLadder.from_payload(decode_map(data)).program
            assert gprog is not None
            c0, c1 = ladder.thermal_constants(gprog.thermal, len(gprog.outputs), readings)
            got = ladder.grid_counts(gprog, q, c0.view(_NoFloat), c1.view(_NoFloat))
        assert got.dtype == np.int64
        assert np.asarray(got)[keep].tolist() == want


def test_a_float_cannot_slip_in() -> None:
    """The guard above is able to fail: the same evaluation given one float position
    array raises."""
    body_q = np.zeros((1, 5), dtype=np.int64).view(_NoFloat)
    with pytest.raises(AssertionError, match="a float entered"):
        _ = body_q + 0.5


def _tie_grid() -> ErrorMapPayload:
    return ErrorMapPayload("m1", 1, MapEncoding.INT32_INCREMENTS,
                           (GridAxis("X", 0.0, 0.002, 2), GridAxis("Y", 0.0, 100.0, 2)),
                           (OutputAxis("X"), OutputAxis("Y"), OutputAxis("Z")),
                           pack_values(MapEncoding.INT32_INCREMENTS,
                                       [0, 1, 2, 0, 1, 2, 1, -2, 5, 1, -2, 5]), 0.001)


def test_the_fanuc_pmc_rounds_a_half_count_up() -> None:
    """At X = 0.001 mm the grid is halfway between 0 and 1, 1 and -2, 2 and 5 counts:
    0.5, -0.5 and 3.5 round up to 1, 0 and 4 (half to even gave 0, -0 and 4)."""
    p = _tie_grid()
    pmc = FanucPMC("m1", ("X", "Y", "Z"), FanucConfig(max_step_counts=100))
    reply = None
    for msg in split_into_chunks(encode_map(p), 1):
        reply = pmc.feed_map(msg, 0.0)
    assert isinstance(reply, MapAck)
    assert isinstance(pmc.store.active, GridLadder)
    shifts = pmc.scan(0.0, {"x": 0.001, "y": 37.0, "z": 0.0})
    assert shifts.tolist() == [1, 0, 4]
    assert np.rint([0.5, -0.5, 3.5]).tolist() == [0.0, -0.0, 4.0]  # what it was


def test_the_ladder_refuses_a_grid_off_whole_counts() -> None:
    p = _tie_grid()
    off = ErrorMapPayload(p.machine, 1, p.encoding,
                          (GridAxis("X", 0.0005, 0.002, 2), p.grid[1]), p.outputs, p.values,
                          0.001)
    with pytest.raises(ValueError, match="grid axis X start is not a whole number of counts"):
        GridLadder.from_payload(off)
    pmc = FanucPMC("m1", ("X", "Y", "Z"), FanucConfig())
    reply = None
    for msg in split_into_chunks(encode_map(off), 1):
        reply = pmc.feed_map(msg, 0.0)
    assert isinstance(reply, MapReject) and "whole number of counts" in reply.text


def test_factored_ladder_writes_what_the_vectors_say_with_reversal() -> None:
    """The simulated PMC's own map object on the factored vector, both approaches."""
    import json
    body = json.loads((VECTORS / "factored_5axis.json").read_text())
    lad = FactoredLadder(decode_factored((VECTORS / body["map"]).read_bytes()),
                         body["temperatures_C"])
    q = np.array([[p["q"][a] for a in body["axes"]] for p in body["points"]])
    neg = np.array([p["negative"] for p in body["points"]])
    got = lad.counts(q) + np.where(neg, lad.program.reversal, 0)
    assert got.tolist() == [p["counts"] for p in body["points"]]
    assert neg.any() and lad.program.reversal.any()
