"""Identification time of the full 3-axis model from 100,000 readings, one core.

Run: ``.venv/bin/python benchmarks/identification.py``. Readings: random points in the
workspace, random sensing directions, 20 % angles, three tool lengths, 0.3 µm/µrad noise,
from a true geometry of cubic components and squareness errors. Reports the time of
:func:`volumetric.identify.fit.fit` (design matrix, degree selection, null-space analysis,
re-weighting, uncertainties) and, as the naive peer, a plain ``numpy.linalg.lstsq`` on the
full design matrix at the maximal degrees (no selection, no identifiability analysis,
which it cannot do), measured in the same run.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time

import numpy as np

from volumetric.identify.design import build_design
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements
from volumetric.model.components import GeometricErrors, Polynomial, component_names, location_names
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import parse_machine


def main() -> None:
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
