"""Writes the test vectors of protocol/README.md section 6 (run from the repository root):

    PYTHONPATH=. .venv/bin/python tests/vectors/make.py [factored grid grid_ties tables]

Each ``<name>.bin`` is a map payload as the machine receives it; ``<name>.json`` gives the
temperatures, the points (in mm or degrees and in counts), the approach direction of each
axis and the counts the Fanuc-style ladder writes there (``machine_sim/ladder.py``). The
files are committed; this script is how they were made (``README.md`` here says what each
holds). Regenerate only when the format or its arithmetic changes on purpose.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.map_build import TRUNNION, errors  # noqa: E402
from machine_sim.lookup import FactoredLadder, GridLadder, positions_in_counts  # noqa: E402
from protocol import ErrorMapPayload, GridAxis, MapEncoding, OutputAxis, pack_values  # noqa: E402
from protocol.mapfactored import decode_factored  # noqa: E402
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
    which = sys.argv[1:] or ["factored", "grid", "grid_ties", "tables"]
    for name in which:
        {"factored": factored, "grid": grid, "grid_ties": grid_ties, "tables": tables}[name]()


if __name__ == "__main__":
    main()
