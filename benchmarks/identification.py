"""Identification time of the full 3-axis model from 100,000 readings, one core; and
``ednc fit`` / ``ednc diagnose`` on a file of 2 million readings on disk (issue 14, item 2).

Run: ``.venv/bin/python benchmarks/identification.py [--readings N]`` (0: in memory only).

In memory. Readings: random points in the
workspace, random sensing directions, 20 % angles, three tool lengths, 0.3 µm/µrad noise,
from a true geometry of cubic components and squareness errors. Reports the time of
:func:`volumetric.identify.fit.fit` (design matrix, degree selection, null-space analysis,
re-weighting, uncertainties) and, as the naive peer, a plain ``numpy.linalg.lstsq`` on the
full design matrix at the maximal degrees (no selection, no identifiability analysis,
which it cannot do), measured in the same run.

From a file. The benchmark writes a campaign of ``--readings`` readings (2 million: 40
probing tests of 5 runs, 20 % angles, four drifting temperature sensors, a spindle_rpm
column; about 510 MB) into a temporary directory and runs, each as a child process whose
wall time and peak RSS (``os.wait4``) are reported:

* ``ednc fit`` (the file read block by block into accumulated normal equations);
* the whole-file path for comparison: :func:`read_measurements` then :func:`fit`
  (readings in memory, the design still in blocks);
* ``ednc diagnose --json`` (its default ``--max-readings`` draw).

Targets (issue 14): fit <= 15 s and <= 1 GB, diagnose <= 60 s and <= 1.5 GB. On this
shared machine wall times depend on the load: the benchmark prints ``os.getloadavg()``
before and after each run and each child's CPU time (user + system), which depends on it
much less. BLAS is held to one thread (as above) for every child.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv

from volumetric.identify.design import build_design
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements
from volumetric.model.components import GeometricErrors, Polynomial, component_names, location_names
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import parse_machine

VMC = {"name": "bench", "chain": "w X Y b Z t", "tool_length_mm": 100,
       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}}
EDNC = str(Path(sys.executable).parent / "ednc")


def write_campaign_file(path: Path, n: int, seed: int = 0) -> int:
    """A measurement CSV of about ``n`` readings (formats.md section 2); returns the count.

    40 tests one after the other, 5 runs each; random points, approach directions and
    sensing directions, three tool lengths, 20 % angles, cubic component errors and
    location errors, 0.3 µm/µrad noise, four temperature sensors on slow sines.
    """
    rng = np.random.default_rng(seed)
    m = parse_machine(VMC)
    comps = {}
    for a in m.axes:
        for name in component_names(a):
            c = rng.normal(0, 4 if name[1] in "XYZ" else 8, 4)
            c[0] = 0
            comps[name] = Polynomial(tuple(c), a.travel[0], a.travel[1] - a.travel[0])
    truth = GeometricErrors(comps, {k: float(rng.normal(0, 20)) for k in location_names(m)})
    tests, runs = 40, 5
    per = max(n // (tests * runs), 1)
    n = per * tests * runs
    with path.open("wb") as fh:
        header = ["test", "run", "time_s", "x_mm", "y_mm", "z_mm", "dir_x", "dir_y", "dir_z",
                  "tool_mm", "quantity", "ux", "uy", "uz", "value", "spindle_rpm",
                  "T_t1_C", "T_t2_C", "T_t3_C", "T_t4_C"]
        fh.write((",".join(header) + "\n").encode())
        for start in range(0, n, 200_000):  # in slices: the generator stays small too
            k = min(200_000, n - start)
            i = np.arange(start, start + k)
            t = i * 0.05
            q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], k) for a in m.axes])
            tool = rng.choice([0.0, 100.0, 200.0], k)
            u = rng.normal(size=(k, 3))
            u /= np.linalg.norm(u, axis=1)[:, None]
            ang = rng.random(k) < 0.2
            ve = volumetric_error(m, truth, q, tool_mm=tool)
            assert ve.orientation_urad is not None
            val = np.where(ang, np.einsum("ni,ni->n", u, ve.orientation_urad),
                           np.einsum("ni,ni->n", u, ve.position_um)) + rng.normal(0, 0.3, k)
            d = rng.choice(np.array([-1, 1], np.int8), (k, 3))
            cols = {
                "test": [f"probe-{j:02d}" for j in i // (per * runs)],
                "run": i // per % runs + 1, "time_s": t,
                "x_mm": q[:, 0], "y_mm": q[:, 1], "z_mm": q[:, 2],
                "dir_x": d[:, 0], "dir_y": d[:, 1], "dir_z": d[:, 2], "tool_mm": tool,
                "quantity": np.where(ang, "angle", "displacement"),
                "ux": u[:, 0], "uy": u[:, 1], "uz": u[:, 2], "value": val,
                "spindle_rpm": rng.choice([0.0, 8000.0], k),
                **{f"T_t{s}_C": 20 + 2 * np.sin(t / 3600 * s) + rng.normal(0, 0.01, k)
                   for s in range(1, 5)},
            }
            pacsv.write_csv(pa.table(cols), fh, write_options=pacsv.WriteOptions(
                include_header=False, quoting_style="none"))
    return n


def run_child(args: list[str]) -> tuple[float, float, float, str]:
    """Wall time (s), CPU time (user + system, s), peak RSS (GB) of one child process
    (``os.wait4``: this child alone) and its stdout."""
    load = os.getloadavg()[0]
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        child = subprocess.Popen(args, stdout=out, stderr=err, text=True)
        _, status, usage = os.wait4(child.pid, 0)
        wall = time.perf_counter() - t0
        child.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        text, problem = out.read(), err.read()
    if child.returncode != 0:
        raise SystemExit(f"{' '.join(args[:2])} failed: {problem}")
    print(f"    (load average {load:.1f} before, {os.getloadavg()[0]:.1f} after)")
    cpu = usage.ru_utime + usage.ru_stime
    return wall, cpu, usage.ru_maxrss / 1e6, text  # ru_maxrss: kB on Linux


def from_file(n: int) -> None:
    with tempfile.TemporaryDirectory(prefix="ednc-bench-") as tmp:
        data = Path(tmp) / "campaign.csv"
        machine = Path(tmp) / "machine.json"
        machine.write_text(json.dumps(VMC))
        t0 = time.perf_counter()
        n = write_campaign_file(data, n)
        print(f"file: {n} readings, {data.stat().st_size / 1e6:.0f} MB, written in "
              f"{time.perf_counter() - t0:.0f} s")
        whole = ("import sys; from volumetric.identify.fit import fit; "
                 "from volumetric.measure.measurement import read_measurements; "
                 "from volumetric.model.machine import load_machine; "
                 "r = fit(load_machine(sys.argv[1]), read_measurements(sys.argv[2])); "
                 "print(r.rms)")
        runs = [
            ("ednc fit (blocks)", [EDNC, "fit", "--machine", str(machine), "--data", str(data)],
             15.0, 1.0),
            ("whole file, then fit()", [sys.executable, "-c", whole, str(machine), str(data)],
             None, None),
            ("ednc diagnose --json", [EDNC, "diagnose", "--machine", str(machine), "--data",
                                      str(data), "--json"], 60.0, 1.5),
        ]
        for label, args, t_max, gb_max in runs:
            wall, cpu, gb, _ = run_child(args)
            verdict = ""
            if t_max is not None and gb_max is not None:
                ok = wall <= t_max and gb <= gb_max
                verdict = f"  target <= {t_max:g} s, <= {gb_max:g} GB: {'met' if ok else 'NOT met'}"
            print(f"{label:24s} {wall:7.1f} s wall, {cpu:6.1f} s CPU, peak RSS {gb:5.2f} GB"
                  f"{verdict}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--readings", type=int, default=2_000_000,
                        help="readings in the file on disk (0: skip that part)")
    args = parser.parse_args()
    in_memory()
    if args.readings > 0:
        from_file(args.readings)


def in_memory() -> None:
    rng = np.random.default_rng(0)
    m = parse_machine({"chain": "w X Y b Z t", "tool_length_mm": 100,
                       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})
    comps = {}
    for a in m.axes:
        for n in component_names(a):
            c = rng.normal(0, 4 if n[1] in "XYZ" else 8, 4)
            c[0] = 0
            comps[n] = Polynomial(tuple(c), a.travel[0], a.travel[1] - a.travel[0])
    truth = GeometricErrors(comps, {k: float(rng.normal(0, 20)) for k in location_names(m)})
    n = 100_000
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in m.axes])
    tool = rng.choice([0.0, 100.0, 200.0], n)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    ang = rng.random(n) < 0.2
    ve = volumetric_error(m, truth, q, tool_mm=tool)
    assert ve.orientation_urad is not None
    val = np.where(ang, np.einsum("ni,ni->n", u, ve.orientation_urad),
                   np.einsum("ni,ni->n", u, ve.position_um)) + rng.normal(0, 0.3, n)
    meas = Measurements(test=np.array(["random"] * n), run=np.zeros(n, np.int64),
                        time_s=np.arange(n, dtype=float),
                        q=np.column_stack([q, np.zeros((n, 3))]),
                        direction=np.zeros((n, 3), np.int8), tool_mm=tool, is_angle=ang, u=u,
                        value=val)
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        r = fit(m, meas)
        best = min(best, time.perf_counter() - t0)
    t0 = time.perf_counter()
    design = build_design(m, meas)
    np.linalg.lstsq(design.matrix, val, rcond=None)
    naive = time.perf_counter() - t0
    print(f"readings {n}, parameters identified {len(r.params)}, "
          f"not identifiable {len(r.unidentifiable)}")
    print(f"ednc fit: {best:.2f} s (best of 3); residual RMS {r.rms}")
    print(f"plain lstsq on the full design at maximal degrees: {naive:.2f} s "
          f"(ratio {naive / best:.2f})")


if __name__ == "__main__":
    main()
