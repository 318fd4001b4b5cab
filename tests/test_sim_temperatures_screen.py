"""The machine's temperature store refuses bad readings and keeps the last good one
(issue 13, bad input and faults): NaN or infinite, outside the plausible range, an
unknown sensor, a jump faster than the configured rate; each refusal counted by reason,
kept and logged (not every time)."""

from __future__ import annotations

import logging

import pytest

from machine_sim.fanuc import FanucConfig, FanucPMC
from machine_sim.runtime import MachineRuntime
from machine_sim.siemens import SiemensConfig, SiemensNC
from machine_sim.temperatures import TemperatureStore
from protocol import TemperatureReading, Temperatures
from volumetric.model.machine import parse_machine


def test_not_a_number_is_refused_and_the_last_good_value_kept() -> None:
    store = TemperatureStore()
    assert store.update("spindle", 24.0, 0.0, "sensor")
    for bad in (float("nan"), float("inf"), float("-inf")):
        assert not store.update("spindle", bad, 1.0, "sensor")
    assert store.values() == {"T_spindle_C": 24.0}
    assert store.readings()["spindle"].taken_s == 0.0  # its age is the good one's
    assert store.refused == {"not_finite": 3}


@pytest.mark.parametrize("celsius", [-20.5, 100.5, -273.15, 850.0])
def test_outside_the_plausible_range_is_refused(celsius: float) -> None:
    store = TemperatureStore()
    assert not store.update("bed", celsius, 0.0, "center")  # not even a first reading
    assert store.values() == {}
    assert store.refused == {"out_of_range": 1}
    assert store.refusals[-1].reason == "out_of_range" and "outside -20..100" in \
        store.refusals[-1].text
    # the edges are plausible
    assert store.update("bed", -20.0, 1.0, "center") and store.update("air", 100.0, 1.0,
                                                                       "center")


def test_the_range_is_configurable() -> None:
    store = TemperatureStore(plausible_C=(10.0, 40.0))
    assert not store.update("bed", 45.0, 0.0, "sensor")
    assert store.update("bed", 35.0, 0.0, "sensor")
    with pytest.raises(ValueError, match="plausible_C"):
        TemperatureStore(plausible_C=(40.0, 10.0))


def test_a_jump_faster_than_the_rate_is_refused_a_slow_change_is_not() -> None:
    store = TemperatureStore(max_rate_K_per_s=0.5, jump_allowance_K=2.0)
    assert store.update("spindle", 22.0, 0.0, "sensor")
    # 10 s later: 0.5 K/s · 10 s + 2 K = 7 K allowed
    assert not store.update("spindle", 29.5, 10.0, "sensor")
    assert store.values()["T_spindle_C"] == 22.0
    assert store.update("spindle", 28.5, 10.0, "sensor")
    # judged against the last good reading, not the refused one: 1 s later 2.5 K allowed
    assert not store.update("spindle", 31.5, 11.0, "center")
    assert store.update("spindle", 30.5, 11.0, "center")
    assert store.refused == {"too_fast": 2}
    assert "from the last good 28.5 °C" in store.refusals[-1].text
    # a sensor replaced or a machine cold-started: after a long gap a big change is fine
    assert store.update("spindle", 20.0, 100.0, "sensor")
    with pytest.raises(ValueError, match="max_rate_K_per_s"):
        TemperatureStore(max_rate_K_per_s=0.0)


def test_unknown_sensors_are_refused_when_the_machine_names_its_own() -> None:
    store = TemperatureStore(sensors=["spindle", "T_bed_C"])
    assert store.update("T_spindle_C", 22.0, 0.0, "center")
    assert store.update("bed", 21.0, 0.0, "center")
    assert not store.update("coolant", 19.0, 0.0, "center")
    assert store.refused == {"unknown_sensor": 1}
    assert set(store.values()) == {"T_spindle_C", "T_bed_C"}
    assert TemperatureStore().update("coolant", 19.0, 0.0, "center")  # no list: any


def test_a_message_with_a_bad_reading_stores_the_good_ones() -> None:
    store = TemperatureStore()
    msg = Temperatures(0, (TemperatureReading("spindle", 24.0),
                           TemperatureReading("bed", 140.0)))
    assert store.apply(msg, now_s=5.0) == 1
    assert store.values() == {"T_spindle_C": 24.0}
    assert store.refused == {"out_of_range": 1}


