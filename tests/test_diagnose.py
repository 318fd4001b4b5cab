"""Diagnosis: hidden effects are found, named and sized; clean data says none; real data.

The campaign test hides one effect chosen at random (kind, axis, sensor, size within the
realistic ranges of :mod:`machine_sim.effects`, seed) in simulated measurement campaigns
on several chains, or none, and requires the diagnosis to name it, its axis and sensor,
and to size it within 30 %.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from machine_sim.campaign import run_campaign, standard_campaign
from machine_sim.effects import Backlash, Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.testprograms import positioning_test
from machine_sim.truth import random_geometry
from tests.support.diagnose import CHAINS, KINDS, N_CASES, machine_for, make_case, run_case
from volumetric.diagnose.diagnosis import DiagnosisError, diagnose
from volumetric.measure.measurement import read_measurements, write_measurements

EDNC = str(Path(sys.executable).parent / "ednc")


def test_hidden_effects_are_found_named_and_sized() -> None:
    results = []
    for seed in range(N_CASES):
        case = make_case(seed)
        ok, said = run_case(case)
        results.append((ok, case, said))
    misses = [f"seed {c.seed} {c.chain!r}: hid {c.kind} {c.axis} {c.sensor} {c.size}; "
              f"said {said}" for ok, c, said in results if not ok]
    hits = sum(ok for ok, _, _ in results)
    print(f"\nhidden-effect hit rate: {hits}/{len(results)}")
    kinds = {c.kind for _, c, _ in results}
    assert kinds == set(KINDS) and len({c.chain for _, c, _ in results}) == len(CHAINS)
    assert not misses, "\n".join(misses)


def test_real_spindle_thermal_test_names_the_thermal_cause_and_beats_2_um(
        real_data: Path) -> None:
    m = machine_for("w X Y b Z t")
    readings = read_measurements(real_data / "fl_thermal_ch3_measurements.csv")
    d = diagnose(m, readings, holdout_after=144000.0)
    assert (d.effect, d.axis) == ("thermal_drift", "z")
    assert d.sensor is not None and d.sensor.startswith("T_t")
    assert d.rms_before_um > 15.0  # the rigid model predicts no drift at all
    static = [c for c in d.candidates if c["effect"] == "thermal_drift" and "model" not in c]
    assert min(c["rms_after_um"] for c in static) > 4.0  # one static sensor is not enough
    assert d.rms_after_um <= 2.0
    terms = d.estimate["dynamic"]["terms"]  # the lagged sensors that carry it
    assert terms
    for t in terms:  # each as fields: what it is computed from, its lag, its coefficient
        assert t["kind"] in ("level", "lag", "time")
        assert (t["sensor"] is None) == (t["kind"] == "time")
        assert (t["tau_s"] > 0) == (t["kind"] == "lag")
        assert t["um_per_K_std"] > 0


def test_what_the_data_cannot_support_is_named_not_guessed() -> None:
    m = machine_for("w X Y b Z t")
    rng = np.random.default_rng(3)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.2, 0.2)), seed=3)
    full = standard_campaign(sim, rng)
    no_temps = full.select(np.ones(len(full), bool))
    object.__setattr__(no_temps, "temperatures", {})
    object.__setattr__(no_temps, "temperature_columns", {})
    d = diagnose(m, no_temps)
    assert "thermal" in d.not_assessed and d.effect == "none"
    one_way = full.select(full.direction[:, 0] >= 0)
    d = diagnose(m, one_way)
    assert "backlash x" in d.not_assessed
    assert not any(c["effect"] == "backlash" and c["axis"] == "x" for c in d.candidates)
    with pytest.raises(DiagnosisError, match="too few readings"):
        diagnose(m, full.select(np.arange(20)))
    # ISO 230-2 targets alone (11 over 800 mm) cannot resolve a ballscrew's period
    sparse = run_campaign(sim, [positioning_test(m, a, targets=11, runs=3) for a in "XYZ"])
    d = diagnose(m, sparse.measurements)
    assert "periodic x" in d.not_assessed and "fine positioning" in d.not_assessed["periodic x"]


def test_diagnose_command_prints_the_documented_json_and_writes_a_report(tmp_path: Path) -> None:
    m = machine_for("w X Y b Z t")
    rng = np.random.default_rng(4)
    sim = SimulatedMachine(m, random_geometry(m, rng),
                           Effects(backlash=(Backlash("y", 8.0),), noise=Noise(0.2, 0.2)), seed=4)
    write_measurements(tmp_path / "d.csv", standard_campaign(sim, rng))
    (tmp_path / "m.json").write_text(json.dumps({"name": "m", "chain": "w X Y b Z t",
        "tool_length_mm": 100.0, "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}}))
    out = subprocess.run([EDNC, "diagnose", "--machine", str(tmp_path / "m.json"), "--data",
                          str(tmp_path / "d.csv"), "--json", "--report", str(tmp_path / "r"),
                          "--out", str(tmp_path / "model.json")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout)
    assert {"effect", "axis", "sensor", "estimate", "rms_before_um", "rms_after_um",
            "candidates"} <= set(got)
    assert (got["effect"], got["axis"], got["sensor"]) == ("backlash", "y", None)
    assert abs(got["estimate"]["reversal_um"] - 8.0) < 0.8
    assert got["rms_after_um"] < got["rms_before_um"]
    assert all({"effect", "axis", "rms_after_um"} <= set(c) for c in got["candidates"])
    assert (tmp_path / "r" / "index.html").exists()
    assert (tmp_path / "r" / "candidates.png").stat().st_size > 1000
    assert (tmp_path / "r" / "direction_y.png").exists()
    model = json.loads((tmp_path / "model.json").read_text())
    assert {"effect": "backlash", "axis": "y"}.items() <= model["terms"][0].items()
