"""What the command line tells a newcomer is true and readable (issue 14, "unclear output"
and "README"): no numpy reprs in messages, units in table headers, sign conventions said
next to the values, defaults stated in ``--help``, ``ednc sim`` explaining (or doing) the
registration its machines need, ``--campaign`` ending in a sentence rather than a
traceback, and a diagnosis report a person can read on its own."""

from __future__ import annotations

import asyncio
import json
import re
import socket
from pathlib import Path

import httpx
import numpy as np
import pytest

from ednc.cli import UserError
from ednc.commands.sim import machine_description, register_fleet
from machine_sim.campaign import standard_campaign, write_campaign
from machine_sim.effects import Backlash, Effects, Noise
from machine_sim.fleet import Fleet, generated_fleet
from machine_sim.instruments import SimulatedMachine
from machine_sim.truth import random_geometry
from protocol.backoff import Backoff
from tests.support.cli import ednc, one_line_error
from tests.support.integration import center, require_loopback_aliases, until
from volumetric.diagnose.diagnosis import Z_MIN, Diagnosis
from volumetric.diagnose.report import estimate_rows, relevant_sensors
from volumetric.errors import ComponentErrorSpecError
from volumetric.measure.tables import export_tables, import_tables
from volumetric.model.components import GeometricErrors, Polynomial
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel

SECRET = "sim-secret-0123456789"
VMC = {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}
HEADER = ("test,run,time_s,x_mm,y_mm,z_mm,dir_x,dir_y,dir_z,tool_mm,quantity,ux,uy,uz,"
          "value")
NUMPY_REPR = re.compile(r"np\.\w+\(|numpy\.")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


# -- numpy scalars in messages


def test_an_angle_reading_in_a_positioning_test_is_named_as_text(tmp_path: Path) -> None:
    data = tmp_path / "d.csv"
    data.write_text(HEADER + "\n" + "Y-angular-C,1,0,0,10,-100,0,1,0,100,angle,0,0,1,3.0\n")
    line = one_line_error(ednc("iso230-2", "--data", str(data)))
    assert "test 'Y-angular-C'" in line
    assert not NUMPY_REPR.search(line), line


def test_a_direction_that_is_not_a_unit_vector_is_shown_as_numbers(tmp_path: Path) -> None:
    data = tmp_path / "d.csv"
    data.write_text(HEADER + "\n" + "X-pos,1,0,10,0,0,1,0,0,100,displacement,0.5,0,0,1.0\n")
    line = one_line_error(ednc("iso230-2", "--data", str(data)))
    assert "u = (0.5, 0.0, 0.0)" in line
    assert not NUMPY_REPR.search(line), line


def test_a_model_table_with_nan_names_the_entry_without_numpy(tmp_path: Path) -> None:
    (tmp_path / "m.json").write_text(json.dumps(VMC))
    model = MachineModel("vmc", GeometricErrors(
        {"EXX": Polynomial((0.0, 1.0), 0.0, 500.0)})).to_json()
    model["components"]["EXX"] = {"type": "table", "positions": [0.0, float("nan")],
                                  "values": [0.0, 1.0]}
    (tmp_path / "model.json").write_text(json.dumps(model))  # json writes NaN
    r = ednc("compensate", "--machine", str(tmp_path / "m.json"), "--model",
             str(tmp_path / "model.json"), "--point", "100,100,-100", "--json")
    line = one_line_error(r)
    assert "nan" in line and not NUMPY_REPR.search(line), line


# -- units and signs


def test_table_headers_carry_units_and_read_back() -> None:
    m = parse_machine(VMC)
    g = GeometricErrors({"EXX": Polynomial((0.0, 8.0), 0.0, 500.0),
                         "EAX": Polynomial((3.0, 1.0), 0.0, 500.0)}, {"EC0Y": 20.0})
    tables = export_tables(m, g, points=11)
    assert tables["X"].splitlines()[0] == "x_mm,EXX_um,EAX_urad"
    assert tables["locations"].splitlines()[:2] == ["name,value,unit", "EC0Y,20,urad"]
    back = import_tables(m, tables.items())
    q = np.linspace(0, 500, 7)
    for name in ("EXX", "EAX"):
        np.testing.assert_allclose(back.components[name](q), g.components[name](q))
    assert back.locations == {"EC0Y": 20.0}
    # the bare ISO 230-1 names of laser software and earlier exports are still read
    bare = import_tables(m, [("X.csv", "x_mm,EXX,EAX\n0,1,2\n500,3,4\n"),
                             ("l.csv", "name,value\nEC0Y,5\n")])
    assert set(bare.components) == {"EXX", "EAX"} and bare.locations == {"EC0Y": 5.0}


