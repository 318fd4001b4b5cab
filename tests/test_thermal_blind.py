"""Dynamic thermal models judged blind: on the split ``ednc diagnose`` chooses for a time
series (forward-chaining blocks), with sensors and time constants selected again in every
fold from its past alone.

The real 46 h spindle test must be predicted far better than by the plain least-squares
models of the same file, and no chosen lag may be slower than half the span it was fitted
on (such a lag cannot be told from a trend and extrapolates wildly: +52 µm/K on an ambient
sensor in one fold before the limit).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from protocol.mapformat import MAX_THERMAL
from server import mapcodec
from tests.support.data import FL_MACHINE
from volumetric.diagnose.diagnosis import (
    FIRST_JUDGED,
    MAP_THERMAL_RECORDS,
    diagnose,
    forward_blocks,
    time_ordered,
)
from volumetric.identify.thermal import first_order_lag, fit_thermal_drift
from volumetric.measure.measurement import read_measurements
from volumetric.model.live import live_lags, live_model
from volumetric.model.machine import parse_machine
from volumetric.model.model import DynamicThermalTerm

FL = FL_MACHINE


def _rms(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(r * r)))


def test_real_thermal_test_judged_blind_beats_every_plain_model(real_data: Path) -> None:
    m = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    assert time_ordered(m)  # the split diagnose uses for it
    order = np.argsort(m.time_s, kind="stable")
    t, y = m.time_s[order], m.value[order]
    temps = {col: m.temperatures[s][order] for s, col in m.temperature_columns.items()}
    blocks = forward_blocks(m)[order]
    judged = blocks >= FIRST_JUDGED
    T = np.column_stack(list(temps.values()))
    dyn = np.full(t.shape, np.nan)
    static = np.full(t.shape, np.nan)
    for k in range(FIRST_JUDGED, int(blocks.max()) + 1):
        train, rows = blocks < k, blocks == k
        model = fit_thermal_drift(t, temps, y, train, time_drift=False)
        span = float(np.ptp(t[train]))
        assert 1 <= len(model.terms) <= 3
        assert all(term.tau_s <= 0.5 * span * (1 + 1e-9) for term in model.terms)
        assert np.all(np.isfinite(model.coef_u)) and np.all(model.coef_u > 0)
        dyn[rows] = (y - model.predict(t, temps))[rows]
        a = np.column_stack([np.ones(t.size), T])
        c = np.linalg.lstsq(a[train], y[train], rcond=None)[0]
        static[rows] = (y - a @ c)[rows]
    blind, plain = _rms(dyn[judged]), _rms(static[judged])
    print(f"\nreal thermal test, blind forward blocks: dynamic {blind:.2f} µm, "
          f"16 static sensors {plain:.2f} µm")
    # measured 3.95 µm (static 8.38, no model 26.8); the target of 2.0 is not met
    assert blind < 4.5
    assert blind < 0.55 * plain


def test_the_default_diagnosis_of_the_real_test_keeps_a_model_its_map_can_carry(
        real_data: Path) -> None:
    # ednc diagnose's own blind figure, on its split, every fold selecting and fitting the
    # lagged model from its past alone; the selection is averaged with the all-sensor
    # part (96 lag and level columns of sixteen sensors), which the center applies live
    # as one lag of a weighted sum per time constant: 16 + 5 records and the selection's
    machine = parse_machine(FL)
    d = diagnose(machine, read_measurements(real_data / "fl_thermal_ch3_measurements.csv"))
    assert d.details["split"] == "forward" and d.effect == "thermal_drift"
    dynamic = d.estimate["dynamic"]
    assert len(dynamic["all_sensor_taus_s"]) == 5 and 1 <= len(dynamic["selected"]) <= 3
    blocks = [b["rms_after_um"] for b in d.details["blocks"]["per_block"]]
    print(f"\nednc diagnose, real thermal test: {d.rms_after_um:.2f} µm blind, blocks {blocks}")
    # measured 3.91 µm (blocks 3.02 / 5.72 / 1.99; no model 26.8); the target of
    # 2.0 is not met. The selection alone gave 3.95 (4.60 / 4.52 / 2.29): the average
    # trades a worse middle block for better first and last ones, and predicts the test
    # cut at 70 % (60 %) at 2.98 (3.42) µm instead of 4.54 (5.83)
    assert d.rms_after_um < 4.2 and d.rms_before_um > 20.0
    assert max(blocks) < 6.0
    # the saved model as the center applies it live: its map carries every record (the
    # diagnosis's budget is the map format's), and the records give the saved term
    assert MAP_THERMAL_RECORDS == MAX_THERMAL
    live = live_model(d.model)
    (term,) = [t for t in d.model.terms if isinstance(t, DynamicThermalTerm)]
    assert len([c for c in term.columns if c.kind != "time"]) > MAX_THERMAL
    # what a sensor 1 K off costs at steady state, largest first: collinear sensors carry
    # coefficients of opposite signs (measured: up to 29 µm/K on the 70 % cut)
    steady = dynamic["steady_um_per_K"]
    assert list(steady) == sorted(steady, key=lambda s: -abs(steady[s]))
    for sensor in term.sensors:
        one = {s: 25.0 + (s == sensor) for s in term.sensors}
        moved = term.steady_um(one) - term.steady_um(dict.fromkeys(term.sensors, 25.0))
        assert steady[sensor] == pytest.approx(moved, abs=1e-3)
    assert len(live.sensors) <= 16 + 5 + 3
    # at steady state, every lag at its sensor's temperature: the records give the term
    steady = {s: 25.0 + 0.1 * k for k, s in enumerate(term.sensors)}
    lagged = {lag.column: lag.state(steady) for lag in live_lags(d.model)}
    records = live.geometry_at({**steady, **lagged}).components["EZZ"](np.zeros(1))[0]
    assert records == pytest.approx(term.steady_um(steady), abs=1e-9)
    # the temperatures and lag states the test ended at (sixteen sensors that move
    # together weigh each other out: set apart from how they move, their records would
    # sum to hundreds of µm, past what a map sends)
    last = {c.sensor: c.input_C for c in term.columns if c.input_C is not None}
    now = last | {lag.column: lag.state({c.sensor: c.state_C for c in term.columns
                                         if c.kind == "lag" and c.tau_s == lag.tau_s})
                  for lag in live_lags(d.model)}
    assert set(now) == set(live.sensors)
    for controller, kind in (("fanuc", "factored"), ("siemens", "tables")):
        content = mapcodec.build_for(machine, live, now,
                                     kind=kind, tolerance_um=0.5, controller=controller)
        assert len(content.thermal) == len(live.sensors) <= MAX_THERMAL
        assert mapcodec.encode(content)


def test_a_lag_slower_than_half_the_training_span_is_not_offered() -> None:
    # the truth is a lag of 0.8 spans: the fit may only approximate it with faster terms
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 40 * 3600.0, 60.0)
    x = 25.0 + np.cumsum(rng.normal(0.0, 0.05, t.size))
    span = float(np.ptp(t))
    y = 8.0 * first_order_lag(t, x, 0.8 * span) + rng.normal(0.0, 0.05, t.size)
    model = fit_thermal_drift(t, {"T_a_C": x}, y, time_drift=False)
    assert model.terms
    assert max(term.tau_s for term in model.terms) <= 0.5 * span * (1 + 1e-9)
    wide = fit_thermal_drift(t, {"T_a_C": x}, y, time_drift=False, max_tau_fraction=1.0)
    assert max(term.tau_s for term in wide.terms) > 0.5 * span  # the limit is what stops it
    for bad in (0.0, -0.5, 1.5, float("nan")):
        with pytest.raises(ValueError, match="max_tau_fraction"):
            fit_thermal_drift(t, {"T_a_C": x}, y, max_tau_fraction=bad)


def test_at_most_three_terms_by_default_however_many_sensors_move() -> None:
    # six independent sensors (heat cycles of different periods), each carrying its own
    # share of the drift: every one of them would pass the stopping rule
    rng = np.random.default_rng(11)
    t = np.arange(0.0, 20 * 3600.0, 30.0)
    periods = 3600.0 * np.array([2.0, 3.1, 4.3, 5.7, 7.9, 11.3])
    temps = {f"T_{j}_C": 25.0 + np.sin(2 * np.pi * t / p + j) for j, p in enumerate(periods)}
    y = sum((j + 1) * v for j, v in enumerate(temps.values())) + rng.normal(0.0, 0.05, t.size)
    model = fit_thermal_drift(t, temps, np.asarray(y), time_drift=False)
    assert len(model.terms) == 3
    more = fit_thermal_drift(t, temps, np.asarray(y), time_drift=False, max_terms=8)
    assert len(more.terms) > 3
