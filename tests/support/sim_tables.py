"""A Siemens-style 5-axis machine, a sampled error model and its tables-kind map payload,
for the tests of the machine-side tables lookup."""

from __future__ import annotations

import numpy as np

from protocol import (
    ChainAxis,
    ComponentTable,
    MapEncoding,
    OutputAxis,
    Spindle,
    TablesPayload,
    ThermalRecord,
)
from tests.support.kinematics import arch, machine
from volumetric.compensate.solver import Weights
from volumetric.model.components import GeometricErrors, Table, component_names
from volumetric.model.machine import Machine, parse_machine

FLOAT32 = MapEncoding.FLOAT32_MM
CHAINS = ["w X Y b Z t", "w b Y X Z t", "w Y b X Z t", "w b X Y Z t",  # 3-axis types
          "w C A X Y b Z t", "w A B X Y b Z t", "w C Y b X Z B t", "w Z b X Y A t",
          "w b X Y Z C A t", "w b X Y Z B C t", "arch"]


def random_machine(chain: str, rng: np.random.Generator) -> Machine:
    """A machine of ``chain`` (or the two-spindle arch) with random pivots and tool."""
    if chain == "arch":
        return arch(float(rng.uniform(-10, 10)), float(rng.uniform(15, 45)))
    pivots = {k: rng.uniform(-80, 80, 3).round(3).tolist() for k in "ABC" if k in chain}
    return machine(chain, pivots_mm=pivots, tool_length_mm=float(rng.uniform(0, 200)))


def random_weights(m: Machine, rng: np.random.Generator) -> Weights:
    """Random solver weights; sometimes a second tool tip that does not count."""
    b = len(m.branches)
    pos = rng.uniform(0.1, 10, (b, 3))
    rotary = any(a.kind == "rotary" for a in m.axes)
    ori = rng.uniform(0.0, 3, (b, 3)) if rotary and rng.random() < 0.7 else np.zeros((b, 3))
    if b > 1 and rng.random() < 0.3:
        pos[1] = 0.0  # the second tool tip does not count: its own axis is unobservable
        ori[1] = 0.0
    return Weights(pos, ori)



def random_tables(m: Machine, rng: np.random.Generator, size: float
                  ) -> tuple[dict[str, Table], list[ComponentTable]]:
    """Per component a table (or none, or a constant): a random polynomial sampled on its
    nodes plus noise, float32 as the wire carries it; nodes need not cover the travel."""
    comps: dict[str, Table] = {}
    tables: list[ComponentTable] = []
    for a in m.axes:
        lo, hi = a.travel
        for name in component_names(a):
            kind = rng.integers(0, 5)
            if kind == 0:
                continue
            n = 1 if kind == 1 else int(rng.integers(2, 40))
            start = lo + rng.uniform(-0.1, 0.2) * (hi - lo)
            step = (hi - lo) * rng.uniform(0.8, 1.2) / max(n - 1, 1)
            s = np.linspace(-1, 1, n)
            poly = np.polynomial.polynomial.polyval(s, rng.normal(0, size, 4))
            vals = (poly + rng.normal(0, size / 10, n)).astype(np.float32).astype(float)
            comps[name] = Table(tuple(start + i * step for i in range(n)), tuple(vals))
            tables.append(ComponentTable(name, start, step, tuple(vals)))
    return comps, tables


def tables_payload(m: Machine, tables: list[ComponentTable], locations: dict[str, float],
                   weights: Weights, *, encoding: MapEncoding = FLOAT32, version: int = 1,
                   thermal: tuple[ThermalRecord, ...] = (), limit: float = 1.0,
                   reversal: dict[str, float] | None = None) -> TablesPayload:
    """What a center sends for machine ``m`` (test-side, from the volumetric description)."""
    axes = tuple(ChainAxis(a.name, a.kind == "rotary", a.side == "tool", a.direction,
                           a.pivot_mm, a.travel) for a in m.axes)
    spindles = tuple(Spindle(b.name, tuple(x.name for x in b.links), b.tool_length_mm,
                             b.tool_direction,
                             tuple(float(v) for v in (*weights.position[i],  # type: ignore[arg-type]
                                                      *weights.orientation[i])))
                     for i, b in enumerate(m.branches))
    rev = reversal or {}
    return TablesPayload(m.name, version, encoding, 0,
                         0.001 if encoding is MapEncoding.INT32_INCREMENTS else 0.0, axes,
                         spindles, tuple(OutputAxis(a.name, rev.get(a.name)) for a in m.axes),
                         tuple(tables), tuple(locations.items()), thermal, limit, limit)


def siemens_5ax(name: str = "sim-5ax") -> Machine:
    return parse_machine({"name": name, "controller": "siemens", "ip": "127.0.0.1",
                          "chain": "w C A X Y b Z t", "tool_length_mm": 120.0,
                          "pivots_mm": {"C": [1.0, -2.0, 3.0], "A": [0.0, 5.0, -40.0]},
                          "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0],
                                        "a": [-90, 30]}})


def sample(m: Machine, seed: int = 0) -> tuple[GeometricErrors, list[ComponentTable]]:
    rng = np.random.default_rng(seed)
    comps, tables = random_tables(m, rng, 6.0)
    return GeometricErrors(comps, {"EC0Y": 15.0, "EX0C": 4.0}), tables
