"""``ednc predict``: a saved model applied to readings it never saw, every term included.

The real 46 h spindle thermal test is cut at 70 % of its time: ``ednc diagnose --out`` on
the first part writes the model behind the figure it claims (lagged thermal states with
their time constants and end states, offsets), and ``ednc predict`` on the rest must land
within 1.5x of that claim and far below the rigid model; the center's live form of the
saved model (lag states stepped reading by reading) gives the same drift. A model from
``ednc fit`` on a simulated machine predicts a second campaign of the same machine to the
noise, offsets included; a dynamic thermal term survives JSON and folds in at its steady
state. A simulated spindle whose growth is a known lagged function of its temperatures,
cut the same way, is predicted to the noise by the saved model.
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.truth import random_geometry
from protocol.mapformat import MAX_THERMAL
from server import mapcodec
from tests.support.data import FL_MACHINE
from tests.support.thermal_sim import NOISE_UM, lagged_spindle
from volumetric.diagnose.diagnosis import diagnose
from volumetric.diagnose.predict import PredictionError, predict
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements, read_measurements, write_measurements
from volumetric.model.lag import first_order_lag, lag_step
from volumetric.model.live import live_lags, live_model
from volumetric.model.machine import parse_machine
from volumetric.model.model import DynamicThermalTerm, LagColumn, MachineModel, ThermalTerm

EDNC = str(Path(sys.executable).parent / "ednc")
FL = FL_MACHINE
VMC = {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0]}}


def _run(*args: str) -> str:
    out = subprocess.run([EDNC, *args], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout


def test_real_thermal_test_cut_at_70_percent_predicts_what_the_diagnosis_claimed(
        tmp_path: Path, real_data: Path) -> None:
    readings = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    cut = float(readings.time_s.min() + 0.7 * np.ptp(readings.time_s))
    write_measurements(tmp_path / "first.csv", readings.select(readings.time_s < cut))
    write_measurements(tmp_path / "rest.csv", readings.select(readings.time_s >= cut))
    (tmp_path / "m.json").write_text(json.dumps(FL))
    d = json.loads(_run("diagnose", "--machine", str(tmp_path / "m.json"), "--data",
                        str(tmp_path / "first.csv"), "--json", "--out",
                        str(tmp_path / "model.json")))
    assert d["split"] == "forward"  # time-ordered: judged on blocks later than the fit
    blocks = d["blocks"]
    assert len(blocks["per_block"]) == 3 and blocks["worst_rms_um"] >= blocks["mean_rms_um"]
    assert d["effect"] == "thermal_drift"
    saved = json.loads((tmp_path / "model.json").read_text())
    assert [t["effect"] for t in saved["terms"]] == ["thermal_dynamic"]
    assert "OFFSET_Z" in saved["info"]["offsets_um"]
    p = json.loads(_run("predict", "--machine", str(tmp_path / "m.json"), "--model",
                        str(tmp_path / "model.json"), "--data", str(tmp_path / "rest.csv"),
                        "--json"))
    assert p["n_readings"] == int((readings.time_s >= cut).sum())
    assert p["rms_um"] <= 1.5 * d["rms_after_um"], (p, d["rms_after_um"])
    assert p["rms_um"] < 0.5 * p["rms_rigid_um"]
    # measured 2.979 µm (claimed 3.76, the rigid part alone 17.51): the selection
    # averaged with every sensor's lags, applied live as one lag per time constant, its
    # prediction as its own fit gave it (with a scale refitted beside the rigid part:
    # 3.0007; the selection alone: 4.54). The target is 3.0.
    assert p["rms_um"] <= 3.0
    assert [t["test"] for t in p["tests"]] == ["spindle-thermal"]
    # the live path (item 6) applies the same term: lag states stepped one reading at a
    # time over everything the center received, records on them, give the drift predict
    # continues from the saved state
    model = MachineModel.from_json(saved)
    (term,) = model.terms
    assert isinstance(term, DynamicThermalTerm)
    temps = {col: readings.temperatures[s] for s, col in readings.temperature_columns.items()}
    rest = readings.time_s >= cut
    ahead = term.series(readings.time_s[rest], {c: v[rest] for c, v in temps.items()})
    live = live_drift(model, readings.time_s, temps)[rest]
    assert np.ptp(ahead) > 20.0
    np.testing.assert_allclose(live, ahead, rtol=0, atol=1e-6)


def live_drift(model: MachineModel, t_s: np.ndarray, temps: dict[str, np.ndarray]
               ) -> np.ndarray:
    """The drift (µm) of ``model``'s live form at every reading, its lag states stepped
    one reading at a time from rest at the first, as the center does: one state per
    sensor and time constant, a lag of several sensors sent as their weighted sum."""
    lags = live_lags(model)
    live = live_model(model)
    out = np.empty(t_s.size)
    state: dict[tuple[str, float], tuple[float, float, float]] = {}
    for k in range(t_s.size):
        values = {c: float(v[k]) for c, v in temps.items()}
        stepped: set[tuple[str, float]] = set()
        for g in lags:
            for s in g.sources:
                if (s, g.tau_s) in stepped:
                    continue
                stepped.add((s, g.tau_s))
                x = values[s]
                t0, x0, y0 = state.get((s, g.tau_s), (float(t_s[k]), x, x))
                state[s, g.tau_s] = (float(t_s[k]), x,
                                     lag_step(y0, x0, x, t_s[k] - t0, g.tau_s))
            values[g.column] = g.state({s: state[s, g.tau_s][2] for s in g.sources})
        out[k] = sum(r.coefficient * (values[r.sensor] - r.t_ref_C) for r in live.terms
                     if isinstance(r, ThermalTerm)) + sum(
            d.intercept_um for d in live.terms if isinstance(d, DynamicThermalTerm))
    return out


def channel(real_data: Path, ch: int) -> Measurements:
    """The real test's readings with channel ``ch``'s drift along z (same times and
    temperatures as ch3's, ``tests/data/README.md``)."""
    readings = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    data = np.genfromtxt(real_data / "fl_thermal_channels.csv", delimiter=",", names=True)
    np.testing.assert_array_equal(data["time_s"], readings.time_s)
    np.testing.assert_allclose(data["ch3_um"], readings.value, rtol=0, atol=1e-9)
    return replace(readings, value=np.asarray(data[f"ch{ch}_um"], dtype=float))


def plain_forward_rms(readings: Measurements, train: np.ndarray) -> float:
    """RMS (µm) after the cut of the plain least squares on every sensor's level and an
    intercept, fitted on the readings before it."""
    temps = np.column_stack([readings.temperatures[s] for s in readings.temperature_columns])
    a = np.column_stack([temps, np.ones(len(readings))])
    x = np.linalg.lstsq(a[train], readings.value[train], rcond=None)[0]
    r = (readings.value - a @ x)[~train]
    return float(np.sqrt(np.mean(r * r)))


def test_real_test_ch1_cut_at_70_percent_saved_model_is_no_worse_than_plain_least_squares(
        tmp_path: Path, real_data: Path) -> None:
    """Issue 27, item 4: the saved model predicts the rest at least as well as the plain
    least squares on all 16 sensors fitted on the same 70 % (it gave 7.01 µm against
    4.54: the diagnosis named nothing and saved the rigid model), and it is one the live
    path carries: one thermal record per sensor level and one per lag state."""
    readings = channel(real_data, 1)
    cut = float(readings.time_s.min() + 0.7 * np.ptp(readings.time_s))
    train = readings.time_s < cut
    write_measurements(tmp_path / "first.csv", readings.select(train))
    write_measurements(tmp_path / "rest.csv", readings.select(~train))
    (tmp_path / "m.json").write_text(json.dumps(FL))
    d = json.loads(_run("diagnose", "--machine", str(tmp_path / "m.json"), "--data",
                        str(tmp_path / "first.csv"), "--json", "--out",
                        str(tmp_path / "model.json")))
    assert d["split"] == "forward"
    p = json.loads(_run("predict", "--machine", str(tmp_path / "m.json"), "--model",
                        str(tmp_path / "model.json"), "--data", str(tmp_path / "rest.csv"),
                        "--json"))
    plain = plain_forward_rms(readings, train)
    assert plain == pytest.approx(4.54, abs=0.01)  # the figure
    # measured 2.48 µm: every sensor's level and lag at 15 min, by ridge (λ 0.01)
    assert p["rms_um"] <= plain, (p["rms_um"], plain)
    model = MachineModel.from_json(json.loads((tmp_path / "model.json").read_text()))
    (term,) = model.terms
    assert isinstance(term, DynamicThermalTerm)
    live = live_model(model)
    machine = parse_machine(FL)
    tables = mapcodec.build_for(machine, live, {s: 25.0 for s in live.sensors},
                                kind="tables", tolerance_um=0.5, controller="siemens")
    assert len(tables.thermal) == len(live.sensors) <= MAX_THERMAL
    temps = {col: readings.temperatures[s] for s, col in readings.temperature_columns.items()}
    ahead = term.series(readings.time_s[~train], {c: v[~train] for c, v in temps.items()})
    np.testing.assert_allclose(live_drift(model, readings.time_s, temps)[~train], ahead,
                               rtol=0, atol=1e-6)


def test_real_test_ch2_cut_at_70_percent_saved_model_is_no_worse_than_plain_least_squares(
        tmp_path: Path, real_data: Path) -> None:
    """Issue 27, item 4, on ch2: no model of every sensor passed the gates against the
    rigid base on the diagnosis's split of the first 70 % (the best at z 0.63), so the
    static T_t11 drift, which passed, was saved and predicted the rest at 6.55 µm
    against the plain least squares' 3.41. The static drift names the effect; what is
    saved is the model of it the split prefers (lagged.named_thermal)."""
    readings = channel(real_data, 2)
    cut = float(readings.time_s.min() + 0.7 * np.ptp(readings.time_s))
    train = readings.time_s < cut
    write_measurements(tmp_path / "first.csv", readings.select(train))
    write_measurements(tmp_path / "rest.csv", readings.select(~train))
    (tmp_path / "m.json").write_text(json.dumps(FL))
    d = json.loads(_run("diagnose", "--machine", str(tmp_path / "m.json"), "--data",
                        str(tmp_path / "first.csv"), "--json", "--out",
                        str(tmp_path / "model.json")))
    assert d["split"] == "forward"
    p = json.loads(_run("predict", "--machine", str(tmp_path / "m.json"), "--model",
                        str(tmp_path / "model.json"), "--data", str(tmp_path / "rest.csv"),
                        "--json"))
    plain = plain_forward_rms(readings, train)
    assert plain == pytest.approx(3.41, abs=0.01)
    assert p["rms_um"] <= plain, (p["rms_um"], plain)
    (term,) = MachineModel.from_json(json.loads((tmp_path / "model.json").read_text())).terms
    assert isinstance(term, DynamicThermalTerm)  # a model of every sensor, not one sensor


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_lagged_spindle_cut_at_70_percent_is_predicted_to_the_noise(seed: int) -> None:
    machine = parse_machine(FL)
    readings = lagged_spindle(seed)
    cut = 0.7 * float(readings.time_s[-1])
    first = readings.select(readings.time_s < cut)
    rest = readings.select(readings.time_s >= cut)
    d = diagnose(machine, first)
    assert d.details["split"] == "forward"
    assert "thermal_drift" in [e["effect"] for e in d.details["effects"]]
    saved = MachineModel.from_json(json.loads(json.dumps(d.model.to_json())))
    dynamic = [t for t in saved.terms if isinstance(t, DynamicThermalTerm)]
    assert len(dynamic) == 1 and "T_a_C" in {c.sensor for c in dynamic[0].columns}
    ahead = predict(machine, saved, rest).to_json()
    # the terms behind the claim are saved, lag states included: forward they do at least
    # as well as claimed (the claim comes from folds fitted on less) and reach the noise
    assert ahead["rms_um"] <= 1.5 * d.rms_after_um, (ahead, d.rms_after_um)
    assert ahead["rms_um"] < 2.0 * NOISE_UM
    assert ahead["rms_rigid_um"] > 5.0 * ahead["rms_um"]
    # the selection averaged with the all-sensor part: every sensor's level and lags, four
    # sensors few enough for a map to carry the live model's records
    sensors = {c.sensor for c in dynamic[0].columns}
    assert sensors == set(first.temperature_columns.values())
    live = live_model(saved)
    tables = mapcodec.build_for(machine, live, {s: 25.0 for s in live.sensors},
                                kind="tables", tolerance_um=0.5, controller="siemens")
    assert len(tables.thermal) == len(live.sensors) <= MAX_THERMAL
    assert mapcodec.encode(tables)
    # on the readings it was fitted on, the saved model (offset moved, lags from rest at
    # the first reading) gives the least-squares fit of the constant beside the averaged
    # drift as its own fit gave it: the residual is orthogonal to the constant, to
    # rounding; and a scale refitted there would be at least 1 (an average of least-
    # squares projections is never larger than y's projection on it), which is why the
    # diagnosis does not refit it: the residual does not point against the drift
    resid = predict(machine, saved, first).residual
    drift = np.zeros(len(first))
    for c in dynamic[0].columns:
        x = first.temperatures[c.sensor.removeprefix("T_").removesuffix("_C")]
        col = x if c.kind == "level" else first_order_lag(first.time_s, x, c.tau_s)
        drift += c.coefficient * col
    ones = np.ones(len(first))
    assert abs(ones @ resid) < 1e-8 * np.linalg.norm(ones) * np.linalg.norm(resid)
    assert (drift - drift.mean()) @ resid >= 0.0
    assert float(np.sqrt(np.mean(resid**2))) < 2.0 * NOISE_UM


def test_a_fitted_model_predicts_another_campaign_of_the_same_machine_to_the_noise() -> None:
    m = parse_machine(VMC)
    rng = np.random.default_rng(8)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.3, 0.3)), seed=1)
    model = fit(m, standard_campaign(sim, rng)).model
    other = standard_campaign(SimulatedMachine(m, sim.geometry, sim.effects, seed=2), rng)
    p = predict(m, model, other).to_json()
    assert p["rms_um"] < 0.45  # 0.3 µm noise, plus what the fit could not pin down
    empty = MachineModel(m.name, model.geometry.__class__())
    assert predict(m, empty, other).to_json()["rms_um"] > 5 * p["rms_um"]


