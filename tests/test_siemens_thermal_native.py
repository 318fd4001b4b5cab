"""A Siemens-style machine applies the thermal records of its map through the NC's own
temperature compensation (issue 13, item 3): per axis the records at the latest
temperatures are an offset and a slope; the slope goes to SD43910/SD43920 where MD32750
bit 1 is on (the NC evaluates it at the axis's own position every IPO cycle), the PLC's
SD43900 carries the rest, the applied total is the map's correction, MD32760 limits the
rate, and when temperatures stop the thermal part holds the last good value."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from machine_sim.lookup import TablesMap
from machine_sim.siemens import (
    SD_ABS_VALUE,
    SD_REF_POSITION,
    SD_SLOPE,
    SiemensConfig,
    SiemensNC,
)
from machine_sim.siemens_thermal import record_setting_data
from protocol import (
    ComponentTable,
    MapAck,
    MapReject,
    TablesPayload,
    ThermalRecord,
    encode_payload,
    split_into_chunks,
)
from tests.support.sim_tables import random_tables, tables_payload
from volumetric.compensate.solver import Weights
from volumetric.model.machine import Machine, parse_machine

F64 = NDArray[np.float64]
RECORDS = (ThermalRecord("spindle", "Z", 1, -2.0, 20.0),  # drift, µm/K
           ThermalRecord("T_x_screw_C", "X", 2, 11.5, 20.0, 0.0),  # expansion, µm/(m·K)
           ThermalRecord("bed", "X", 2, -4.0, 21.0, -100.0),  # about another reference
           ThermalRecord("spindle", "X", 1, -0.4, 20.0),
           ThermalRecord("column", "Y", 2, 8.0, 19.0, 50.0))
TEMPS = {"spindle": 31.0, "x_screw": 27.5, "bed": 22.5, "column": 23.0}


def record_error_um(axis: str, q: float, temps: dict[str, float]) -> float:
    """The records' positioning error of ``axis`` at ``q``, µm, from the protocol's
    definition (ThermalRecord docstring), not from the code under test."""
    total = 0.0
    for r in RECORDS:
        name = r.sensor[2:-2] if r.sensor.startswith("T_") else r.sensor
        if r.axis != axis or name not in temps:
            continue
        dt = temps[name] - r.t_ref_C
        total += r.coefficient * dt * ((q - r.q_min) * 1e-3 if r.kind == 2 else 1.0)
    return total


def three_axis() -> Machine:
    return parse_machine({"name": "sie-3ax", "controller": "siemens", "ip": "127.0.0.1",
                          "chain": "w X Y b Z t", "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}})


def thermal_map(m: Machine, seed: int = 1, geometry: bool = True,
                records: tuple[ThermalRecord, ...] = RECORDS) -> TablesPayload:
    tables: list[ComponentTable] = []
    if geometry:
        _, tables = random_tables(m, np.random.default_rng(seed), 4.0)
    return tables_payload(m, tables, {"EC0Y": 10.0} if geometry else {}, Weights.default(m),
                          thermal=records)


def push(nc: SiemensNC, p: TablesPayload) -> None:
    reply: MapAck | MapReject | None = None
    for msg in split_into_chunks(encode_payload(p), p.version, 512):
        reply = nc.feed_map(msg, 0.0)
    assert isinstance(reply, MapAck), reply


def settle(nc: SiemensNC, pos: F64, now_s: float = 0.0, cycles: int = 400) -> F64:
    for _ in range(cycles):
        applied = nc.ipo_cycle(now_s, pos)
    return applied.copy()


def map_at(p: TablesPayload, temps: dict[str, float], q: F64) -> F64:
    """What the map corrects at q and these temperatures, as the machine evaluates it."""
    out: F64 = TablesMap.from_payload(p, temps).lookup(q[None, :])[0]
    return out


def test_record_setting_data_cancel_the_records_along_each_axis() -> None:
    data = record_setting_data(RECORDS, {f"T_{k}_C": v for k, v in TEMPS.items()},
                               ["X", "Y", "Z"])
    assert data["Z"].slope == 0.0 and data["X"].ref_mm == 0.0  # the first record's q_min
    for axis in "XYZ":
        for q in np.linspace(-300.0, 500.0, 9):
            assert data[axis].correction_mm(float(q)) * 1e3 == pytest.approx(
                -record_error_um(axis, float(q), TEMPS), abs=1e-9)
    assert abs(record_error_um("X", 500.0, TEMPS)) > 20.0  # not trivially near zero
    # a sensor without a reading counts as at its reference; an axis the NC lacks is
    # left to the cycle
    partial = {k: v for k, v in TEMPS.items() if k != "column"}
    some = record_setting_data(RECORDS, partial, ["X", "Z"])
    assert set(some) == {"X", "Z"}
    assert some["X"].correction_mm(100.0) * 1e3 == pytest.approx(
        -record_error_um("X", 100.0, partial), abs=1e-9)


@pytest.mark.parametrize("comp_type", [3, 1])
def test_the_applied_total_is_the_maps_correction_with_the_slope_in_sd43910(
        comp_type: int) -> None:
    m = three_axis()
    p = thermal_map(m)
    nc = SiemensNC(m.name, m.axis_names, SiemensConfig(temp_comp_type=comp_type,
                                                       velo_factor=1.0))
    push(nc, p)
    for sensor, celsius in TEMPS.items():
        assert nc.temperatures.update(sensor, celsius, 0.0, "sensor")
    x = m.axis_names.index("X")
    for q in ([100.0, 50.0, -20.0], [450.0, 250.0, -280.0], [0.0, 0.0, 0.0]):
        pos = np.array(q)
        applied = settle(nc, pos)
        np.testing.assert_allclose(applied, map_at(p, TEMPS, pos), rtol=0, atol=1e-12)
        # the thermal part: the map's correction at these temperatures minus at the
        # references, which is what the records say along each axis (to second order)
        thermal = map_at(p, TEMPS, pos) - map_at(p, {}, pos)
        for j, axis in enumerate(m.axis_names):
            assert thermal[j] * 1e3 == pytest.approx(-record_error_um(axis, q[j], TEMPS),
                                                     abs=0.01)
    if comp_type == 3:  # the NC evaluates the slope itself
        want = -(11.5 * 7.5 - 4.0 * 1.5) * 1e-6
        assert nc.read_sd(SD_SLOPE, "X") == pytest.approx(want, rel=1e-12)
        assert nc.read_sd(SD_REF_POSITION, "X") == 0.0
        assert nc.read_sd(SD_REF_POSITION, "Y") == 50.0
        # SD43900 holds the rest: the whole correction at the PLC's position minus the
        # NC's slope term there
        assert nc.read_sd(SD_ABS_VALUE, "X") == pytest.approx(
            float(np.float32(map_at(p, TEMPS, pos)[x])) - want * (pos[x] - 0.0), abs=1e-12)
    else:  # bit 1 off: nothing in SD43910, the PLC carries the slope
        assert nc.read_sd(SD_SLOPE, "X") == 0.0
    assert nc.map_thermal["X"].slope == pytest.approx(-(11.5 * 7.5 - 4.0 * 1.5) * 1e-6)
    assert not nc.alarms


def test_the_ncs_slope_follows_the_axis_without_the_plcs_latency() -> None:
    # X moves at 10 m/min; the PLC writes every 4th IPO cycle. With the slope in
    # SD43910 the applied thermal correction is the map's at the axis's position in
    # every IPO cycle; with bit 1 off it lags by up to 4 cycles of travel times the slope
    m = three_axis()
    p = thermal_map(m, geometry=False,
                    records=(ThermalRecord("x_screw", "X", 2, 40.0, 20.0, 0.0),))
    worst = {}
    for comp_type in (3, 1):
        nc = SiemensNC(m.name, m.axis_names, SiemensConfig(
            temp_comp_type=comp_type, plc_every=4, velo_factor=1.0))
        push(nc, p)
        nc.temperatures.update("x_screw", 45.0, 0.0, "sensor")  # +25 K: 1 µm per mm
        settle(nc, np.array([100.0, 0.0, 0.0]), cycles=8)
        gap = 0.0
        for k in range(200):
            pos = np.array([100.0 + k * 0.6667, 0.0, 0.0])
            applied = nc.ipo_cycle(0.0, pos)
            gap = max(gap, abs(float(applied[0] - map_at(p, {"x_screw": 45.0}, pos)[0])))
        worst[comp_type] = gap
    # what still lags is the map's departure from a straight line: the solve evaluates
    # the expansion at q + dq, a slope of s/(1 + s), s²·Δq ≈ 1e-6 mm per mm of travel
    assert worst[3] < 5e-6
    assert worst[1] > 1e-3  # three cycles of 0.67 mm at 1 µm/mm


def test_md32760_limits_the_rate_of_a_temperature_step() -> None:
    m = three_axis()
    p = thermal_map(m)
    nc = SiemensNC(m.name, m.axis_names, SiemensConfig(plc_every=1))
    push(nc, p)
    pos = np.array([400.0, 100.0, -100.0])
    nc.temperatures.update("x_screw", 20.0, 0.0, "sensor")
    before = settle(nc, pos, cycles=50)
    nc.temperatures.update("x_screw", 29.0, 1.0, "sensor")  # +9 K: ~41 µm on X at 400 mm
    step = nc.max_step_mm()
    target = map_at(p, {"x_screw": 29.0}, pos)
    assert abs(target[0] - before[0]) > 5 * step[0]  # the step takes several cycles
    last = before
    for _ in range(20):
        now = nc.ipo_cycle(1.0, pos).copy()
        assert np.all(np.abs(now - last) <= step + 1e-15)
        last = now
    np.testing.assert_allclose(last, target, rtol=0, atol=1e-12)


def test_when_temperatures_stop_the_thermal_part_holds_the_last_good_value() -> None:
    m = three_axis()
    p = thermal_map(m)
    nc = SiemensNC(m.name, m.axis_names, SiemensConfig(stale_after_s=5.0, plc_every=1))
    push(nc, p)
    pos = np.array([300.0, 150.0, -150.0])
    for t in range(11):  # a warming spindle, read every second
        assert nc.temperatures.update("spindle", 22.0 + 0.3 * t, float(t), "sensor")
        settle(nc, pos, float(t), cycles=5)
    assert nc.thermal_stale == frozenset()
    good = {"spindle": 25.0}
    # then nothing for 20 s, but a broken reading and a spike
    assert not nc.temperatures.update("spindle", float("nan"), 12.0, "sensor")
    assert not nc.temperatures.update("spindle", 85.0, 13.0, "sensor")
    applied = settle(nc, pos, 30.0, cycles=50)
    assert nc.thermal_stale == {"spindle"}
    np.testing.assert_allclose(applied, map_at(p, good, pos), rtol=0, atol=1e-12)
    assert abs(map_at(p, good, pos) - map_at(p, {}, pos))[2] > 5e-3  # the part is there
    assert nc.temperatures.refused == {"not_finite": 1, "too_fast": 1}
    # readings come back: fresh again, the thermal part follows them
    nc.temperatures.update("spindle", 25.5, 31.0, "sensor")
    applied = settle(nc, pos, 31.0, cycles=50)
    assert nc.thermal_stale == frozenset()
    np.testing.assert_allclose(applied, map_at(p, {"spindle": 25.5}, pos), rtol=0,
                               atol=1e-12)
