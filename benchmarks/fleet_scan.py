"""PLC cycles of a whole fleet on one core: grid maps (Fanuc ladder) or tables maps.

    .venv/bin/python benchmarks/fleet_scan.py [--machines 1000] [--seconds 10] [--scan-ms 8]
    .venv/bin/python benchmarks/fleet_scan.py --mode tables [--scan-ms 4]
        [--mix "w X Y b Z t=0.5,w C A X Y b Z t=0.5"] [--plc-every 1] [--cold] [--no-compare]

``grid`` (default): 1,000 Fanuc-style machines, each with its own error map (3-D grid,
11 x 7 x 7 nodes, 3 outputs, random origins and spacings); each scan looks every map up
(:class:`machine_sim.lookup.FleetLadder`: multilinear interpolation, quantisation, range
clamp, step limit).

``tables``: Siemens-style machines, each with its own tables map (format version 2): per
axis six ISO 230-1 component tables of 33 points over its travel, the location errors,
orientation weighed on a 5-axis chain. The fleet is a mix of chains (``--mix``: chain and
share, comma separated; ``--chain`` is a mix of one); machines of one chain structure
share one :class:`machine_sim.chaineval.ChainBatch`, so a cycle is one call per chain
(:class:`machine_sim.chaineval_cycle.FleetCycle`): table lookups, the exact chain, the
weighted least-squares solve refined at q + dq, clamp and float32 rounding. Each machine
starts its refinement from its previous cycle's correction (as its PLC would; ``--cold``
starts from zero). ``--plc-every n`` runs each machine's lookup every n-th cycle in n
staggered groups (Siemens' PLC-to-IPO ratio).

Every machine moves along its own path. A cycle is *missed* when it finishes after the end
of its slot (an overrun, whether from its own work or a late wake-up), and every slot that
began and ended meanwhile is missed too. Prints the cycle's compute time (wall: mean, p99,
max), its CPU time (this thread's: mean, p99; the wall time minus what other processes
took from us), and the share of missed cycles; the target is below 1 %. In tables mode
the same cycles are then run, not against the clock, with the straightforward evaluation
(:meth:`~machine_sim.chaineval.ChainBatch.corrections_reference`, rows first) for the
ratio in the same run (``--no-compare`` skips it).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from machine_sim.chaineval import ChainBatch
from machine_sim.lookup import FleetLadder, GridMap
from protocol.codes import MapEncoding
from protocol.mapformat import ErrorMapPayload, GridAxis, OutputAxis
from protocol.maptables import ChainAxis, ComponentTable, Spindle, TablesPayload

F64 = NDArray[np.float64]
TRAVEL = {"X": (0.0, 500.0), "Y": (0.0, 300.0), "Z": (-300.0, 0.0), "A": (-90.0, 30.0),
          "B": (-90.0, 90.0), "C": (-180.0, 180.0)}
UNIT = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def fleet_maps(n: int, rng: np.random.Generator) -> list[GridMap]:
    maps = []
    for i in range(n):
        grid = (GridAxis("X", 0.0, rng.uniform(40, 60), 11),
                GridAxis("Y", 0.0, rng.uniform(40, 60), 7),
                GridAxis("Z", -rng.uniform(280, 320), 50.0, 7))
        values = rng.integers(-60, 60, (11 * 7 * 7, 3)).astype("<i4").tobytes()
        p = ErrorMapPayload(f"m{i:04d}", 1, MapEncoding.INT32_INCREMENTS, grid,
                            (OutputAxis("X"), OutputAxis("Y"), OutputAxis("Z")), values)
        maps.append(GridMap.from_payload(p))
    return maps


def tables_map(name: str, chain: str, rng: np.random.Generator) -> TablesPayload:
    """A Siemens-style machine's tables map: 33-point tables of smooth random errors."""
    tokens = chain.split()
    side = tokens.index("b")
    axes = []
    for i, t in enumerate(tokens[1:-1], start=1):
        if t == "b":
            continue
        rotary = t in "ABC"
        d = UNIT[{"A": "X", "B": "Y", "C": "Z"}.get(t, t)]
        pivot = tuple(rng.uniform(-50, 50, 3).round(2)) if rotary else (0.0, 0.0, 0.0)
        axes.append(ChainAxis(t, rotary, i > side, d, pivot, TRAVEL[t]))
    tables = []
    for a in axes:
        lo, hi = a.travel
        s = np.linspace(-1, 1, 33)
        for c in "XYZABC":
            v = np.polynomial.polynomial.polyval(s, rng.normal(0, 5, 4))
            tables.append(ComponentTable(f"E{c}{a.name}", lo, (hi - lo) / 32, tuple(v)))
    locations = []
    for a in axes:
        for c in ("XYZABC" if a.rotary else "ABC"):
            if a.rotary or (a.name, c) in (("Y", "C"), ("Z", "A"), ("Z", "B")):
                locations.append((f"E{c}0{a.name}", float(rng.normal(0, 20))))
    rotary = any(a.rotary for a in axes)
    weights = (1.0, 1.0, 1.0) + ((1.0, 1.0, 1.0) if rotary else (0.0, 0.0, 0.0))
    spindle = Spindle("main", tuple(a.name for a in axes), 100.0, (0.0, 0.0, -1.0),
                      weights)
    return TablesPayload(name, 1, MapEncoding.FLOAT32_MM, 0, 0.0, tuple(axes), (spindle,),
                         tuple(OutputAxis(a.name) for a in axes), tuple(tables),
                         tuple(locations), limit_mm=0.5, limit_deg=0.5)