@pytest.mark.parametrize(("name", "text", "message"), [
    ("X.csv", "x_mm,EAX_um\n0,1\n500,2\n", r"'EAX_um': EAX is in µrad \(EAX_urad\), not µm"),
    ("X.csv", "x_mm,EXX_urad\n0,1\n500,2\n", r"'EXX_urad': EXX is in µm \(EXX_um\)"),
    ("l.csv", "name,value,unit\nEC0Y,5,um\n", r"l.csv:2 column unit: EC0Y is in urad"),
])
def test_a_unit_that_contradicts_the_name_is_refused(name: str, text: str,
                                                      message: str) -> None:
    with pytest.raises(ComponentErrorSpecError, match=message):
        import_tables(parse_machine(VMC), [(name, text)])


def test_iso230_2_table_states_the_sign_of_the_reversal(tmp_path: Path) -> None:
    rows = []
    for run in (1, 2):
        for d in (1, -1):
            for x in (0.0, 100.0, 200.0):
                value = -4.0 * d  # a lagging axis: short by 4 µm in both directions
                rows.append(f"X-pos,{run},{len(rows)},{x},0,0,{d},0,0,100,displacement,1,0,0,"
                            f"{value + 0.01 * len(rows)}")
    data = tmp_path / "d.csv"
    data.write_text(HEADER + "\n" + "\n".join(rows) + "\n")
    r = ednc("iso230-2", "--data", str(data))
    assert r.returncode == 0, r.stderr
    assert "B = x̄↑ - x̄↓ per target (negative: the axis lags behind the motion" in r.stdout
    b_col = [float(line.split()[6]) for line in r.stdout.splitlines()[3:6]]
    assert all(b < -7.9 for b in b_col), r.stdout


def test_sim_help_states_that_campaigns_have_no_noise_unless_asked() -> None:
    r = ednc("sim", "--help")
    text = " ".join(re.sub(r"[│╭╮╰╯─]", " ", r.stdout).split())
    assert "Default: no effects and no noise (noise 0 µm, 0 µrad)" in text, text
    assert "--register" in text


# -- ednc sim --campaign on machines whose rotary axes sit at the edge of the travel


def test_campaign_finds_rtest_balls_for_a_table_at_the_corner_of_the_travel(
        tmp_path: Path) -> None:
    # C's axis at x = y = 0, the corner of the X/Y travel: no two balls on opposite sides
    # of it are both reachable, which ended in a traceback before.
    spec = {"name": "corner", "chain": "w C X b Y Z t", "tool_length_mm": 100.0,
            "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0], "c": [-180, 180]},
            "pivots_mm": {"C": [0.0, 0.0, 0.0]}}
    (tmp_path / "m.json").write_text(json.dumps(spec))
    r = ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine",
             str(tmp_path / "m.json"))
    assert r.returncode == 0, r.stderr
    assert "C-rtest-1" in (tmp_path / "c.csv").read_text()


def test_campaign_without_any_rtest_position_is_one_clear_line(tmp_path: Path) -> None:
    spec = {"name": "far", "chain": "w C A X b Y Z t", "tool_length_mm": 100.0,
            "travel_mm": {"x": [0, 100], "y": [0, 100], "z": [-100, 0], "a": [-120, 30],
                          "c": [-180, 180]},
            "pivots_mm": {"A": [0.0, 3000.0, -150.0], "C": [4000.0, 300.0, -100.0]}}
    (tmp_path / "m.json").write_text(json.dumps(spec))
    line = one_line_error(ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine",
                               str(tmp_path / "m.json")))
    assert "no R-test set-up for axis" in line and "pivots_mm" in line


# -- ednc sim --machines: registration


def test_a_run_nobody_welcomes_says_the_machines_must_be_registered() -> None:
    port = free_port()  # nothing listens: no machine is welcomed
    r = ednc("sim", "--center", f"127.0.0.1:{port}", "--machines", "2", "--secret", SECRET,
             "--duration", "1.5")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.strip().splitlines()[-1])["welcomes"] == 0
    assert "no machine was welcomed" in r.stderr
    assert "--register --api-key KEY" in r.stderr


@pytest.mark.parametrize(("args", "message"), [
    (["--register"], "--register needs --api-key"),
    (["--register", "--api-key", "k", "--api", "http://127.0.0.1:{port}"],
     "--register: cannot reach the center's REST API at http://127.0.0.1:{port}"),
])
def test_register_problems_are_one_line(args: list[str], message: str) -> None:
    port = free_port()
    r = ednc("sim", "--center", f"127.0.0.1:{free_port()}", "--machines", "1", "--secret",
             SECRET, *(a.format(port=port) for a in args), "--duration", "1")
    assert message.format(port=port) in one_line_error(r)


