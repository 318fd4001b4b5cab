"""Several machines warm up at once, end to end over Mosquitto and TCP (issue 13, done
when): a Fanuc-style ladder with a factored map and a Siemens-style NC with a tables map,
each carrying its spindle-growth term, one center between them. Their spindle temperatures
are published on MQTT, interleaved; the center forwards each in a Temperatures message.
Every cycle of both machines is recorded: in each one, the map's z correction is the one
of the temperature the machine held when its latest PLC cycle began (the ladder's scan;
on the Siemens-style NC the PLC runs every ``plc_every`` interpolation cycles), so a
temperature takes effect in the first PLC cycle after it arrives; neither machine ever
gets a second map."""

from __future__ import annotations

import asyncio
import uuid
from contextlib import AsyncExitStack
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from machine_sim.link import SimulatedCNC
from machine_sim.lookup import FactoredLadder, TablesMap
from machine_sim.siemens import SiemensNC
from server.numeric import plain_json
from tests.support.integration import (
    DEADLINE_S,
    THERMAL,
    THERMAL_TABLES,
    before_rounding,
    cnc,
    diagnosed_spindle,
    mqtt_plant,
    require_loopback_aliases,
    until,
)

pytestmark = [pytest.mark.services, pytest.mark.slow]

COLUMN = "T_spindle_C"


@dataclass
class Cycles:
    """Per cycle of one machine: the temperature it held when its latest PLC cycle began
    and the map's z correction at a fixed point after the cycle (mm), while a map is
    active."""

    ref: np.ndarray
    z: int
    held: list[float] = field(default_factory=list)
    z_mm: list[float] = field(default_factory=list)
    plc_held: float | None = None

    def record(self, sim: SimulatedCNC) -> None:
        rt = sim.runtime
        step = rt.step

        def recorded(now_s: float) -> np.ndarray:
            c = rt.controller
            plc = not isinstance(c, SiemensNC) or c.cycles % c.config.plc_every == 0
            if plc:
                self.plc_held = c.temperatures.values().get(COLUMN)
            out = step(now_s)
            active = c.store.active
            if self.plc_held is not None and active is not None:
                self.held.append(self.plc_held)
                self.z_mm.append(float(before_rounding(active, self.ref)[0, self.z]))
            return out

        rt.step = recorded  # type: ignore[method-assign]


async def test_two_machines_warm_up_and_each_cycle_applies_its_latest_temperature(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    require_loopback_aliases()
    specs = (THERMAL, THERMAL_TABLES)  # hot-07 Fanuc-style, hot-08 Siemens-style
    models = {s.name: await asyncio.to_thread(diagnosed_spindle, s) for s in specs}
    top = f"ednc-it-{uuid.uuid4().hex[:12]}"
    cycles: dict[str, Cycles] = {}
    async with asyncio.timeout(DEADLINE_S), AsyncExitStack() as stack:
        plant, pub = await mqtt_plant(stack, tmp_path, mqtt_broker, top)
        sims = {}
        for s in specs:
            await plant.register(s)
            await plant.post_model(s.name, plain_json(models[s.name][0].to_json()))
            # the sensors publish to MQTT: the center forwards them to the machine
            sims[s.name] = await stack.enter_async_context(cnc(s, plant.port,
                                                               own_sensors=False))
        for s in specs:
            sim = sims[s.name]
            await sim.ready.wait()
            await until(lambda st=sim.runtime.controller.store: st.version == 1)
            await until(plant.applied(s.name, 1))
            m = s.machine
            kind = FactoredLadder if m.controller == "fanuc" else TablesMap
            assert isinstance(sim.runtime.controller.store.active, kind)
            ref = np.array([[0.5 * (a.travel[0] + a.travel[1]) for a in m.axes]])
            cycles[s.name] = Cycles(ref, m.axis_names.index("Z"))
            cycles[s.name].record(sim)
        # interleaved 1 K steps, half a second apart: within the intake's plausible rate
        for k in range(4):
            for s in specs:
                term = models[s.name][1]
                celsius = round(term.t_ref_C + 1.0 * (k + 1), 3)
                await pub.publish(f"{top}/{s.name}/temperature/spindle", f"{celsius:.3f}")
            for s in specs:
                ctl = sims[s.name].runtime.controller
                want = round(models[s.name][1].t_ref_C + 1.0 * (k + 1), 3)
                await until(lambda c=ctl, w=want: abs(c.temperatures.values().get(
                    COLUMN, -1e9) - w) < 1e-6)
            await asyncio.sleep(0.5)
        for s in specs:
            maps = await plant.maps(s.name)
            pushed = await plant.events(kind="pushed", machine=s.name)
            assert len(maps) == 1 and len(pushed) == 1, (s.name, maps, pushed)
    for s in specs:
        c = cycles[s.name]
        term = models[s.name][1]
        held = np.array(c.held)
        z_um = np.array(c.z_mm) * 1e3
        assert len(np.unique(held)) == 4, np.unique(held)  # every step reached the machine
        # each cycle's correction is that of the temperature held at its start: the same
        # temperature always gives the same z, and z moves by -k per K between them
        base = z_um - (-term.coefficient) * (held - held[0])
        temps = [round(float(t), 3) for t in sorted(set(held))]
        print(f"\n{s.name}: {len(held)} cycles at {temps} °C; z "
              f"correction {z_um.min():+.3f} .. {z_um.max():+.3f} µm, off the model's "
              f"-k·ΔT by at most {np.ptp(base):.4f} µm")
        assert np.ptp(z_um) > 2.0  # 3 K of a ~-2.5 µm/K growth: a move the test can see
        assert np.ptp(base) < 0.05, np.ptp(base)
