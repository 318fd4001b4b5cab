"""Rotary axes as they are: periodic error motions are identified, compensated and named.

A five-axis machine of the demo's chain and pivots (C a full turn, A ±110°) gets a random
rigid geometry with smooth (polynomial) rotary components, then a hidden periodic error
motion on C: a random order per turn (1 to 3), random amplitudes and phases on every
component of C. The diagnosis must name ``rotary_periodic`` on ``c`` with that order and
the indexing amplitude within 30 %; a smooth machine must not be called periodic; and the
model ``ednc fit`` identifies must make the worst tool-tip error 97 % smaller when its
corrections are applied to the true machine.
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
from volumetric.diagnose.candidates import RotaryFits, candidates
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
def test_a_hidden_periodic_rotary_error_motion_is_named_with_its_order(seed: int) -> None:
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(4200 + seed)
    order = int(rng.integers(1, 4))
    smooth = smooth_rotary(machine, random_geometry(machine, rng), rng)
    truth, index_amp = hidden_harmonic(machine, smooth, rng, order)
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=seed)
    d = diagnose(machine, standard_campaign(sim, rng))
    assert (d.effect, d.axis) == ("rotary_periodic", "c"), d.candidates[:3]
    assert d.estimate["order"] == order
    got = d.estimate["components"]["ECC"][str(order)]
    assert abs(got - index_amp) <= 0.3 * index_amp, (got, index_amp)
    assert d.rms_after_um < 1.2 * NOISE.displacement_um  # what is left is the noise


def test_smooth_rotary_axes_are_not_called_periodic() -> None:
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(77)
    truth = smooth_rotary(machine, random_geometry(machine, rng), rng)
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=5)
    d = diagnose(machine, standard_campaign(sim, rng))
    assert d.effect == "none", d.candidates[:3]


def test_the_rotary_fits_serve_another_base_on_the_same_readings() -> None:
    # the diagnosis refits its base (other degrees) on the same readings and keeps the
    # rotary candidates' rigid fits: with them kept, a candidate must be what a fresh
    # library gives for the new base, replacing all of the new base's columns
    machine = parse_machine(FIVE_AXIS)
    rng = np.random.default_rng(4200)
    truth, _ = hidden_harmonic(machine, smooth_rotary(machine, random_geometry(machine, rng),
                                                      rng), rng, 2)
    m = standard_campaign(SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=0), rng)
    train = np.ones(len(m), dtype=bool)
    resid = np.zeros(len(m))
    params = fit(machine, m, fourier=False).params
    kept: RotaryFits = {}
    first = [c for c in candidates(machine, m, resid, train, params, kept)[0]
             if c.effect == "rotary_periodic"]
    # both axes travel far enough for harmonics (C a full turn, A 220°)
    assert [c.axis for c in first] == ["c", "a"] and set(kept) == {"C", "A"}
    fitted = dict(kept)
    fewer = params[:-4]
    again = [c for c in candidates(machine, m, resid, train, fewer, kept)[0]
             if c.effect == "rotary_periodic"]
    fresh = [c for c in candidates(machine, m, resid, train, fewer)[0]
             if c.effect == "rotary_periodic"]
    assert all(kept[k] is fitted[k] for k in fitted)  # not fitted again
    assert [c.axis for c in again] == [c.axis for c in fresh] == ["c", "a"]
    for a, f in zip(again, fresh, strict=True):
        assert a.drop == f.drop == tuple(range(len(fewer)))
        np.testing.assert_array_equal(a.columns, f.columns)


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
