"""Rotary axes as they are: periodic error motions are identified and compensated.

A five-axis machine of the demo's chain and pivots (C a full turn, A ±110°) gets a random
rigid geometry with smooth (polynomial) rotary components, then a hidden periodic error
motion on C: a random order per turn (1 to 3), random amplitudes and phases on every
component of C. The diagnosis's base is the model ``ednc fit`` gives (harmonics up to 4
per turn on both rotary axes), so such a motion is the base's, not an effect: the
diagnosis names nothing and the base leaves only the noise (a cyclic error beyond the
base's harmonics is ``tests/test_diagnose_five_axis.py``'s); a smooth machine is not
called periodic; and the model ``ednc fit`` identifies must make the worst tool-tip error
97 % smaller when its corrections are applied to the true machine.
"""

from __future__ import annotations

import numpy as np
import pytest

from machine_sim.campaign import run_campaign, standard_campaign, standard_programs
from machine_sim.effects import Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.program import Dwell
from machine_sim.testprograms import rtest
from machine_sim.truth import random_geometry, rotary_error_motions
from volumetric.compensate.solver import compensate
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify.fit import fit
from volumetric.model.components import Component, GeometricErrors, Polynomial, Table
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine, parse_machine

FIVE_AXIS = {"name": "5ax", "chain": "w C A X b Y Z t",
             "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0], "a": [-110, 110],
                           "c": [-180, 180]},
             "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
             "tool_length_mm": 100.0}
NOISE = Noise(0.25, 0.25)


def smooth_rotary(machine: Machine, geometry: GeometricErrors, rng: np.random.Generator
                  ) -> GeometricErrors:
    """The geometry with smooth rotary components: a cubic of the angle on A (±110°), none
    on C (over a full turn an error must come back to itself, which a cubic does not: a
    perfect table apart from its location errors)."""
    comps: dict[str, Component] = dict(geometry.components)
    for a in machine.axes:
        if a.kind == "rotary":
            for c in "XYZABC":
                size = 3.0 if c in "XYZ" else 15.0
                coef = (0.0, *(rng.uniform(-1, 1, 3) * size)) if a.name == "A" else (0.0,)
                comps[f"E{c}{a.name}"] = Polynomial(coef, 0.0, 180.0)
    return GeometricErrors(comps, geometry.locations)


def hidden_harmonic(machine: Machine, geometry: GeometricErrors, rng: np.random.Generator,
                    order: int) -> tuple[GeometricErrors, float]:
    """Add an ``order``-per-turn error motion to every component of C; returns the new
    geometry and the true indexing (ECC) amplitude, µrad."""
    q = np.linspace(-180.0, 180.0, 145)
    theta = np.deg2rad(q)
    comps: dict[str, Component] = dict(geometry.components)
    index_amp = 0.0
    for c in "XYZABC":
        amp = float(rng.uniform(3.0, 8.0) if c in "XYZ" else rng.uniform(15.0, 40.0))
        ph = float(rng.uniform(0, 2 * np.pi))
        base = geometry.components[f"E{c}C"](q)
        comps[f"E{c}C"] = Table(tuple(q.tolist()),
                                tuple((base + amp * np.sin(order * theta + ph)).tolist()))
        if c == "C":
            index_amp = amp
    return GeometricErrors(comps, geometry.locations), index_amp


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_low_order_rotary_error_motion_is_the_bases_not_an_effect(seed: int) -> None:
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(4200 + seed)
    order = int(rng.integers(1, 4))
    smooth = smooth_rotary(machine, random_geometry(machine, rng), rng)
    truth, _ = hidden_harmonic(machine, smooth, rng, order)
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=seed)
    d = diagnose(machine, standard_campaign(sim, rng))
    assert d.effect == "none", (d.effect, d.axis, d.candidates[:3])
    assert not any(e["effect"] == "rotary_periodic" for e in d.details["effects"])
    assert d.rms_before_um < 1.2 * NOISE.displacement_um  # the base carries the motion


def test_smooth_rotary_axes_are_not_called_periodic() -> None:
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(77)
    truth = smooth_rotary(machine, random_geometry(machine, rng), rng)
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=5)
    d = diagnose(machine, standard_campaign(sim, rng))
    assert d.effect == "none", d.candidates[:3]


# R-test balls reachable over each rotary axis's sweep, spread along and around the axis
BALLS = {"C": [(300.0, 300.0, -400.0), (450.0, 300.0, -100.0), (400.0, 200.0, -250.0),
               (400.0, 400.0, -150.0)],
         "A": [(50.0, 300.0, -250.0), (450.0, 300.0, -100.0), (250.0, 350.0, -150.0),
               (450.0, 250.0, -150.0)]}


def test_compensation_with_periodic_rotary_components_removes_97_percent() -> None:
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(31)
    base = random_geometry(machine, rng)
    truth = GeometricErrors({**base.components, **rotary_error_motions(machine, rng)},
                            base.locations)
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=2)
    programs = standard_programs(machine, rng)
    for axis, balls in BALLS.items():
        for k, ball in enumerate(balls, start=3):
            programs += [[Dwell(120.0)], rtest(machine, axis, ball, label=f"{axis}-rtest-{k}")]
    model = fit(machine, run_campaign(sim, programs).measurements).model
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], 2000) for a in machine.axes])
    nominal, _ = tool_pose(machine, q, orientation=False)
    before, _ = tool_pose(machine, q, truth, orientation=False)
    after, _ = tool_pose(machine, q + compensate(machine, model.geometry, q).dq, truth,
                         orientation=False)
    # up to a constant offset: the workpiece zero, which no reading can tell from the part
    e0 = before - nominal
    e1 = after - nominal
    worst0 = float(np.linalg.norm(e0 - e0.mean(axis=0), axis=1).max()) * 1e3
    worst1 = float(np.linalg.norm(e1 - e1.mean(axis=0), axis=1).max()) * 1e3
    assert worst0 > 50.0
    assert worst1 <= 0.03 * worst0, (worst0, worst1)
