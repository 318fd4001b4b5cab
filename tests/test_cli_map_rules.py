"""``ednc map`` (issue 30): a factored map that misses its tolerance is written with
``--allow-over-tolerance`` (and with ``--json``) like every other kind, refused with the
hint at the terminal without it; ``--json`` reports a format-3 grid's thermal records."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from protocol.mapformat import decode_map
from tests.support.kinematics import random_errors
from volumetric.model.machine import parse_machine
from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm

MACHINE = {"name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.21",
           "chain": "w X Y b Z t", "travel_mm": {"x": [0, 500], "y": [0, 300],
                                                 "z": [-300, 0]},
           "tool_length_mm": 100.0}


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    m = parse_machine(MACHINE)
    model = MachineModel("vmc-01", random_errors(m, np.random.default_rng(1), 5.0), (
        ThermalTerm("thermal_expansion", "x", "T_x_C", 11.0, 20.0, 0.0),
        BacklashTerm("x", 9.8)))
    (tmp_path / "m.json").write_text(json.dumps(MACHINE))
    (tmp_path / "model.json").write_text(json.dumps(model.to_json()))
    return tmp_path / "m.json", tmp_path / "model.json"


def _ednc(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()",
                           *map(str, args)], capture_output=True, text=True, timeout=600)


def test_an_over_tolerance_factored_map_is_written_when_allowed(
        files: tuple[Path, Path], tmp_path: Path) -> None:
    """Corrections clamped to ±2 µm leave ~28 µm as sent: over any tolerance."""
    mach, model = files
    out = tmp_path / "f.bin"
    args: list[str | Path] = [
        "map", "--machine", mach, "--model", model, "--out", out, "--kind", "factored",
        "--tolerance-um", "1", "--temperature", "T_x_C=23", "--limit-mm", "0.002"]
    refused = _ednc(*args)
    assert refused.returncode == 2 and "--allow-over-tolerance" in refused.stderr
    assert not out.exists()
    allowed = _ednc(*args, "--allow-over-tolerance", "--json")
    assert allowed.returncode == 0, allowed.stderr
    body = json.loads(allowed.stdout)
    assert body["kind"] == "factored" and body["over_tolerance"] is True
    assert body["worst_error_um"] > 10 and body["format_version"] == 5
    assert out.read_bytes()[4:6] == b"\x05\x00" and "warning" in allowed.stderr


def test_map_json_reports_a_format_3_grids_thermal_records(
        files: tuple[Path, Path], tmp_path: Path) -> None:
    mach, model = files
    out = tmp_path / "g.bin"
    run = _ednc("map", "--machine", mach, "--model", model, "--out", out, "--kind", "grid",
                "--tolerance-um", "2", "--temperature", "T_x_C=23", "--json")
    assert run.returncode == 0, run.stderr
    body = json.loads(run.stdout)
    payload = decode_map(out.read_bytes())
    assert payload.format_version == body["format_version"] == 3
    assert body["thermal"] == [{"effect": "thermal_expansion", "axis": "x",
                                "sensor": "T_x_C"}]
    assert [(r.sensor, r.axis) for r in payload.thermal] == [("x", "X")]
