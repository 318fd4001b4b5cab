"""End to end in the numeric core: measure, identify, map, compensate, verify (ISO 230-6).

A simulated machine with noisy instruments is measured, its model identified, its map
built and quantised for its controller, encoded and decoded as the protocol sends it, and
the machine re-measured with the map applied the way its PLC applies it.
"""

from __future__ import annotations

import numpy as np
import pytest

from machine_sim.campaign import map_compensation, run_campaign, standard_campaign
from machine_sim.effects import Backlash, Effects, Noise, ThermalDrift
from machine_sim.instruments import SimulatedMachine
from machine_sim.lookup import GridMap
from machine_sim.program import Dwell, SpindleOn
from machine_sim.testprograms import diagonal_test
from machine_sim.truth import random_geometry
from protocol import decode_map, encode_map
from server.mapcodec import grid_to_payload
from volumetric.compensate.gridmap import build_map
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine, parse_machine
from volumetric.verify.iso230_6 import diagonal_ranges, improvement

NOISE_UM = 0.3


@pytest.mark.parametrize(("chain", "controller"), [("w X Y b Z t", "fanuc"),
                                                   ("w b Y X Z t", "siemens")])
def test_compensation_cuts_diagonal_ranges_by_90_percent_down_to_the_noise_floor(
        chain: str, controller: str) -> None:
    m = parse_machine({"name": "m", "chain": chain, "controller": controller,
                       "tool_length_mm": 100.0,
                       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})
    rng = np.random.default_rng(21)
    # errors of a few tens of µm, as on a machine that needs compensation
    sim = SimulatedMachine(m, random_geometry(m, rng, scale=2.0),
                           Effects(noise=Noise(NOISE_UM, NOISE_UM)), seed=21)
    model = fit(m, standard_campaign(sim, rng)).model
    emap = build_map(m, model, tolerance_um=0.25, controller=controller)
    grid = GridMap.from_payload(decode_map(encode_map(grid_to_payload(emap))))
    increment = 0.001 if controller == "fanuc" else None
    programs = [diagonal_test(m, d, points=20, runs=2)
                for d in ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN")]
    before = run_campaign(sim, programs).measurements
    after = run_campaign(sim, programs,
                         compensation=map_compensation(m, grid, increment_mm=increment)
                         ).measurements
    pre, post = diagonal_ranges(before), diagonal_ranges(after)
    gain = improvement(pre, post)
    print(f"\n{chain} {controller}: ranges before {pre}, after {post}")
    assert min(pre.values()) > 20.0  # the machine really is wrong
    assert all(gain[d] >= 0.90 for d in pre), gain
    # residual against the floor: instrument noise plus the controller's rounding
    quant = 0.001e3 / np.sqrt(12) if controller == "fanuc" else 0.0  # µm, uniform on ±0.5 LSB
    floor = float(np.hypot(NOISE_UM, quant))
    # the tool tip's constant offset is the workpiece zero's business, not the map's
    offset, *_ = np.linalg.lstsq(after.u, after.value, rcond=None)
    resid = after.value - after.u @ offset
    rms = float(np.sqrt(np.mean(resid**2)))
    print(f"residual RMS {rms:.3f} µm, floor {floor:.3f} µm")
    assert rms <= 1.5 * floor


def _offset_free_rms(m: Measurements) -> float:
    offset, *_ = np.linalg.lstsq(m.u, m.value, rcond=None)
    return float(np.sqrt(np.mean((m.value - m.u @ offset) ** 2)))


def _vmc(controller: str = "siemens") -> Machine:
    return parse_machine({"name": "m", "chain": "w X Y b Z t", "controller": controller,
                          "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})


DIAGONALS = ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN")


def test_a_diagnosed_backlash_becomes_direction_dependent_compensation() -> None:
    m = _vmc()
    rng = np.random.default_rng(31)
    sim = SimulatedMachine(m, random_geometry(m, rng, scale=2.0),
                           Effects(backlash=(Backlash("x", 10.0),), noise=Noise(0.2, 0.2)),
                           seed=31)
    d = diagnose(m, standard_campaign(sim, rng))
    assert (d.effect, d.axis) == ("backlash", "x")
    rigid = fit(m, standard_campaign(sim, rng)).model
    programs = [diagonal_test(m, g, points=20, runs=2) for g in DIAGONALS]
    residual = {}
    for label, model in (("rigid", rigid), ("extended", d.model)):
        emap = build_map(m, model, tolerance_um=0.25, controller="siemens")
        grid = GridMap.from_payload(decode_map(encode_map(grid_to_payload(emap))))
        after = run_campaign(sim, programs, compensation=map_compensation(m, grid)).measurements
        residual[label] = _offset_free_rms(after)
    print(f"\nresidual after compensation: {residual}")
    assert residual["extended"] < 0.5 * residual["rigid"]
    assert residual["extended"] < 0.5


def test_a_diagnosed_thermal_drift_makes_the_map_follow_the_temperature() -> None:
    """A drift along z is a shift of the whole workspace: diagonal ranges do not see it,
    the part does. Measure the shift of the compensated tool tip from a cold to a warm
    machine, with each model's map built at the temperatures of the moment."""
    m = _vmc()
    rng = np.random.default_rng(32)
    sensor = "spindle"
    sim = SimulatedMachine(m, random_geometry(m, rng, scale=2.0),
                           Effects(drift=(ThermalDrift("z", sensor, -3.0),),
                                   noise=Noise(0.2, 0.2)), seed=32)
    d = diagnose(m, standard_campaign(sim, rng))
    assert (d.effect, d.axis, d.sensor) == ("thermal_drift", "z", f"T_{sensor}_C")
    rigid = fit(m, standard_campaign(sim, rng)).model
    diagonals = [diagonal_test(m, g, points=20, runs=1) for g in DIAGONALS]
    states = {"cold": diagonals, "warm": [[SpindleOn(9000.0), Dwell(3600.0)], *diagonals]}
    shift_z: dict[str, dict[str, float]] = {"rigid": {}, "extended": {}}
    for state, programs in states.items():
        probe = run_campaign(sim, programs).measurements
        temps = {col: float(probe.temperatures[s].mean())
                 for s, col in probe.temperature_columns.items()}
        for label, model in (("rigid", rigid), ("extended", d.model)):
            emap = build_map(m, model, temps if model.sensors else None, tolerance_um=0.25,
                             controller="siemens")
            grid = GridMap.from_payload(decode_map(encode_map(grid_to_payload(emap))))
            after = run_campaign(sim, programs,
                                 compensation=map_compensation(m, grid)).measurements
            offset, *_ = np.linalg.lstsq(after.u, after.value, rcond=None)
            shift_z[label][state] = float(offset[2])
    moved = {k: abs(v["warm"] - v["cold"]) for k, v in shift_z.items()}
    print(f"\nz shift of the compensated tool tip, cold to warm: {moved} µm")
    assert moved["rigid"] > 10.0  # the spindle grew: tens of µm uncompensated
    assert moved["extended"] < 0.1 * moved["rigid"]
