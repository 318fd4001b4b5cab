"""``deploy/fleet.yaml`` describes machines every command can work with (issue 25: its
five-axis machine lacked ``pivots_mm`` and no campaign could be measured on it)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from machine_sim.fleet import load_fleet
from tests.support.cli import ednc
from volumetric.model.machine import missing_pivots, parse_machine

FLEET = Path(__file__).resolve().parents[1] / "deploy" / "fleet.yaml"
MACHINES = yaml.safe_load(FLEET.read_text())["machines"]


def test_the_fleet_file_loads_with_every_machine() -> None:
    entries, _ = load_fleet(FLEET)
    assert [e.machine.name for e in entries] == [m["machine"]["name"] for m in MACHINES]
    assert len(entries) == 8  # six EDNC clients, one Modbus and one OPC UA controller


@pytest.mark.parametrize("entry", MACHINES, ids=[m["machine"]["name"] for m in MACHINES])
def test_every_machine_is_complete_and_measurable(entry: dict[str, object],
                                                  tmp_path: Path) -> None:
    spec = entry["machine"]
    assert isinstance(spec, dict)
    machine = parse_machine(spec)
    assert missing_pivots(spec, machine) is None
    (tmp_path / "m.json").write_text(json.dumps(spec))
    r = ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine", str(tmp_path / "m.json"))
    assert r.returncode == 0, r.stderr
    assert "readings" in r.stdout


def test_the_five_axis_machine_without_pivots_is_refused_with_an_example(
        tmp_path: Path) -> None:
    spec = dict(next(m["machine"] for m in MACHINES if m["machine"]["name"] == "5ax-05"))
    spec.pop("pivots_mm")
    (tmp_path / "m.json").write_text(json.dumps(spec))
    r = ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine", str(tmp_path / "m.json"))
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert 'add for example "pivots_mm": {"C": [' in r.stderr, r.stderr