def parse_mix(text: str, machines: int) -> list[tuple[str, int]]:
    """``"CHAIN=SHARE,CHAIN=SHARE"`` (a bare chain: share 1) → machines per chain."""
    parts = []
    for item in text.split(","):
        chain, _, share = item.partition("=")
        parts.append((chain.strip(), float(share) if share.strip() else 1.0))
    total = sum(w for _, w in parts)
    if not parts or total <= 0 or any(w < 0 for _, w in parts):
        raise SystemExit(f"--mix {text!r}: give CHAIN=SHARE items with shares >= 0")
    counts = [round(machines * w / total) for _, w in parts]
    counts[-1] = machines - sum(counts[:-1])
    return [(c, n) for (c, _), n in zip(parts, counts, strict=True) if n > 0]


def tables_cycle(args: argparse.Namespace, rng: np.random.Generator
                 ) -> tuple[Callable[[int, F64, bool], None], F64, F64, str]:
    """The fleet's cycle ``cycle(k, q, reference)``, the travel centre and half-range of
    each machine (M, A_max) and a description of the mix."""
    mix = parse_mix(args.mix or args.chain, args.machines)
    batches: list[tuple[ChainBatch, int, list[tuple[NDArray[np.int64], slice]]]] = []
    width = max(len(c.split()) - 3 for c, _ in mix)
    lo = np.zeros((args.machines, width))
    hi = np.ones((args.machines, width))
    first = 0
    for chain, n in mix:
        maps = [tables_map(f"m{first + i:04d}", chain, rng) for i in range(n)]
        batch = ChainBatch(maps)
        rows = np.arange(first, first + n)
        a = len(batch.axes)
        lo[rows, :a] = [x.travel[0] for x in maps[0].axes]
        hi[rows, :a] = [x.travel[1] for x in maps[0].axes]
        # each PLC group: its machines' indices in the batch and, as a slice, their rows
        # of the fleet's positions and of the batch's last corrections (views, no copies)
        groups = [(np.arange(g, n, args.plc_every), slice(g, n, args.plc_every))
                  for g in range(args.plc_every)]
        batches.append((batch, first, groups))
        first += n
    last = [np.zeros((len(b), len(b.outputs))) for b, _, _ in batches]

    def cycle(k: int, q: F64, reference: bool = False) -> None:
        for (batch, at, groups), prev in zip(batches, last, strict=True):
            idx, sel = groups[k % len(groups)]
            start = None if args.cold or k < len(groups) else prev[sel]
            steps = 6 if start is None else args.steps
            qi = q[at:at + len(batch)][sel, :len(batch.axes)]
            solve = batch.corrections_reference if reference else batch.corrections
            c = solve(idx, qi, start, steps)
            prev[sel] = c
            batch.finish(idx, c)

    what = ", ".join(f"{n} x {c!r}" for c, n in mix)
    return cycle, 0.5 * (lo + hi), 0.45 * (hi - lo), what


