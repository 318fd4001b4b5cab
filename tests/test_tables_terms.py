"""``ednc tables`` keeps a model's extension terms: terms.json beside the tables, read back
exactly; a term it cannot carry is refused by name; exports without it import as rigid."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import numpy as np
import pytest

from volumetric.compensate.maps import reversal_of
from volumetric.compensate.solver import corrections
from volumetric.errors import ComponentErrorSpecError
from volumetric.measure.tables import TERMS_FILE, export_model, import_model
from volumetric.model.components import GeometricErrors, Polynomial, Table
from volumetric.model.machine import parse_machine
from volumetric.model.model import (
    BacklashTerm,
    DynamicThermalTerm,
    LagColumn,
    MachineModel,
    PeriodicTerm,
    Term,
    ThermalTerm,
)

SPEC = {"name": "vmc", "chain": "w X Y b Z t",
        "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}
M = parse_machine(SPEC)
EDNC = str(Path(sys.executable).parent / "ednc")
TEMPS = {"T_spindle_C": 27.3, "T_bed_C": 22.9, "T_column_C": 24.1}

# digits a six-figure CSV cell would lose: the terms must come back bit for bit
TERMS: tuple[Term, ...] = (
    BacklashTerm("x", 7.734912345678901),
    PeriodicTerm("y", 1.2345678901234, 10.000000001, -math.pi / 7),
    ThermalTerm("thermal_expansion", "x", "T_bed_C", 11.53210987654, 20.123456789, 0.0),
    ThermalTerm("thermal_drift", "z", "T_spindle_C", -0.8123456789, 21.987654321),
    DynamicThermalTerm("z", 3.14159265358979, (
        LagColumn("level", "T_spindle_C", 0.0, 0.41234567, 0.0123),
        LagColumn("lag", "T_spindle_C", 1234.56789, -1.9876543210, 0.05, 24.1234567, 25.5),
        LagColumn("lag", "T_column_C", 600.0, 0.3, 0.0, None, None),
        LagColumn("time", "", 0.0, 0.123456789, 0.001)), 1.5e9 + 0.25, 1.5e9 + 7200.125),
    DynamicThermalTerm("y", -0.5, (LagColumn("level", "T_bed_C", 0.0, 0.2),)),
)


def _grid_geometry() -> GeometricErrors:
    """Tables whose nodes are the export's positions (11 per axis) and whose values a
    six-figure cell writes exactly: the geometry, too, comes back exactly."""
    x, y = tuple(np.linspace(0, 500, 11)), tuple(np.linspace(0, 300, 11))
    rng = np.random.default_rng(14)
    return GeometricErrors(
        {"EXX": Table(x, tuple(np.round(rng.normal(0, 5, 11), 3))),
         "EAX": Table(x, tuple(np.round(rng.normal(0, 3, 11), 3))),
         "EYY": Table(y, tuple(np.round(rng.normal(0, 5, 11), 3)))},
        {"EC0Y": 12.5, "EB0Z": -3.25})


def _without_info(model: MachineModel) -> dict[str, Any]:
    data = model.to_json()
    data.pop("info")
    return data


def _random_points(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0, 500, n), rng.uniform(0, 300, n),
                            rng.uniform(-300, 0, n)])


def test_every_term_kind_round_trips_exactly() -> None:
    model = MachineModel("vmc", _grid_geometry(), TERMS, {"n_readings": 10})
    files = export_model(M, model, points=11)
    assert sorted(files) == ["X.csv", "Y.csv", "locations.csv", TERMS_FILE]
    back = import_model(M, files.items())
    assert _without_info(back) == _without_info(model)
    assert back.terms == model.terms
    q = _random_points(40, 1)
    np.testing.assert_array_equal(corrections(M, back.geometry_at(TEMPS), q),
                                  corrections(M, model.geometry_at(TEMPS), q))
    assert back.reversal_um() == {"x": 7.734912345678901}
    t = 1.5e9 + 7200.125 + np.linspace(0, 3600, 13)
    series = {k: v + np.linspace(0, 2, 13) for k, v in TEMPS.items()}
    for a, b in zip(back.terms[4:], model.terms[4:], strict=True):
        assert isinstance(a, DynamicThermalTerm) and isinstance(b, DynamicThermalTerm)
        np.testing.assert_array_equal(a.series(t, series), b.series(t, series))


def test_terms_file_says_units_descriptions_and_the_reversal_convention() -> None:
    doc = json.loads(export_model(M, MachineModel("vmc", GeometricErrors(), TERMS))[TERMS_FILE])
    assert doc["format"] == "ednc-terms/1" and doc["machine"] == "vmc"
    assert [t["effect"] for t in doc["terms"]] == [
        "backlash", "periodic", "thermal_expansion", "thermal_drift", "thermal_dynamic",
        "thermal_dynamic"]
    for t in doc["terms"]:
        assert isinstance(t["description"], str) and "\n" not in t["description"]
        assert f"axis {t['axis']}" in t["description"] or f"along {t['axis']}" in t[
            "description"]
    for key in ("reversal_um", "period_mm", "t_ref_C", "tau_s", "coefficient"):
        assert key in doc["units"]
    backlash = doc["terms"][0]["description"]
    assert "negative approach minus error on a positive approach" in backlash
    assert "negative approach minus error on a positive approach" in doc["description"]
    assert "lagged" in doc["terms"][4]["description"]
    assert "τ 1234.57 s" in doc["terms"][4]["description"]
    # what the convention says of the map is what the map builder does
    (rev_x, rev_y, rev_z) = reversal_of(M, MachineModel("vmc", GeometricErrors(), TERMS),
                                        None)
    assert rev_x == pytest.approx(-7.734912345678901e-3, rel=1e-6)
    assert rev_y is None and rev_z is None


@dataclass(frozen=True)
class WearTerm:
    """A term kind the tables format does not know."""

    axis: str
    rate_um_per_h: float


@pytest.mark.parametrize(("term", "message"), [
    (WearTerm("x", 0.1), r"cannot export term 1 \(WearTerm of axis x\): the tables format "
                         r"carries backlash, periodic"),
    (BacklashTerm("x", math.nan), r"cannot export term 1 \(backlash of axis x\): "
                                  r"reversal_um is nan"),
    (DynamicThermalTerm("z", 0.0, (LagColumn("lag", "T_bed_C", 60.0, math.inf),)),
     r"term 1 \(thermal_dynamic of axis z\): columns\[0\]\.coefficient is inf"),
    (PeriodicTerm("q", 1.0, 5.0), r"term 1 \(periodic of axis q\): machine 'vmc' has axes"),
])
def test_a_term_the_format_cannot_carry_is_refused_by_name(term: object, message: str
                                                           ) -> None:
    model = MachineModel("vmc", _grid_geometry(), (BacklashTerm("y", 2.0), cast(Term, term)))
    with pytest.raises(ComponentErrorSpecError, match=message):
        export_model(M, model)


@pytest.mark.parametrize(("name", "text", "message"), [
    ("terms.json", '{"format": "ednc-model/1", "terms": []}', r"terms.json: not a terms file"),
    ("terms.json", "{", r"terms.json: not JSON"),
    ("terms.json", '{"format": "ednc-terms/1", "machine": "mill", "terms": []}',
     r"terms are of machine 'mill', the description of 'vmc'"),
    ("terms.json", '{"format": "ednc-terms/1", "terms": [{"effect": "backlash", '
                   '"axis": "x", "reversal_um": NaN}]}', r"terms.json: NaN is not a finite"),
    ("terms.json", '{"format": "ednc-terms/1", "terms": [{"effect": "wear", "axis": "x"}]}',
     r"terms.json: terms\[0\]: unknown effect 'wear'"),
    ("terms.json", '{"format": "ednc-terms/1", "terms": [{"effect": "backlash", '
                   '"axis": "a", "reversal_um": 3}]}',
     r"terms.json: term 0 \(backlash of axis a\): machine 'vmc' has axes"),
    ("terms.json", '{"format": "ednc-terms/1", "terms": {}}', r"'terms' must be a list"),
])
def test_bad_terms_files_are_refused_naming_the_file(name: str, text: str, message: str
                                                     ) -> None:
    with pytest.raises(ComponentErrorSpecError, match=message):
        import_model(M, [("X.csv", "x_mm,EXX_um\n0,1\n500,2\n"), (name, text)])


def test_two_terms_files_are_refused() -> None:
    doc = export_model(M, MachineModel("vmc", GeometricErrors(), TERMS))[TERMS_FILE]
    with pytest.raises(ComponentErrorSpecError, match=r"more than one terms file: a\.json, b"):
        import_model(M, [("a.json", doc), ("b.json", doc)])


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([EDNC, "tables", *args], capture_output=True, text=True)


def test_cli_round_trip_of_a_diagnosed_model_and_old_exports(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps(SPEC))
    geo = GeometricErrors({"EXX": Polynomial((0.0, 8.0, -3.0), 0.0, 500.0),
                           "EBY": Polynomial((12.0, 5.0), 0.0, 300.0)}, {"EC0Y": 20.0})
    model = MachineModel("vmc", geo, TERMS, {"n_readings": 1000})
    (tmp_path / "model.json").write_text(json.dumps(model.to_json()))
    out = _run("export", "--machine", str(tmp_path / "m.json"), "--model",
               str(tmp_path / "model.json"), "--out", str(tmp_path / "t"), "--points", "201")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "t" / TERMS_FILE).is_file()
    out = _run("import", "--machine", str(tmp_path / "m.json"), str(tmp_path / "t"),
               "--out", str(tmp_path / "back.json"))
    assert out.returncode == 0, out.stderr
    assert "6 extension terms" in out.stdout
    back = MachineModel.from_json(json.loads((tmp_path / "back.json").read_text()))
    assert back.to_json()["terms"] == model.to_json()["terms"]
    q = _random_points(30, 2)
    d = corrections(M, back.geometry_at(TEMPS), q) - corrections(M, model.geometry_at(TEMPS), q)
    assert np.abs(d).max() < 1e-5  # mm: the polynomials sampled at 201 positions

    # an export of an earlier version (bare ISO names, no terms file) imports as rigid
    (tmp_path / "t" / TERMS_FILE).unlink()
    (tmp_path / "t" / "X.csv").write_text("x_mm,EXX\n0,0\n500,-750\n")
    out = _run("import", "--machine", str(tmp_path / "m.json"), str(tmp_path / "t"),
               "--out", str(tmp_path / "rigid.json"))
    assert out.returncode == 0, out.stderr
    rigid = MachineModel.from_json(json.loads((tmp_path / "rigid.json").read_text()))
    assert rigid.terms == () and set(rigid.geometry.components) == {"EXX", "EBY"}


def test_cli_refuses_a_term_it_cannot_carry_and_writes_nothing(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps(SPEC))
    data = MachineModel("vmc", _grid_geometry(), TERMS).to_json()
    data["terms"][3]["coefficient"] = math.inf  # a model JSON may hold Infinity
    (tmp_path / "model.json").write_text(json.dumps(data))
    out = _run("export", "--machine", str(tmp_path / "m.json"), "--model",
               str(tmp_path / "model.json"), "--out", str(tmp_path / "t"))
    assert out.returncode == 2
    # refused by the export or already by the model reader, naming the term and the value
    assert re.search(r"term(s\[| )3.*thermal_drift.*coefficient.*inf", out.stderr), out.stderr
    assert len(out.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "t").exists()


def test_export_then_import_gives_the_model_back_whole_and_predicts_the_same(
        tmp_path: Path) -> None:
    """The fit's tool-tip offsets and the exact component functions come back (predict
    was 0.50 -> 2.47 µm RMS after a round trip that dropped the offsets); an edited table
    is taken as edited."""
    from machine_sim.campaign import standard_campaign
    from machine_sim.effects import Effects
    from machine_sim.instruments import SimulatedMachine
    from machine_sim.truth import random_geometry
    from volumetric.diagnose.predict import predict

    spec = {**SPEC, "tool_length_mm": 100.0}
    m = parse_machine(spec)
    geo = random_geometry(m, np.random.default_rng(3))
    offsets = {"OFFSET_X": 1.7, "OFFSET_Y": -0.9, "OFFSET_Z": 2.4}
    model = MachineModel("vmc", geo, (BacklashTerm("x", 6.0),),
                         {"offsets_um": offsets, "n_readings": 10})
    rng = np.random.default_rng(4)
    readings = standard_campaign(SimulatedMachine(m, geo, Effects(), seed=1), rng)
    (tmp_path / "m.json").write_text(json.dumps(spec))
    (tmp_path / "model.json").write_text(json.dumps(model.to_json()))
    out = _run("export", "--machine", str(tmp_path / "m.json"), "--model",
               str(tmp_path / "model.json"), "--out", str(tmp_path / "t"))
    assert out.returncode == 0, out.stderr
    out = _run("import", "--machine", str(tmp_path / "m.json"), str(tmp_path / "t"),
               "--out", str(tmp_path / "back.json"))
    assert out.returncode == 0, out.stderr
    back = MachineModel.from_json(json.loads((tmp_path / "back.json").read_text()))
    assert back.info["offsets_um"] == offsets
    assert back.geometry.to_json() == model.geometry.to_json()
    before, after = predict(m, model, readings), predict(m, back, readings)
    assert after.to_json()["rms_um"] == before.to_json()["rms_um"] > 0
    # a table edited by hand is read as edited (the exact functions no longer match it)
    x = (tmp_path / "t" / "X.csv").read_text().splitlines()
    cells = x[3].split(",")
    cells[1] = str(float(cells[1]) + 5.0)
    (tmp_path / "t" / "X.csv").write_text("\n".join([*x[:3], ",".join(cells), *x[4:]]) + "\n")
    out = _run("import", "--machine", str(tmp_path / "m.json"), str(tmp_path / "t"),
               "--out", str(tmp_path / "edited.json"))
    assert out.returncode == 0, out.stderr
    edited = json.loads((tmp_path / "edited.json").read_text())
    assert edited["components"]["EXX"]["type"] == "table"
    assert edited["info"]["offsets_um"] == offsets
