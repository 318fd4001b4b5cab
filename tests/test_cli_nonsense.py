"""Every bad input of issue 25 ("the CLI computes nonsense or crashes"), each reproduced on
the main of that day, is refused in one line (exit 2, no traceback), or answered soundly:
readings of absurd size, a model file ``{}``, a machine of 1e9 mm travel, negative seeds and
counts, an output directory that does not exist, ``lookup`` outside the map's travel or with
temperatures the map does not use, a three-axis campaign against a five-axis description.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.support.cli import ednc, one_line_error

TRAVEL: dict[str, list[float]] = {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}
VMC: dict[str, Any] = {"name": "vmc", "controller": "fanuc", "chain": "w X Y b Z t",
                       "tool_length_mm": 100.0, "travel_mm": TRAVEL}
FIVE_AXIS: dict[str, Any] = {**VMC, "chain": "w C A X b Y Z t",
             "travel_mm": {**TRAVEL, "a": [-110, 110], "c": [-180, 180]},
             "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]}}


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A campaign, its model, a map of it, and the bad variants the cases use."""
    d = tmp_path_factory.mktemp("nonsense")
    (d / "vmc.json").write_text(json.dumps(VMC))
    (d / "vmc-siemens.json").write_text(json.dumps({**VMC, "controller": "siemens"}))
    (d / "5ax.json").write_text(json.dumps(FIVE_AXIS))
    (d / "huge.json").write_text(json.dumps({**VMC, "travel_mm": {**TRAVEL, "x": [0, 1e9]}}))
    r = ednc("sim", "--campaign", str(d / "c.csv"), "--machine", str(d / "vmc.json"),
             "--effect", "noise:0.3", "--seed", "1")
    assert r.returncode == 0, r.stderr
    r = ednc("fit", "--machine", str(d / "vmc.json"), "--data", str(d / "c.csv"),
             "--out", str(d / "model.json"))
    assert r.returncode == 0, r.stderr
    r = ednc("map", "--machine", str(d / "vmc-siemens.json"), "--model",
             str(d / "model.json"), "--out", str(d / "map.bin"), "--json")
    assert r.returncode == 0, r.stderr
    rows = list(csv.reader((d / "c.csv").open()))
    value = rows[0].index("value")
    for name, cell in (("1e300", "1e300"), ("1e9", "1e9")):
        bad = [list(row) for row in rows]
        bad[5][value] = cell  # line 6 of the file
        with (d / f"reading-{name}.csv").open("w", newline="") as fh:
            csv.writer(fh, lineterminator="\n").writerows(bad)
    (d / "empty-model.json").write_text("{}")
    (d / "far.csv").write_text("x,y,z\n5000,300,-250\n")
    (d / "inside.csv").write_text("x,y,z\n400,300,-250\n")
    return d


