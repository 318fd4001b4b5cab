"""``ednc sim``: the campaign mode writes a readable CSV, the fleet mode's input errors are
one clear line, fleet files are checked entry by entry."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from machine_sim.fleet import FleetSpecError, generated_fleet, load_fleet, parse_center
from volumetric.measure.measurement import read_measurements

VMC = {"name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.21", "chain": "w X Y b Z t",
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}, "tool_length_mm": 100.0}


def ednc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()", *args],
                          capture_output=True, text=True, timeout=300)


def test_campaign_mode_writes_the_standard_campaign(tmp_path: Path) -> None:
    spec = tmp_path / "vmc.json"
    spec.write_text(json.dumps(VMC))
    out, truth = tmp_path / "c.csv", tmp_path / "truth.json"
    r = ednc("sim", "--campaign", str(out), "--machine", str(spec), "--effect",
             "backlash:x:8", "--effect", "noise:0.2:0.5", "--truth", str(truth), "--seed", "3")
    assert r.returncode == 0, r.stderr
    m = read_measurements(out)
    assert len(m) > 2000 and "T_spindle_C" in m.temperature_columns.values()
    pos = m.select(m.test == "X-positioning")
    up = pos.value[pos.direction[:, 0] > 0].mean()
    down = pos.value[pos.direction[:, 0] < 0].mean()
    assert up - down == pytest.approx(-8.0, abs=0.2)  # noise 0.2 µm over 105 readings each
    assert "EXX" in json.loads(truth.read_text())["geometry"]["components"]


@pytest.mark.parametrize(("args", "message"), [
    (["sim", "--machines", "2"], "--machines needs --secret"),
    (["sim", "--machines", "2", "--secret", "short", "--center", "h:1"], "at least 16 bytes"),
    (["sim", "--machines", "2", "--secret", "0123456789abcdef", "--center", "nohost"],
     "expected HOST:PORT"),
    (["sim"], "give --machines N"),
    (["sim", "--campaign", "x.csv"], "--campaign needs --machine"),
])
def test_bad_options_are_one_line_and_exit_2(args: list[str], message: str) -> None:
    r = ednc(*args)
    assert r.returncode == 2
    assert message in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_bad_effect_names_the_problem(tmp_path: Path) -> None:
    spec = tmp_path / "vmc.json"
    spec.write_text(json.dumps(VMC))
    r = ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine", str(spec),
             "--effect", "backlash:w:3")
    assert r.returncode == 2 and "no axis 'w'" in r.stderr
    r = ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine", str(spec),
             "--effect", "wobble:x")
    assert r.returncode == 2 and "expected backlash:AXIS:B_um" in r.stderr


def test_fleet_file_is_read_and_checked(tmp_path: Path) -> None:
    (tmp_path / "vmc.json").write_text(json.dumps(VMC))
    other = {**VMC, "name": "vmc-02", "controller": "siemens"}
    good = {"center": "127.0.0.1:7070", "machines": [
        {"machine": "vmc.json", "secret": "0123456789abcdef", "seed": 4},
        {"machine": other, "secret": "fedcba9876543210", "ip": "127.0.0.1"}]}
    path = tmp_path / "fleet.json"
    path.write_text(json.dumps(good))
    entries, settings = load_fleet(path)
    assert [e.machine.name for e in entries] == ["vmc-01", "vmc-02"]
    assert entries[0].seed == 4 and entries[1].ip == "127.0.0.1"
    assert settings["center"] == "127.0.0.1:7070"
    bad = {"machines": [good["machines"][0], {"machine": "vmc.json", "secret": "x" * 16}]}
    path.write_text(json.dumps(bad))
    with pytest.raises(FleetSpecError, match=r"machines\[1\]: machine name 'vmc-01' appears"):
        load_fleet(path)
    path.write_text(json.dumps({"machines": [{"machine": "vmc.json", "secret": "short"}]}))
    with pytest.raises(FleetSpecError, match=r"machines\[0\]: secret must be"):
        load_fleet(path)
    path.write_text(json.dumps({"machines": [{"machine": "missing.json", "secret": "x" * 16}]}))
    with pytest.raises(FleetSpecError, match=r"machines\[0\].machine: .*missing.json"):
        load_fleet(path)


def test_generated_fleet_and_center_address() -> None:
    fleet = generated_fleet(4, "0123456789abcdef", seed=10)
    assert [e.machine.name for e in fleet] == ["sim-001", "sim-002", "sim-003", "sim-004"]
    assert [e.machine.controller for e in fleet] == ["fanuc", "siemens"] * 2
    assert [e.seed for e in fleet] == [10, 11, 12, 13]
    assert parse_center("[::1]:7070") == ("::1", 7070)
    assert parse_center("center.local:7070") == ("center.local", 7070)
    with pytest.raises(FleetSpecError, match="HOST:PORT"):
        parse_center("center:99999")
    assert np.all([len(e.secret) >= 16 for e in fleet])
