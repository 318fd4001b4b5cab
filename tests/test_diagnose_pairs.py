"""Several effects at once: a campaign hiding two effects of different families gets both
named, each with its axis, sensor and size within 30 %; a clean one gets none.

Each case draws its chain, the two families, their axes, sensors, sizes (the realistic
ranges of :mod:`machine_sim.effects`) and the noise from its seed;
``benchmarks/diagnosis_pairs.py`` runs the same kind of cases by the hundred.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest

from machine_sim.campaign import run_campaign, standard_campaign
from machine_sim.effects import Backlash, Effects, Noise, Periodic, ThermalDrift, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.testprograms import rtest
from machine_sim.thermal import default_thermal
from machine_sim.truth import random_geometry
from volumetric.diagnose.base import base_without
from volumetric.diagnose.candidates import along_axes, candidates
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify.design import build_design
from volumetric.identify.fit import fit
from volumetric.model.machine import Machine, parse_machine

CHAINS = ["w X Y b Z t", "w b Y X Z t", "w X b Y Z t", "w Y b X Z t"]
FIVE_AXIS = {"name": "5ax", "chain": "w C A X b Y Z t",
             "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0], "a": [-110, 110],
                           "c": [-180, 180]},
             "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
             "tool_length_mm": 100.0}
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


def test_an_effect_along_an_axis_is_read_turned_with_the_rotary_table() -> None:
    """An R-test's readings turn with the table: a backlash of Y shows on the x reading at
    C = 90°. The candidates' direction is the simulator's exact image of the effect, not
    the reading's own y component (which misses it by the whole backlash)."""
    machine = parse_machine(FIVE_AXIS)
    geometry = random_geometry(machine, np.random.default_rng(3))
    program = [rtest(machine, "C", (400.0, 200.0, -250.0))]
    b = 6.0
    m = run_campaign(SimulatedMachine(machine, geometry, Effects(backlash=(Backlash("y", b),)),
                                      seed=1), program).measurements
    clean = run_campaign(SimulatedMachine(machine, geometry, Effects(), seed=1),
                         program).measurements
    seen = m.value - clean.value
    along = along_axes(machine, m)
    assert np.abs(seen - (-0.5 * b * m.direction[:, 1] * along[:, 1])).max() < 1e-3
    # the reading's own component is not it (what the check above would otherwise pass)
    assert np.abs(seen - (-0.5 * b * m.direction[:, 1] * m.u[:, 1])).max() > 0.5 * b
    # a three-axis machine reads the axes' directions as they are
    three = machine_for(CHAINS[2])
    m3 = standard_campaign(SimulatedMachine(three, random_geometry(three, np.random.default_rng(4)),
                                            Effects(), seed=2), np.random.default_rng(5))
    expected = np.where(m3.is_angle[:, None], 0.0, m3.u)
    assert np.array_equal(along_axes(three, m3), expected)


@pytest.mark.parametrize(("seed", "kinds"), [(0, ("backlash", "thermal_drift")),
                                             (2, ("thermal_expansion", "backlash"))])
def test_a_five_axis_pair_on_one_axis_is_named_and_sized(seed: int, kinds: tuple[str, str]
                                                         ) -> None:
    """Both effects on the same linear axis of a five-axis machine whose campaign holds
    R-tests of both rotary axes (readings in the turning table's frame)."""
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(7300 + seed)
    sensors = list(default_thermal(machine).names)
    t1, e1 = one_effect(kinds[0], rng, sensors)
    t2, e2 = one_effect(kinds[1], rng, [s for s in sensors if s != t1["sensor"]])
    axis = str(rng.choice(["x", "y", "z"]))
    t1, t2 = {**t1, "axis": axis}, {**t2, "axis": axis}
    eff = Effects(expansion=tuple(replace_axis(e, axis) for e in e1.expansion + e2.expansion),
                  drift=tuple(replace_axis(e, axis) for e in e1.drift + e2.drift),
                  backlash=tuple(replace_axis(e, axis) for e in e1.backlash + e2.backlash),
                  periodic=tuple(replace_axis(e, axis) for e in e1.periodic + e2.periodic),
                  noise=Noise(0.3, 0.4))
    sim = SimulatedMachine(machine, random_geometry(machine, rng), eff, seed=seed)
    effects = diagnose(machine, standard_campaign(sim, rng)).to_json()["effects"]
    assert named(t1, effects) and named(t2, effects), (t1, t2, effects)


def replace_axis(effect: Any, axis: str) -> Any:
    return dataclasses.replace(effect, axis=axis)


def test_the_base_degrees_are_chosen_again_without_the_named_effects() -> None:
    """A 12 µm backlash in the readings makes BIC take the rigid model's higher degrees
    for noise; chosen again on the readings with the fitted backlash taken out, they are
    what the same machine without the backlash gets."""
    machine = machine_for(CHAINS[1])
    geometry = random_geometry(machine, np.random.default_rng(11))
    noise = Noise(0.2, 0.3)
    m = standard_campaign(SimulatedMachine(machine, geometry, Effects(
        backlash=(Backlash("z", 12.0),), noise=noise), seed=3), np.random.default_rng(12))
    clean = standard_campaign(SimulatedMachine(machine, geometry, Effects(noise=noise), seed=3),
                              np.random.default_rng(12))
    base = fit(machine, m, fourier=False)
    reference = fit(machine, clean, fourier=False)

    def distance(a: dict[str, int], b: dict[str, int]) -> int:
        return sum(abs(a.get(k, -1) - b.get(k, -1)) for k in set(a) | set(b))

    assert distance(base.degrees, reference.degrees) >= 10  # the premise: BIC was misled
    design = build_design(machine, m, fourier=False)
    a0 = design.matrix[:, design.columns([p.name for p in base.params])]
    train = np.ones(len(m), dtype=bool)
    found, _ = candidates(machine, m, m.value, train, base.params)
    backlash = [c for c in found if (c.effect, c.axis) == ("backlash", "z")]
    again = base_without(machine, m, train, a0, base.weights, backlash, base)
    assert again is not None
    assert distance(again.degrees, reference.degrees) <= 2, (again.degrees, reference.degrees)
    # its values are fitted on the readings as they are, the backlash beside them unmodelled
    assert again.values.shape == (len(again.params),)
    assert base_without(machine, m, train, a0, base.weights, [], base) is None