def run_clock(run: Callable[[int, F64], None], centre: F64, amp: F64, freq: F64,
              period: float, scans: int) -> tuple[F64, F64, int, float]:
    """Cycles against the clock: compute wall and CPU times (ms), missed slots, wall s."""
    compute: list[float] = []
    cpu: list[float] = []
    missed = 0
    t0 = time.perf_counter()
    k = 0
    while k < scans:
        slot = t0 + k * period
        pause = slot - time.perf_counter()
        if pause > 0:
            time.sleep(pause)
        start = time.perf_counter()
        c0 = time.thread_time()
        q = centre + amp * np.sin(2 * np.pi * freq * (k * period))
        run(k, q)
        cpu.append(time.thread_time() - c0)
        done = time.perf_counter()
        compute.append(done - start)
        if done > slot + period:  # this cycle overran its slot
            missed += 1
        # slots that began and ended while this one ran are lost as well
        lost = min(max(int((done - t0) / period) - (k + 1), 0), scans - k - 1)
        missed += lost
        k += 1 + lost
    return (np.array(compute) * 1e3, np.array(cpu) * 1e3, missed,
            time.perf_counter() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mode", choices=("grid", "tables"), default="grid")
    ap.add_argument("--machines", type=int, default=1000)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--scan-ms", type=float, default=None,
                    help="cycle period; 8 ms (grid) or 4 ms (tables) by default")
    ap.add_argument("--chain", default="w C A X Y b Z t",
                    help="tables mode: one chain for the whole fleet (see --mix)")
    ap.add_argument("--mix", default=None,
                    help='tables mode: chains and shares, "w X Y b Z t=0.5,w C A X Y b Z t=0.5"')
    ap.add_argument("--plc-every", type=int, default=1, help="tables mode: PLC/IPO ratio")
    ap.add_argument("--cold", action="store_true", help="tables mode: no warm start")
    ap.add_argument("--steps", type=int, default=1,
                    help="tables mode: refinement steps per cycle from the previous one")
    ap.add_argument("--no-compare", action="store_true",
                    help="tables mode: skip the straightforward evaluation's figure")
    ap.add_argument("--compare-cycles", type=int, default=200,
                    help="tables mode: cycles of the straightforward evaluation")
    args = ap.parse_args()
    scan_ms = args.scan_ms or (8.0 if args.mode == "grid" else 4.0)
    rng = np.random.default_rng(0)
    m = args.machines
    run: Callable[[int, F64], None]
    reference: Callable[[int, F64], None] | None = None
    if args.mode == "grid":
        ladder = FleetLadder(fleet_maps(m, rng))
        centre = np.column_stack([rng.uniform(100, 400, m), rng.uniform(50, 250, m),
                                  rng.uniform(-250, -50, m)])
        amp = rng.uniform(10, 100, (m, 3))
        what = "grid maps, Fanuc ladder"

        def run(k: int, q: F64) -> None:  # k unused: one signature for both modes
            ladder.scan(q)
    else:
        cycle, centre, half, mix = tables_cycle(args, rng)
        amp = half * rng.uniform(0.2, 1.0, half.shape)
        what = (f"tables maps: {mix}; PLC every {args.plc_every} cycle(s), "
                f"{'cold' if args.cold else 'warm'} start")

        def run(k: int, q: F64) -> None:
            cycle(k, q, False)

        if not args.no_compare:
            def reference(k: int, q: F64) -> None:
                cycle(k, q, True)
    freq = rng.uniform(0.05, 0.5, amp.shape)
    period = scan_ms / 1000.0
    scans = int(args.seconds / period)
    run(0, centre)  # warm-up: first-call allocations are not a cycle
    ms, cpu, missed, wall = run_clock(run, centre, amp, freq, period, scans)
    print(f"machines: {m} ({what})")
    print(f"cycle: {scan_ms:g} ms, cycles: {scans}, wall: {wall:.2f} s")
    print(f"cycle compute (wall): mean {ms.mean():.3f} ms, p99 {np.percentile(ms, 99):.3f} ms, "
          f"max {ms.max():.3f} ms ({ms.mean() / scan_ms * 100:.1f} % of the period)")
    print(f"cycle CPU: mean {cpu.mean():.3f} ms, p99 {np.percentile(cpu, 99):.3f} ms")
    print(f"missed cycles: {missed} of {scans} slots "
          f"({missed / scans * 100:.2f} %, target < 1 %)")
    if reference is not None:
        # the same cycles with the straightforward evaluation, back to back (not against
        # the clock: it cannot keep it), for the ratio measured under the same load
        n = args.compare_cycles
        old = np.zeros(n)
        new = np.zeros(n)
        for k in range(n):
            q = centre + amp * np.sin(2 * np.pi * freq * (k * period))
            c0 = time.thread_time()
            reference(k, q)
            old[k] = time.thread_time() - c0
            c0 = time.thread_time()
            run(k, q)
            new[k] = time.thread_time() - c0
        old *= 1e3
        new *= 1e3
        print(f"straightforward evaluation (rows first), {n} cycles interleaved with the "
              f"fleet cycle's: CPU mean {old.mean():.3f} ms, p99 "
              f"{np.percentile(old, 99):.3f} ms; fleet cycle mean {new.mean():.3f} ms, p99 "
              f"{np.percentile(new, 99):.3f} ms ({old.mean() / new.mean():.1f}x)")


if __name__ == "__main__":
    main()
