"""The plain least squares on every sensor and its ridge version
(volumetric.identify.thermal.plain): the same numbers as a direct least-squares fit, lags
that make it a model with rates, a penalty that takes the sensors' noise out, refusals;
in the diagnosis, offered only when a map can carry it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from tests.support.thermal_sim import lagged_spindle
from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.gates import MAX_EFFECTS
from volumetric.diagnose.lagged import MAP_THERMAL_RECORDS, all_sensor_drift
from volumetric.identify.thermal.plain import SHRINKAGE_GRID, fit_all_sensors
from volumetric.measure.measurement import Measurements
from volumetric.model.lag import first_order_lag


def series(seed: int, n: int = 600, sensors: int = 6
           ) -> tuple[np.ndarray, dict[str, np.ndarray], np.random.Generator]:
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 60.0
    temps = {f"T_s{i}_C": 20.0 + np.cumsum(rng.normal(0, 0.05, n)) for i in range(sensors)}
    return t, temps, rng


def test_least_squares_is_the_direct_fit_on_levels_and_lags() -> None:
    t, temps, rng = series(0)
    x = np.column_stack(list(temps.values()))
    y = x @ rng.normal(0, 2, x.shape[1]) + rng.normal(0, 0.1, t.size)
    train = t < t[400]
    for tau in (None, 900.0):
        cols = x if tau is None else np.column_stack([x, first_order_lag(t, x, tau)])
        a = np.column_stack([np.ones(t.size), cols])
        want = np.linalg.lstsq(a[train], y[train], rcond=None)[0]
        model = fit_all_sensors(t, temps, y, train, rate_tau_s=tau)
        assert model.shrinkage == 0.0 and not model.steps
        assert [term.kind for term in model.terms] == (
            ["level"] * 6 + ([] if tau is None else ["lag"] * 6))
        np.testing.assert_allclose(model.coef, want[1:], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(model.predict(t, temps), a @ want, rtol=0, atol=1e-8)
        assert np.all(model.coef_u > 0) and model.cv_rms_um > 0


def test_a_lag_term_carries_a_drift_that_follows_the_rate() -> None:
    # drift = 3 µm/K of level and -40 µm per K/h of rate (τ 900 s): the version with
    # lags fits it to the noise, the levels alone cannot
    t, temps, rng = series(1)
    x = temps["T_s0_C"]
    rate = (x - first_order_lag(t, x, 900.0)) * 4.0  # K/h
    y = 3.0 * x - 40.0 * rate + rng.normal(0, 0.05, t.size)
    train = t < t[400]
    with_rates = fit_all_sensors(t, temps, y, train, rate_tau_s=900.0)
    levels = fit_all_sensors(t, temps, y, train)
    ahead = [float(np.sqrt(np.mean((y - m.predict(t, temps))[~train] ** 2)))
             for m in (with_rates, levels)]
    assert ahead[0] < 0.1 < ahead[1]


def test_ridge_takes_collinear_noise_out_where_least_squares_extrapolates_it() -> None:
    # one true sensor seen through sixteen noisy copies: least squares gives the copies
    # large coefficients of opposite signs, ridge keeps their average
    rng = np.random.default_rng(2)
    n = 800
    t = np.arange(n) * 60.0
    true = 20.0 + 2.0 * np.sin(2 * np.pi * t / 20_000.0)
    temps = {f"T_s{i}_C": true + rng.normal(0, 0.02, n) for i in range(16)}
    y = 5.0 * true + rng.normal(0, 1.0, n)
    train = t < t[300]
    plain = fit_all_sensors(t, temps, y, train)
    ridge = fit_all_sensors(t, temps, y, train, shrink=True)
    assert ridge.shrinkage in SHRINKAGE_GRID and ridge.shrinkage > SHRINKAGE_GRID[0]
    assert np.ptp(ridge.coef) < 0.5 * np.ptp(plain.coef)
    assert abs(ridge.coef.sum() - 5.0) < 0.2
    ahead = [float(np.sqrt(np.mean((y - m.predict(t, temps))[~train] ** 2)))
             for m in (ridge, plain)]
    assert ahead[0] < ahead[1]
    assert ridge.cv_rms_um <= plain.cv_rms_um


def test_bad_input_is_refused_with_a_clear_message() -> None:
    t, temps, _ = series(3, n=100)
    y = np.zeros(t.size)
    with pytest.raises(ValueError, match="no temperatures"):
        fit_all_sensors(t, {}, y)
    with pytest.raises(ValueError, match="rate_tau_s"):
        fit_all_sensors(t, temps, y, rate_tau_s=0.0)
    with pytest.raises(ValueError, match="too few"):
        fit_all_sensors(t[:30], {k: v[:30] for k, v in temps.items()}, y[:30])
    with pytest.raises(ValueError, match="not finite"):
        fit_all_sensors(t, temps, np.full(t.size, np.nan))
    with pytest.raises(ValueError, match="train_mask"):
        fit_all_sensors(t, temps, y, np.ones(t.size))


def test_an_all_sensor_model_beyond_a_maps_thermal_records_is_not_offered() -> None:
    # the live path sends one record per sensor level and one per lag state; a map
    # carries MAP_THERMAL_RECORDS, of which the other effects a diagnosis names may take
    # MAX_EFFECTS - 1: 30 sensors' levels fit, with their rates (one more state) 29
    base = lagged_spindle(0)
    n = len(base)
    rng = np.random.default_rng(4)

    def with_sensors(k: int) -> Measurements:
        temps = {f"s{i}": base.temperatures["a"] + rng.normal(0, 0.05, n) for i in range(k)}
        return replace(base, temperatures=temps,
                       temperature_columns={s: f"T_{s}_C" for s in temps})

    assert MAP_THERMAL_RECORDS - (MAX_EFFECTS - 1) == 30
    static = Candidate("thermal_drift", "z", "T_s0_C", np.zeros((n, 1)))
    order = np.argsort(base.time_s, kind="stable")
    train = np.ones(n, dtype=bool)
    for k, tau, offered in ((30, None, True), (31, None, False), (29, 900.0, True),
                            (30, 900.0, False)):
        m = with_sensors(k)
        c = all_sensor_drift(m, static, m.value, train, order, tau, False)
        assert (c is not None) is offered, (k, tau)
        if c is not None:
            assert c.columns.shape == (n, k if tau is None else 2 * k)
            assert len(c.extra["terms"]) == c.columns.shape[1] and not c.fixed
    shrunk = all_sensor_drift(with_sensors(4), static, base.value, train, order, 900.0, True)
    assert shrunk is not None and shrunk.fixed and shrunk.columns.shape == (n, 1)
    assert shrunk.extra["description"]["all_sensors"]["rate_tau_s"] == 900.0
