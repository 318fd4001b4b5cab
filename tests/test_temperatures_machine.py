"""The machine endpoint's temperatures (machine_sim/temperatures.py): newest reading wins,
forwarded readings are dated by their age, staleness, own sensors read by the runtime, and
Temperatures messages from a real center over TCP land in ``controller.temperatures``."""

from __future__ import annotations

import pytest

from machine_sim.runtime import MachineRuntime
from machine_sim.temperatures import TemperatureStore, column_of
from protocol import TemperatureReading, Temperatures
from volumetric.model.machine import parse_machine

DESCRIPTION = {"name": "vmc-01", "controller": "fanuc", "ip": "127.0.0.1",
               "chain": "w X Y b Z t",
               "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
               "tool_length_mm": 100.0}


def test_message_readings_are_dated_by_their_age_and_sources_do_not_overwrite_newer(
) -> None:
    store = TemperatureStore(stale_after_s=10.0)
    msg = Temperatures(0, (TemperatureReading("spindle", 24.0, 2000),
                           TemperatureReading("air", 20.0)))
    assert store.apply(msg, now_s=100.0) == 2
    assert store.readings()["spindle"].taken_s == pytest.approx(98.0)
    assert store.values(100.0) == {"T_spindle_C": 24.0, "T_air_C": 20.0}
    # the center's readings replace each other in order, whatever their stamps say
    assert store.apply(Temperatures(0, (TemperatureReading("spindle", 23.0, 5000),)),
                       now_s=100.5) == 1
    assert store.values()["T_spindle_C"] == 23.0
    # the machine's own sensor, newer, wins over an older forwarded reading
    assert store.update("spindle", 25.0, 101.0, "sensor")
    assert store.apply(Temperatures(0, (TemperatureReading("spindle", 22.0, 1000),)),
                       now_s=101.5) == 0
    assert store.values()["T_spindle_C"] == 25.0
    assert store.readings()["spindle"].source == "sensor"
    assert store.apply(Temperatures(0, (TemperatureReading("spindle", 26.0),)),
                       now_s=102.0) == 1
    assert store.values()["T_spindle_C"] == 26.0
    assert store.messages == 4


def test_stale_readings_are_kept_and_flagged() -> None:
    store = TemperatureStore(stale_after_s=5.0)
    store.update("spindle", 22.0, 0.0, "center")
    store.update("air", 20.0, 4.0, "center")
    assert store.stale(4.0) == frozenset()
    assert store.stale(7.0) == {"spindle"}
    assert store.values(7.0)["T_spindle_C"] == 22.0  # still used
    assert store.age_s("spindle", 7.0) == pytest.approx(7.0)
    assert store.age_s("bed", 7.0) is None
    with pytest.raises(ValueError, match="stale_after_s"):
        TemperatureStore(0.0)


def test_columns() -> None:
    assert column_of("spindle") == "T_spindle_C"
    assert column_of("T_spindle_C") == "T_spindle_C"


@pytest.mark.parametrize(("controller", "own"), [("siemens", True), ("fanuc", False)])
def test_runtime_reads_its_own_sensors_where_it_has_them(controller: str, own: bool) -> None:
    machine = parse_machine({**DESCRIPTION, "controller": controller})
    rt = MachineRuntime(machine, seed=1, sensor_period_s=1.0)
    for k in range(300):  # 1.2 s of 4 ms (or 2.4 s of 8 ms) cycles
        rt.step(k * rt.cycle_s)
    store = rt.controller.temperatures
    if not own:
        assert store.readings() == {}
        return
    readings = store.readings()
    assert set(readings) == set(rt.temperatures(0.0))
    assert all(r.source == "sensor" for r in readings.values())
    assert max(r.taken_s for r in readings.values()) >= 1.0  # read again after a period
    assert "T_spindle_C" in store.values()
