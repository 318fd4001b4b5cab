"""Five-axis machines of the 12 documented types and their diagnosis campaigns, for
``tests/test_diagnose_five_axis.py`` and ``benchmarks/diagnosis_five_axis.py``.

A machine of type (translational 1-4, rotary 1-3, :mod:`volumetric.model.typenumbers`)
gets the linear travels of the three-axis benchmark, C a full turn, A and B ±110°, pivots
in the middle of the workspace. Its campaign is the standard one
(:func:`machine_sim.campaign.standard_programs`: positioning, straightness, angular,
diagonals, rotary positioning and two R-tests per rotary axis at 12 angles) plus, per
rotary axis, the same R-test set-ups read every :data:`FINE_STEP_DEG` (an R-test with
that angular step resolves cyclic errors up to ``180 / step - 1`` per turn).
"""

from __future__ import annotations

import numpy as np

from machine_sim.campaign import run_campaign, standard_programs
from machine_sim.instruments import SimulatedMachine
from machine_sim.program import Dwell, Program
from machine_sim.testprograms import rtest, rtest_balls
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.typenumbers import chain_for_type_numbers

FINE_STEP_DEG = 2.5
"""Angular step of the fine R-tests (resolves up to 71 per turn)."""
TYPES = [(t, r) for r in (1, 2, 3) for t in (1, 2, 3, 4)]
"""The 12 five-axis types (translational, rotary)."""
TRAVEL = {"x": [0.0, 800.0], "y": [0.0, 600.0], "z": [-500.0, 0.0]}


def five_axis_machine(t: int, r: int) -> Machine:
    """A machine of type (t, r) with C a full turn and A, B ±110°."""
    chain = chain_for_type_numbers(t, r)
    travel: dict[str, list[float]] = dict(TRAVEL)
    pivots: dict[str, list[float]] = {}
    for name in ("A", "B", "C"):
        if name in chain.split():
            travel[name.lower()] = [-180.0, 180.0] if name == "C" else [-110.0, 110.0]
            # workpiece-side axes turn about the table's middle, tool-side ones about
            # the spindle head (the tool tip's start position)
            pivots[name] = [400.0, 300.0, -250.0] if chain.index(name) < chain.index("b") \
                else [0.0, 0.0, 150.0]
    return parse_machine({"name": f"5ax-t{t}r{r}", "chain": chain, "travel_mm": travel,
                          "pivots_mm": pivots, "tool_length_mm": 100.0})


def fine_rtests(machine: Machine, step_deg: float = FINE_STEP_DEG) -> list[Program]:
    """Per rotary axis, its standard R-test set-ups read every ``step_deg`` over their
    angle range (a full turn without repeating its end)."""
    out: list[Program] = []
    for a in machine.axes:
        if a.kind != "rotary":
            continue
        for k, st in enumerate(rtest_balls(machine, a.name), start=1):
            lo, hi = float(st.angles_deg.min()), float(st.angles_deg.max())
            if a.travel[1] - a.travel[0] >= 360.0 - 1e-9 and hi - lo > 300.0:
                angles = np.arange(a.travel[0], a.travel[0] + 360.0 - 1e-9, step_deg)
            else:
                angles = np.arange(lo, hi + 1e-9, step_deg)
            out += [[Dwell(120.0)], rtest(machine, a.name, st.ball_mm, angles_deg=angles,
                                          tool_mm=st.tool_mm, label=f"{a.name}-rtest-fine-{k}")]
    return out


FIVE_AX_04 = {"name": "5ax-04", "chain": "w C A X b Y Z t",
              "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0], "a": [-110, 110],
                            "c": [-180, 180]},
              "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
              "tool_length_mm": 100.0}
"""The demo's 5ax-04 chain and pivots (as ``benchmarks/diagnosis_rotary.py``)."""
BALLS_04 = {"C": [(300.0, 300.0, -400.0), (450.0, 300.0, -100.0), (400.0, 200.0, -250.0),
                  (400.0, 400.0, -150.0)],
            "A": [(50.0, 300.0, -250.0), (450.0, 300.0, -100.0), (250.0, 350.0, -150.0),
                  (450.0, 250.0, -150.0)]}
"""R-test balls of 5ax-04 reachable over each rotary axis's sweep, spread along and
around the axis so that every rotation of the axis moves some ball."""


def rich_campaign_04(sim: SimulatedMachine, rng: np.random.Generator, *,
                     step_deg: float = 5.0, runs: int = 3) -> Measurements:
    """5ax-04's standard campaign plus R-tests at the four balls of each rotary axis read
    every ``step_deg`` (C over its turn, A over the 90 % of its travel the standard
    R-test visits)."""
    machine = sim.machine
    programs = standard_programs(machine, rng, runs=runs)
    for name, balls in BALLS_04.items():
        a = machine.axis(name)
        if a.travel[1] - a.travel[0] >= 360.0 - 1e-9:
            angles = np.arange(a.travel[0], a.travel[0] + 360.0 - 1e-9, step_deg)
        else:
            margin = 0.05 * (a.travel[1] - a.travel[0])
            angles = np.arange(a.travel[0] + margin, a.travel[1] - margin + 1e-9, step_deg)
        for k, ball in enumerate(balls, start=3):
            programs += [[Dwell(120.0)], rtest(machine, name, ball, angles_deg=angles,
                                              label=f"{name}-rtest-{k}")]
    return run_campaign(sim, programs).measurements


def five_axis_campaign(sim: SimulatedMachine, rng: np.random.Generator, *,
                       step_deg: float = FINE_STEP_DEG, runs: int = 3) -> Measurements:
    """The standard campaign (``runs`` positioning blocks) plus :func:`fine_rtests`."""
    programs = standard_programs(sim.machine, rng, runs=runs)
    programs += fine_rtests(sim.machine, step_deg)
    return run_campaign(sim, programs).measurements
