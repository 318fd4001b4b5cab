"""Exact volumetric error throughput over 1,000,000 grid points, against a naive loop.

Run: ``.venv/bin/python benchmarks/volumetric_throughput.py``. One core
(OMP/OPENBLAS threads pinned to 1). The naive approach is the textbook one: one 4x4
homogeneous transform per link and per point, multiplied in a Python loop; it runs on a
sample of points and its rate is measured on that sample in the same run.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time

import numpy as np
from numpy.typing import NDArray

from volumetric.model.components import GeometricErrors, Polynomial, component_names, location_names
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Machine, parse_machine


def realistic_errors(m: Machine, rng: np.random.Generator) -> GeometricErrors:
    comps = {}
    for a in m.axes:
        span = a.travel[1] - a.travel[0]
        for n in component_names(a):
            comps[n] = Polynomial(tuple(rng.normal(0, 5, 5)), a.travel[0], span)
    return GeometricErrors(comps, {n: float(rng.normal(0, 20)) for n in location_names(m)})


def grid(m: Machine, n_total: int) -> NDArray[np.float64]:
    per = round(n_total ** (1 / len(m.axes)))
    axes = [np.linspace(a.travel[0], a.travel[1], per) for a in m.axes]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel() for g in mesh])


def naive_rate(m: Machine, e: GeometricErrors, q: NDArray[np.float64]) -> float:
    """Points per second of the per-point 4x4 loop (the helper in tests/support/kinematics.py)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.support.kinematics import naive_pose

    t0 = time.perf_counter()
    for row in q:
        naive_pose(m, e, row)
        naive_pose(m, None, row)
    return len(q) / (time.perf_counter() - t0)


def main() -> None:
    rng = np.random.default_rng(0)
    machines = {
        "3-axis (w X Y b Z t)": parse_machine({"chain": "w X Y b Z t", "tool_length_mm": 100,
            "travel_mm": {"x": [0, 800], "y": [0, 650], "z": [-500, 0]}}),
        "5-axis (w C A X b Y Z t)": parse_machine({"chain": "w C A X b Y Z t",
            "tool_length_mm": 100,
            "travel_mm": {"x": [0, 800], "y": [0, 650], "z": [-500, 0], "a": [-120, 120],
                          "c": [0, 360]}, "pivots_mm": {"A": [0, 0, -150]}}),
    }
    head = ("machine", "points", "s", "points/s", "naive/s", "ratio")
    print("{:28s} {:>9s} {:>7s} {:>12s} {:>9s} {:>7s}".format(*head))
    for label, m in machines.items():
        e = realistic_errors(m, rng)
        q = grid(m, 1_000_000)
        volumetric_error(m, e, q[:10_000])  # warm-up
        best = float("inf")
        for _ in range(3):
            t0 = time.perf_counter()
            volumetric_error(m, e, q)
            best = min(best, time.perf_counter() - t0)
        rate = len(q) / best
        slow = naive_rate(m, e, q[rng.choice(len(q), 300, replace=False)])
        print(f"{label:28s} {len(q):9d} {best:7.3f} {rate:12,.0f} {slow:9,.0f} {rate / slow:6.0f}x")


if __name__ == "__main__":
    main()