Case = Callable[[Path], list[str]]
CASES: dict[str, tuple[Case, str]] = {
    "fit on a reading of 1e300 um": (
        lambda d: ["fit", "--machine", f"{d}/vmc.json", "--data", f"{d}/reading-1e300.csv"],
        "line 6"),
    "diagnose on a reading of 1e300 um": (
        lambda d: ["diagnose", "--machine", f"{d}/vmc.json", "--data",
                   f"{d}/reading-1e300.csv"], "line 6"),
    "fit on a reading of 1e9 um": (
        lambda d: ["fit", "--machine", f"{d}/vmc.json", "--data", f"{d}/reading-1e9.csv"],
        "line 6"),
    "diagnose on a reading of 1e9 um": (
        lambda d: ["diagnose", "--machine", f"{d}/vmc.json", "--data",
                   f"{d}/reading-1e9.csv"], "line 6"),
    "fit --out into a missing directory": (
        lambda d: ["fit", "--machine", f"{d}/vmc.json", "--data", f"{d}/c.csv",
                   "--out", "/missing/dir/x.json"], "/missing/dir"),
    "map of a machine with 1e9 mm travel": (
        lambda d: ["map", "--machine", f"{d}/huge.json", "--model", f"{d}/model.json",
                   "--out", f"{d}/huge.bin"], "travel_mm.x"),
    "sim --seed -1": (
        lambda d: ["sim", "--campaign", f"{d}/s.csv", "--machine", f"{d}/vmc.json",
                   "--seed", "-1"], "--seed"),
    "predict with a model file {}": (
        lambda d: ["predict", "--machine", f"{d}/vmc.json", "--model",
                   f"{d}/empty-model.json", "--data", f"{d}/c.csv"], "empty-model.json"),
    "lookup at x = 5000 mm on a 0-800 mm axis": (
        lambda d: ["lookup", "--map", f"{d}/map.bin", "--points", f"{d}/far.csv"],
        "outside"),
    "lookup --temperature on a map without thermal records": (
        lambda d: ["lookup", "--map", f"{d}/map.bin", "--points", f"{d}/inside.csv",
                   "--temperature", "T_spindle_C=30"], "T_spindle_C"),
    "diagnose --max-readings -5": (
        lambda d: ["diagnose", "--machine", f"{d}/vmc.json", "--data", f"{d}/c.csv",
                   "--max-readings", "-5"], "--max-readings"),
    "map --increment 0 on a Siemens-style machine": (
        lambda d: ["map", "--machine", f"{d}/vmc-siemens.json", "--model",
                   f"{d}/model.json", "--out", f"{d}/inc.bin", "--increment", "0"],
        "--increment"),
    "a 3-axis campaign fitted against a 5-axis description": (
        lambda d: ["fit", "--machine", f"{d}/5ax.json", "--data", f"{d}/c.csv"], "a_deg"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_nonsense_is_refused_in_one_line(work: Path, name: str) -> None:
    args, expected = CASES[name]
    line = one_line_error(ednc(*args(work)))
    assert expected in line, line


def test_fit_out_is_checked_before_the_fit(work: Path) -> None:
    """The refusal comes before the readings are even read: a bad data file is not
    named, the output is."""
    line = one_line_error(ednc("fit", "--machine", f"{work}/vmc.json", "--data",
                               f"{work}/reading-1e9.csv", "--out", "/missing/dir/x.json"))
    assert "/missing/dir" in line and "reading-1e9" not in line


def test_max_readings_says_what_it_uses(work: Path) -> None:
    r = ednc("diagnose", "--machine", f"{work}/vmc.json", "--data", f"{work}/c.csv",
             "--max-readings", "10", "--json")
    assert r.returncode == 0, r.stderr
    total = sum(1 for _ in (work / "c.csv").open()) - 1
    # each test keeps at least its share; the message says how many are diagnosed
    said = [w for w in r.stderr.split() if w.isdigit()]
    assert said and int(said[0]) != 10, r.stderr
    assert str(total) in r.stderr


def test_map_works_at_the_default_tolerance_on_a_fanuc_style_machine(work: Path) -> None:
    out = work / "fanuc.bin"
    text = ednc("map", "--machine", f"{work}/vmc.json", "--model", f"{work}/model.json",
                "--out", str(out))
    assert text.returncode == 0, text.stderr
    as_json = ednc("map", "--machine", f"{work}/vmc.json", "--model", f"{work}/model.json",
                   "--out", str(out), "--json")
    assert as_json.returncode == 0, as_json.stderr
    s = json.loads(as_json.stdout)
    # tolerance_um is the tolerance the map was held to, and the map meets it
    assert s["over_tolerance"] is False
    assert s["worst_error_um"] <= s["tolerance_um"]
    assert f"{s['tolerance_um']:g} µm" in text.stdout


def test_compensate_takes_the_approach_and_agrees_with_lookup(work: Path) -> None:
    """A backlash B: the correction after a positive approach is B/2 above the rigid one,
    after a negative approach B/2 below, and ``lookup`` (positive approach) agrees."""
    model = json.loads((work / "model.json").read_text())
    model["terms"] = [{"effect": "backlash", "axis": "x", "reversal_um": 10.0}]
    (work / "model-backlash.json").write_text(json.dumps(model))
    machine = f"{work}/vmc-siemens.json"
    got = {}
    for approach in ("+", "-"):
        r = ednc("compensate", "--machine", machine, "--model", f"{work}/model-backlash.json",
                 "--point", "400,300,-250", "--approach", approach, "--json")
        assert r.returncode == 0, r.stderr
        body = json.loads(r.stdout)
        assert body["approach"] == approach and body["backlash_um"] == {"x": 10.0}
        got[approach] = body["points"][0]["correction"]["x"]
    assert got["+"] - got["-"] == pytest.approx(0.010, abs=1e-9)
    text = ednc("compensate", "--machine", machine, "--model", f"{work}/model-backlash.json",
                "--point", "400,300,-250")
    assert "positive approach" in text.stdout and "backlash x 10 µm" in text.stdout
    r = ednc("map", "--machine", machine, "--model", f"{work}/model-backlash.json",
             "--out", f"{work}/backlash.bin")
    assert r.returncode == 0, r.stderr
    (work / "one.csv").write_text("x,y,z\n400,300,-250\n")
    r = ednc("lookup", "--map", f"{work}/backlash.bin", "--points", f"{work}/one.csv", "--json")
    assert r.returncode == 0, r.stderr
    applied = json.loads(r.stdout)["points"][0]["correction"]["x"]
    assert applied == pytest.approx(got["+"], abs=5e-4)  # the map's tolerance, 0.5 µm
    assert abs(applied - got["-"]) > 9e-3


def test_json_output_never_holds_infinity_or_nan() -> None:
    from ednc.inputs import dump_json

    text = dump_json({"A_um": float("inf"), "B_um": [float("nan"), 1.0]})
    assert json.loads(text) == {"A_um": None, "B_um": [None, 1.0]}
    assert "Infinity" not in text and "NaN" not in text


def test_iso230_2_json_is_json(work: Path) -> None:
    rows = [line for line in (work / "c.csv").read_text().splitlines()
            if line.startswith(("test,", "X-positioning,"))]
    (work / "xpos.csv").write_text("\n".join(rows) + "\n")
    r = ednc("iso230-2", "--data", f"{work}/xpos.csv", "--json")
    assert r.returncode == 0, r.stderr
    assert set(json.loads(r.stdout)) == {"A_um", "B_um", "E_um", "M_um", "R_um"}


def test_the_service_refuses_the_model_the_cli_refuses() -> None:
    """The REST API's model upload uses the same check: ``{}`` and a model with a term on an
    axis the machine lacks are refused alike."""
    from server.numeric import ModelError, check_model
    from volumetric.model.machine import parse_machine
    from volumetric.model.modelcheck import ModelContentError
    from volumetric.model.modelcheck import check_model as core_check

    with pytest.raises(ModelError, match="format"):
        check_model({}, VMC)
    bad = {"format": "ednc-model/1", "machine": "vmc", "components": {}, "locations": {},
           "terms": [{"effect": "backlash", "axis": "c", "reversal_um": 3.0}]}
    with pytest.raises(ModelError, match="no axis 'c'"):
        check_model(bad, VMC)
    with pytest.raises(ModelContentError, match="no axis 'c'"):
        core_check(bad, parse_machine(VMC))
    empty = {"format": "ednc-model/1", "machine": "vmc", "components": {}, "locations": {}}
    with pytest.raises(ModelError, match="no error"):
        check_model(empty, VMC)


def test_the_rest_commands_refuse_in_one_line(work: Path, tmp_path: Path) -> None:
    """``ednc model upload`` checks the model offline first, then names an unreachable
    center; ``ednc machine register`` checks the description first."""
    line = one_line_error(ednc("model", "upload", "--machine", "vmc", "--model",
                               f"{work}/empty-model.json", "--api", "http://127.0.0.1:9"))
    assert "empty-model.json" in line and "format" in line
    line = one_line_error(ednc("model", "upload", "--machine", "vmc", "--model",
                               f"{work}/model.json", "--api", "http://127.0.0.1:9"))
    assert "nothing is listening at http://127.0.0.1:9" in line
    line = one_line_error(ednc("machine", "register", "--machine", f"{work}/huge.json",
                               "--secret", "0123456789abcdef", "--api", "http://127.0.0.1:9"))
    assert "travel_mm.x" in line


def test_the_service_refuses_the_readings_the_cli_refuses(work: Path) -> None:
    """The measurement upload reads with the CLI's reader (plausible sizes, with the line)
    and checks the rotary columns against the machine as ``fit`` does."""
    from server.numeric import MeasurementError, count_measurement_rows

    text = (work / "c.csv").read_text()
    assert count_measurement_rows(text, "c.csv", VMC) == text.count("\n") - 1
    with pytest.raises(MeasurementError, match="no a_deg column"):
        count_measurement_rows(text, "c.csv", FIVE_AXIS)
    with pytest.raises(MeasurementError, match="line 6"):
        count_measurement_rows((work / "reading-1e9.csv").read_text(), "bad.csv", VMC)


def test_the_service_refuses_the_description_the_cli_refuses() -> None:
    from server.numeric import check_machine_description

    no_pivots = {k: v for k, v in FIVE_AXIS.items() if k != "pivots_mm"}
    with pytest.raises(ValueError, match='add for example "pivots_mm"'):
        check_machine_description(no_pivots)
    with pytest.raises(ValueError, match=r"travel_mm\.x"):
        check_machine_description({**VMC, "travel_mm": {**TRAVEL, "x": [0, 1e9]}})
    check_machine_description(FIVE_AXIS)


def test_sizes_that_overflow_the_arithmetic_are_refused() -> None:
    """What the fuzz found: a location of 1e300 µrad (NaN through the kinematics' sines),
    a tool of 1e300 mm (overflow in the Jacobian), a backlash of 1e300 µm, a pivot 1e300 mm
    away."""
    from volumetric.errors import MachineSpecError
    from volumetric.model.machine import parse_machine
    from volumetric.model.modelcheck import ModelContentError, check_model

    machine = parse_machine(VMC)
    base = {"format": "ednc-model/1", "machine": "vmc", "components": {}, "locations": {}}
    for body, match in (({**base, "locations": {"EB0Z": 1e300}}, r"locations\.EB0Z"),
                        ({**base, "terms": [{"effect": "backlash", "axis": "x",
                                             "reversal_um": 1e300}]}, "reversal_um"),
                        ({**base, "components": {"EXX": {"type": "polynomial",
                                                         "coefficients": [0, 1e6]}}},
                         r"components\.EXX")):
        with pytest.raises(ModelContentError, match=match):
            check_model(body, machine)
    with pytest.raises(MachineSpecError, match="tool_length_mm"):
        parse_machine({**VMC, "tool_length_mm": 1e300})
    with pytest.raises(MachineSpecError, match=r"pivots_mm\.C"):
        parse_machine({**FIVE_AXIS, "pivots_mm": {"A": [0, 300, -150], "C": [1e300, 0, 0]}})
