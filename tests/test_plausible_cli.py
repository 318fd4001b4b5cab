"""The cases of issue 32 at the command line: a plausible number in the wrong unit is
refused (or warned about) by the first command that reads it, with its likely cause;
outputs of absurd size are refused before any work; the other named cases."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from machine_sim.fleet import generated_fleet, load_fleet
from tests.support.api import backlash_csv
from tests.support.cli import EDNC, ednc, one_line_error
from tests.support.link import description, model_body

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def vmc(tmp_path: Path) -> tuple[str, str]:
    """A machine description and a model of it with a spindle drift term."""
    m, model = tmp_path / "m.json", tmp_path / "model.json"
    m.write_text(json.dumps(description("vmc-01", "siemens")))
    model.write_text(json.dumps(model_body(thermal_sensor="T_spindle_C")))
    return str(m), str(model)


def test_compensate_refuses_a_temperature_of_1e6_and_names_kelvin(
        vmc: tuple[str, str]) -> None:
    m, model = vmc
    base = ["compensate", "--machine", m, "--model", model, "--point", "100,100,-100"]
    line = one_line_error(ednc(*base, "--temperature", "T_spindle_C=1e6"))
    assert "1e+06 °C is outside -20..100 °C" in line
    line = one_line_error(ednc(*base, "--temperature", "T_spindle_C=295.15"))
    assert "looks like kelvin" in line and "subtract 273.15" in line
    hot = ednc(*base, "--temperature", "T_spindle_C=72", "--json")
    assert hot.returncode == 0, hot.stderr
    assert "if this is °F, it is 22.2 °C" in hot.stderr  # warned, computed all the same


def test_lookup_refuses_what_it_clamped_silently(vmc: tuple[str, str],
                                                  tmp_path: Path) -> None:
    m, model = vmc
    out = tmp_path / "map.bin"
    r = ednc("map", "--machine", m, "--model", model, "--out", str(out), "--kind", "tables",
             "--temperature", "T_spindle_C=20", "--json")
    assert r.returncode == 0, r.stderr
    (tmp_path / "p.csv").write_text("x,y,z\n100,100,-100\n")
    line = one_line_error(ednc("lookup", "--map", str(out), "--points",
                               str(tmp_path / "p.csv"), "--temperature", "spindle=1e6"))
    assert "outside -20..100 °C" in line


def test_tables_export_of_1e8_points_is_refused_before_any_work(
        vmc: tuple[str, str], tmp_path: Path) -> None:
    m, model = vmc
    out = tmp_path / "tables"
    started = time.monotonic()
    line = one_line_error(ednc("tables", "export", "--machine", m, "--model", model,
                               "--out", str(out), "--points", "100000000"))
    assert "--points 100000000: must be within [2, 100000]" in line
    assert not out.exists()
    assert time.monotonic() - started < 60  # refused, not computed (a generous bound)


def test_export_step_in_micrometres_is_refused_by_its_size(vmc: tuple[str, str],
                                                           tmp_path: Path) -> None:
    m, model = vmc
    line = one_line_error(ednc("export", "--machine", m, "--model", model, "--format",
                               "iso230-1", "--out", str(tmp_path / "x"), "--step", "1e-6"))
    assert "over the limit of 1.07 GB" in line and "larger --step" in line
    assert not (tmp_path / "x").exists()


def test_cec_for_a_fanuc_machine_is_refused(tmp_path: Path) -> None:
    m, model = tmp_path / "m.json", tmp_path / "model.json"
    m.write_text(json.dumps(description("vmc-01", "fanuc")))
    model.write_text(json.dumps(model_body()))
    line = one_line_error(ednc("export", "--machine", str(m), "--model", str(model),
                               "--format", "cec", "--out", str(tmp_path / "x.mpf")))
    assert "fanuc controller" in line and "SINUMERIK" in line


def test_a_campaign_on_a_machine_in_metres_is_refused_with_the_cause(tmp_path: Path) -> None:
    spec = {**description(), "travel_mm": {"x": [0, 0.5], "y": [0, 0.3], "z": [-0.3, 0]}}
    (tmp_path / "m.json").write_text(json.dumps(spec))
    line = one_line_error(ednc("sim", "--campaign", str(tmp_path / "c.csv"), "--machine",
                               str(tmp_path / "m.json")))
    assert "look like metres" in line and '"x": [0, 500]' in line
    assert not (tmp_path / "c.csv").exists()


def test_a_german_spreadsheet_csv_is_named_and_utf16_is_read(tmp_path: Path) -> None:
    text = backlash_csv(8.0)
    german = tmp_path / "de.csv"
    german.write_text(text.replace(",", ";").replace(".", ","), encoding="utf-8")
    line = one_line_error(ednc("iso230-2", "--data", str(german), "--json"))
    assert str(german) in line and "semicolons and decimal commas" in line
    assert "'CSV UTF-8 (comma delimited)'" in line
    utf8, utf16 = tmp_path / "a.csv", tmp_path / "w.csv"
    utf8.write_text(text, encoding="utf-8")
    utf16.write_bytes(text.encode("utf-16"))  # with its byte-order mark, as Excel writes
    a, b = (ednc("iso230-2", "--data", str(p), "--json") for p in (utf8, utf16))
    assert a.returncode == 0 and b.returncode == 0, b.stderr
    assert json.loads(a.stdout) == json.loads(b.stdout)
    bare = tmp_path / "bare.csv"
    bare.write_bytes(text.encode("utf-16-le"))  # no mark: cannot be told for sure
    line = one_line_error(ednc("iso230-2", "--data", str(bare), "--json"))
    assert str(bare) in line and "UTF-16" in line


def test_help_shows_no_type_after_a_flag_and_map_names_its_default() -> None:
    r = ednc("compensate", "--help")
    assert r.returncode == 0 and "--json" in r.stdout
    assert "<bool>" not in r.stdout
    r = ednc("map", "--help")
    assert "corrections on a grid chosen" not in r.stdout
    assert "smallest" in r.stdout and "<bool>" not in r.stdout


def test_a_fleet_entry_named_by_file_keeps_its_link(tmp_path: Path) -> None:
    spec = {**description("ua-03", "siemens", "127.2.9.3"),
            "link": {"kind": "opcua", "endpoint": "opc.tcp://127.2.9.3:48400",
                     "user": "ednc", "password_ref": "env:EDNC_OPCUA_PASSWORD"}}
    (tmp_path / "ua-03.json").write_text(json.dumps(spec))
    fleet = tmp_path / "fleet.json"
    fleet.write_text(json.dumps({"machines": [
        {"machine": "ua-03.json", "secret": "s3cret-s3cret-s3cret"}]}))
    entries, _ = load_fleet(fleet)
    assert entries[0].link_kind == "opcua"
    assert entries[0].link is not None and entries[0].link["endpoint"].endswith(":48400")
    # no machine connects to a center: none is asked for
    r = subprocess.run([EDNC, "sim", "--fleet", str(fleet), "--duration", "1"],
                       capture_output=True, text=True, timeout=120,
                       env={**os.environ, "EDNC_OPCUA_PASSWORD": "sim-pw-0123"})
    assert "--center" not in r.stderr, r.stderr
    assert r.returncode == 0 and "ua-03: siemens-style controller serving" in r.stdout, \
        r.stderr


def test_generated_fleets_of_different_links_do_not_collide() -> None:
    fleets = {link: generated_fleet(2, "s3cret-s3cret-s3cret", link=link)
              for link in ("ednc", "modbus", "opcua")}
    names = [e.machine.name for f in fleets.values() for e in f]
    ips = [e.machine.ip for f in fleets.values() for e in f]
    assert len(set(names)) == len(names) == 6 and len(set(ips)) == 6
    assert names[:2] == ["sim-001", "sim-002"]  # the EDNC fleet as before


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def test_serve_on_a_taken_port_fails_at_once_without_announcing_it(tmp_path: Path) -> None:
    with socket.socket() as held:
        held.bind(("127.0.0.1", 0))
        held.listen()
        port = held.getsockname()[1]
        env = {**{k: v for k, v in os.environ.items() if not k.startswith("EDNC_")},
               "EDNC_DATABASE_URL": f"sqlite:///{tmp_path / 'c.db'}", "EDNC_API_KEY": "k" * 16}
        r = subprocess.run([EDNC, "serve", "--port", str(port)], capture_output=True,
                           text=True, timeout=60, env=env)
    line = one_line_error(r)
    assert f"cannot serve HTTP on 127.0.0.1:{port}" in line and "--port" in line
    assert "ednc serve: HTTP" not in r.stdout + r.stderr
    # and nothing listening where a register goes: said as such, not as a refused key
    (tmp_path / "m.json").write_text(json.dumps(description()))
    line = one_line_error(ednc("machine", "register", "--machine", str(tmp_path / "m.json"),
                               "--secret", "s3cret-s3cret-s3cret", "--api",
                               f"http://127.0.0.1:{_free_port()}", "--api-key", "k" * 16))
    assert "nothing is listening at http://127.0.0.1:" in line


@pytest.fixture
def center(tmp_path: Path) -> tuple[str, str]:
    """``ednc serve`` on free ports: (API URL, key)."""
    import httpx

    port, key = _free_port(), "serve-key-0123456"
    env = {**{k: v for k, v in os.environ.items() if not k.startswith("EDNC_")},
           "EDNC_DATABASE_URL": f"sqlite:///{tmp_path / 'c.db'}", "EDNC_API_KEY": key,
           "EDNC_MACHINE_PORT": "0"}
    proc = subprocess.Popen([EDNC, "serve", "--port", str(port)], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 180.0  # waiting for start-up, not measuring it
        while True:
            try:
                httpx.get(f"{base}/api/status", timeout=1.0)
                break
            except httpx.TransportError:
                assert proc.poll() is None and time.monotonic() < deadline, "no center"
                time.sleep(0.1)
        yield base, key
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_machine_register_list_update_delete(center: tuple[str, str], tmp_path: Path) -> None:
    api, key = center
    auth = ["--api", api, "--api-key", key]
    first, second = tmp_path / "a.json", tmp_path / "b.json"
    first.write_text(json.dumps(description("vmc-01", "fanuc", "10.0.0.21")))
    second.write_text(json.dumps(description("vmc-02", "fanuc", "10.0.0.21")))  # same ip
    secret = ["--secret", "s3cret-s3cret-s3cret"]
    r = ednc("machine", "register", "--machine", str(first), *secret, *auth)
    assert r.returncode == 0 and "registered vmc-01" in r.stdout, r.stderr
    again = ednc("machine", "register", "--machine", str(first), *secret, *auth)
    assert again.returncode == 0 and "already registered" in again.stdout
    line = one_line_error(ednc("machine", "register", "--machine", str(second), *secret,
                               *auth))
    assert line.startswith("ednc: error: vmc-02 is not registered") and "10.0.0.21" in line
    listed = json.loads(ednc("machine", "list", "--json", *auth).stdout)
    assert [m["name"] for m in listed] == ["vmc-01"]
    # update: checked as on registration (here by REST itself) and applied
    moved = tmp_path / "c.json"
    moved.write_text(json.dumps(description("vmc-01", "fanuc", "10.0.0.22")))
    r = ednc("machine", "update", "vmc-01", "--machine", str(moved), *auth)
    assert r.returncode == 0, r.stderr
    line = one_line_error(ednc("machine", "update", "vmc-01", "--secret", "short", *auth))
    assert "secret" in line and "422" in line
    r = ednc("machine", "list", *auth)
    assert "vmc-01\tfanuc\t10.0.0.22\tednc" in r.stdout
    line = one_line_error(ednc("machine", "delete", "vmc-01", *auth))
    assert "--yes" in line
    r = ednc("machine", "delete", "vmc-01", "--yes", *auth)
    assert r.returncode == 0, r.stderr
    assert json.loads(ednc("machine", "list", "--json", *auth).stdout) == []
    line = one_line_error(ednc("machine", "delete", "vmc-01", "--yes", *auth))
    assert "no machine 'vmc-01'" in line


def test_ctrl_c_on_the_demo_ends_without_a_traceback() -> None:
    # tasks.py and the demo in one process group, as a terminal's Ctrl-C reaches them
    proc = subprocess.Popen([sys.executable, str(ROOT / "tasks.py"), "demo", "--offline"],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True,
                            env={**os.environ, "COLUMNS": "120"},
                            # a shell's background job starts with SIGINT ignored (and
                            # its children inherit that): a terminal's does not
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert proc.stdout is not None
    for line in proc.stdout:  # the demo is running once it prints its first rule
        if "EDNC control center demo" in line:
            break
    time.sleep(1.0)
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert "Traceback" not in out + err and "KeyboardInterrupt" not in err, err[-3000:]
    assert "stopped" in err
