"""Fanuc-style 5-axis factored maps (format version 5): bytes as sent at <= 1.0 µm.

    .venv/bin/python benchmarks/factored_size.py [--seeds N] [--basis-deg D]

Issue 24's target: a 5-axis factored map at <= 1.0 µm as sent in <= 8 kB (a small PMC's
data area). Per machine and seed (random cubic component errors of ~5 µm/µrad and
location errors, tens of µm at the tool tip, as in ``benchmarks/map_build.py``): payload
bytes, terms, table values, worst tool-tip error as sent (the endpoint's integer
arithmetic, rotary rounded first) on 8,192 independent random points, and build time.
For comparison, the same map's size in format version 4's layout (int32 values, 16- and
24-byte table headers, 36-byte axis records), computed from the same tables. Then the
test fleet's own Fanuc-style 5-axis machine 5ax-09 (``w C A X b Y Z t``), from the model
fitted to its laser campaign and from its true geometry. ``--basis-deg`` overrides the
spacing of the trigonometric basis tables (``factoredfit.BASIS_STEP_DEG``, 8.192° nodes;
2.0 gives format version 5's first builder, 2.048° nodes) to compare in one session.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.map_build import FIVE_AX_04, TRUNNION, errors  # noqa: E402
from server.mapcodec import encode  # noqa: E402
from tests.support.integration import FANUC_5AX, campaign  # noqa: E402
from volumetric.compensate import factoredfit  # noqa: E402
from volumetric.compensate.factoredmap import FactoredMap, build_factored_map  # noqa: E402
from volumetric.identify.fit import fit  # noqa: E402
from volumetric.model.machine import parse_machine  # noqa: E402
from volumetric.model.model import MachineModel  # noqa: E402


def line(label: str, fm: FactoredMap, build_s: float) -> int:
    """Print one map's row; its encoded size."""
    r = fm.report
    assert r is not None
    size = len(encode(fm))
    print(f"{label}: {size:6,d} B (v4 layout {v4_bytes(fm):6,d} B)"
          f"  {len(fm.terms):3d} terms  {fm.entries:5d} values  as sent "
          f"{r.worst_error_um:.3f} µm (unrounded {r.worst_interpolation_um:.3f})  "
          f"{r.rounds} round(s)  {build_s:5.1f} s", flush=True)
    return size


def v4_bytes(fm: FactoredMap) -> int:
    """The size the same tables took in format version 4 (int32 values)."""
    return (64 + 36 * len(fm.axes) + sum(24 + 4 * b.values.size for b in fm.bases)
            + sum(16 + 4 * t.table.values.size for t in fm.terms) + 4 + 48 * len(fm.thermal))


def main() -> None:
    seeds = int(sys.argv[sys.argv.index("--seeds") + 1]) if "--seeds" in sys.argv else 3
    if "--basis-deg" in sys.argv:
        factoredfit.BASIS_STEP_DEG = float(sys.argv[sys.argv.index("--basis-deg") + 1])
    rows = []
    for spec in (FIVE_AX_04, TRUNNION):
        m = parse_machine({**spec, "controller": "fanuc"})
        for seed in range(seeds):
            geo = errors(m, np.random.default_rng(2024 + seed), 5.0)
            t0 = time.perf_counter()
            fm = build_factored_map(m, MachineModel(m.name, geo), tolerance_um=1.0)
            rows.append(line(f"{m.name:9s} seed {2024 + seed}", fm, time.perf_counter() - t0))
    print(f"largest {max(rows):,d} B, median {int(np.median(rows)):,d} B over {len(rows)} maps")
    sim, readings, _ = campaign(FANUC_5AX.name)
    m = sim.machine
    for label, model in (("fitted", fit(m, readings).model),
                         ("true  ", MachineModel(m.name, sim.geometry))):
        t0 = time.perf_counter()
        fm = build_factored_map(m, model, tolerance_um=1.0)
        line(f"{m.name:9s} {label}   ", fm, time.perf_counter() - t0)

if __name__ == "__main__":
    main()
