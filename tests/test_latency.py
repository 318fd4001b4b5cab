"""Compensation latency in motion (machine_sim/latency.py): on a straight move at constant
feed through a compensation of constant gradient, the naive lookup lags by exactly
gradient x feed x latency, and the set-point lookup (and, away from the move's ends, the
velocity feed-forward) removes the lag. Replayed cycle by cycle, not timed."""

from __future__ import annotations

import numpy as np
import pytest

from machine_sim.latency import FANUC, SIEMENS, LoopTiming, applied_corrections, extra_error
from machine_sim.program import Linear, MachineState, MotionLimits, execute
from volumetric.model.machine import parse_machine

MACHINE = parse_machine({"name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.1",
                         "chain": "w X Y b Z t",
                         "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]},
                         "tool_length_mm": 100.0})
GRADIENT = 1e-4  # mm of correction per mm of X travel (0.1 µm/mm, a steep map)
FEED = 10_000.0  # mm/min
V = FEED / 60.0  # mm/s


def correction(q: np.ndarray) -> np.ndarray:
    out = np.zeros_like(q)
    out[:, 0] = GRADIENT * q[:, 0]
    return out


TRAJ = execute(MACHINE, [Linear({"x": 700.0}, FEED)],
               start=MachineState.home(MACHINE, {"x": 100.0}),
               limits=MotionLimits(overhead_s=0.0))
START = float(TRAJ.knots_s[-2])   # the feed move runs from START to END
END = float(TRAJ.knots_s[-1])


def lag_um(timing: LoopTiming, lookup: str) -> tuple[np.ndarray, np.ndarray]:
    """(times, applied minus right along X in µm) during the move, 0.1 s from its ends."""
    t, _, applied, right = applied_corrections(correction, TRAJ, timing, lookup)  # type: ignore[arg-type]
    inside = (t > START + 0.1) & (t < END - 0.1)
    return t[inside], (applied[inside, 0] - right[inside, 0]) * 1000.0


@pytest.mark.parametrize("timing", [FANUC, SIEMENS], ids=["fanuc", "siemens"])
def test_naive_lookup_lags_by_gradient_feed_latency(timing: LoopTiming) -> None:
    _, lag = lag_um(timing, "naive")
    latency = timing.delay_cycles * timing.cycle_s
    hold = (timing.update_cycles - 1) * timing.cycle_s
    # the value is older by the latency, plus up to the hold while it is held
    assert lag.max() == pytest.approx(-GRADIENT * V * latency * 1000.0, rel=1e-6)
    assert lag.min() == pytest.approx(-GRADIENT * V * (latency + hold) * 1000.0, rel=1e-6)
    assert FANUC.delay_cycles * FANUC.cycle_s == pytest.approx(0.016)


@pytest.mark.parametrize("timing", [FANUC, SIEMENS], ids=["fanuc", "siemens"])
@pytest.mark.parametrize("lookup", ["setpoint", "feedforward"])
def test_corrected_lookup_removes_the_lag_on_a_straight_move(timing: LoopTiming,
                                                             lookup: str) -> None:
    _, lag = lag_um(timing, lookup)
    _, naive = lag_um(timing, "naive")
    assert abs(naive.mean()) > 0.2  # what there is to remove: about 0.2 to 0.3 µm
    assert abs(lag.max() + lag.min()) < 1e-9  # centred on zero: no lag left
    # what is left is the hold of a value over several NC cycles, centred on zero
    hold_um = GRADIENT * V * (timing.update_cycles - 1) * timing.cycle_s / 2 * 1000.0
    assert np.abs(lag).max() == pytest.approx(hold_um, abs=1e-9)


def test_extra_error_is_the_tool_tip_distance() -> None:
    naive = extra_error(MACHINE, correction, TRAJ, FANUC, "naive")
    setpoint = extra_error(MACHINE, correction, TRAJ, FANUC, "setpoint")
    assert naive.worst_um == pytest.approx(GRADIENT * V * 0.016 * 1000.0, rel=1e-6)
    assert setpoint.worst_um < 1e-9
    assert naive.time_s[0] == pytest.approx(2 * FANUC.cycle_s)  # first value in effect
    with pytest.raises(ValueError, match="bad loop timing"):
        LoopTiming(0.0, 1, 1)
