"""What Siemens CEC exports leave at the tool tip (the table of docs/native-exports.md).

    .venv/bin/python benchmarks/native_exports.py [--seeds N]

Per machine and control: random true geometries of ``machine_sim.truth.random_geometry``
(seeds 0..N-1) exported as the model (``volumetric.compensate.cec.cec_export``), the file
written (``cec_text``) and read back by the independent evaluator of the tests
(``tests/support/cec_eval.py``, the K3 manual's rules on the file's text), applied to the
model's exact tool-tip error on 4,000 random points (100 mm tool). Printed: tables, worst
tool-tip error before and after, the drop (also with each axis's mean error removed
before and after: the constant the workpiece zero absorbs), and the time to export.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from machine_sim.truth import random_geometry  # noqa: E402
from tests.support import cec_eval  # noqa: E402
from volumetric.compensate.cec import cec_export  # noqa: E402
from volumetric.compensate.cec_check import tool_tip, tool_tip_error  # noqa: E402
from volumetric.compensate.cec_text import CecFile, cec_text  # noqa: E402
from volumetric.model.machine import parse_machine  # noqa: E402

MACHINES = {
    "3-axis w X Y b Z t": {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
                           "travel_mm": {"x": [0, 800], "y": [0, 500], "z": [-500, 0]}},
    "5-axis w C A X b Y Z t": {
        "name": "5ax", "chain": "w C A X b Y Z t", "tool_length_mm": 100.0,
        "pivots_mm": {"A": [400, 300, -250], "C": [400, 300, -250]},
        "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0], "a": [-110, 110],
                      "c": [-180, 180]}},
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=10)
    args = ap.parse_args()
    print("machine | control | tables | worst before µm | worst after µm | drop % | "
          "drop % with each axis's mean removed | s")
    for label, spec in MACHINES.items():
        m = parse_machine(spec)
        cols = {f"{a.name}1": i for i, a in enumerate(m.axes)}
        rng = np.random.default_rng(1)
        q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], 4000) for a in m.axes])
        for control, lec in (("840d", False), ("828d", False), ("828d", True)):
            rows = []
            for seed in range(args.seeds):
                geo = random_geometry(m, np.random.default_rng(seed))
                t0 = time.perf_counter()
                e = cec_export(m, geo, tool_mm=100.0, control=control, positioning=not lec)
                text = cec_text(e, tool_tip(m, geo, e, n=500), machine_name=m.name,
                                model_note="benchmark", f=CecFile())
                dt = time.perf_counter() - t0
                dq = cec_eval.compensation(cec_eval.parse(text), cols, q)
                eb = tool_tip_error(m, geo, q, 0 * q, 100.0)
                ea = tool_tip_error(m, geo, q, dq, 100.0)
                before, after = np.linalg.norm(eb, axis=1), np.linalg.norm(ea, axis=1)
                zb = np.linalg.norm(eb - eb.mean(axis=0), axis=1).max()
                za = np.linalg.norm(ea - ea.mean(axis=0), axis=1).max()
                rows.append((len(e.tables), before.max(), after.max(), dt, zb, za))
            r = np.array(rows)
            drop = 100 * (1 - r[:, 2] / r[:, 1])
            zdrop = 100 * (1 - r[:, 5] / r[:, 4])
            name = control + (" --lec (EXX.. not written)" if lec else "")
            print(f"{label} | {name} | {int(r[:, 0].min())}-{int(r[:, 0].max())} | "
                  f"{r[:, 1].min():.1f}-{r[:, 1].max():.1f} | {r[:, 2].min():.2f}-"
                  f"{r[:, 2].max():.2f} | {drop.min():.1f}-{drop.max():.1f} (median "
                  f"{np.median(drop):.1f}) | mean removed {zdrop.min():.1f}-{zdrop.max():.1f} "
                  f"| {r[:, 3].max():.2f}")


if __name__ == "__main__":
    main()
