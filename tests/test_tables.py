"""Component-error tables with ISO 230-1 column names: out, in, and bad cells named."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from volumetric.errors import ComponentErrorSpecError
from volumetric.measure.tables import export_tables, import_tables
from volumetric.model.components import GeometricErrors, Polynomial
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel

M = parse_machine({"name": "vmc", "chain": "w X Y b Z t",
                   "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}})
EDNC = str(Path(sys.executable).parent / "ednc")


def test_export_then_import_reproduces_the_error_field() -> None:
    g = GeometricErrors({"EXX": Polynomial((0.0, 8.0, -3.0), 0.0, 500.0),
                         "EBY": Polynomial((12.0, 5.0), 0.0, 300.0)}, {"EC0Y": 20.0})
    tables = export_tables(M, g, points=101)
    assert tables["X"].splitlines()[0] == "x_mm,EXX_um"
    again = import_tables(M, tables.items())
    q = np.column_stack([np.linspace(0, 500, 77), np.linspace(0, 300, 77),
                         np.linspace(-300, 0, 77)])
    d = volumetric_error(M, again, q).position_um - volumetric_error(M, g, q).position_um
    assert np.abs(d).max() < 0.01  # linear interpolation of 101 points of a parabola


@pytest.mark.parametrize(("text", "message"), [
    ("x_mm,EXX\n0,1\n10,nan\n", r"t.csv:3 column EXX: 'nan' is not a finite number"),
    ("x_mm,EXY\n0,1\n", r"'EXY' is not a component error of axis X"),
    ("q_mm,EXX\n0,1\n", r"not an axis position column"),
    ("x_mm,EXX\n0,1\n0,2\n", r"increase strictly"),
    ("x_mm,EXX\n0\n", r"t.csv:2: 1 cells"),
    ("name,value\nEA0Y,3\n", r"not a location error of this machine"),
])
def test_bad_tables_are_refused_with_file_line_and_column(text: str, message: str) -> None:
    with pytest.raises(ComponentErrorSpecError, match=message):
        import_tables(M, [("t.csv", text)])


def test_tables_commands_round_trip(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps({"name": "vmc", "chain": "w X Y b Z t",
        "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}))
    model = MachineModel("vmc", GeometricErrors({"EXX": Polynomial((0.0, 5.0), 0.0, 500.0)}))
    (tmp_path / "model.json").write_text(json.dumps(model.to_json()))
    out = subprocess.run([EDNC, "tables", "export", "--machine", str(tmp_path / "m.json"),
                          "--model", str(tmp_path / "model.json"), "--out",
                          str(tmp_path / "t")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    out = subprocess.run([EDNC, "tables", "import", "--machine", str(tmp_path / "m.json"),
                          str(tmp_path / "t" / "X.csv"), "--out", str(tmp_path / "back.json")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    back = MachineModel.from_json(json.loads((tmp_path / "back.json").read_text()))
    np.testing.assert_allclose(back.geometry.components["EXX"](np.array([250.0])), [2.5])
    (tmp_path / "t" / "X.csv").write_text("x_mm,EXX\n0,1\n5,x\n")
    out = subprocess.run([EDNC, "tables", "import", "--machine", str(tmp_path / "m.json"),
                          str(tmp_path / "t" / "X.csv"), "--out", str(tmp_path / "b.json")],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "X.csv:3 column EXX" in out.stderr