def test_dynamic_thermal_term_round_trips_and_folds_in_at_steady_state() -> None:
    term = DynamicThermalTerm("z", -1.5, (
        LagColumn("lag", "T_a_C", 1800.0, -2.0, 0.1, 24.0, 25.0),
        LagColumn("level", "T_b_C", 0.0, 0.5, 0.05, None, 22.0),
        LagColumn("time", "", 0.0, 0.2, 0.01)), 0.0, 3600.0)
    model = MachineModel("m", random_geometry(parse_machine(VMC), np.random.default_rng(0)),
                         (term,))
    back = MachineModel.from_json(json.loads(json.dumps(model.to_json())))
    assert back.terms == (term,)
    assert back.sensors == ("T_a_C", "T_b_C")
    # steady state: lag = temperature; time column at the saved state's time (1 h)
    assert term.steady_um({"T_a_C": 26.0, "T_b_C": 20.0}) == pytest.approx(
        -1.5 - 2.0 * 26.0 + 0.5 * 20.0 + 0.2 * 1.0)
    geo = back.geometry_at({"T_a_C": 26.0, "T_b_C": 20.0})
    base = model.geometry.components["EZZ"](np.array([-100.0]))
    assert geo.components["EZZ"](np.array([-100.0])) - base == pytest.approx(
        term.steady_um({"T_a_C": 26.0, "T_b_C": 20.0}))
    # a series that continues the saved one starts from the saved lag state, not at rest
    t = np.array([3600.0, 3660.0])
    temps = {"T_a_C": np.array([25.0, 25.0]), "T_b_C": np.array([22.0, 22.0])}
    cont = term.series(t, temps)
    fresh = DynamicThermalTerm("z", -1.5, term.columns, 0.0, None).series(t, temps)
    assert cont[0] == pytest.approx(-1.5 - 2.0 * 24.0 + 0.5 * 22.0 + 0.2 * 1.0)
    assert fresh[0] == pytest.approx(-1.5 - 2.0 * 25.0 + 0.5 * 22.0 + 0.2 * 1.0)


def test_missing_temperatures_are_named() -> None:
    m = parse_machine(VMC)
    term = DynamicThermalTerm("z", 0.0, (LagColumn("lag", "T_gone_C", 600.0, 1.0),))
    rng = np.random.default_rng(3)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.3, 0.3)), seed=1)
    readings = standard_campaign(sim, rng, runs=1, targets=5)
    with pytest.raises(PredictionError, match="T_gone_C"):
        predict(m, MachineModel(m.name, sim.geometry, (term,)), readings)
