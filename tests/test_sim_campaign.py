"""Campaigns on simulated machines: the standard mix, determinism, the CSV round trip,
multi-spindle machines and the program executor's errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from machine_sim.campaign import (
    machine_directions,
    machine_positions,
    map_compensation,
    run_campaign,
    standard_campaign,
    standard_programs,
    write_campaign,
)
from machine_sim.effects import Backlash, Effects, Noise, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.lookup import GridMap
from machine_sim.program import Dwell, Linear, Rapid, SpindleOn, execute
from machine_sim.program import ProgramError as SimProgramError
from machine_sim.testprograms import diagonal_test, positioning_test, straightness_test
from machine_sim.truth import random_geometry
from protocol.codes import MapEncoding
from protocol.mapformat import ErrorMapPayload, GridAxis, OutputAxis
from volumetric.measure.measurement import read_measurements
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Machine, parse_machine
from volumetric.verify.iso230_6 import DIAGONALS, diagonal_ranges, improvement

TRAVEL = {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}


def vmc() -> Machine:
    return parse_machine({"name": "vmc", "chain": "w X Y b Z t", "travel_mm": TRAVEL,
                          "tool_length_mm": 100.0})


def arch() -> Machine:
    t = np.deg2rad(30.0)
    return parse_machine({
        "name": "arch", "chain": "w X b Y t",
        "travel_mm": {"x": [10, 500], "y": [10, 290], "z1": [-300, -10], "z2": [-300, -10]},
        "spindles": [
            {"name": "S1", "axis": "Z1", "direction": [0, 0, 1], "tool_length_mm": 50.0},
            {"name": "S2", "axis": "Z2", "direction": [0.0, -float(np.sin(t)),
                                                       float(np.cos(t))],
             "tool_length_mm": 60.0},
        ],
    })


def noisy_sim(seed: int) -> SimulatedMachine:
    m = vmc()
    eff = Effects(expansion=(ThermalExpansion("x", "x_screw", 6.0),),
                  backlash=(Backlash("y", 5.0),), noise=Noise(0.3, 0.8))
    return SimulatedMachine(m, random_geometry(m, np.random.default_rng(1)), eff, seed=seed)


def test_standard_campaign_is_a_few_thousand_readings_over_hours() -> None:
    sim = noisy_sim(3)
    meas = standard_campaign(sim, np.random.default_rng(5))
    assert 2000 <= len(meas) <= 5000
    assert meas.time_s[-1] > 3 * 3600  # long enough for the machine to warm and cool
    assert np.all(np.diff(meas.time_s) > 0)
    tests = set(meas.test.tolist())
    for axis in "XYZ":
        assert f"{axis}-positioning" in tests and f"{axis}-positioning-fine" in tests
        assert {f"{axis}-angular-{c}" for c in "ABC"} <= tests
    assert {"X-straightness-Y", "X-straightness-Z", "Z-straightness-X"} <= tests
    assert {"diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN"} <= tests
    pos = meas.select(meas.test == "X-positioning")
    assert sorted(set(pos.run.tolist())) == [1, 2, 3, 4, 5]
    assert set(meas.temperature_columns.values()) >= {"T_spindle_C", "T_x_screw_C",
                                                      "T_air_C"}
    assert np.ptp(meas.temperatures["spindle"]) > 3.0  # the warm-up shows
    assert meas.is_angle.sum() > 500


def test_campaign_is_deterministic_by_seed() -> None:
    progs = standard_programs(vmc(), np.random.default_rng(5), runs=2, targets=6)
    a = run_campaign(noisy_sim(3), progs).measurements
    b = run_campaign(noisy_sim(3), progs).measurements
    c = run_campaign(noisy_sim(4), progs).measurements
    np.testing.assert_array_equal(a.value, b.value)
    np.testing.assert_array_equal(a.temperatures["air"], b.temperatures["air"])
    assert np.max(np.abs(a.value - c.value)) > 0.1
    p1 = standard_programs(vmc(), np.random.default_rng(5), runs=2, targets=6)
    p2 = standard_programs(vmc(), np.random.default_rng(6), runs=2, targets=6)
    assert p1 == progs and p1 != p2  # the rng draws the ISO 230-2 target offsets


def test_csv_round_trip(tmp_path: Path) -> None:
    sim = noisy_sim(3)
    res = run_campaign(sim, standard_programs(sim.machine, np.random.default_rng(5), runs=2,
                                              targets=6))
    path = tmp_path / "campaign.csv"
    write_campaign(path, res.measurements)
    back = read_measurements(path)
    m = res.measurements
    for attr in ("test", "run", "time_s", "q", "direction", "tool_mm", "is_angle", "u",
                 "value"):
        np.testing.assert_array_equal(getattr(back, attr), getattr(m, attr), err_msg=attr)
    assert back.temperature_columns == m.temperature_columns
    for k in m.temperatures:
        np.testing.assert_array_equal(back.temperatures[k], m.temperatures[k])
    np.testing.assert_array_equal(back.extra["spindle_rpm"], m.extra["spindle_rpm"])
    header = path.read_text().splitlines()[0].split(",")
    assert header[:3] == ["test", "run", "time_s"] and "T_spindle_C" in header


def test_multi_spindle_campaign_reads_each_branch() -> None:
    m = arch()
    g = random_geometry(m, np.random.default_rng(2))
    sim = SimulatedMachine(m, g)
    meas = standard_campaign(sim, np.random.default_rng(1), runs=2, targets=5)
    assert meas.spindle is not None
    assert set(meas.spindle.tolist()) == {"S1", "S2"}
    assert "Z2-positioning" in set(meas.test.tolist())
    q = machine_positions(m, meas)
    d = machine_directions(m, meas)
    assert d.shape == q.shape
    for name in ("S1", "S2"):
        rows = meas.spindle == name
        err = volumetric_error(m, g, q[rows], spindle=name, tool_mm=meas.tool_mm[rows])
        assert err.orientation_urad is not None
        want = np.where(meas.is_angle[rows],
                        np.einsum("ni,ni->n", err.orientation_urad, meas.u[rows]),
                        np.einsum("ni,ni->n", err.position_um, meas.u[rows]))
        np.testing.assert_allclose(meas.value[rows], want, rtol=0, atol=1e-9)
    # the tilted spindle's positioning senses along its own direction
    z2 = meas.select(meas.test == "Z2-positioning")
    np.testing.assert_allclose(z2.u, np.broadcast_to(m.axis("Z2").direction, z2.u.shape))


def test_straightness_senses_across_and_needs_a_cross_direction() -> None:
    m = vmc()
    prog = straightness_test(m, "x", "z", targets=3, runs=1)
    res = run_campaign(SimulatedMachine(m, random_geometry(m, np.random.default_rng(0))),
                       [prog])
    np.testing.assert_array_equal(res.measurements.u, np.tile([0.0, 0.0, 1.0], (6, 1)))
    assert set(res.measurements.test.tolist()) == {"X-straightness-Z"}
    with pytest.raises(ValueError, match="needs a sense across it"):
        straightness_test(m, "x", "x")


def test_executor_times_moves_and_dwells() -> None:
    m = vmc()
    traj = execute(m, [Rapid({"x": 250.0}), Linear({"x": 260.0}, 600.0), Dwell(5.0),
                       SpindleOn(1000.0), Dwell(60.0)])
    overhead = 0.4
    rapid = 250.0 / (15000.0 / 60.0) + overhead
    linear = 10.0 / (600.0 / 60.0) + overhead
    assert traj.final.time_s == pytest.approx(rapid + linear + 5.0 + 60.0)
    grid = np.arange(0.0, traj.final.time_s + 1.0, 1.0)
    rpm, speeds = traj.loads(grid, m)
    assert rpm[-3] == pytest.approx(1000.0)  # spinning at the end
    assert rpm[0] == 0.0
    # the mean X speed over the campaign integrates back to the distance travelled
    assert float(np.sum(speeds["x"][:-1]) * 1000.0 / 60.0) == pytest.approx(260.0)


@pytest.mark.parametrize(("program", "message"), [
    ([Rapid({"x": 600.0})], r"instruction 0 \(Rapid\): axis X target 600.0 is outside"),
    ([Rapid({"x": 1.0}), Linear({"q": 1.0}, 100.0)], r"instruction 1 \(Linear\).*no axis"),
    ([Linear({"x": 1.0}, 0.0)], r"feed must be > 0"),
    ([Dwell(-1.0)], r"dwell must be >= 0"),
])
def test_executor_names_the_bad_instruction(program: list[object], message: str) -> None:
    with pytest.raises(SimProgramError, match=message):
        execute(vmc(), program)  # type: ignore[arg-type]


def test_positioning_targets_get_iso_random_offsets() -> None:
    m = vmc()
    prog = positioning_test(m, "x", targets=11, runs=1, rng=np.random.default_rng(0))
    res = run_campaign(SimulatedMachine(m, random_geometry(m, np.random.default_rng(0))),
                       [prog])
    x = np.unique(res.measurements.q[:, 0])
    assert x.size == 11
    steps = np.diff(x)
    assert np.ptp(steps) > 1.0  # not a regular grid, so periodic errors are not aliased


def correction_map(m: Machine, sim: SimulatedMachine, backlash_x_um: int = 0) -> GridMap:
    """A map built straight from the truth: on a 3-axis machine whose axes are the base
    x, y, z, the correction along each axis is minus the error along it; an X backlash B
    (error -(B/2)·d) needs +B/2 for a positive approach and the reversal -B."""
    grid = (GridAxis("X", 0.0, 25.0, 21), GridAxis("Y", 0.0, 25.0, 13),
            GridAxis("Z", -300.0, 25.0, 13))
    axes = [g.start + g.step * np.arange(g.count) for g in grid]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    err = volumetric_error(m, sim.geometry, nodes).position_um  # µm, x y z
    counts = np.rint(-err).astype("<i4")  # 1 count = 1 µm
    counts[:, 0] += backlash_x_um // 2
    outs = (OutputAxis("X", -backlash_x_um), OutputAxis("Y"), OutputAxis("Z"))
    p = ErrorMapPayload(m.name, 1, MapEncoding.INT32_INCREMENTS, grid, outs, counts.tobytes())
    return GridMap.from_payload(p)


def test_compensated_campaign_cuts_the_diagonal_errors_by_most() -> None:
    m = vmc()
    eff = Effects(backlash=(Backlash("x", 8.0),))
    sim = SimulatedMachine(m, random_geometry(m, np.random.default_rng(9), scale=2.0), eff)
    progs = [diagonal_test(m, d, points=11, runs=1) for d in DIAGONALS]
    before = diagonal_ranges(run_campaign(sim, progs).measurements)
    shift = map_compensation(m, correction_map(m, sim, backlash_x_um=8),
                             increment_mm=0.001)
    res = run_campaign(sim, progs, compensation=shift)
    after = diagonal_ranges(res.measurements)
    assert min(before.values()) > 10.0  # a machine worth compensating
    gains = improvement(before, after)
    assert all(g >= 0.9 for g in gains.values()), gains
    # with the reversal value the compensated readings do not depend on the direction
    # left: rounding of node values and of the shift (each <= 0.5 µm per axis, projected
    # on u) and the interpolation between 25 mm nodes
    assert np.max(np.abs(res.measurements.value)) < 1.5
