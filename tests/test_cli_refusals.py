"""Nonsense is refused, not computed (issue 14, "accepted in silence"): a negative tool
length, a model of another machine, points outside the travel, an unknown sensor."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.support.cli import ednc, one_line_error
from volumetric.errors import MachineSpecError
from volumetric.model.components import GeometricErrors, Polynomial
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel

VMC = {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}


@pytest.mark.parametrize("length", [-100.0, -1e-3, float("inf"), float("nan"), 1e5, 1e300])
def test_a_tool_length_below_zero_or_not_finite_is_refused(length: float) -> None:
    with pytest.raises(MachineSpecError, match="tool_length_mm"):
        parse_machine({**VMC, "tool_length_mm": length})
    spindles = [{"name": "S1", "axis": "Z1", "direction": [0, 0, 1], "tool_length_mm": length}]
    with pytest.raises(MachineSpecError, match=r"spindles\[0\]\.tool_length_mm"):
        parse_machine({**VMC, "chain": "w X Y b t", "spindles": spindles,
                       "travel_mm": {"x": [0, 500], "y": [0, 300], "z1": [-300, 0]}})


def test_a_tool_at_the_gauge_line_is_fine() -> None:
    assert parse_machine({**VMC, "tool_length_mm": 0}).branches[0].tool_length_mm == 0.0


def test_the_cli_refuses_a_negative_tool_length(tmp_path: Path) -> None:
    machine = tmp_path / "m.json"
    machine.write_text(json.dumps({**VMC, "tool_length_mm": -100}))
    line = one_line_error(ednc("sim", "--campaign", str(tmp_path / "c.csv"),
                               "--machine", str(machine)))
    assert "tool_length_mm" in line and "-100" in line
    assert not (tmp_path / "c.csv").exists()


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    machine = tmp_path / "m.json"
    machine.write_text(json.dumps(VMC))
    geo = GeometricErrors(components={"EXX": Polynomial((0.0, 5.0, -2.0), 250.0, 250.0)},
                          locations={"EC0Y": 20.0})
    model = tmp_path / "model.json"
    model.write_text(json.dumps(MachineModel("vmc", geo).to_json()))
    return machine, model


def test_compensate_refuses_points_outside_the_travel_unless_told(
        files: tuple[Path, Path]) -> None:
    machine, model = files
    line = one_line_error(ednc("compensate", "--machine", str(machine), "--model", str(model),
                               "--point", "250,150,-100", "--point", "5000,150,-100"))
    assert "point 2" in line and "X = 5000 mm" in line and "[0, 500]" in line
    assert "--extrapolate" in line
    ok = ednc("compensate", "--machine", str(machine), "--model", str(model),
              "--point", "5000,150,-100", "--extrapolate", "--json")
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["points"]
    inside = ednc("compensate", "--machine", str(machine), "--model", str(model),
                  "--point", "500,0,-300", "--json")  # the travel's ends are inside
    assert inside.returncode == 0, inside.stderr


def test_a_model_of_another_machine_is_refused(files: tuple[Path, Path],
                                               tmp_path: Path) -> None:
    _, model = files
    other = tmp_path / "other.json"
    other.write_text(json.dumps({**VMC, "name": "vmc-02"}))
    for command in (["compensate", "--point", "250,150,-100"],
                    ["export", "--format", "iso230-1", "--out", str(tmp_path / "x")]):
        line = one_line_error(ednc(*command, "--machine", str(other), "--model", str(model)))
        assert "'vmc'" in line and "'vmc-02'" in line, line


def test_an_unknown_temperature_sensor_is_refused(files: tuple[Path, Path]) -> None:
    machine, model = files
    line = one_line_error(ednc("compensate", "--machine", str(machine), "--model", str(model),
                               "--point", "250,150,-100", "--temperature", "T_spindel_C=25"))
    assert "T_spindel_C" in line and "does not use" in line


HEADER = "test,run,time_s,x_mm,y_mm,z_mm,dir_x,dir_y,dir_z,tool_mm,quantity,ux,uy,uz,value"


@pytest.mark.parametrize("command", ["fit", "diagnose"])
def test_readings_outside_the_travel_are_refused_naming_the_line(command: str,
                                                                 tmp_path: Path) -> None:
    machine = tmp_path / "m.json"
    machine.write_text(json.dumps(VMC))
    rows = [f"X-pos,1,{i},{x},150,-100,1,1,1,100,displacement,1,0,0,0.5"
            for i, x in enumerate([0, 250, 588, 500])]
    data = tmp_path / "c.csv"
    data.write_text("\n".join([HEADER, *rows]) + "\n")
    line = one_line_error(ednc(command, "--machine", str(machine), "--data", str(data)))
    assert "line 4" in line and "x = 588 mm" in line and "[0, 500]" in line, line
    assert "--allow-outside-travel" in line
    allowed = ednc(command, "--machine", str(machine), "--data", str(data),
                   "--allow-outside-travel")
    assert "outside the travel" not in allowed.stderr


def test_unidentifiable_parameters_are_named_in_words() -> None:
    from ednc.commands.fit import term_text

    assert term_text("EBZ[0]") == "EBZ constant term"
    assert term_text("EXX[2]") == "EXX quadratic term"
    assert term_text("ECX[7]") == "ECX order-7 term"
    assert term_text("EC0Y") == "EC0Y"
