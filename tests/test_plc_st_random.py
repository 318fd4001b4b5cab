"""The compiled Structured Text program against ``ednc lookup``'s arithmetic
(``machine_sim/lookup.py``: FactoredLadder, GridLadder) on 5,000 random points per map:
the 5-axis factored vector map, a 3-axis factored map built here and the 3-axis int32
grid vector map (format version 3), with thermal records at
readings written to the program's temperature slots, each point approached from a random
side per axis (reversal values): 0 count differences."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from machine_sim.lookup import FactoredLadder, positions_in_counts
from protocol.mapfactored import decode_factored
from tests.support.stplc import loaded

VECTORS = Path(__file__).parent / "vectors"
VMC = {"name": "vmc-st", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}, "controller": "fanuc"}


def three_axis_factored() -> tuple[bytes, dict[str, list[float]]]:
    """A factored map of a 3-axis machine with cubic component errors, a spindle drift,
    a screw expansion and reversals on X and Y."""
    from server.mapcodec import encode
    from volumetric.compensate.factoredmap import build_factored_map
    from volumetric.model.components import GeometricErrors, Polynomial, component_names
    from volumetric.model.machine import parse_machine
    from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm

    m = parse_machine(VMC)
    rng = np.random.default_rng(31)
    comps = {n: Polynomial(tuple(rng.normal(0, 5.0, 4)), a.travel[0],
                           a.travel[1] - a.travel[0])
             for a in m.axes for n in component_names(a)}
    terms = (ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 20.0),
             ThermalTerm("thermal_expansion", "x", "T_x_screw_C", 11.5, 20.0, 0.0),
             BacklashTerm("x", 6.0), BacklashTerm("y", 4.0))
    fm = build_factored_map(m, MachineModel(m.name, GeometricErrors(comps, {}), terms),
                            tolerance_um=1.0)
    travel = {a.name.upper(): [float(a.travel[0]), float(a.travel[1])] for a in m.axes}
    return encode(fm), travel


def _five_axis() -> tuple[bytes, dict[str, list[float]]]:
    import json
    body = json.loads((VECTORS / "factored_5axis.json").read_text())
    return (VECTORS / body["map"]).read_bytes(), body["travel"]


@pytest.mark.parametrize("which", ["5-axis", "3-axis"])
def test_5000_random_points_equal_ednc_lookup(which: str) -> None:
    data, travel = _five_axis() if which == "5-axis" else three_axis_factored()
    p = decode_factored(data)
    axes = [a.name.upper() for a in p.axes]
    temps_C = {"spindle": 24.1234, "x_screw": 19.0}
    readings = {"spindle": 24123, "x_screw": 19000}  # round_half_up(°C · 1000)
    plc = loaded(data, readings)
    ladder = FactoredLadder(p, temps_C)
    assert p.thermal and any(a.reversal for a in p.axes)
    rng = np.random.default_rng(2026)
    lo = np.array([travel[a][0] for a in axes])
    hi = np.array([travel[a][1] for a in axes])
    q = lo - 2.0 + (hi - lo + 4.0) * rng.random((5000, len(axes)))  # a little outside too
    q[:2500] = np.round(q[:2500], 3)
    negative = rng.random(q.shape) < 0.5
    qc = positions_in_counts(q, p.counts_per_unit)
    lim = np.array([a.limit for a in p.axes])
    want = np.clip(ladder.counts(q) + np.where(negative, ladder.program.reversal, 0),
                   -lim, lim)
    got = np.array([plc.lookup(qc[i].tolist(), negative[i].tolist()) for i in range(len(q))])
    bad = np.flatnonzero((got != want).any(axis=1))
    assert bad.size == 0, (f"{bad.size} of 5000 differ, first at {q[bad[0]]} "
                           f"{negative[bad[0]]}: {got[bad[0]]} vs {want[bad[0]]}")
    # the points exercise what they claim: reversals and the thermal records change counts
    assert np.any(want != np.clip(ladder.counts(q), -lim, lim))
    cold = FactoredLadder(p)
    assert np.any(cold.counts(q) != ladder.counts(q))


def test_5000_random_points_of_an_int32_grid_with_thermal_records() -> None:
    import json

    from machine_sim.lookup import GridLadder
    from protocol.mapformat import decode_map

    body = json.loads((VECTORS / "grid_3axis.json").read_text())
    data = (VECTORS / body["map"]).read_bytes()
    p = decode_map(data)
    axes = body["axes"]
    temps_C = {"spindle": 27.5, "x_screw": 16.25}
    plc = loaded(data, {"spindle": 27500, "x_screw": 16250}, axes)
    ladder = GridLadder.from_payload(p, temps_C)
    assert ladder.program is not None and p.thermal
    outs = [axes.index(o.name.upper()) for o in p.outputs]
    rng = np.random.default_rng(2027)
    lo = np.array([body["travel"][a][0] for a in axes])
    hi = np.array([body["travel"][a][1] for a in axes])
    q = lo - 2.0 + (hi - lo + 4.0) * rng.random((5000, len(axes)))
    q[:2500] = np.round(q[:2500], 3)
    negative = rng.random(q.shape) < 0.5
    qc = positions_in_counts(q, 1000)
    want = ladder.counts(q) + np.where(negative[:, outs], ladder.program.reversal, 0)
    got = np.array([plc.lookup(qc[i].tolist(), negative[i].tolist())[outs]
                    for i in range(len(q))])
    bad = np.flatnonzero((got != want).any(axis=1))
    assert bad.size == 0, (f"{bad.size} of 5000 differ, first at {q[bad[0]]}: "
                           f"{got[bad[0]]} vs {want[bad[0]]}")
    assert np.any(ladder.program.reversal != 0) and np.any(negative)
