"""A Fanuc-style machine whose spindle grows with heat, end to end: the center's diagnosis
model (a thermal drift along z on ``T_spindle_C``, found by ``volumetric.diagnose.diagnosis``
in a simulated campaign) is uploaded through the REST API; the machine gets one map that
carries the term (a factored map, format version 4, or for a ladder that takes grids only a
grid of format version 3: either way its ladder applies it by multiply-add), at once,
without waiting for a temperature; spindle temperatures published on MQTT reach it through
the center's Temperatures messages, and its z correction moves by the model's
coefficient × ΔT per step while the map version stays 1 (no rebuild, one push); the
machine stays compensated as it warms."""

from __future__ import annotations

import asyncio
import copy
import uuid
from contextlib import AsyncExitStack
from pathlib import Path

import numpy as np
import pytest

from machine_sim.lookup import ActiveMap, FactoredLadder, GridMap
from tests.support.integration import (
    DEADLINE_S,
    THERMAL,
    before_rounding,
    campaign,
    diagnosed_spindle,
    mqtt_plant,
    require_loopback_aliases,
    until,
    with_model,
)
from volumetric.model.model import ThermalTerm

pytestmark = [pytest.mark.services, pytest.mark.slow]



def _snapshot(active: ActiveMap) -> ActiveMap:
    """The map as it is now: its thermal constants change in place with every temperature."""
    snap = copy.copy(active)
    object.__setattr__(snap, "thermal_mm", active.thermal_mm.copy())
    return snap


@pytest.mark.parametrize("factored", [True, False], ids=["factored", "grid"])
async def test_mqtt_temperature_moves_the_map_by_the_model(
        tmp_path: Path, mqtt_broker: tuple[str, int], factored: bool) -> None:
    require_loopback_aliases()
    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL)
    top = f"ednc-it-{uuid.uuid4().hex[:12]}"
    name = THERMAL.name
    topic = f"{top}/{name}/temperature/spindle"
    m = THERMAL.machine
    ref = np.array([[0.5 * (a.travel[0] + a.travel[1]) for a in m.axes]])
    z = m.axis_names.index("Z")
    seen: list[float] = []
    snapshots: list[ActiveMap] = []
    kind = FactoredLadder if factored else GridMap
    temps: list[float] = []
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant, pub = await mqtt_plant(stack, tmp_path, mqtt_broker, top)
        # the map carries the term: built at its reference, it needs no temperature
        sim = await with_model(stack, plant, THERMAL, model, factored=factored)
        ctl = sim.runtime.controller
        store = ctl.store
        await until(plant.applied(name, 1))
        assert isinstance(store.active, kind)
        assert (store.active.payload.thermal if isinstance(store.active, FactoredLadder)
                else store.active.thermal)
        # steps of 1.5 K, a second apart: within the intake's plausible rate of change
        for k in range(3):
            celsius = round(term.t_ref_C + 1.5 * (k + 1), 3)  # as published
            await pub.publish(topic, f"{celsius:.3f}")
            await until(lambda c=celsius: abs(ctl.temperatures.values().get(
                "T_spindle_C", -1e9) - c) < 1e-6)
            await asyncio.sleep(0.1)  # a few 20 ms cycles: the next one folds it in
            active = store.active
            assert isinstance(active, kind) and active.version == 1
            seen.append(float(before_rounding(active, ref[:, [m.axis_names.index(a)
                                                               for a in active.inputs]])[0, z])
                        * 1e3)
            snapshots.append(_snapshot(active))
            temps.append(celsius)
            await asyncio.sleep(1.0)
        maps = await plant.maps(name)
        pushed = await plant.events(kind="pushed", machine=name)
    assert len(maps) == 1 and len(pushed) == 1  # one map, one push, three temperatures
    steps = np.diff(seen)  # µm of z correction per temperature step
    expected = -term.coefficient * np.diff(temps)  # the correction opposes the growth
    print(f"\nthermal in the {kind.__name__}: k = {term.coefficient:.3f} µm/K; z correction moved "
          f"{steps.round(3)} µm per 1.5 K step (expected {expected.round(3)})")
    assert abs(expected[0]) > 2.0  # a move the test can see
    # exact before the ladder's rounding (the term is added, not interpolated) to the
    # ladder's fixed point: the published temperatures are whole m°C, the thermal constant
    # is held in 2^-16 counts (each rounded by at most half of that) and the coefficient in
    # 2^-32 counts per m°C (protocol/README.md section 6): within 2^-15 µm at 0.001 mm
    np.testing.assert_allclose(steps, expected, rtol=0, atol=2.0**-15)
    _check_shift(snapshots[0], snapshots[-1], term, temps[-1] - temps[0])
    _check_still_compensated(snapshots[0], snapshots[-1], temps[0], temps[-1])


