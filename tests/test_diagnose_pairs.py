"""Several effects at once: a campaign hiding two effects of different families gets both
named, each with its axis, sensor and size within 30 %; a clean one gets none.

Each case draws its chain, the two families, their axes, sensors, sizes (the realistic
ranges of :mod:`machine_sim.effects`) and the noise from its seed;
``benchmarks/diagnosis_pairs.py`` runs the same kind of cases by the hundred.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

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


def one_effect(kind: str, rng: np.random.Generator, sensors: list[str]
               ) -> tuple[dict[str, Any], Effects]:
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
        s = str(rng.choice([x for x in sensors if x != "air"]))
        k = float(rng.uniform(0.5, 5)) * float(rng.choice([-1, 1]))
        return ({"effect": kind, "axis": axis, "sensor": s, "size": {"um_per_K": k}},
                Effects(drift=(ThermalDrift(axis, s, k),)))
    s = str(rng.choice([x for x in sensors if x.endswith("screw") or x == "column"]))
    alpha = float(rng.uniform(2, 12))
    return ({"effect": kind, "axis": axis, "sensor": s, "size": {"um_per_m_K": alpha}},
            Effects(expansion=(ThermalExpansion(axis, s, alpha),)))


def named(truth: dict[str, Any], effects: list[dict[str, Any]]) -> bool:
    for e in effects:
        if (e["effect"], e["axis"]) != (truth["effect"], truth["axis"]):
            continue
        if truth["sensor"] is not None and e["sensor"] != f"T_{truth['sensor']}_C":
            continue
        return all(abs(e["estimate"][k] - (abs(v) if k in ("reversal_um", "amplitude_um")
                                            else v)) <= 0.3 * abs(v)
                   for k, v in truth["size"].items())
    return False


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_two_hidden_effects_of_different_families_are_both_named_and_sized(seed: int) -> None:
    rng = np.random.default_rng(7000 + seed)
    m = machine_for(CHAINS[int(rng.integers(len(CHAINS)))])
    sensors = list(default_thermal(m).names)
    k1, k2 = (str(k) for k in rng.choice(FAMILIES, 2, replace=False))
    t1, e1 = one_effect(k1, rng, sensors)
    t2, e2 = one_effect(k2, rng, [s for s in sensors if s != t1["sensor"]])
    eff = Effects(expansion=e1.expansion + e2.expansion, drift=e1.drift + e2.drift,
                  backlash=e1.backlash + e2.backlash, periodic=e1.periodic + e2.periodic,
                  noise=Noise(float(rng.uniform(0.1, 0.4)), float(rng.uniform(0.2, 0.6))))
    sim = SimulatedMachine(m, random_geometry(m, rng), eff, seed=seed)
    d = diagnose(m, standard_campaign(sim, rng))
    effects = d.to_json()["effects"]
    assert named(t1, effects) and named(t2, effects), (t1, t2, effects)
    assert effects[0]["effect"] == d.effect  # the strongest is the top-level answer
    # each entry's RMS counts the effects up to it: it can only fall
    rms = [e["rms_after_um"] for e in effects]
    assert rms == sorted(rms, reverse=True) and d.rms_after_um == pytest.approx(rms[-1], abs=1e-3)


def test_a_clean_campaign_names_no_effect_at_all() -> None:
    rng = np.random.default_rng(7100)
    m = machine_for(CHAINS[1])
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.3, 0.4)), seed=4)
    d = diagnose(m, standard_campaign(sim, rng))
    assert d.effect == "none" and d.to_json()["effects"] == []
