"""Native exports: Siemens CEC tables compensate what 1-D tables can hold (and name the
rest), ISO 230-1 CSV gives back the map's tables exactly, and ``ednc export`` writes them."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

from tests.support.kinematics import machine, random_q
from volumetric.compensate.native import cec_mpf, cec_tables, iso230_1_tables
from volumetric.compensate.solver import corrections
from volumetric.compensate.tablesmap import build_tables_map
from volumetric.measure.tables import import_tables
from volumetric.model.components import GeometricErrors, Polynomial, Sinusoid
from volumetric.model.model import MachineModel

EDNC = Path(sys.executable).parent / "ednc"


def displacement_only() -> GeometricErrors:
    """Positioning, straightness and squareness: everything a CEC table can hold."""
    return GeometricErrors({
        "EXX": Polynomial((2.0, 0.02, -3e-5)), "EYX": Polynomial((0.0, -0.01, 2e-5)),
        "EYY": Sinusoid(1.5, 40.0), "EZY": Polynomial((1.0, 0.004)),
        "EZZ": Polynomial((0.0, -0.03)), "EXZ": Polynomial((0.0, 0.0, 4e-5)),
    }, {"EC0Y": 25.0, "EB0Z": -15.0, "EA0Z": 10.0})


def cec_corrections(tables: list[tuple[str, str, float, float, np.ndarray]],
                    names: tuple[str, ...], q: np.ndarray) -> np.ndarray:
    out = np.zeros_like(q)
    for src, dst, start, step, values in tables:
        pos = start + step * np.arange(values.size)
        out[:, names.index(dst)] += np.interp(q[:, names.index(src)], pos, values)
    return out


def test_cec_tables_sum_to_the_corrections_of_what_they_can_hold() -> None:
    mach = machine("w X Y b Z t")
    geo = displacement_only()
    t = build_tables_map(mach, MachineModel(mach.name, geo), tolerance_um=0.05,
                         controller="siemens")
    e = cec_tables(t)
    assert e.left_out == ()
    assert all(c.values.size <= 200 for c in e.tables)
    q = random_q(mach, np.random.default_rng(3), 2000)
    got = cec_corrections([(c.input, c.output, c.start, c.step, c.values) for c in e.tables],
                          mach.axis_names, q)
    want = corrections(mach, geo, q)
    assert np.abs(want).max() > 0.01  # over 10 µm to compensate
    assert np.abs(got - want).max() * 1e3 < 0.1  # µm: first order and resampling only


def test_cec_names_what_needs_the_chain() -> None:
    mach = machine("w X Y b Z t")
    geo = GeometricErrors({**displacement_only().components, "EBX": Polynomial((5.0, 0.01))},
                          dict(displacement_only().locations))
    t = build_tables_map(mach, MachineModel(mach.name, geo), tolerance_um=0.1,
                         controller="siemens")
    e = cec_tables(t)
    assert [name for name, _ in e.left_out] == ["EBX"]
    text = cec_mpf(t)
    assert "left uncompensated: EBX" in text
    n = len(e.tables)
    assert len(re.findall(r"^\$AN_CEC_INPUT_AXIS\[\d+\]=\([XYZ]1\)$", text, re.M)) == n
    assert text.rstrip().endswith("M17")


def test_iso230_1_csv_gives_back_the_tables_exactly() -> None:
    mach = machine("w C A X b Y Z t", pivots_mm={"A": [0.0, 0.0, 50.0]},
                   travel_mm={"x": [0, 400], "y": [0, 300], "z": [-300, 0], "a": [-90, 30],
                              "c": [-180, 180]})
    rng = np.random.default_rng(4)
    comps = {n: Polynomial(tuple(rng.normal(0, 3, 4)), -180.0, 360.0)
             for n in ("ECC", "EXC", "EBA")}
    comps["EXX"] = Polynomial(tuple(rng.normal(0, 3, 3)), 0.0, 400.0)
    t = build_tables_map(mach, MachineModel(mach.name, GeometricErrors(comps, {"EX0C": 12.0})),
                         tolerance_um=0.2, controller="siemens")
    files = iso230_1_tables(t)
    back = import_tables(mach, [(f"{k}.csv", v) for k, v in files.items()])
    mine = t.geometry()
    q = random_q(mach, np.random.default_rng(5), 500)
    for name, f in mine.components.items():
        axis = mach.axis_names.index(name[2:])
        assert np.allclose(back.components[name](q[:, axis]), f(q[:, axis]), atol=1e-6), name
    assert back.locations == {"EX0C": 12.0}


def test_ednc_export_writes_the_files_and_refuses_bad_options(tmp_path: Path) -> None:
    mach_json = {"name": "vmc", "controller": "siemens", "ip": "10.0.0.7",
                 "chain": "w X Y b Z t", "tool_length_mm": 100.0,
                 "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}
    (tmp_path / "m.json").write_text(json.dumps(mach_json))
    model = MachineModel("vmc", displacement_only())
    (tmp_path / "model.json").write_text(json.dumps(model.to_json()))
    base = [str(EDNC), "export", "--machine", str(tmp_path / "m.json"),
            "--model", str(tmp_path / "model.json")]
    r = subprocess.run([*base, "--format", "cec", "--out", str(tmp_path / "cec.mpf"),
                        "--json"], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["tables"] == 9 and info["left_out"] == []  # 6 components, 3 squareness
    assert "$AN_CEC[0,0]=" in (tmp_path / "cec.mpf").read_text()
    r = subprocess.run([*base, "--format", "iso230-1", "--out", str(tmp_path / "iso")],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in (tmp_path / "iso").iterdir()) == [
        "X.csv", "Y.csv", "Z.csv", "locations.csv"]
    r = subprocess.run([*base, "--format", "heidenhain", "--out", str(tmp_path / "x")],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 2 and "expected cec or iso230-1" in r.stderr
    assert "Traceback" not in r.stderr
