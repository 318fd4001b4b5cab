"""Five-axis machines with periodic rotary error motions: fit, compensate, apply to the truth.

Run: ``.venv/bin/python benchmarks/diagnosis_rotary.py [N] [--polynomial]`` (the latter:
rotary components as polynomials of the angle, as before the Fourier basis). For N seeds,
a machine of the demo's ``5ax-04`` chain and pivots (``w C A X b Y Z t``, C a full turn,
A ±110°) gets a random rigid geometry whose rotary components are replaced by once- and
twice-per-turn error motions (:func:`machine_sim.truth.rotary_error_motions`:
eccentricity, axial runout, wobble, cyclic indexing error), measured by the standard
campaign plus R-tests of both rotary axes at four more ball positions (:data:`BALLS`;
rotary positioning, linear-axis tests, 0.25 µm noise). The model of ``ednc fit``
(:func:`volumetric.identify.fit.fit`) gives the corrections of
:func:`volumetric.compensate.solver.compensate` at random points of the workspace; the
corrections are applied to the true machine and the worst tool-tip position error is
reported before and after (up to a constant offset, the workpiece zero), with
``ednc diagnose``'s answer on the same readings.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math
import sys
import time

import numpy as np

from machine_sim.campaign import run_campaign, standard_programs
from machine_sim.effects import Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.program import Dwell
from machine_sim.testprograms import rtest
from machine_sim.truth import random_geometry, rotary_error_motions
from volumetric.compensate.solver import compensate
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify import design
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements
from volumetric.model.components import GeometricErrors
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine, parse_machine

FIVE_AXIS = {"name": "5ax", "chain": "w C A X b Y Z t",
             "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0], "a": [-110, 110],
                           "c": [-180, 180]},
             "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
             "tool_length_mm": 100.0}


# R-test balls (workpiece frame, mm) reachable over each rotary axis's whole sweep, spread
# along and around the axis so that every rotation of the axis moves some ball.
BALLS = {"C": [(300.0, 300.0, -400.0), (450.0, 300.0, -100.0), (400.0, 200.0, -250.0),
               (400.0, 400.0, -150.0)],
         "A": [(50.0, 300.0, -250.0), (450.0, 300.0, -100.0), (250.0, 350.0, -150.0),
               (450.0, 250.0, -150.0)]}


def five_axis_campaign(sim: SimulatedMachine, rng: np.random.Generator) -> Measurements:
    """The standard campaign plus R-tests of both rotary axes at four balls each."""
    programs = standard_programs(sim.machine, rng)
    for axis, balls in BALLS.items():
        for k, ball in enumerate(balls, start=3):
            programs += [[Dwell(120.0)], rtest(sim.machine, axis, ball,
                                              label=f"{axis}-rtest-{k}", runs=1)]
    return run_campaign(sim, programs).measurements


def worst_tool_tip_um(machine: Machine, truth: GeometricErrors, model: GeometricErrors,
                      q: np.ndarray) -> tuple[float, float]:
    """Worst tool-tip position error (µm) at q, uncompensated and with the model's
    corrections applied to the true machine."""
    nominal, _ = tool_pose(machine, q, orientation=False)
    before, _ = tool_pose(machine, q, truth, orientation=False)
    c = compensate(machine, model, q)
    after, _ = tool_pose(machine, q + c.dq, truth, orientation=False)
    # a constant offset is the workpiece zero, which the user sets by probing: no reading
    # can tell it from a shifted part, so both sides are judged up to it
    d0 = before - nominal
    d1 = after - nominal
    e0 = np.linalg.norm(d0 - d0.mean(axis=0), axis=1) * 1e3
    e1 = np.linalg.norm(d1 - d1.mean(axis=0), axis=1) * 1e3
    return float(e0.max()), float(e1.max())


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    n = int(args[0]) if args else 6
    if "--polynomial" in sys.argv:
        # the model as it was: polynomial components for every rotary axis
        design.PERIODIC_SPAN_DEG = math.inf
    machine = parse_machine(FIVE_AXIS)
    gains = []
    for seed in range(n):
        rng = np.random.default_rng(700 + seed)
        base = random_geometry(machine, rng)
        truth = GeometricErrors({**base.components, **rotary_error_motions(machine, rng)},
                                base.locations)
        sim = SimulatedMachine(machine, truth, Effects(noise=Noise(0.25, 0.25)), seed=seed)
        meas = five_axis_campaign(sim, rng)
        t0 = time.perf_counter()
        result = fit(machine, meas)
        t_fit = time.perf_counter() - t0
        q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], 3000)
                             for a in machine.axes])
        before, after = worst_tool_tip_um(machine, truth, result.model.geometry, q)
        gain = 1.0 - after / before
        gains.append(gain)
        t0 = time.perf_counter()
        d = diagnose(machine, meas)
        t_diag = time.perf_counter() - t0
        print(f"seed {seed}: {len(meas)} readings, fit rms {result.rms} ({t_fit:.1f} s); "
              f"worst tool tip {before:.1f} -> {after:.2f} µm ({100 * gain:.1f} % better); "
              f"diagnose: {d.effect} {d.axis} {d.estimate} held-out {d.rms_before_um:.2f} -> "
              f"{d.rms_after_um:.2f} µm ({t_diag:.1f} s); every effect named: "
              f"{[(e['effect'], e['axis']) for e in d.details.get('effects', [])]}",
              flush=True)
    print(f"gain: min {100 * min(gains):.1f} %, median {100 * float(np.median(gains)):.1f} %")


if __name__ == "__main__":
    main()
