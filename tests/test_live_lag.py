"""The live form of a lagged thermal model (volumetric.model.live): the lag states the
center follows one reading at a time land where the whole series does, and the model
written as thermal records on them gives the saved model's drift."""

from __future__ import annotations

import numpy as np
import pytest

from server.intake import model_columns
from server.push.adapter import thermal_sensors
from volumetric.model.components import GeometricErrors
from volumetric.model.lag import first_order_lag, lag_step
from volumetric.model.live import live_lags, live_model, live_needs
from volumetric.model.model import DynamicThermalTerm, LagColumn, MachineModel, ThermalTerm

TERM = DynamicThermalTerm("z", 1.5, (
    LagColumn("level", "T_a_C", 0.0, 2.0, input_C=21.0),
    LagColumn("lag", "T_a_C", 600.0, -3.0, state_C=20.5, input_C=21.0),
    LagColumn("lag", "T_b_C", 3000.0, 1.2),
    LagColumn("time", "", 0.0, 0.4)), t0_s=0.0, t_state_s=7200.0)
MODEL = MachineModel("m", GeometricErrors({}, {}), (TERM,))


def series(seed: int, n: int = 300) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Irregular times (repeats included) and two wandering temperatures."""
    rng = np.random.default_rng(seed)
    dt = rng.choice([0.0, 0.01, 1.0, 15.0, 300.0, 4000.0], n - 1)
    t = np.concatenate(([0.0], np.cumsum(dt)))
    return t, 20 + np.cumsum(rng.normal(0, 0.1, n)), 20 + np.cumsum(rng.normal(0, 0.05, n))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_one_step_at_a_time_is_the_whole_series(seed: int) -> None:
    t, x, _ = series(seed)
    y = [x[0]]
    for k in range(1, t.size):
        y.append(lag_step(y[-1], x[k - 1], x[k], t[k] - t[k - 1], 600.0))
    np.testing.assert_allclose(y, first_order_lag(t, x, 600.0), rtol=0, atol=1e-9)


def test_a_lag_step_needs_a_positive_time_constant() -> None:
    with pytest.raises(ValueError, match="tau_s"):
        lag_step(20.0, 20.0, 21.0, 1.0, 0.0)


def test_the_live_model_gives_the_saved_drift_over_any_history() -> None:
    lags = live_lags(MODEL)
    assert [(g.column, g.weights, g.tau_s) for g in lags] == [
        ("T_lag1_C", (("T_a_C", 1.0),), 600.0), ("T_lag2_C", (("T_b_C", 1.0),), 3000.0)]
    live = live_model(MODEL)
    records = [t for t in live.terms if isinstance(t, ThermalTerm)]
    assert [(r.sensor, r.coefficient) for r in records] == [
        ("T_a_C", 2.0), ("T_lag1_C", -3.0), ("T_lag2_C", 1.2)]
    t, a, b = series(4)
    # the time column is held at the saved state's time (0.4 µm/h over 2 h)
    held = DynamicThermalTerm("z", 1.5 + 0.8, TERM.columns[:3], 0.0, None)
    expected = held.series(t, {"T_a_C": a, "T_b_C": b})  # from rest at the first reading
    lag1, lag2 = first_order_lag(t, a, 600.0), first_order_lag(t, b, 3000.0)
    got = [float(live.geometry_at({"T_a_C": a[k], "T_lag1_C": lag1[k],
                                   "T_lag2_C": lag2[k]}).components["EZZ"](np.zeros(1))[0])
           for k in range(t.size)]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
    # and a lag state the map ignored (the steady-state fold before) would differ
    steady = [TERM.steady_um({"T_a_C": a[k], "T_b_C": b[k]}) for k in range(t.size)]
    assert np.max(np.abs(np.asarray(steady) - expected)) > 0.1


def test_lags_of_one_time_constant_are_one_state_of_their_weighted_sum() -> None:
    """An averaged model (every sensor's level and lags at a few time constants, as
    ``ednc diagnose`` saves it) is one record per sensor level and one per time constant,
    whatever the number of sensors: sixteen sensors at five time constants are 21
    records, not 96, and fit a map's 32."""
    rng = np.random.default_rng(7)
    sensors = [f"T_s{i}_C" for i in range(16)]
    taus = (600.0, 1200.0, 2400.0, 4800.0, 9600.0)
    columns = [LagColumn("level", s, 0.0, float(rng.normal(0, 2)), input_C=21.0)
               for s in sensors]
    columns += [LagColumn("lag", s, tau, float(rng.normal(0, 2)),
                          state_C=20.0 + float(rng.normal(0, 1)), input_C=21.0)
                for tau in taus for s in sensors]
    # a selected term on a sensor and time constant the average also has (the same lag
    # of the same readings, so the same saved state): one state, coefficients summed
    (twin,) = [c for c in columns if c.sensor == sensors[3] and c.tau_s == 1200.0]
    columns.append(LagColumn("lag", sensors[3], 1200.0, 5.0, state_C=twin.state_C,
                             input_C=21.0))
    columns.append(LagColumn("level", sensors[3], 0.0, -1.0, input_C=21.0))
    term = DynamicThermalTerm("x", -3.0, tuple(columns), 0.0, 3600.0)
    model = MachineModel("m", GeometricErrors({}, {}), (term,))
    lags = live_lags(model)
    assert [g.tau_s for g in lags] == list(taus)
    assert all(g.sources == tuple(sensors) for g in lags)
    assert all(abs(sum(abs(w) for _, w in g.weights) - 1.0) < 1e-12 for g in lags)
    live = live_model(model)
    records = [t for t in live.terms if isinstance(t, ThermalTerm)]
    assert len(records) == 16 + 5
    n = 400
    t = np.cumsum(rng.uniform(1.0, 120.0, n))
    temps = {s: 20 + np.cumsum(rng.normal(0, 0.05, n)) for s in sensors}
    # from the saved states, as the center would continue them
    saved = DynamicThermalTerm("x", -3.0, tuple(columns), 0.0, float(t[0]) - 60.0)
    expected = saved.series(t, temps)
    live = live_model(MachineModel("m", GeometricErrors({}, {}), (saved,)))
    per_sensor = {}
    for tau in taus:
        for s in sensors:
            (c,) = [c for c in columns[16:16 + 80] if c.sensor == s and c.tau_s == tau]
            per_sensor[s, tau] = first_order_lag(
                np.concatenate(([saved.t_state_s], t)),
                np.concatenate(([c.input_C], temps[s])), tau, x0=c.state_C)[1:]
    got, sent_range = [], []
    for k in range(n):
        readings = {s: float(temps[s][k]) for s in sensors}
        for g in lags:
            states = {s: float(per_sensor[s, g.tau_s][k]) for s in sensors}
            readings[g.column] = g.state(states)
            sent_range.append((readings[g.column], min(states.values()),
                               max(states.values())))
        got.append(float(live.geometry_at(readings).components["EXX"](np.zeros(1))[0]))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9)
    # what is sent is a temperature within its sensors' states, however the signs fall
    assert all(lo - 1e-9 <= v <= hi + 1e-9 for v, lo, hi in sent_range)