def _check_shift(grid1: ActiveMap, grid2: ActiveMap, term: ThermalTerm, dt_K: float) -> None:
    """The same map at two temperatures differs by the drift term alone, everywhere: z by
    -k·ΔT, x and y not at all (each within one Fanuc increment, the ladder's rounding)."""
    assert grid1.grid == grid2.grid and grid1.outputs == grid2.outputs
    rng = np.random.default_rng(3)
    travel = {a.name: a.travel for a in THERMAL.machine.axes}
    q = np.column_stack([rng.uniform(*travel[a], 500) for a in grid1.inputs])
    delta = (np.rint(grid2.lookup(q) * 1e3) - np.rint(grid1.lookup(q) * 1e3))  # counts = µm
    expected_z = -term.coefficient * dt_K  # the correction opposes the tool's growth
    z = grid1.outputs.index("Z")
    print(f"\nthermal: k = {term.coefficient:.3f} µm/K, ΔT = {dt_K:.1f} K: map z moved "
          f"{delta[:, z].mean():+.2f} µm (expected {expected_z:+.2f}), spread "
          f"{np.ptp(delta[:, z]):.2f} µm")
    increment_um = 1.0  # Fanuc IS-B
    assert abs(expected_z) > 5 * increment_um  # a shift the test can see
    np.testing.assert_allclose(delta[:, z], expected_z, rtol=0, atol=increment_um)
    others = [k for k in range(len(grid1.outputs)) if k != z]
    np.testing.assert_allclose(delta[:, others], 0.0, rtol=0, atol=increment_um)


def _check_still_compensated(grid1: ActiveMap, grid2: ActiveMap, t1: float, t2: float
                             ) -> None:
    """On the true machine: warmed from t1 to t2, the tool tip drifts along z; with the
    map's terms at t2 the compensated tool tip stays where they held it at t1."""
    from machine_sim.campaign import map_compensation

    sim, _, _ = campaign(THERMAL.name)
    m = sim.machine
    rng = np.random.default_rng(4)
    q = np.column_stack([rng.uniform(*a.travel, 300) for a in m.axes])
    still = np.zeros(q.shape, dtype=np.int8)
    start = {"spindle": 20.0}  # the drift's reference (THERMAL's effect)

    def z_bias(grid: ActiveMap, t: float) -> float:
        shift = map_compensation(m, grid, increment_mm=0.001)(q, still)
        e = sim.true_error(q, temperatures={"spindle": t}, start_temperatures=start,
                           compensation=shift).position_um
        return float(e[:, 2].mean())

    held = z_bias(grid1, t1)
    uncorrected = z_bias(grid1, t2) - held
    corrected = z_bias(grid2, t2) - held
    print(f"thermal: z drift from {t1:.1f} to {t2:.1f} °C: {uncorrected:+.2f} µm with the old "
          f"temperature, {corrected:+.2f} µm with the new one (same map)")
    assert abs(uncorrected) > 5.0  # 3 K of a -2.5 µm/K drift
    assert abs(corrected) < 0.1 * abs(uncorrected)
