"""The thermal model a forward split saves as a combination of its models
(:mod:`volumetric.diagnose.combination`): inverse-MSE weights over the future splits, a
split's figure weighted from the other splits alone, the terms of every model summed into
one linear model.

The real 46 h test cut at 40 h, ch1: the forward choice took the ridge model with 1 h lags
(it won every future split by more than the margin), which predicted the rest at 4.11 µm
where main a718b29's saved model gave 4.00. The combination changes only what is saved:
the ch5 cut at 60 % is still named a thermal drift, judged by the chosen model's figures.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from tests.support.data import FL_MACHINE
from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.choice import Future
from volumetric.diagnose.combination import (
    Component,
    combined_candidate,
    inverse_mse_weights,
    records_of,
)
from volumetric.diagnose.diagnosis import diagnose
from volumetric.diagnose.gates import Scored
from volumetric.diagnose.predict import predict
from volumetric.identify.thermal import ThermalTerm as ThermalColumn
from volumetric.measure.measurement import Measurements, read_measurements
from volumetric.model.machine import parse_machine
from volumetric.model.model import DynamicThermalTerm, MachineModel

FL = FL_MACHINE


def test_weights_are_inverse_mean_squared_errors() -> None:
    w = inverse_mse_weights(np.array([[1.0, 1.0], [2.0, 2.0], [1.0, 3.0]]))
    # 1 / mean of squares: 1, 1/4, 1/5
    np.testing.assert_allclose(w, np.array([1.0, 0.25, 0.2]) / 1.45)


def component(name: str, rms: tuple[float, ...], scale: float,
              terms: list[tuple[ThermalColumn, float, float]]) -> Component:
    c = Candidate("thermal_drift", "z", name, np.zeros((4, 1)))
    fut = Future(Scored(c, np.zeros(4), 0.0, 0.0, 0.0), np.array(rms))
    return Component(name, fut, [scale * np.arange(4.0) + b for b in range(len(rms))],
                     scale * np.arange(4.0), terms)


def test_the_combination_is_one_linear_model_and_each_split_weighted_without_itself() -> None:
    t1 = ThermalColumn("level", "T_a_C")
    lag = ThermalColumn("lag", "T_a_C", 900.0)
    a = component("a", (1.0, 1.0, 2.0), 1.0, [(t1, 2.0, 0.1)])
    b = component("b", (2.0, 2.0, 1.0), 3.0, [(t1, 4.0, 0.2), (lag, -1.0, 0.3)])
    c = combined_candidate([a, b], "z", "T_a_C", 0.0)
    w = inverse_mse_weights(np.array([a.future.rms_um, b.future.rms_um]))
    assert c.fixed
    np.testing.assert_allclose(c.columns[:, 0], w[0] * a.full + w[1] * b.full)
    terms = {d["name"]: d["um_per_K"] for d in c.extra["description"]["terms"]}
    assert terms == pytest.approx({"T_a_C": w[0] * 2.0 + w[1] * 4.0,
                                   "T_a_C lag 900 s": -w[1]})
    assert records_of(c.extra["terms"]) == 2
    # the last split is judged with weights from the first two alone: there a is the
    # better model (1 against 2 µm), though it is the worse one in the last split
    wl = inverse_mse_weights(np.array([[1.0, 1.0], [2.0, 2.0]]))
    assert wl[0] == pytest.approx(0.8)
    np.testing.assert_allclose(c.per_fold[2][:, 0],
                               wl[0] * a.per_fold[2] + wl[1] * b.per_fold[2])


def channel(real_data: Path, ch: int) -> Measurements:
    """The real test's readings with channel ``ch``'s drift along z."""
    readings = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    data = np.genfromtxt(real_data / "fl_thermal_channels.csv", delimiter=",", names=True)
    np.testing.assert_array_equal(data["time_s"], readings.time_s)
    return replace(readings, value=np.asarray(data[f"ch{ch}_um"], dtype=float))


def test_real_test_ch1_cut_at_40_h_saves_the_combination(real_data: Path) -> None:
    readings = channel(real_data, 1)
    train = readings.time_s < 144_000.0
    machine = parse_machine(FL)
    d = diagnose(machine, readings.select(train))
    combination = d.estimate["dynamic"]["combination"]
    assert sum(combination["weights"].values()) == pytest.approx(1.0, abs=1e-3)
    saved = MachineModel.from_json(json.loads(json.dumps(d.model.to_json())))
    (term,) = saved.terms
    assert isinstance(term, DynamicThermalTerm)
    ahead = predict(machine, saved, readings.select(~train)).to_json()["rms_um"]
    # the ridge model with 1 h lags alone: 4.11 µm; main a718b29's saved model 4.00
    assert ahead <= 4.00, ahead


def test_real_test_ch5_cut_at_60_pct_names_the_drift_and_saves_the_combination(
        real_data: Path) -> None:
    # ch5 cut at 60 %: the forward choice takes a model on every sensor and the
    # combination is saved in its place; its own held-out figure (7.96 µm) is higher than
    # the chosen model's (5.17), and when the diagnosis judged by it (933cec9) the
    # unexplained structure was named before the drift. Only the saved model changes.
    readings = channel(real_data, 5)
    t = readings.time_s
    train = t < float(t.min() + 0.6 * np.ptp(t))
    machine = parse_machine(FL)
    d = diagnose(machine, readings.select(train))
    assert d.effect == "thermal_drift"
    assert d.details["effects"][0]["effect"] == "thermal_drift"
    comb = d.estimate["dynamic"]["combination"]
    # the figures the diagnosis reports are the chosen model's; the saved one's beside
    assert d.details["effects"][0]["rms_after_um"] == comb["chosen_rms_after_um"]
    assert comb["saved_rms_after_um"] > comb["chosen_rms_after_um"]
    saved = MachineModel.from_json(json.loads(json.dumps(d.model.to_json())))
    (term,) = saved.terms
    assert isinstance(term, DynamicThermalTerm)
    # the saved term is the combination's: the chosen model's lags have one time constant
    # (1 h), the combination's every model's
    assert comb["chosen"] == "all sensors + lags 60 min, ridge"
    taus = {x["tau_s"] for x in d.estimate["dynamic"]["terms"] if x["kind"] == "lag"}
    assert len(taus) > 1 and sum(comb["weights"].values()) == pytest.approx(1.0, abs=1e-3)
    ahead = predict(machine, saved, readings.select(~train)).to_json()["rms_um"]
    # main 7b1197a's saved model (the chosen one) 3.50 µm
    assert ahead <= 3.50, ahead
