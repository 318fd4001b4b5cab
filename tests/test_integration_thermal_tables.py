"""Thermal terms travel with the map, end to end over Mosquitto and TCP: a Siemens-style
machine gets one tables map carrying its spindle-growth term; spindle temperatures
published on MQTT reach it through the center in Temperatures messages, and its applied
compensation follows them (z by -k·ΔT) while the map version stays 1: no rebuild, no push
per temperature."""

from __future__ import annotations

import asyncio
import uuid
from contextlib import AsyncExitStack
from pathlib import Path

import numpy as np
import pytest

from machine_sim.lookup import TablesMap
from tests.support.integration import (
    DEADLINE_S,
    THERMAL_TABLES,
    diagnosed_spindle,
    mqtt_plant,
    require_loopback_aliases,
    until,
    with_model,
)

pytestmark = [pytest.mark.services, pytest.mark.slow]



async def test_temperatures_move_the_compensation_without_a_new_map(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    require_loopback_aliases()
    model, term = await asyncio.to_thread(diagnosed_spindle, THERMAL_TABLES)
    top = f"ednc-it-{uuid.uuid4().hex[:12]}"
    name = THERMAL_TABLES.name
    topic = f"{top}/{name}/temperature/spindle"
    m = THERMAL_TABLES.machine
    ref = np.array([[0.5 * (a.travel[0] + a.travel[1]) for a in m.axes]])
    z = m.axis_names.index("Z")
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant, pub = await mqtt_plant(stack, tmp_path, mqtt_broker, top)
        # its sensors are not on its own PLC: they publish to MQTT, the center forwards
        # them; a tables map needs no temperature to be built: it comes at once
        sim = await with_model(stack, plant, THERMAL_TABLES, model, own_sensors=False)
        ctl = sim.runtime.controller
        store = ctl.store
        await until(plant.applied(name, 1))
        assert isinstance(store.active, TablesMap)
        seen: list[float] = []
        # steps of 1.5 K, a second apart: within the intake's plausible rate of change
        for k in range(3):
            celsius = round(term.t_ref_C + 1.5 * (k + 1), 3)
            await pub.publish(topic, f"{celsius:.3f}")
            await until(lambda c=celsius: abs(ctl.temperatures.values().get(
                "T_spindle_C", -1e9) - c) < 1e-6)
            await asyncio.sleep(0.1)  # a few 20 ms cycles: the next one folds it in
            active = store.active
            assert isinstance(active, TablesMap) and active.version == 1
            seen.append(float(active.lookup(ref)[0, z]) * 1e3)
            await asyncio.sleep(1.0)
        maps = await plant.maps(name)
        pushed = await plant.events(kind="pushed", machine=name)
    assert len(maps) == 1 and len(pushed) == 1  # one map, one push, three temperatures
    steps = np.diff(seen)  # µm of z correction per temperature step
    expected = -term.coefficient * np.array([1.5, 1.5])  # the correction opposes the growth
    print(f"\nthermal in the map: k = {term.coefficient:.3f} µm/K; z correction moved "
          f"{steps.round(3)} µm per 1.5 K step (expected {expected.round(3)})")
    assert abs(expected[0]) > 2.0  # a move the test can see
    np.testing.assert_allclose(steps, expected, rtol=0, atol=0.05)
