"""Plausible numbers in the wrong unit, and one format given for another (issue 32's
kept-back kinds): each is refused with its likely cause, or warned about where real data
could look the same, by the first reader that meets it (:mod:`volumetric.plausible`)."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest

from tests.support.api import CSV_HEADER, backlash_csv
from tests.support.cli import ednc, one_line_error
from tests.support.link import description, model_body
from volumetric.errors import ComponentErrorSpecError, MachineSpecError
from volumetric.measure.measurement import MeasurementFormatError, read_measurements
from volumetric.measure.plausible import measurement_warnings
from volumetric.measure.tables import read_table_files
from volumetric.model.machine import description_warnings, load_machine, parse_machine
from volumetric.plausible.files import what_is
from volumetric.plausible.temperatures import temperature_problem, temperature_warning
from volumetric.plausible.times import stamp_problem

CEC = ("%_N_VMC_CEC_MPF\n;$PATH=/_N_MPF_DIR\n$AN_CEC_INPUT_AXIS[0]=(AX1)\n"
       "$AN_CEC_OUTPUT_AXIS[0]=(AX1)\n$AN_CEC[0,0]=0.0012\nM30\n")
FANUC = "%\nN03605 P1\nN10000 P0\nN10001 P-3\nN10002 P2\n%\n"


def _csv(tmp_path: Path, text: str, name: str = "d.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _refusal(path: Path) -> str:
    with pytest.raises(MeasurementFormatError) as err:
        read_measurements(path)
    return str(err.value)


@pytest.mark.parametrize(("old", "new", "said"), [
    ("time_s", "time_ms", "'time_ms' is in milliseconds; the format wants 'time_s'"),
    ("x_mm", "x_in", "'x_in' is in inches; the format wants 'x_mm' in mm (multiply by 25.4)"),
    ("tool_mm", "tool_m", "'tool_m' is in metres"),
    ("value", "value_nm", "'value_nm' is in nm; the format wants 'value' in µm"),
    ("value", "value_arcsec", "wants 'value' in µrad (multiply by 4.848)"),
])
def test_a_column_named_in_another_unit_is_refused_with_the_factor(
        tmp_path: Path, old: str, new: str, said: str) -> None:
    text = backlash_csv(4.0)
    header, rest = text.split("\n", 1)
    cells = header.split(",")
    cells[cells.index(old)] = new
    assert said in _refusal(_csv(tmp_path, ",".join(cells) + "\n" + rest))


def test_temperature_columns_in_fahrenheit_or_kelvin(tmp_path: Path) -> None:
    text = backlash_csv(4.0)
    header, *rows = text.strip().split("\n")
    named_f = "\n".join([header + ",T_air_F"] + [r + ",68.0" for r in rows]) + "\n"
    assert "'T_air_F' is in °F; the format wants 'T_air_C'" in _refusal(_csv(tmp_path, named_f))
    kelvin = "\n".join([header + ",T_air_C"] + [r + ",293.4" for r in rows]) + "\n"
    said = _refusal(_csv(tmp_path, kelvin))
    assert "293.4 °C is outside -20..100 °C" in said and "kelvin" in said
    fahrenheit = "\n".join([header + ",T_air_C"] + [r + ",68.5" for r in rows]) + "\n"
    m = read_measurements(_csv(tmp_path, fahrenheit))  # a hot spindle could read so
    warned = measurement_warnings(m, "d.csv")
    assert any("T_air_C: 68.5 °C is hot" in w and "20.3 °C" in w for w in warned), warned


def test_readings_in_nm_are_refused_and_in_mm_warned(tmp_path: Path) -> None:
    text = backlash_csv(4.0)
    header, *rows = text.strip().split("\n")

    def scaled(factor: float) -> str:
        out = [header]
        for r in rows:
            cells = r.split(",")
            cells[-1] = repr(float(cells[-1]) * factor + 2500.0 * (factor > 1))
            out.append(",".join(cells))
        return "\n".join(out) + "\n"

    said = _refusal(_csv(tmp_path, scaled(1000.0)))
    assert "they look like nm" in said and "divide by 1000" in said
    m = read_measurements(_csv(tmp_path, scaled(1e-3)))
    assert any("look like mm (multiply by 1000)" in w for w in measurement_warnings(m, "x"))
    assert measurement_warnings(read_measurements(_csv(tmp_path, text)), "x") == []


def test_angles_in_degrees_and_a_campaign_in_milliseconds_are_warned(tmp_path: Path) -> None:
    rows = [CSV_HEADER]
    for i in range(20):  # pitch readings of 0.0004-0.001° (7-17 µrad), 1000 ms apart
        rows.append(f"X-pitch,1,{i * 1e6},{25.0 * i},150,-150,1,0,0,100,angle,0,1,0,"
                    f"{0.0004 + 0.00003 * i:.6f}")
    m = read_measurements(_csv(tmp_path, "\n".join(rows) + "\n"))
    warned = " ".join(measurement_warnings(m, "p.csv"))
    assert "look like degrees" in warned and "if time_s is milliseconds" in warned


def test_travels_in_micrometres_refused_in_radians_and_metres_warned() -> None:
    spec = {**description(), "travel_mm": {"x": [0, 800_000], "y": [0, 300], "z": [-300, 0]}}
    with pytest.raises(MachineSpecError, match="look like µm; this is mm"):
        parse_machine(spec)
    five = {**description(), "chain": "w C X Y b Z t", "pivots_mm": {"C": [250, 150, 0]},
            "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0],
                          "c": [-3.1416, 3.1416]}}
    warned = description_warnings(parse_machine(five))
    assert len(warned) == 1 and "looks like radians" in warned[0]
    metres = {**description(), "travel_mm": {"x": [0, 0.5], "y": [0, 0.3], "z": [-0.3, 0]}}
    assert "look like metres" in description_warnings(parse_machine(metres))[0]


def test_temperatures_and_stamps_in_the_wrong_unit() -> None:
    assert temperature_problem(22.0) is None
    assert "kelvin" in (temperature_problem(295.15) or "")
    assert "m°C" in (temperature_problem(21_500.0) or "")
    assert temperature_warning([20.0, 72.0], "t") is None  # one cool reading: °C
    assert "22.2 °C" in (temperature_warning([72.0], "t") or "")
    now = time.time()
    assert stamp_problem(now) is None
    assert "milliseconds" in (stamp_problem(now * 1000) or "")
    assert "microseconds" in (stamp_problem(now * 1e6) or "")
    assert "like seconds" in (stamp_problem(now / 1000, "timestamp_ms") or "")


@pytest.mark.parametrize(("text", "kind"), [
    (CEC, "siemens"), (FANUC, "fanuc"), ("G10 L50\nN10000 R-3\nG11\n", "fanuc"),
    (json.dumps(model_body()), "model"), (json.dumps(description()), "machine"),
])
def test_native_files_are_known(text: str, kind: str) -> None:
    assert what_is(text.encode()) == kind
    assert what_is(b"EDMP\x05\x00") == "map"


@pytest.mark.parametrize("content", [CEC, FANUC])
def test_a_controllers_file_where_a_csv_model_or_description_belongs(
        tmp_path: Path, content: str) -> None:
    native = tmp_path / "native.txt"
    native.write_text(content)
    said = _refusal(native)
    assert ("Siemens" in said or "Fanuc" in said) and "not a measurement CSV" in said
    with pytest.raises(MachineSpecError, match="not a machine description"):
        load_machine(native)
    with pytest.raises(ComponentErrorSpecError, match="not a component-error table"):
        read_table_files([native])
    (tmp_path / "m.json").write_text(json.dumps(description()))
    line = one_line_error(ednc("compensate", "--machine", str(tmp_path / "m.json"),
                               "--model", str(native), "--point", "100,100,-100"))
    assert "not a model JSON" in line


def test_a_map_or_a_model_given_for_another_file(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps(description()))
    (tmp_path / "map.bin").write_bytes(b"EDMP" + bytes(60))
    line = one_line_error(ednc("fit", "--machine", str(tmp_path / "m.json"), "--data",
                               str(tmp_path / "map.bin")))
    assert "EDNC map payload" in line and "not a measurement CSV" in line
    (tmp_path / "model.json").write_text(json.dumps(model_body()))
    line = one_line_error(ednc("compensate", "--machine", str(tmp_path / "model.json"),
                               "--model", str(tmp_path / "model.json"), "--point", "1,1,1"))
    assert "this is a model JSON" in line and "not a machine description" in line


def test_a_table_column_in_arcseconds_is_refused(tmp_path: Path) -> None:
    table = tmp_path / "X.csv"
    table.write_text("x_mm,EXX_um,EAX_arcsec\n0,0,0\n500,1.5,2.0\n")
    files = read_table_files([table])
    from volumetric.measure.tables import import_model

    with pytest.raises(ComponentErrorSpecError, match=r"EAX_arcsec.*multiply by 4\.848"):
        import_model(parse_machine(description()), files)


def test_the_limits_are_one_set_at_every_entry_point() -> None:
    from machine_sim.temperatures import PLAUSIBLE_C as MACHINE_C
    from server.intake import PLAUSIBLE_C
    from server.schemas.machine import MAX_LENGTH_MM
    from volumetric.measure.plausible import LIMITS
    from volumetric.model.machine import MAX_TOOL_LENGTH_MM
    from volumetric.plausible import LINEAR_POSITION, TEMPERATURE, TOOL_LENGTH

    assert PLAUSIBLE_C == MACHINE_C == (TEMPERATURE.lo, TEMPERATURE.hi) == (-20.0, 100.0)
    assert LIMITS["x_mm"] is LINEAR_POSITION and LINEAR_POSITION.hi == MAX_LENGTH_MM
    assert LIMITS["tool_mm"] is TOOL_LENGTH and TOOL_LENGTH.hi == MAX_TOOL_LENGTH_MM
    assert np.isclose(TOOL_LENGTH.hi, 10_000.0)
