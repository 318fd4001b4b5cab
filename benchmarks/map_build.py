"""Error-map build time and size for a 3-axis and a 5-axis machine, and lookup throughput.

    .venv/bin/python benchmarks/map_build.py

Prints, per machine: build time, grid, nodes, payload bytes and the worst interpolation
error on the independent check set; then the vectorised ``ErrorMap.lookup`` against a plain
per-point Python loop over the same map, measured in the same run.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.gridmap import ErrorMap, build_map
from volumetric.model.components import GeometricErrors, Polynomial, component_names, location_names
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]


def errors(m: Machine, rng: np.random.Generator, size: float) -> GeometricErrors:
    """Cubic component errors (coefficients ~size µm or µrad over the travel) and location
    errors of ~2·size: tens of µm at the tool tip, as on an uncompensated machining centre."""
    comps = {}
    for a in m.axes:
        lo, hi = a.travel
        for n in component_names(a):
            comps[n] = Polynomial(tuple(rng.normal(0, size, 4)), lo, hi - lo)
    return GeometricErrors(comps, {n: float(rng.normal(0, 2 * size)) for n in location_names(m)})


def naive_lookup(m: ErrorMap, p: F64) -> F64:
    out = np.empty((p.shape[0], len(m.outputs)))
    for n, row in enumerate(p):
        acc = np.zeros(len(m.outputs))
        base, frac = [], []
        for g, x in zip(m.grid, row, strict=True):
            x = min(max(float(x), g.start), g.stop)
            i = min(int((x - g.start) // g.step), g.count - 2)
            base.append(i)
            frac.append((x - g.start) / g.step - i)
        for corner in np.ndindex(*([2] * len(m.grid))):
            w = math.prod(f if c else 1 - f for c, f in zip(corner, frac, strict=True))
            acc += w * m.values[tuple(b + c for b, c in zip(base, corner, strict=True))]
        out[n] = acc
    return out


def bench(label: str, spec: dict[str, object], tolerance_um: float, controller: str) -> None:
    m = parse_machine(spec)
    geo = errors(m, np.random.default_rng(2024), 5.0)
    t0 = time.perf_counter()
    emap = build_map(m, MachineModel(m.name, geo), tolerance_um=tolerance_um,
                     controller="fanuc" if controller == "fanuc" else "siemens")
    build_s = time.perf_counter() - t0
    r = emap.report
    assert r is not None
    grid = " x ".join(f"{g.name}{g.count}" for g in emap.grid)
    print(f"{label}: built in {build_s:.2f} s, grid {grid} = {r.nodes} nodes, "
          f"{r.bytes} bytes, worst interpolation {r.worst_interpolation_um:.3f} µm "
          f"(tolerance {tolerance_um} µm), as sent ({controller}) {r.worst_error_um:.3f} µm, "
          f"{r.rounds} round(s)")
    rng = np.random.default_rng(0)
    lo = np.array([g.start for g in emap.grid])
    hi = np.array([g.stop for g in emap.grid])
    pts = lo + (hi - lo) * rng.random((200_000, len(emap.grid)))
    t0 = time.perf_counter()
    fast = emap.lookup(pts)
    fast_s = time.perf_counter() - t0
    few = pts[:2000]
    t0 = time.perf_counter()
    slow = naive_lookup(emap, few)
    slow_s = time.perf_counter() - t0
    assert np.allclose(slow, fast[:2000], atol=1e-12)
    print(f"  lookup: vectorised {pts.shape[0] / fast_s / 1e6:.2f} M points/s, "
          f"per-point loop {few.shape[0] / slow_s / 1e3:.1f} k points/s "
          f"(x{(slow_s / few.shape[0]) / (fast_s / pts.shape[0]):.0f})")


def main() -> None:
    bench("3-axis vmc (w X Y b Z t)", {
        "name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
        "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
    }, 0.5, "fanuc")
    trunnion = {
        "name": "trunnion", "chain": "w C A X Y b Z t", "tool_length_mm": 100.0,
        "travel_mm": {"x": [-250, 250], "y": [-200, 200], "z": [-300, 0],
                      "a": [-120, 30], "c": [-180, 180]},
        "pivots_mm": {"A": [0.0, 0.0, 50.0]},
    }
    for tolerance in (1.0, 0.5):
        bench("5-axis trunnion (w C A X Y b Z t)", trunnion, tolerance, "siemens")
    bench("5-axis trunnion (w C A X Y b Z t)", trunnion, 1.0, "fanuc")

if __name__ == "__main__":
    main()