async def test_registered_generated_machines_are_welcomed(tmp_path: Path) -> None:
    require_loopback_aliases()
    entries = generated_fleet(2, SECRET, seed=5)
    async with center(f"sqlite:///{tmp_path / 'c.db'}") as plant:
        added, known = await register_fleet(plant.client, entries, SECRET)
        assert (added, known) == (["sim-001", "sim-002"], [])
        listed = {m["name"]: m for m in (await plant.client.get("/api/machines")).json()}
        assert listed["sim-002"]["ip"] == machine_description(entries[1].machine)["ip"]
        # a second run leaves them as they are
        assert await register_fleet(plant.client, entries, SECRET) == ([], added)
        fleet = Fleet(entries, ("127.0.0.1", plant.port), cycle_s=0.02,
                      backoff=Backoff(initial_s=0.05, factor=1.0, cap_s=0.5))
        async with fleet, asyncio.timeout(60):
            await until(lambda: fleet.summary()["welcomes"] >= 2)
        wrong = httpx.AsyncClient(transport=httpx.ASGITransport(app=plant.app),
                                  base_url="http://center", headers={"X-API-Key": "nope"})
        async with wrong:
            with pytest.raises(UserError, match="refused the API key"):
                await register_fleet(wrong, generated_fleet(1, SECRET, seed=9), SECRET)


# -- the diagnosis report


def _diagnosis(effect: str, sensor: str | None, candidates: list[dict[str, object]]
               ) -> Diagnosis:
    return Diagnosis(effect, "x", sensor, {}, 2.0, 1.0, candidates, {},
                     MachineModel("m", GeometricErrors({})))


def test_temperature_plots_only_when_temperature_matters() -> None:
    columns = {"spindle": "T_spindle_C", "bed": "T_bed_C", "air": "T_air_C"}
    weak = {"effect": "thermal_drift", "axis": "x", "sensor": "T_bed_C", "z": Z_MIN / 5,
            "gain": 0.01, "rms_after_um": 1.9}
    keep, note = relevant_sensors(_diagnosis("backlash", None, [weak]), columns)
    assert keep == []
    assert "T_spindle_C, T_bed_C, T_air_C are left out" in note and "z = 0.20" in note
    keep, note = relevant_sensors(_diagnosis("thermal_drift", "T_spindle_C", [weak]), columns)
    assert keep == ["spindle"] and "T_bed_C" in note
    strong = {**weak, "z": Z_MIN * 3}
    keep, _ = relevant_sensors(_diagnosis("thermal_drift", "T_spindle_C", [strong]), columns)
    assert keep == ["spindle", "bed"]


def test_estimates_carry_their_uncertainty_and_unit() -> None:
    rows = dict(estimate_rows({"reversal_um": 8.0006, "reversal_um_std": 0.0938,
                               "sign": "lags behind the motion", "um_per_m_K": 11.52,
                               "um_per_m_K_std": 0.4}))
    assert rows == {"reversal_um": "8.001 ± 0.094 µm", "sign": "lags behind the motion",
                    "um_per_m_K": "11.52 ± 0.4 µm/(m·K)"}


def test_report_page_says_what_from_what_when_and_stands_alone(tmp_path: Path) -> None:
    m = parse_machine(VMC)
    rng = np.random.default_rng(3)
    sim = SimulatedMachine(m, random_geometry(m, rng), Effects(
        backlash=(Backlash("x", 8.0),), noise=Noise(0.3, 0.3)), seed=3)
    write_campaign(tmp_path / "campaign.csv", standard_campaign(sim, rng))
    (tmp_path / "vmc.json").write_text(json.dumps(VMC))
    r = ednc("diagnose", "--machine", str(tmp_path / "vmc.json"), "--data",
             str(tmp_path / "campaign.csv"), "--report", str(tmp_path / "r"))
    assert r.returncode == 0, r.stderr
    page = (tmp_path / "r" / "index.html").read_text()
    assert "campaign.csv" in page and "vmc.json" in page
    assert re.search(r"report made</th><td>\d{4}-\d\d-\d\d \d\d:\d\d UTC", page)
    assert "<table class='summary'>" in page and "<style>" in page
    assert re.search(r"reversal_um: [78]\.\d+ ± 0\.\d+ µm", page)
    assert "Sign convention: reversal_um is B ≥ 0" in page
    # every plot is in the page itself; none is a temperature plot for a backlash
    assert page.count("src='data:image/png;base64,") == page.count("<figure>") >= 5
    assert "temperature_" not in page and "are left out" in page
    assert not list((tmp_path / "r").glob("temperature_*.png"))
