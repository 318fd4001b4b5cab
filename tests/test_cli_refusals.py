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


@pytest.mark.parametrize("length", [-100.0, -1e-3, float("inf"), float("nan")])
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
    geo = GeometricErrors(components={"EXX": Polynomial((0.0, 5.0, -2.0))},
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
