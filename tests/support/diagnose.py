"""Simulated campaigns with one hidden effect, for the diagnosis test and
``benchmarks/diagnosis_hit_rate.py``: ``make_case`` picks the effect, axis, sensor and
size from a seed, ``run_case`` diagnoses the campaign and says whether it found them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Backlash, Effects, Noise, Periodic, ThermalDrift, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.thermal import default_thermal
from machine_sim.truth import random_geometry
from volumetric.diagnose.diagnosis import diagnose
from volumetric.model.machine import Machine, parse_machine

CHAINS = ["w X Y b Z t", "w b Y X Z t", "w X b Y Z t", "w Y b X Z t"]


KINDS = ["none", "backlash", "periodic", "thermal_drift", "thermal_expansion"]


N_CASES = 25


def machine_for(chain: str) -> Machine:
    return parse_machine({"name": "m", "chain": chain, "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})


@dataclass(frozen=True)
class Case:
    seed: int
    chain: str
    kind: str
    axis: str | None
    sensor: str | None
    size: dict[str, float]
    effects: Effects


def make_case(seed: int) -> Case:
    rng = np.random.default_rng(1000 + seed)
    chain = CHAINS[seed % len(CHAINS)]
    kind = KINDS[seed % len(KINDS)]
    axis = str(rng.choice(["x", "y", "z"]))
    noise = Noise(float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.2, 0.6)))
    sensors = default_thermal(machine_for(chain)).names
    sensor: str | None = None
    size: dict[str, float] = {}
    if kind == "none":
        return Case(seed, chain, kind, None, None, {}, Effects(noise=noise))
    if kind == "backlash":
        size = {"reversal_um": float(rng.uniform(2, 15))}
        eff = Effects(backlash=(Backlash(axis, size["reversal_um"]),), noise=noise)
    elif kind == "periodic":
        size = {"amplitude_um": float(rng.uniform(0.8, 5)), "period_mm": float(rng.uniform(5, 25))}
        eff = Effects(periodic=(Periodic(axis, size["amplitude_um"], size["period_mm"],
                                         float(rng.uniform(0, 6.28))),), noise=noise)
    elif kind == "thermal_drift":
        sensor = str(rng.choice([s for s in sensors if s != "air"]))
        k = float(rng.uniform(0.5, 5)) * float(rng.choice([-1, 1]))
        size = {"um_per_K": k}
        eff = Effects(drift=(ThermalDrift(axis, sensor, k),), noise=noise)
    else:
        sensor = str(rng.choice([s for s in sensors if s.endswith("screw") or s == "column"]))
        alpha = float(rng.uniform(2, 12))
        size = {"um_per_m_K": alpha}
        eff = Effects(expansion=(ThermalExpansion(axis, sensor, alpha),), noise=noise)
    return Case(seed, chain, kind, axis, sensor, size, eff)


def run_case(case: Case) -> tuple[bool, str]:
    m = machine_for(case.chain)
    rng = np.random.default_rng(case.seed)
    sim = SimulatedMachine(m, random_geometry(m, rng), case.effects, seed=case.seed)
    d = diagnose(m, standard_campaign(sim, rng))
    said = f"{d.effect} {d.axis} {d.sensor} {d.estimate}"
    if case.kind == "none":
        return d.effect == "none", said
    if (d.effect, d.axis) != (case.kind, case.axis):
        return False, said
    if case.sensor is not None and d.sensor != f"T_{case.sensor}_C":
        return False, said
    for key, true in case.size.items():
        got = d.estimate[key]
        if key == "reversal_um" or key == "amplitude_um":
            true = abs(true)
        if not abs(got - true) <= 0.3 * abs(true):
            return False, said
    return True, said
