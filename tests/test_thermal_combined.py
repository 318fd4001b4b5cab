"""The all-sensor part of a dynamic thermal model (volumetric.identify.thermal, step 6):
what it adds up to, when it joins, and what it does ahead of the rows it was fitted on."""

from __future__ import annotations

import numpy as np
import pytest

from tests.support.thermal_sim import NOISE_UM, lagged_spindle
from volumetric.identify.thermal import (
    DENSE_TAUS_S,
    ThermalTerm,
    first_order_lag,
    fit_thermal_drift,
)


def spindle(seed: int) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    r = lagged_spindle(seed)
    return r.time_s, {f"T_{k}_C": v for k, v in r.temperatures.items()}, r.value


def test_model_is_the_equal_weight_average_of_the_two_parts() -> None:
    t, temps, y = spindle(3)
    train = t < 0.7 * t[-1]
    alone = fit_thermal_drift(t, temps, y, train, time_drift=False)
    both = fit_thermal_drift(t, temps, y, train, time_drift=False, dense_taus_s=DENSE_TAUS_S)
    assert both.selected == alone.terms and alone.terms
    assert both.dense_taus_s == DENSE_TAUS_S
    # the all-sensor part, written out: per τ, OLS on 1, every level and its lag τ
    T = np.column_stack(list(temps.values()))
    dense = np.mean([
        (a := np.column_stack([np.ones(t.size), T, first_order_lag(t, T, tau)]))
        @ np.linalg.lstsq(a[train], y[train], rcond=None)[0] for tau in DENSE_TAUS_S], axis=0)
    expected = 0.5 * alone.predict(t, temps) + 0.5 * dense
    np.testing.assert_allclose(both.predict(t, temps), expected, rtol=0, atol=1e-8)
    # one linear model over the union: the selected terms, every level, every lag per τ
    names = list(temps)
    assert set(both.terms) == set(alone.terms) | {ThermalTerm("level", k) for k in names} | {
        ThermalTerm("lag", k, tau) for k in names for tau in DENSE_TAUS_S}
    assert len(both.terms) == len(both.coef) == len(both.coef_u)
    assert np.all(np.isfinite(both.coef_u)) and np.all(both.coef_u > 0)
    assert both.cv_rms_um > both.train_rms_um > 0


def test_nothing_joins_a_selection_that_took_nothing() -> None:
    # the selection decides whether there is a drift at all; on noise it takes no term, and
    # the all-sensor part must not bring in what it refused
    rng = np.random.default_rng(5)
    t, temps, _ = spindle(4)
    y = rng.normal(0.0, 1.0, t.size)
    model = fit_thermal_drift(t, temps, y, time_drift=False, dense_taus_s=DENSE_TAUS_S)
    assert model.terms == () and model.dense_taus_s == ()


def test_too_few_rows_per_column_keep_the_selection_alone() -> None:
    t, temps, y = spindle(5)
    rows = np.arange(0, t.size, 40)  # 60 readings: fewer than 10 per column of 2 x 4 + 1
    model = fit_thermal_drift(t[rows], {k: v[rows] for k, v in temps.items()}, y[rows],
                              time_drift=False, dense_taus_s=DENSE_TAUS_S)
    assert model.terms and model.dense_taus_s == () and model.terms == model.selected


@pytest.mark.parametrize("seed", range(8))
def test_the_average_predicts_the_simulated_spindle_ahead(seed: int) -> None:
    # fitted on the first 70 % of 40 h, judged on the rest. On this sparse truth the
    # selection alone is usually right (0.29-0.40 µm, noise 0.3) and the average pays for
    # the dense part's noise (0.33-0.44 µm, up to a quarter more; one seed where the
    # selection went wrong gains, 0.56 -> 0.44): it stays at the noise's level
    t, temps, y = spindle(seed)
    train = t < 0.7 * t[-1]
    model = fit_thermal_drift(t, temps, y, train, time_drift=False, dense_taus_s=DENSE_TAUS_S)
    assert model.dense_taus_s == DENSE_TAUS_S
    ahead = float(np.sqrt(np.mean((y - model.predict(t, temps))[~train] ** 2)))
    assert ahead <= 1.5 * NOISE_UM
