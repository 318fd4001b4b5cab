"""One scan of the PLC program of ``plc/`` (IEC 61131-3 Structured Text) on a 5-axis
factored map: operations counted, and microseconds of the code MATIEC's iec2c and gcc -O2
make of it.

    .venv/bin/python benchmarks/plc_scan.py [--map tests/vectors/factored_5axis.bin]
        [--scans 20000]

Operations per scan are counted from the map (its tables, factors, terms, axes) with the
per-step counts of protocol/README.md §6.5 as ``plc/ednc_factored.st`` writes them
(plc/README.md lists them per step): a table lookup 14 (one 64-bit multiply), a constant 2,
a basis factor 3 (one multiply), a term's add 2, the thermal step 5 per axis (one
multiply), the clamp 3 per axis, the rounding 4 per rotary axis and per choice 3 per
rotary and 2R + 7 per linear axis (R + 1 multiplies), 1 compare; reversal, final clamp and
step limit 8 per axis. The time is the compiled program's whole scan (window protocol,
status, evaluation), measured through ctypes: the same scans with no map applied are
timed too (protocol and status alone), the one scan that takes the map in (copy, CRC-32,
decode), and the Python PLC's evaluation of one point
(``machine_sim.lookup.FactoredLadder``, numpy on one row) in the same run for the ratio.
The S7-1500 estimate multiplies the operations by the CPU classes' published fixed-point
instruction times (datasheets: CPU 1511 96 ns, 1515 48 ns, 1516 16 ns, 1518 1 ns),
doubled for 64-bit words: an estimate, not a measurement.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from machine_sim.lookup import FactoredLadder
from machine_sim.stplc import StPlc
from protocol.ctrlmem import plan_map_write
from protocol.mapfactored import FactoredPayload, decode_factored

ROOT = Path(__file__).resolve().parent.parent
S7_FIXED_NS = {"CPU 1511": 96, "CPU 1515": 48, "CPU 1516": 16, "CPU 1518": 1}


def operations(p: FactoredPayload) -> tuple[int, int]:
    """(operations, of which 64-bit multiplies) of one scan's evaluation of ``p``."""
    d = len(p.axes)
    rot = sum(a.rotary for a in p.axes)
    lin = d - rot
    ops = mul = 0
    for table_n in [len(b.values) for b in p.bases] + [len(t.values) for t in p.terms]:
        ops += 14 if table_n > 1 else 2
        mul += 1 if table_n > 1 else 0
    for t in p.terms:
        ops += 3 * len(t.factors) + 2
        mul += len(t.factors)
    ops += (5 + 3 + 8) * d
    mul += d
    if rot and lin:
        choices = 1 << rot
        ops += 4 * rot + choices * (3 * rot + lin * (2 * rot + 7) + 1)
        mul += choices * lin * (rot + 1)
    return ops, mul


def scan_time_us(var: Any, scan: Callable[[], None], rows: list[list[int]]) -> float:
    """Mean time of one compiled scan, µs: each row of axis counts written into the
    program's ``q`` variable (``var``, a ctypes array) and ``scan()`` called, less the
    same loop without the scan (the Python side's share)."""
    t0 = time.perf_counter()
    for row in rows:
        var[:len(row)] = row
        scan()
    t1 = time.perf_counter()
    for row in rows:
        var[:len(row)] = row
    t2 = time.perf_counter()
    return ((t1 - t0) - (t2 - t1)) / len(rows) * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--map", type=Path, default=ROOT / "tests/vectors/factored_5axis.bin")
    ap.add_argument("--scans", type=int, default=20_000)
    args = ap.parse_args()
    data = args.map.read_bytes()
    p = decode_factored(data)
    axes = [a.name for a in p.axes]
    rng = np.random.default_rng(1)
    lo = np.array([a.start for a in p.axes])
    hi = np.array([a.start + ((a.count - 1) << a.shift) for a in p.axes])
    q = (lo + (hi - lo) * rng.random((args.scans, len(axes)))).astype(np.int64)
    rows = q.tolist()

    def timed(plc: StPlc) -> float:
        return scan_time_us(plc.program.var("q"), plc.program.scan, rows)

    idle = StPlc(p.machine, axes)
    idle.scan([0] * len(axes))
    with_map = StPlc(p.machine, axes)
    with_map.scan([0] * len(axes))
    switches = []
    for seq in range(1, 8):   # the switch: copy, CRC-32, decode, swap (best of 7)
        for w in plan_map_write(with_map.layout, 1 + seq % 2, data, p.version, seq):
            with_map.window[w.offset:w.offset + len(w.data)] = w.data
        t0 = time.perf_counter()
        with_map.scan([0] * len(axes))
        switches.append((time.perf_counter() - t0) * 1e6)
    t_switch = min(switches)
    assert with_map.state & 1, "the map was not applied"
    t_idle = min(timed(idle) for _ in range(3))
    t_map = min(timed(with_map) for _ in range(3))
    ladder = FactoredLadder(p)
    mm = q[:2000].astype(float) / p.counts_per_unit
    t0 = time.perf_counter()
    for i in range(mm.shape[0]):
        ladder.counts(mm[i:i + 1])
    t_py = (time.perf_counter() - t0) / mm.shape[0] * 1e6
    ops, mul = operations(p)
    print(f"map {args.map.name}: {len(data)} bytes, {len(axes)} axes "
          f"({sum(a.rotary for a in p.axes)} rotary), {len(p.bases)} basis tables, "
          f"{len(p.terms)} terms, {len(p.thermal)} thermal records")
    print(f"operations per scan (evaluation): {ops}, of which {mul} 64-bit multiplies")
    print(f"compiled ST scan (gcc -O2 of iec2c's C): {t_map:.2f} µs with the map, "
          f"{t_idle:.2f} µs without (window protocol and status); the scan that "
          f"handles the switch (copy, CRC-32, decode): {t_switch:.0f} µs")
    print(f"Python PLC, one point (FactoredLadder): {t_py:.1f} µs, "
          f"{t_py / max(t_map, 1e-9):.0f}x the compiled scan")
    for cpu, ns in S7_FIXED_NS.items():
        est = ops * 2 * ns / 1000.0
        print(f"S7-1500 {cpu} estimate: {est:.0f} µs per scan "
              f"({'fits' if est <= 1000 else 'exceeds'} the 1 ms budget)")


if __name__ == "__main__":
    main()