def test_a_sensor_of_zero_weight_is_not_followed() -> None:
    """A lag column whose coefficient is zero (or sums to zero) is no source: the center
    would otherwise wait for that sensor's readings before sending the state."""
    term = DynamicThermalTerm("z", 0.0, (
        LagColumn("lag", "T_a_C", 600.0, 2.0), LagColumn("lag", "T_b_C", 600.0, 0.0),
        LagColumn("lag", "T_c_C", 600.0, 1.0), LagColumn("lag", "T_c_C", 600.0, -1.0),
        LagColumn("lag", "T_d_C", 1200.0, 0.0)))
    lags = live_lags(MachineModel("m", GeometricErrors({}, {}), (term,)))
    assert [(g.column, g.weights, g.tau_s) for g in lags] == [
        ("T_lag1_C", (("T_a_C", 1.0),), 600.0)]


def test_a_model_without_lags_is_its_own_live_form() -> None:
    plain = MachineModel("m", GeometricErrors({}, {}),
                         (ThermalTerm("thermal_drift", "z", "T_a_C", 1.0, 20.0),))
    assert live_model(plain) is plain and live_lags(plain) == ()


def test_what_the_center_needs_is_read_from_the_json() -> None:
    body = MODEL.to_json()
    needs = live_needs(body["terms"])
    assert needs.lags == live_lags(MODEL)
    assert needs.records == {"T_a_C", "T_lag1_C", "T_lag2_C"}
    assert needs.inputs == {"T_a_C", "T_b_C"}
    # the push builds records on these; the intake accepts readings of these
    assert thermal_sensors(body) == needs.records
    assert model_columns(body) == needs.records | needs.inputs
    bad = {**body, "terms": [{"effect": "thermal_dynamic", "axis": "z",
                              "columns": [{"kind": "lag", "sensor": "T_a_C", "tau_s": -1,
                                           "coefficient": 1.0}]}]}
    assert thermal_sensors(bad) == frozenset()  # unreadable: the build will say why
