"""One scan of the PLC program of ``plc/`` on a 5-axis tables map (format version 2,
protocol/README.md §6.3, ``FB_TablesEval`` of ``plc/ednc_tables.st``, LREAL): operations
counted, and microseconds of the code MATIEC's iec2c and gcc -O2 make of it.

    .venv/bin/python benchmarks/plc_scan_tables.py [--map tests/vectors/tables_5axis.bin]
        [--scans 5000]

The map is the tables vector (the demo's 5-axis trunnion, ``w C A X Y b Z t``, as the center
builds it, in int32 counts; two thermal records at readings). Timed: the evaluation block
alone (a harness program that runs ``FB_TablesEval`` once per scan at held readings), the
whole program (``PRG_Ednc``: window protocol, status, evaluation, reversal, clamp, step
limit) with the map applied through its window and without a map, and in the same run the
Python evaluation of one point by ``ednc lookup``'s code (``machine_sim.lookup.TablesMap``,
numpy on one row) for the ratio. By default each scan solves from dq = 0 (the
refinement's steps until no step exceeds 1e-7, as ``ednc lookup``); with the block's
``oneStep`` it takes one step from the last scan's dq (§6.3 allows it), measured too.

Operations per scan are counted from the map's structure and the scan's own refinement
steps and Jacobi sweeps (the block reports both), per step as ``plc/ednc_tables.st``
writes it: an LREAL multiply, add, subtract, divide, compare or a SIN, COS, ATAN or SQRT
is one operation (the transcendental ones counted apart too). The S7-1500 estimate
multiplies the operations by the CPU classes' published floating-point instruction times
(datasheets: CPU 1511 384 ns, 1515 192 ns, 1516 64 ns, 1518 6 ns) and adds 10 such times
per transcendental call: an estimate, not a measurement.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # tests.support, run as a script

from benchmarks.plc_scan import scan_time_us  # noqa: E402
from machine_sim.lookup import TablesMap  # noqa: E402
from machine_sim.stplc import StPlc  # noqa: E402
from protocol.ctrlmem import plan_map_write  # noqa: E402
from protocol.maptables import TablesPayload, decode_tables  # noqa: E402
from tests.support.sttables import TablesHarness  # noqa: E402

TABLES_FORMATS = 0x1D  # int32 values, tables, thermal records, factored maps
S7_FLOAT_NS = {"CPU 1511": 384, "CPU 1515": 192, "CPU 1516": 64, "CPU 1518": 6}


def operations(p: TablesPayload, steps: float, sweeps: float) -> tuple[float, float]:
    """(operations, of which SIN/COS/ATAN/SQRT) of one scan of ``p`` with ``steps``
    refinement steps and ``sweeps`` Jacobi sweeps, as the ST writes each step."""
    names = p.axis_names
    a, k, s = len(names), len(p.outputs), len(p.spindles)
    orient = any(w > 0 for sp in p.spindles for w in sp.weights[3:])
    rows = (6 if orient else 3) * s
    rotary = [x.rotary for x in p.axes]
    outputs = {o.name for o in p.outputs}
    links = [[names.index(n) for n in sp.axes] for sp in p.spindles]
    ops = trig = 0.0
    ops += a                                                   # positions / P
    ops += sum(4 if r.kind == 1 else 7 for r in p.thermal)     # thermal constants
    ops += 4 * sum(rotary)                                     # nominal turns
    trig += 2 * sum(rotary)
    for ln in links:                                           # nominal walk, Jacobian
        for j in ln:
            ops += 21 if rotary[j] else 6
            if rotary[j]:
                ops += 45 + (45 + (18 if orient else 0) if names[j] in outputs else 0)
            elif names[j] in outputs:
                ops += 18
    ops += rows
    trig += rows                                               # sqrt of the weights
    pairs = k * (k - 1) / 2
    ops += k * (4 * rows + 1) + k * (2 * rows + 1) + k * rows * (4 * k + 2)
    trig += 2 * k
    ops += sweeps * pairs * (6 * rows + 4) + max(sweeps - 1, 0) * pairs * (12 + 6 * rows
                                                                           + 6 * k)
    trig += sweeps * pairs + max(sweeps - 1, 0) * pairs * 2
    per_step = k + 10 * len(p.tables) + 49 * a + 4 * len(p.thermal)
    per_step += sum(30 for x in p.axes if len(x.name) > 1)     # spindle axes' frames
    per_step += sum(180 if rotary[j] else 69 for ln in links for j in ln)
    per_step += s * (6 + (73 if orient else 0)) + k * (2 * rows + 3)
    step_trig = 2 * sum(1 for ln in links for j in ln if rotary[j]) + (2 * s if orient
                                                                       else 0)
    ops += steps * per_step
    trig += steps * step_trig
    return ops + trig, trig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--map", type=Path, default=ROOT / "tests/vectors/tables_5axis.bin")
    ap.add_argument("--scans", type=int, default=5_000)
    args = ap.parse_args()
    data = args.map.read_bytes()
    p = decode_tables(data)
    vec = args.map.with_suffix(".json")
    temps_c: dict[str, float] = (json.loads(vec.read_text())["temperatures_C"]
                                 if vec.exists() else {})
    sensors = list(dict.fromkeys(r.sensor for r in p.thermal))
    axes = list(p.axis_names)
    rng = np.random.default_rng(1)
    lo = np.array([x.travel[0] for x in p.axes])
    hi = np.array([x.travel[1] for x in p.axes])
    # a moving machine: every axis on a sine over its travel, 1 ms scans, up to 10 m/min
    # (60 deg/s); and random points, each far from the last (the Jacobi sweeps' worst)
    t = np.arange(args.scans)[:, None] * 1e-3
    amp = 0.45 * (hi - lo)
    speed = np.where([x.rotary for x in p.axes], 60.0, 166.7)   # mm/s, deg/s
    omega = speed / amp * rng.uniform(0.5, 1.0, len(axes))
    path = 0.5 * (lo + hi) + amp * np.sin(omega * t + rng.uniform(0, 6.3, len(axes)))
    scattered = lo + (hi - lo) * rng.random((args.scans, len(axes)))

    fb = TablesHarness(p.machine, axes)
    code, failed = fb.load(data)
    assert code == 0 and not failed, (code, failed)
    fb.set_readings([round(temps_c.get(s, 20.0) * 1000) for s in sensors])
    var, scan = fb.program.var("q"), fb.program.scan

    def counted(rows: list[list[int]]) -> tuple[float, float]:
        """Mean refinement steps and Jacobi sweeps per scan over ``rows``."""
        steps = sweeps = 0
        for row in rows:
            var[:len(row)] = row
            scan()
            steps += int(fb.program.var("steps")[0])
            sweeps += int(fb.program.var("sweeps")[0])
        return steps / len(rows), sweeps / len(rows)

    figures = {}
    for name, q, one_step in (("moving", path, 0), ("scattered", scattered, 0),
                         ("moving, oneStep", path, 1)):
        fb.program.var("oneStep")[0] = one_step
        rows = np.floor(q * 1000 + 0.5).astype(np.int64).tolist()
        n_steps, n_sweeps = counted(rows)
        t_fb = min(scan_time_us(var, scan, rows) for _ in range(3))
        figures[name] = (n_steps, n_sweeps, t_fb, rows)
    fb.program.var("oneStep")[0] = 0
    whole = StPlc(p.machine, axes, formats=TABLES_FORMATS)
    whole.scan([0] * len(axes))
    for w in plan_map_write(whole.layout, 1, data, p.version, 1):
        whole.window[w.offset:w.offset + len(w.data)] = w.data
    whole.scan([0] * len(axes))
    assert whole.state & 1, "the map was not applied"
    idle = StPlc(p.machine, axes, formats=TABLES_FORMATS)
    idle.scan([0] * len(axes))
    rows = figures["moving"][3]
    t_map = min(scan_time_us(whole.program.var("q"), whole.program.scan, rows) for _ in range(3))
    t_idle = min(scan_time_us(idle.program.var("q"), idle.program.scan, rows) for _ in range(3))
    tm = TablesMap.from_payload(p, {s: temps_c.get(s, 20.0) for s in sensors})
    mm = path[:1000]
    t0 = time.perf_counter()
    for i in range(mm.shape[0]):
        tm.lookup(mm[i:i + 1])
    t_py = (time.perf_counter() - t0) / mm.shape[0] * 1e6
    print(f"map {args.map.name}: {len(data)} bytes, {len(axes)} chain axes "
          f"({sum(x.rotary for x in p.axes)} rotary), {len(p.spindles)} spindle(s), "
          f"{len(p.tables)} tables of {sum(len(t.values) for t in p.tables)} values, "
          f"{len(p.locations)} location errors, {len(p.thermal)} thermal records")
    for name, (n_steps, n_sweeps, t_fb, _) in figures.items():
        ops, trig = operations(p, n_steps, n_sweeps)
        print(f"{name} ({args.scans} scans): {n_steps:.2f} refinement steps, "
              f"{n_sweeps:.2f} Jacobi sweeps per scan (mean); {ops:.0f} operations, "
              f"{trig:.0f} of them SIN/COS/ATAN/SQRT; FB_TablesEval alone "
              f"{t_fb:.2f} µs per scan (gcc -O2 of iec2c's C)")
    n_steps, n_sweeps, t_fb, _ = figures["moving"]
    ops, trig = operations(p, n_steps, n_sweeps)
    print(f"compiled ST, whole program PRG_Ednc (moving): {t_map:.2f} µs per scan with the map, "
          f"{t_idle:.2f} µs without (window protocol and status)")
    print(f"Python, one point (ednc lookup's TablesMap): {t_py:.1f} µs, "
          f"{t_py / max(t_fb, 1e-9):.0f}x the compiled block (moving)")
    one, one_trig = operations(p, *figures["moving, oneStep"][:2])
    for cpu, ns in S7_FLOAT_NS.items():
        est = (ops + 9 * trig) * ns / 1000.0
        est1 = (one + 9 * one_trig) * ns / 1000.0
        print(f"S7-1500 {cpu} estimate (moving): {est:.0f} µs per scan "
              f"({'fits' if est <= 1000 else 'exceeds'} the 1 ms budget); with oneStep "
              f"{est1:.0f} µs")


if __name__ == "__main__":
    main()
