"""Dynamic thermal-drift regressors (volumetric.identify.thermal): lag against analytic responses,
the selection on a synthetic truth, and the held-out figures on a real 46 h spindle test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.support.thermal_sim import NOISE_UM, TRUE_LAGS, lagged_spindle
from volumetric.identify.thermal import (
    ThermalTerm,
    first_order_lag,
    fit_thermal_drift,
    thermal_regressors,
)
from volumetric.measure.measurement import read_measurements

SPLIT_S = 144_000.0  # end of the heat/cool cycles; the variable-speed block follows


# --- first_order_lag -------------------------------------------------------------------


def irregular_times(n: int, seed: int) -> np.ndarray:
    """Sorted, irregular sample times (s) with a repeated time and one long gap."""
    rng = np.random.default_rng(seed)
    steps = rng.exponential(60.0, n - 1)
    steps[n // 3] = 0.0  # two readings at the same time
    steps[n // 2] = 20_000.0  # a gap of many time constants
    return np.concatenate([[0.0], np.cumsum(steps)])


def test_step_response_is_exact_on_irregular_samples() -> None:
    t = irregular_times(400, seed=1)
    tau = 900.0
    y = first_order_lag(t, np.full(t.shape, 2.0), tau, x0=0.0)
    np.testing.assert_allclose(y, 2.0 * (1.0 - np.exp(-t / tau)), rtol=0, atol=1e-12)


def test_ramp_response_is_exact_on_irregular_samples() -> None:
    # x = r t from rest at 0: y = r (t - τ (1 - exp(-t/τ))). The first-order hold is exact
    # for a piecewise-linear input, so the irregular spacing costs nothing.
    t = irregular_times(500, seed=2)
    tau, r = 1_500.0, 3e-4
    y = first_order_lag(t, r * t, tau)
    expected = r * (t - tau * (1.0 - np.exp(-t / tau)))
    np.testing.assert_allclose(y, expected, rtol=0, atol=1e-9 * r * t[-1])


def test_sine_on_sparse_irregular_samples_matches_dense_reference() -> None:
    tau, period = 2_000.0, 7_200.0
    dense = np.linspace(0.0, 40_000.0, 400_001)
    reference = first_order_lag(dense, np.sin(2 * np.pi * dense / period), tau)
    rng = np.random.default_rng(3)
    sparse = np.sort(rng.choice(dense.shape[0], 300, replace=False))
    sparse[0] = 0
    t = dense[sparse]
    y = first_order_lag(t, np.sin(2 * np.pi * t / period), tau)
    # Linear interpolation of a sine between readings ~130 s apart is what limits this.
    assert np.max(np.abs(y - reference[sparse])) < 0.02
    # and the dense reference is the analytic solution (steady state plus start transient)
    w = 2 * np.pi / period
    analytic = (np.sin(w * dense) - w * tau * np.cos(w * dense)
                + w * tau * np.exp(-dense / tau)) / (1 + (w * tau) ** 2)
    assert np.max(np.abs(reference - analytic)) < 1e-6


def test_lag_of_columns_equals_lag_of_each_column() -> None:
    t = irregular_times(300, seed=4)
    rng = np.random.default_rng(4)
    x = np.cumsum(rng.normal(size=(t.shape[0], 3)), axis=0)
    both = first_order_lag(t, x, 700.0)
    for j in range(3):
        np.testing.assert_allclose(both[:, j], first_order_lag(t, x[:, j], 700.0),
                                   rtol=0, atol=1e-12)


def test_lag_is_linear_and_keeps_constants() -> None:
    t = irregular_times(200, seed=5)
    rng = np.random.default_rng(5)
    x1, x2 = rng.normal(size=(2, t.shape[0]))
    combined = first_order_lag(t, 3.0 * x1 - 2.0 * x2 + 20.0, 400.0)
    separate = 3.0 * first_order_lag(t, x1, 400.0) - 2.0 * first_order_lag(t, x2, 400.0) + 20.0
    np.testing.assert_allclose(combined, separate, rtol=0, atol=1e-10)
    np.testing.assert_allclose(first_order_lag(t, np.full(t.shape, 21.5), 400.0), 21.5,
                               rtol=0, atol=1e-12)


def test_repeated_time_leaves_the_lag_unchanged() -> None:
    t = np.array([0.0, 100.0, 100.0, 200.0])
    y = first_order_lag(t, np.array([0.0, 1.0, 5.0, 5.0]), 50.0, x0=0.0)
    assert y[2] == y[1]


@pytest.mark.parametrize(("t", "x", "tau", "message"), [
    (np.array([0.0, 30.0, 15.0]), np.zeros(3), 10.0, "row 2"),
    (np.array([0.0, 15.0, 30.0]), np.array([1.0, np.nan, 1.0]), 10.0, "row 1"),
    (np.array([0.0, 15.0, 30.0]), np.zeros(3), 0.0, "tau_s"),
    (np.array([0.0, 15.0, 30.0]), np.zeros(4), 10.0, "shape"),
    (np.array([0.0, np.inf]), np.zeros(2), 10.0, "row 1"),
])
def test_lag_rejects_bad_input(t: np.ndarray, x: np.ndarray, tau: float,
                               message: str) -> None:
    with pytest.raises(ValueError, match=message):
        first_order_lag(t, x, tau)


# --- thermal_regressors ----------------------------------------------------------------


def test_regressor_names_and_columns() -> None:
    t = np.arange(0.0, 3_600.0, 60.0)
    temps = {"T_a_C": 20 + t / 3600, "T_b_C": 21 + 0 * t}
    X, names = thermal_regressors(t, temps, taus_s=(600.0,), rate_taus_s=(300.0,),
                                  gradients=[("T_a_C", "T_b_C")], time_drift=True,
                                  inputs={"spindle_rpm": 1000 + 0 * t})
    assert names == ["T_a_C", "T_b_C", "T_a_C lag 600 s", "T_b_C lag 600 s",
                     "T_a_C rate 300 s", "T_b_C rate 300 s", "spindle_rpm",
                     "spindle_rpm lag 600 s", "T_a_C - T_b_C", "time drift h"]
    assert X.shape == (t.shape[0], len(names))
    np.testing.assert_allclose(X[:, 2], first_order_lag(t, temps["T_a_C"], 600.0))
    # a ramp of 1 K/h has, once settled, a smoothed rate of 1 K/h
    assert X[-1, 4] == pytest.approx(1.0, abs=1e-4)
    np.testing.assert_allclose(X[:, 8], temps["T_a_C"] - temps["T_b_C"])
    np.testing.assert_allclose(X[:, 9], t / 3600)
    assert ThermalTerm("lag", "T_t3_C", 3600.0).name == "T_t3_C lag 3600 s"


def test_regressors_name_the_bad_signal() -> None:
    t = np.arange(5.0)
    with pytest.raises(ValueError, match="'T_x_C' is not finite at row 3"):
        thermal_regressors(t, {"T_x_C": np.array([1.0, 1, 1, np.nan, 1])})
    with pytest.raises(ValueError, match="'T_y_C' has shape"):
        thermal_regressors(t, {"T_y_C": np.ones(4)})
    with pytest.raises(ValueError, match="unknown temperature 'T_q_C'"):
        thermal_regressors(t, {"T_x_C": np.ones(5)}, gradients=[("T_x_C", "T_q_C")])


# --- selection on a known truth --------------------------------------------------------


def smooth_random_temperatures(t: np.ndarray, k: int, seed: int) -> np.ndarray:
    """k independent temperature-like signals (°C): lagged random heat inputs."""
    rng = np.random.default_rng(seed)
    dense = np.arange(0.0, t[-1] + 600.0, 600.0)
    heat = np.repeat(rng.uniform(-3.0, 3.0, size=(dense.shape[0] // 12 + 1, k)), 12,
                     axis=0)[: dense.shape[0]]
    temps = 20.0 + first_order_lag(dense, heat, 2_000.0, x0=np.zeros(k))
    return np.column_stack([np.interp(t, dense, temps[:, j]) for j in range(k)])


def test_selection_finds_the_lagged_sensor_and_its_time_constant() -> None:
    # Readings at irregular times with gaps, as in a measurement campaign.
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.exponential(300.0, 1500))
    t[700:] += 30_000.0  # an overnight gap
    raw = smooth_random_temperatures(t, 5, seed=8)
    temps = {f"T_s{j}_C": raw[:, j] for j in range(5)}
    true_tau = 5_400.0
    y = 3.0 + 8.0 * first_order_lag(t, raw[:, 2], true_tau) + rng.normal(0.0, 0.3, t.shape)
    model = fit_thermal_drift(t, temps, y)
    assert model.terms[0].source == "T_s2_C"
    assert model.terms[0].kind == "lag"
    assert model.terms[0].tau_s == pytest.approx(true_tau, rel=0.1)
    assert model.coef[0] == pytest.approx(8.0, rel=0.05)
    assert len(model.terms) <= 2  # the noise does not buy extra terms
    assert model.train_rms_um == pytest.approx(0.3, rel=0.2)


@pytest.mark.parametrize("seed", range(8))
def test_backfitting_finds_the_true_time_constant_of_the_first_lag(seed: int) -> None:
    # The first lag's τ is refined while it alone stands for the whole drift, so it also
    # makes up for the slow ambient term that joins later; refined again with that term in
    # (backfit), it comes back to the truth (the default keeps it: see fit_thermal_drift).
    r = lagged_spindle(seed)
    temps = {f"T_{k}_C": v for k, v in r.temperatures.items()}
    model = fit_thermal_drift(r.time_s, temps, r.value, time_drift=False, backfit=True)
    first = model.terms[0]
    tau, coef = TRUE_LAGS["T_a_C"]
    assert (first.source, first.kind) == ("T_a_C", "lag")
    assert first.tau_s == pytest.approx(tau, rel=0.1)
    assert model.coef[0] == pytest.approx(coef, rel=0.15)
    assert model.train_rms_um < 1.15 * NOISE_UM


def test_pure_noise_selects_nothing() -> None:
    rng = np.random.default_rng(11)
    t = np.arange(0.0, 200_000.0, 60.0)
    raw = smooth_random_temperatures(t, 3, seed=12)
    y = rng.normal(0.0, 1.0, t.shape)
    model = fit_thermal_drift(t, {f"T_{j}_C": raw[:, j] for j in range(3)}, y)
    assert model.terms == ()
    np.testing.assert_allclose(model.predict(t, {f"T_{j}_C": raw[:, j] for j in range(3)}),
                               model.intercept_um)


def test_fit_rejects_bad_input() -> None:
    t = np.arange(0.0, 100.0)
    temps = {"T_a_C": np.ones(100)}
    with pytest.raises(ValueError, match="too few"):
        fit_thermal_drift(t, temps, np.zeros(100), np.arange(100) < 10)
    with pytest.raises(ValueError, match="y is not finite at training row 5"):
        y = np.zeros(100)
        y[5] = np.nan
        fit_thermal_drift(t, temps, y)
    with pytest.raises(ValueError, match="no temperatures"):
        fit_thermal_drift(t, {}, np.zeros(100))
    with pytest.raises(ValueError, match="sorted"):
        fit_thermal_drift(t[::-1], temps, np.zeros(100))


# --- the real spindle test -------------------------------------------------------------


def rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r**2)))


@pytest.fixture
def spindle(real_data: Path) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray,
                                      dict[str, np.ndarray]]:
    """The FL_THERMAL test as measurement CSV: time (s), temperatures by column name (°C),
    ch3 drift along the tool axis (µm), and the spindle speed as an extra input (rpm)."""
    m = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    temps = {column: m.temperatures[sensor]
             for sensor, column in m.temperature_columns.items()}
    return m.time_s, temps, m.value, {"spindle_rpm": m.extra["spindle_rpm"]}


def test_real_baselines_reproduce_the_issue(spindle: tuple[np.ndarray, dict[str, np.ndarray],
                                                             np.ndarray, dict[str, np.ndarray]]
                                            ) -> None:
    t, temps, y, _ = spindle
    assert len(temps) == 16
    held = t >= SPLIT_S
    # no thermal model at all: the drift itself
    assert rms(y[held]) > 20.0
    # static linear model in all 16 temperatures with an intercept, OLS on t < 144 000 s;
    # our reproduction gives 5.56 µm (without the intercept it would be 3.8 µm, from
    # differences of the absolute temperatures 0.1 °C: a different model)
    X = np.column_stack([np.ones(t.shape[0]), *temps.values()])
    c = np.linalg.lstsq(X[~held], y[~held], rcond=None)[0]
    assert 5.50 < rms(y[held] - X[held] @ c) < 5.62


def test_real_dynamic_model_beats_two_micrometres(
        spindle: tuple[np.ndarray, dict[str, np.ndarray], np.ndarray, dict[str, np.ndarray]]
) -> None:
    t, temps, y, inputs = spindle
    held = t >= SPLIT_S
    y_train = np.where(held, np.nan, y)  # the held-out drift cannot reach the fit
    model = fit_thermal_drift(t, temps, y_train, ~held)
    assert rms(y[held] - model.predict(t, temps)[held]) <= 2.0
    assert 1 <= len(model.terms) <= 5
    assert np.all(model.coef_u > 0) and np.all(np.isfinite(model.coef_u))
    # the spindle speed is offered but need not be used; either way it must still reach 2 µm
    with_rpm = fit_thermal_drift(t, temps, y_train, ~held, inputs=inputs)
    assert rms(y[held] - with_rpm.predict(t, temps, inputs)[held]) <= 2.0


def test_real_drift_from_sparse_readings(
        spindle: tuple[np.ndarray, dict[str, np.ndarray], np.ndarray, dict[str, np.ndarray]]
) -> None:
    # A campaign that reads drift and temperatures only every 5 min (every 20th row), at
    # each of five phases: the dynamic model must beat the static one at every phase and
    # reach 2 µm at the median. (The spindle coolant sensor cycles in about 20 min, so
    # sparser readings alias it; see benchmarks/thermal_fl_study.py for the full picture.)
    t, temps, y, _ = spindle
    dynamic, static = [], []
    for phase in range(0, 20, 4):
        rows = np.arange(phase, t.shape[0], 20)
        ts, ys = t[rows], y[rows]
        sub = {k: v[rows] for k, v in temps.items()}
        train = ts < SPLIT_S
        model = fit_thermal_drift(ts, sub, np.where(train, ys, np.nan), train)
        dynamic.append(rms((ys - model.predict(ts, sub))[~train]))
        X = np.column_stack([np.ones(rows.shape[0]), *sub.values()])
        c = np.linalg.lstsq(X[train], ys[train], rcond=None)[0]
        static.append(rms((ys - X @ c)[~train]))
    assert all(d < s for d, s in zip(dynamic, static, strict=True)), (dynamic, static)
    assert float(np.median(dynamic)) <= 2.0, dynamic
