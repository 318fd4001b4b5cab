"""Simulated machine physics: the instrument reads the model's error, each effect alone
leaves its documented signature, the truth and the thermal model behave as documented."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
import pytest

from machine_sim.campaign import machine_directions, machine_positions, run_campaign
from machine_sim.effects import (
    Backlash,
    Effects,
    Noise,
    Periodic,
    ThermalDrift,
    ThermalExpansion,
    TimeDrift,
)
from machine_sim.instruments import SimulatedMachine
from machine_sim.program import Dwell, Measure, Program, Rapid, SpindleOff, SpindleOn
from machine_sim.testprograms import (
    angular_test,
    diagonal_test,
    hold_tool_at,
    positioning_test,
    rotary_positioning_test,
    rtest,
    rtest_balls,
    straightness_test,
)
from machine_sim.thermal import Sensor, ShopAir, ThermalConfig, simulate_thermal
from machine_sim.truth import random_geometry
from volumetric.model.components import GeometricErrors, Polynomial, component_names
from volumetric.model.exact import volumetric_error
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine, parse_machine
from volumetric.verify.iso230_2 import evaluate_positioning

TRAVEL = {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}


def vmc() -> Machine:
    return parse_machine({"name": "vmc", "chain": "w X Y b Z t", "travel_mm": TRAVEL,
                          "tool_length_mm": 100.0})


def five_axis() -> Machine:
    return parse_machine({"name": "5ax", "chain": "w C X Y b Z A t",
                          "travel_mm": {**TRAVEL, "a": [-90, 90], "c": [-180, 180]},
                          "pivots_mm": {"C": [250, 150, 0], "A": [0, 0, 50]},
                          "tool_length_mm": 120.0})


def mixed_programs(m: Machine) -> list[Program]:
    progs: list[Program] = [positioning_test(m, "X", targets=6, runs=2),
                            straightness_test(m, "Y", "Z", targets=5, runs=1),
                            angular_test(m, "Z", "A", targets=5, runs=1)]
    if "Z" in m.axis_names:
        progs.append(diagonal_test(m, "diag-NPP", points=5, runs=1))
    for a in m.axes:
        if a.kind == "rotary":
            progs.append(rotary_positioning_test(m, a.name, targets=5, runs=1))
            st = rtest_balls(m, a.name, targets=5)[1]
            progs.append(rtest(m, a.name, st.ball_mm, angles_deg=st.angles_deg,
                               tool_mm=st.tool_mm))
    return progs


@pytest.mark.parametrize("make", [vmc, five_axis])
def test_reading_is_the_model_error_without_effects_and_noise(make: Callable[[], Machine]
                                                             ) -> None:
    m = make()
    g = random_geometry(m, np.random.default_rng(7), scale=3.0)
    sim = SimulatedMachine(m, g, seed=1)
    progs = mixed_programs(m)
    if "C" in m.axis_names:  # rotate the table for one test so the workpiece frame turns
        progs.append([Rapid({"c": 30.0, "a": 10.0}),
                      *positioning_test(m, "Y", targets=4, runs=1,
                                        line={"x": 100, "z": -50, "c": 30, "a": 10})])
    res = run_campaign(sim, progs)
    meas = res.measurements
    q = machine_positions(m, meas)
    err = volumetric_error(m, g, q, tool_mm=meas.tool_mm)
    assert err.orientation_urad is not None
    want = np.where(meas.is_angle, np.einsum("ni,ni->n", err.orientation_urad, meas.u),
                    np.einsum("ni,ni->n", err.position_um, meas.u))
    np.testing.assert_allclose(meas.value, want, rtol=0, atol=1e-9)
    assert np.ptp(want) > 1.0  # the geometry is not trivially zero here
    assert meas.is_angle.any() and not meas.is_angle.all()


def test_effects_enter_the_chain_like_a_positioning_error_of_their_axis() -> None:
    """Oracle: an effect of size e on axis K equals adding e to EKK in the rigid model,
    also on a five-axis machine whose table turns the workpiece frame."""
    m = five_axis()
    g = random_geometry(m, np.random.default_rng(3))
    rng = np.random.default_rng(4)
    n = 200
    q = np.column_stack([rng.uniform(*a.travel, n) for a in m.axes])
    d = rng.choice([-1, 1], size=q.shape).astype(np.int8)
    eff = Effects(backlash=(Backlash("x", 10.0),), periodic=(Periodic("z", 3.0, 10.0, 0.5),))
    sim = SimulatedMachine(m, g, eff)
    got = sim.true_error(q, d)
    jx, jz = m.axis_names.index("X"), m.axis_names.index("Z")
    want = np.empty((n, 3))
    for i in range(n):
        extra_x = -5.0 * d[i, jx]
        extra_z = 3.0 * np.sin(2 * np.pi * (q[i, jz] + 300.0) / 10.0 + 0.5)
        comps = dict(g.components)
        comps["EXX"] = _shifted(comps["EXX"], extra_x)
        comps["EZZ"] = _shifted(comps["EZZ"], extra_z)
        e = volumetric_error(m, GeometricErrors(comps, g.locations), q[i:i + 1])
        want[i] = e.position_um[0]
    np.testing.assert_allclose(got.position_um, want, rtol=0, atol=1e-8)


def _shifted(f: object, c: float) -> Polynomial:
    assert isinstance(f, Polynomial)
    coeffs = list(f.coefficients)
    coeffs[0] += c
    return Polynomial(tuple(coeffs), f.origin, f.scale)


def _positioning(sim: SimulatedMachine, axis: str = "x", **kw: object) -> object:
    prog = positioning_test(sim.machine, axis, **kw)  # type: ignore[arg-type]
    return run_campaign(sim, [prog])


def test_backlash_alone_gives_its_reversal() -> None:
    m = vmc()
    g = random_geometry(m, np.random.default_rng(1))
    sim = SimulatedMachine(m, g, Effects(backlash=(Backlash("y", 9.0),)))
    res = run_campaign(sim, [positioning_test(m, "y", targets=8, runs=3)])
    r = evaluate_positioning(res.measurements)
    # x̄↑ - x̄↓ = -B at every target (documented sign), |B| = 9
    np.testing.assert_allclose(r.reversal_um, -9.0, atol=1e-9)
    assert r.B_um == pytest.approx(9.0, abs=1e-9)
    plain = run_campaign(dataclasses.replace(sim, effects=Effects()),
                         [positioning_test(m, "y", targets=8, runs=3)])
    assert evaluate_positioning(plain.measurements).B_um < 1e-9


def test_backlash_on_another_axis_leaves_this_axis_alone() -> None:
    m = vmc()
    g = random_geometry(m, np.random.default_rng(1))
    sim = SimulatedMachine(m, g, Effects(backlash=(Backlash("x", 9.0),)))
    res = run_campaign(sim, [positioning_test(m, "y", targets=8, runs=2)])
    assert evaluate_positioning(res.measurements).B_um < 1e-9


def test_periodic_alone_gives_its_amplitude_and_period() -> None:
    m = vmc()
    sim = SimulatedMachine(m, GeometricErrors(),
                           Effects(periodic=(Periodic("x", 2.5, 16.0, 1.1),)))
    targets = np.arange(200.0, 260.0, 0.7)
    res = run_campaign(sim, [positioning_test(m, "x", targets=targets, runs=1)])
    x, v = res.measurements.q[:, 0], res.measurements.value
    best = None
    for period in np.arange(5.0, 25.0, 0.01):
        basis = np.column_stack([np.sin(2 * np.pi * x / period),
                                 np.cos(2 * np.pi * x / period)])
        coef, *_ = np.linalg.lstsq(basis, v, rcond=None)
        ss = float(np.sum((basis @ coef - v) ** 2))
        if best is None or ss < best[0]:
            best = (ss, period, float(np.hypot(*coef)))
    assert best is not None
    assert best[1] == pytest.approx(16.0, abs=0.01)
    assert best[2] == pytest.approx(2.5, rel=1e-6)


def quiet_thermal(*sensors: Sensor) -> ThermalConfig:
    return ThermalConfig(sensors, ShopAir(daily_amplitude_K=0.0, wander_K=0.0), step_s=1.0)


def warm_up(rpm: float, seconds: float) -> Program:
    return [SpindleOn(rpm), Dwell(seconds), SpindleOff()]


def test_thermal_expansion_alone_gives_its_slope() -> None:
    m = vmc()
    thermal = quiet_thermal(Sensor("spindle", 1200.0, spindle_K_per_krpm=1.0),
                            Sensor("air", 0.0))
    eff = Effects(expansion=(ThermalExpansion("x", "spindle", 8.0, reference_C=20.0),))
    sim = SimulatedMachine(m, GeometricErrors(), eff, thermal, seed=5)
    progs: list[Program] = []
    for _ in range(4):
        progs += [warm_up(8000.0, 1200.0), positioning_test(m, "x", targets=6, runs=1)]
    res = run_campaign(sim, progs)
    meas = res.measurements
    true_t = res.thermal.true_at(meas.time_s)["spindle"]
    assert np.ptp(true_t) > 2.0  # the campaign really warms the machine (by ~2.8 K)
    regressor = (true_t - 20.0) * meas.q[:, 0] * 1e-3
    slope = float(regressor @ meas.value / (regressor @ regressor))
    assert slope == pytest.approx(8.0, rel=1e-9)
    # the recorded sensor follows the true temperature within its lag (20 s times the
    # fastest rate of change) and its noise (0.02 K, 5 sigma)
    rate = np.max(np.abs(np.gradient(res.thermal.true_C["spindle"], res.thermal.time_s)))
    bound = 20.0 * rate + 5 * 0.02
    assert np.max(np.abs(meas.temperatures["spindle"] - true_t)) < bound


def test_thermal_drift_alone_follows_the_temperature_change() -> None:
    m = vmc()
    thermal = quiet_thermal(Sensor("spindle", 1200.0, spindle_K_per_krpm=1.5),
                            Sensor("air", 0.0))
    eff = Effects(drift=(ThermalDrift("z", "spindle", -2.0),))
    sim = SimulatedMachine(m, GeometricErrors(), eff, thermal, seed=5)
    spot = [Measure("Z-drift", 1, "displacement", (0.0, 0.0, 1.0), settle_s=120.0)] * 40
    res = run_campaign(sim, [[SpindleOn(8000.0)], spot])
    meas = res.measurements
    true_t = res.thermal.true_at(meas.time_s)["spindle"]
    np.testing.assert_allclose(meas.value, -2.0 * (true_t - res.thermal.start()["spindle"]),
                               atol=1e-9)
    assert meas.value[-1] < -10.0  # 1.5 K/krpm * 8 krpm * (1 - e^-4) * -2 µm/K


def test_lagged_thermal_drift_follows_the_lagged_temperature() -> None:
    m = vmc()
    thermal = quiet_thermal(Sensor("spindle", 1200.0, spindle_K_per_krpm=1.5),
                            Sensor("air", 0.0))
    eff = Effects(drift=(ThermalDrift("z", "spindle", -2.0, lag_s=900.0),))
    sim = SimulatedMachine(m, GeometricErrors(), eff, thermal, seed=5)
    spot = [Measure("Z-drift", 1, "displacement", (0.0, 0.0, 1.0), settle_s=60.0)] * 120
    res = run_campaign(sim, [[SpindleOn(8000.0)], spot[:60], [SpindleOff()], spot[60:]])
    h = res.thermal
    # an independent first-order lag: explicit Euler on a 0.1 s grid of the true series
    fine_t = np.arange(h.time_s[0], h.time_s[-1], 0.1)
    fine_x = np.interp(fine_t, h.time_s, h.true_C["spindle"])
    lagged = np.empty_like(fine_x)
    lagged[0] = fine_x[0]
    for i in range(1, fine_t.size):
        lagged[i] = lagged[i - 1] + 0.1 / 900.0 * (fine_x[i - 1] - lagged[i - 1])
    want = -2.0 * (np.interp(res.measurements.time_s, fine_t, lagged) - lagged[0])
    # the model holds each 1 s step's temperature where Euler interpolates it: they part
    # by at most k * (largest change over one step, ~0.01 K) / 2 = 0.01 µm
    np.testing.assert_allclose(res.measurements.value, want, rtol=0, atol=0.01)
    unlagged = -2.0 * (h.true_at(res.measurements.time_s)["spindle"] - h.start()["spindle"])
    assert np.max(np.abs(unlagged - want)) > 1.0  # the lag matters at this size


def test_time_drift_alone_grows_with_time() -> None:
    m = vmc()
    sim = SimulatedMachine(m, GeometricErrors(), Effects(time=(TimeDrift("y", 1.5),)))
    spot = [Measure("Y-drift", 1, "displacement", (0.0, 1.0, 0.0), settle_s=600.0)] * 12
    meas = run_campaign(sim, [spot]).measurements
    np.testing.assert_allclose(meas.value, 1.5 * meas.time_s / 3600.0, rtol=0, atol=1e-12)
    assert meas.value[-1] == pytest.approx(3.0)  # 2 h at 1.5 µm/h


def test_noise_has_its_standard_deviation() -> None:
    m = vmc()
    g = random_geometry(m, np.random.default_rng(1))
    sim = SimulatedMachine(m, g, Effects(noise=Noise(0.5, 2.0)), seed=11)
    res = run_campaign(sim, [positioning_test(m, "x", targets=21, runs=25),
                             angular_test(m, "x", "B", targets=21, runs=25)])
    meas = res.measurements
    resid = meas.value - res.true_value
    # 1050 readings each: the sample standard deviation is within 3 standard errors
    for mask, sigma in ((~meas.is_angle, 0.5), (meas.is_angle, 2.0)):
        s = float(np.std(resid[mask], ddof=1))
        assert abs(s / sigma - 1) < 3 / np.sqrt(2 * mask.sum())


def test_directions_recorded_are_the_last_motion() -> None:
    m = vmc()
    res = run_campaign(SimulatedMachine(m, GeometricErrors()),
                       [positioning_test(m, "z", targets=4, runs=1)])
    meas = res.measurements
    d = machine_directions(m, meas)[:, m.axis_names.index("Z")]
    z = meas.q[:, 2]
    assert d.tolist() == [1, 1, 1, 1, -1, -1, -1, -1]
    assert np.all(np.diff(z[:4]) > 0) and np.all(np.diff(z[4:]) < 0)


def test_random_geometry_is_realistic_and_reproducible() -> None:
    m = five_axis()
    g1 = random_geometry(m, np.random.default_rng(42), form="table")
    g2 = random_geometry(m, np.random.default_rng(42), form="table")
    assert g1.to_json() == g2.to_json()
    g1.check(m)
    for a in m.axes:
        lo, hi = a.travel
        q = np.linspace(lo, hi, 201) if a.kind == "linear" else np.linspace(-180, 180, 73)
        for name in component_names(a):
            v = g1.components[name](q)
            if a.kind == "linear":
                assert v[0] == pytest.approx(0.0, abs=1e-12), name  # zero at start
                limit = 40.0 if name[1] == a.name or name[1] in "ABC" else 6.0
            else:
                assert float(g1.components[name](np.array([0.0]))[0]) == pytest.approx(
                    0.0, abs=1e-9)
                limit = 50.0
            assert np.max(np.abs(v)) < limit, name
    positioning = g1.components["EXX"](np.linspace(0, 500, 11))
    assert np.ptp(positioning) > 0.5  # not trivially flat
    assert set(g1.locations) >= {"EC0Y", "EA0Z", "EB0Z", "EX0C", "EA0A"}


def test_thermal_model_warms_to_its_steady_state_and_lags() -> None:
    config = quiet_thermal(Sensor("spindle", 600.0, spindle_K_per_krpm=1.0, lag_s=30.0,
                                  noise_K=0.0))
    t = np.arange(0.0, 12000.0, 1.0)
    rpm = np.where(t < 6000.0, 5000.0, 0.0)
    h = simulate_thermal(config, t, rpm, {}, seed=1)
    true = h.true_C["spindle"]
    assert true[5999] == pytest.approx(25.0, abs=1e-3)  # 10 time constants: 5 K up
    assert true[600] == pytest.approx(20.0 + 5.0 * (1 - np.exp(-1)), abs=1e-6)
    assert true[-1] == pytest.approx(20.0, abs=1e-3)  # cooled back
    sensed = h.sensed_C["spindle"]
    assert np.all(sensed[1:6000] < true[1:6000])  # the sensor lags while warming


def test_thermal_model_is_deterministic_by_seed() -> None:
    config = ThermalConfig((Sensor("air", 0.0),), ShopAir(wander_K=0.3), step_s=5.0)
    t = np.arange(0.0, 36000.0, 5.0)
    a = simulate_thermal(config, t, np.zeros_like(t), {}, seed=3)
    b = simulate_thermal(config, t, np.zeros_like(t), {}, seed=3)
    c = simulate_thermal(config, t, np.zeros_like(t), {}, seed=4)
    np.testing.assert_array_equal(a.true_C["air"], b.true_C["air"])
    assert np.max(np.abs(a.true_C["air"] - c.true_C["air"])) > 0.01


def test_effect_on_a_missing_axis_or_sensor_is_named() -> None:
    m = vmc()
    with pytest.raises(ValueError, match=r"Effects.backlash\[0\].*no axis 'w'"):
        SimulatedMachine(m, GeometricErrors(), Effects(backlash=(Backlash("w", 3.0),)))
    with pytest.raises(ValueError, match="sensor 'nowhere'"):
        SimulatedMachine(m, GeometricErrors(),
                         Effects(drift=(ThermalDrift("z", "nowhere", 1.0),)))
    with pytest.raises(ValueError, match="reversal_um must be >= 0"):
        Backlash("x", -1.0)
    with pytest.raises(ValueError, match="period_mm must be > 0"):
        Periodic("x", 1.0, 0.0)


@pytest.mark.parametrize("chain", ["w C X Y b Z A t", "w C A X b Y Z t", "w Y b X Z C A t"])
def test_rtest_holds_the_nominal_tool_tip_on_the_ball(chain: str) -> None:
    m = parse_machine({"name": "r", "chain": chain, "tool_length_mm": 100.0,
                       "travel_mm": {**TRAVEL, "a": [-120, 30]},
                       "pivots_mm": {"C": [250, 150, -200], "A": [250, 150, -150]}})
    for a in ("A", "C"):
        for st in rtest_balls(m, a, targets=7):
            prog = rtest(m, a, st.ball_mm, angles_deg=st.angles_deg, tool_mm=st.tool_mm)
            res = run_campaign(SimulatedMachine(m, GeometricErrors()), [prog])
            q = machine_positions(m, res.measurements)
            tip, _ = tool_pose(m, q, None, tool_mm=res.measurements.tool_mm,
                               orientation=False)
            np.testing.assert_allclose(tip, np.broadcast_to(st.ball_mm, tip.shape),
                                       rtol=0, atol=1e-9)
            turned = np.unique(np.round(q[:, m.axis_names.index(a)], 9))
            assert turned.size == 7  # every angle visited
    with pytest.raises(ValueError, match="outside its travel"):
        hold_tool_at(m, np.array([2000.0, 0.0, 0.0]), {})
