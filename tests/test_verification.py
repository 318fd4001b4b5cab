"""End to end in the numeric core: measure, identify, map, compensate, verify (ISO 230-6).

A simulated machine with noisy instruments is measured, its model identified, its map
built and quantised for its controller, encoded and decoded as the protocol sends it, and
the machine re-measured with the map applied the way its PLC applies it.
"""

from __future__ import annotations

import numpy as np
import pytest

from machine_sim.campaign import map_compensation, run_campaign, standard_campaign
from machine_sim.effects import Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.lookup import GridMap
from machine_sim.testprograms import diagonal_test
from machine_sim.truth import random_geometry
from protocol import decode_map, encode_map
from volumetric.errormap import build_map
from volumetric.fit import fit
from volumetric.iso230_6 import diagonal_ranges, improvement
from volumetric.machine import parse_machine

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
    grid = GridMap.from_payload(decode_map(encode_map(emap.to_payload())))
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