def test_refusals_are_logged_once_per_sensor_and_reason_per_period(
        caplog: pytest.LogCaptureFixture) -> None:
    store = TemperatureStore(log_every_s=60.0)
    with caplog.at_level(logging.WARNING, logger="machine_sim.temperatures"):
        for t in range(5):
            store.update("spindle", float("nan"), float(t), "sensor")
        store.update("bed", float("nan"), 0.0, "sensor")
        store.update("spindle", 500.0, 1.0, "sensor")
        store.update("spindle", float("nan"), 61.0, "sensor")
    texts = [r.getMessage() for r in caplog.records]
    assert len(texts) == 4, texts  # spindle/not_finite twice (0 s, 61 s), bed, out of range
    assert sum("not_finite" in t for t in texts) == 3
    assert store.refused["not_finite"] == 7  # every one counted


def test_the_siemens_nc_and_the_runtime_configure_their_screen() -> None:
    nc = SiemensNC("s", ["X", "Y", "Z"], SiemensConfig(max_temp_rate_K_per_s=0.2,
                                                        temp_jump_allowance_K=1.0,
                                                        stale_after_s=7.0))
    assert nc.temperatures.stale_after_s == 7.0
    nc.temperatures.update("spindle", 22.0, 0.0, "sensor")
    assert not nc.temperatures.update("spindle", 24.0, 1.0, "sensor")
    # a demo's accelerated thermal time: the plausible rate scales with it
    m = parse_machine({"name": "vmc", "controller": "fanuc", "ip": "127.0.0.1",
                       "chain": "w X Y b Z t", "tool_length_mm": 100.0,
                       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}})
    slow = MachineRuntime(m).controller.temperatures.max_rate_K_per_s
    fast = MachineRuntime(m, thermal_speedup=60.0).controller.temperatures.max_rate_K_per_s
    assert fast == pytest.approx(60.0 * slow)


def test_the_fanuc_ladder_configures_its_screen_too() -> None:
    pmc = FanucPMC("f", ["X", "Y", "Z"], FanucConfig(max_temp_rate_K_per_s=0.2,
                                                     temp_jump_allowance_K=1.0,
                                                     stale_after_s=7.0,
                                                     plausible_C=(0.0, 50.0)))
    t = pmc.temperatures
    assert t.stale_after_s == 7.0
    assert not t.update("spindle", 55.0, 0.0, "sensor")  # outside its range
    assert t.update("spindle", 22.0, 0.0, "sensor")
    assert not t.update("spindle", 24.0, 1.0, "sensor")  # 2 K in 1 s > 0.2 K/s + 1 K
    assert t.update("spindle", 23.0, 1.0, "sensor")
    assert t.stale(8.5) == frozenset({"spindle"}) and not t.stale(7.5)


def test_a_reading_dated_before_the_newest_still_counts_as_a_change() -> None:
    # the cycle refolds the map's thermal records when updated_s moves: a forwarded
    # reading dated by its age before the machine's own newest one must move it too
    store = TemperatureStore()
    store.update("spindle", 24.0, 10.0, "sensor")
    before = store.updated_s
    assert store.update("bed", 21.0, 8.0, "center")
    assert store.updated_s > before and store.updated_s < 10.0 + 1e-9
    same = store.updated_s
    assert not store.update("bed", float("nan"), 11.0, "center")  # refused: no change
    assert store.updated_s == same


async def test_telemetry_leaves_out_an_own_sensor_that_went_stale() -> None:
    """A Siemens-style machine reports the readings its PLC holds; one that stopped
    answering is left out once stale, so it ages on the center's board (which then shows
    it stale) instead of repeating its last value as if fresh."""
    import asyncio

    from machine_sim.link import SimulatedCNC

    m = parse_machine({"name": "vmc", "controller": "siemens", "ip": "127.0.0.1",
                       "chain": "w X Y b Z t", "tool_length_mm": 100.0,
                       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}})
    rt = MachineRuntime(m, siemens=SiemensConfig(stale_after_s=0.2), sensor_period_s=0.01)
    cnc = SimulatedCNC(m, ("127.0.0.1", 1), b"0123456789abcdef", runtime=rt)
    assert cnc.telemetry().temperatures == ()  # nothing read yet
    rt.step(cnc.now())
    held = {s.name: s.celsius for s in cnc.telemetry().temperatures}
    assert held and held == {k: r.celsius for k, r in rt.controller.temperatures.readings()
                             .items()}
    rt.sensor_period_s = 1e9  # the sensors stop answering; the PLC keeps its last values
    await asyncio.sleep(0.3)
    rt.step(cnc.now())
    assert cnc.telemetry().temperatures == ()
    assert rt.controller.temperatures.values()  # still used, held at the last good value
