"""Two hidden effects at once: are both named, with estimates within 30 %?

Run: ``.venv/bin/python benchmarks/diagnosis_pairs.py [N]``. For N seeds, a three-axis
machine (one of four chains) with a random true geometry gets two effects of different
families (backlash, ballscrew periodic, thermal drift, thermal expansion), each on a random
axis with a random size in the realistic ranges of :mod:`machine_sim.effects`, and random
noise (0.1 to 0.4 µm); the standard campaign measures it and :func:`diagnose` must list
both in ``effects`` (axis and, for thermal ones, sensor right; size within 30 %). Prints
per case what was hidden and found, the hit rate and the time per diagnosis.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys
import time
from typing import Any

import numpy as np

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Backlash, Effects, Noise, Periodic, ThermalDrift, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.thermal import default_thermal
from machine_sim.truth import random_geometry
from volumetric.diagnose.diagnosis import diagnose
from volumetric.model.machine import Machine, parse_machine

CHAINS = ["w X Y b Z t", "w b Y X Z t", "w X b Y Z t", "w Y b X Z t"]
FAMILIES = ["backlash", "periodic", "thermal_drift", "thermal_expansion"]


def machine_for(chain: str) -> Machine:
    return parse_machine({"name": "m", "chain": chain, "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})


def hidden(kind: str, rng: np.random.Generator, sensors: tuple[str, ...], used: set[str]
           ) -> tuple[dict[str, Any], Effects]:
    """One effect of ``kind``: (what diagnose should say, the Effects holding it)."""
    axis = str(rng.choice(["x", "y", "z"]))
    if kind == "backlash":
        b = float(rng.uniform(2, 15))
        return ({"effect": kind, "axis": axis, "sensor": None, "size": {"reversal_um": b}},
                Effects(backlash=(Backlash(axis, b),)))
    if kind == "periodic":
        a, p = float(rng.uniform(0.8, 5)), float(rng.uniform(5, 25))
        return ({"effect": kind, "axis": axis, "sensor": None,
                 "size": {"amplitude_um": a, "period_mm": p}},
                Effects(periodic=(Periodic(axis, a, p, float(rng.uniform(0, 6.28))),)))
    if kind == "thermal_drift":
        s = str(rng.choice([x for x in sensors if x != "air" and x not in used]))
        k = float(rng.uniform(0.5, 5)) * float(rng.choice([-1, 1]))
        return ({"effect": kind, "axis": axis, "sensor": f"T_{s}_C", "size": {"um_per_K": k}},
                Effects(drift=(ThermalDrift(axis, s, k),)))
    s = str(rng.choice([x for x in sensors if (x.endswith("screw") or x == "column")
                        and x not in used]))
    alpha = float(rng.uniform(2, 12))
    return ({"effect": kind, "axis": axis, "sensor": f"T_{s}_C", "size": {"um_per_m_K": alpha}},
            Effects(expansion=(ThermalExpansion(axis, s, alpha),)))


def found(truth: dict[str, Any], effects: list[dict[str, Any]]) -> bool:
    for e in effects:
        if (e["effect"], e["axis"]) != (truth["effect"], truth["axis"]):
            continue
        if truth["sensor"] is not None and e["sensor"] != truth["sensor"]:
            continue
        return all(abs(e["estimate"][k] - abs(v) if k in ("reversal_um", "amplitude_um")
                       else e["estimate"][k] - v) <= 0.3 * abs(v)
                   for k, v in truth["size"].items())
    return False


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    hits = 0
    times = []
    for seed in range(n):
        rng = np.random.default_rng(5000 + seed)
        chain = CHAINS[seed % len(CHAINS)]
        m = machine_for(chain)
        sensors = default_thermal(m).names
        kinds = rng.choice(FAMILIES, 2, replace=False)
        t1, e1 = hidden(str(kinds[0]), rng, sensors, set())
        t2, e2 = hidden(str(kinds[1]), rng, sensors,
                        {str(t1["sensor"])[2:-2]} if t1["sensor"] else set())
        eff = Effects(expansion=e1.expansion + e2.expansion, drift=e1.drift + e2.drift,
                      backlash=e1.backlash + e2.backlash, periodic=e1.periodic + e2.periodic,
                      noise=Noise(float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.2, 0.6))))
        sim = SimulatedMachine(m, random_geometry(m, rng), eff, seed=seed)
        readings = standard_campaign(sim, rng)
        t0 = time.perf_counter()
        d = diagnose(m, readings)
        times.append(time.perf_counter() - t0)
        effects = d.details.get("effects", [])
        ok = found(t1, effects) and found(t2, effects)
        hits += ok
        said = [(e["effect"], e["axis"], e["sensor"]) for e in effects]
        print(f"seed {seed} {chain}: hidden {t1['effect']} {t1['axis']} {t1['sensor']} + "
              f"{t2['effect']} {t2['axis']} {t2['sensor']}; found {said} "
              f"{'OK' if ok else 'MISS'} ({times[-1]:.1f} s)", flush=True)
    print(f"pairs found: {hits}/{n}; diagnosis {np.median(times):.1f} s median, "
          f"{max(times):.1f} s worst")


if __name__ == "__main__":
    main()
