"""Identification: recovers the machine, chooses degrees, names what it cannot identify."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Effects, Noise
from machine_sim.instruments import SimulatedMachine
from machine_sim.truth import random_geometry
from volumetric.identify.fit import FitError, fit
from volumetric.measure.measurement import Measurements, write_measurements
from volumetric.model.components import GeometricErrors, Polynomial
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Machine, parse_machine

EDNC = str(Path(sys.executable).parent / "ednc")
VMC = {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}}


def readings(m: Machine, truth: GeometricErrors, rng: np.random.Generator, n: int,
             noise: float, *, angles: bool = True, tools: tuple[float, ...] = (0.0, 150.0)
             ) -> Measurements:
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in m.axes])
    tool = rng.choice(np.array(tools), n)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    ang = (rng.random(n) < 0.2) if angles else np.zeros(n, bool)
    ve = volumetric_error(m, truth, q, tool_mm=tool)
    assert ve.orientation_urad is not None
    val = np.where(ang, np.einsum("ni,ni->n", u, ve.orientation_urad),
                   np.einsum("ni,ni->n", u, ve.position_um)) + rng.normal(0, noise, n)
    return Measurements(test=np.array(["random"] * n), run=np.zeros(n, np.int64),
                        time_s=np.arange(n, dtype=float), q=np.column_stack([q, np.zeros((n, 3))]),
                        direction=np.zeros((n, 3), np.int8), tool_mm=tool, is_angle=ang, u=u,
                        value=val)


def field_error(m: Machine, a: GeometricErrors, b: GeometricErrors,
                rng: np.random.Generator) -> float:
    """Worst difference of two error fields up to a constant offset (the readings' zero)."""
    q = np.column_stack([rng.uniform(x.travel[0], x.travel[1], 3000) for x in m.axes])
    d = volumetric_error(m, a, q).position_um - volumetric_error(m, b, q).position_um
    return float(np.abs(d - d.mean(axis=0)).max())


def test_standard_campaign_on_a_simulated_machine_recovers_its_error_field() -> None:
    m = parse_machine(VMC)
    rng = np.random.default_rng(5)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.3, 0.3)), seed=3)
    meas = standard_campaign(sim, rng)
    r = fit(m, meas)
    assert abs(r.rms["displacement_um"] - 0.3) < 0.05  # the residual is the noise
    truth_max = float(np.abs(volumetric_error(
        m, sim.geometry, np.column_stack([np.linspace(*a.travel, 50) for a in m.axes])
    ).position_um).max())
    assert truth_max > 10.0
    assert field_error(m, r.model.geometry, sim.geometry, rng) < 1.0


def test_degrees_follow_the_data_not_the_maximum() -> None:
    m = parse_machine(VMC)
    truth = GeometricErrors({"EXX": Polynomial((0.0, 10.0, -6.0), 0.0, 800.0)},
                            {"EC0Y": 15.0})
    r = fit(m, readings(m, truth, np.random.default_rng(1), 4000, 0.2))
    assert r.degrees["EXX"] == 2  # a parabola, found as such
    assert all(d <= 1 for k, d in r.degrees.items() if k != "EXX")
    ec0y = next(p for p in r.model.info["parameters"] if p["name"] == "EC0Y")
    assert abs(ec0y["value"] - 15.0) < 4 * ec0y["std"] and ec0y["std"] < 0.5


def test_uncertainties_cover_the_truth() -> None:
    m = parse_machine(VMC)
    truth = GeometricErrors(locations={"EC0Y": 12.0, "EB0Z": -8.0, "EA0Z": 20.0})
    hits = 0
    for seed in range(20):
        r = fit(m, readings(m, truth, np.random.default_rng(seed), 800, 0.5), select=False)
        p = {x["name"]: x for x in r.model.info["parameters"]}
        hits += abs(p["EB0Z"]["value"] + 8.0) < 2 * p["EB0Z"]["std"]
    assert hits >= 15  # 95 % intervals: about 19 of 20


def test_position_readings_with_one_tool_cannot_separate_angular_constants() -> None:
    m = parse_machine(VMC)
    truth = GeometricErrors({"EBY": Polynomial((30.0,))})
    r = fit(m, readings(m, truth, np.random.default_rng(2), 3000, 0.2, angles=False,
                        tools=(100.0,)))
    names = {u["parameter"] for u in r.unidentifiable}
    partners = {p for u in r.unidentifiable for p in u["confounded_with"]}
    assert names  # something is reported, with its partners
    assert names | partners >= {"EBY[0]"} or "EBY[0]" in names | partners
    fitted = {p["name"] for p in r.model.info["parameters"]}
    assert names.isdisjoint(fitted)  # reported parameters carry no number
    assert field_error(m, r.model.geometry, truth, np.random.default_rng(3)) < 0.2


def test_components_the_readings_never_see_are_reported_as_not_measured() -> None:
    m = parse_machine(VMC)
    n = 200
    x = np.linspace(0, 800, n)
    q = np.column_stack([x, np.full(n, 300.0), np.full(n, -250.0), np.zeros((n, 3))])
    meas = Measurements(test=np.array(["X-positioning"] * n), run=np.zeros(n, np.int64),
                        time_s=np.arange(n, dtype=float), q=q,
                        direction=np.zeros((n, 3), np.int8), tool_mm=np.zeros(n),
                        is_angle=np.zeros(n, bool), u=np.tile([1.0, 0, 0], (n, 1)),
                        value=0.01 * x + np.random.default_rng(0).normal(0, 0.1, n))
    r = fit(m, meas)
    assert "EYX" in r.not_measured and "EZZ" in r.not_measured  # never projected on u
    assert "EXX" not in r.not_measured


def test_too_few_readings_is_a_clear_error() -> None:
    m = parse_machine(VMC)
    truth = GeometricErrors({"EXX": Polynomial((0.0, 10.0), 0.0, 800.0)})
    with pytest.raises(FitError, match="cannot identify"):
        fit(m, readings(m, truth, np.random.default_rng(4), 20, 0.1), select=False)


def test_fit_command_writes_a_model_with_iso_names(tmp_path: Path) -> None:
    m = parse_machine(VMC)
    rng = np.random.default_rng(8)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(noise=Noise(0.2, 0.2)), seed=1)
    data = tmp_path / "d.csv"
    write_measurements(data, standard_campaign(sim, rng))
    (tmp_path / "m.json").write_text(json.dumps(VMC))
    out = subprocess.run([EDNC, "fit", "--machine", str(tmp_path / "m.json"), "--data",
                          str(data), "--out", str(tmp_path / "model.json")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    model = json.loads((tmp_path / "model.json").read_text())
    assert {"EXX", "EYY", "EZZ"} <= set(model["components"])
    assert set(model["locations"]) <= {"EC0Y", "EB0Z", "EA0Z"}
    bad = tmp_path / "bad.csv"
    bad.write_text("test,run\nX,1\n")
    out = subprocess.run([EDNC, "fit", "--machine", str(tmp_path / "m.json"), "--data",
                          str(bad)], capture_output=True, text=True)
    assert out.returncode == 2 and "missing" in out.stderr and "Traceback" not in out.stderr
