"""``ednc sim --link modbus|opcua`` as a user runs it: generated machines serve their
controller windows at their own loopback addresses, and ``ednc discover`` finds them."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import time

import pytest

from tests.support.cli import EDNC, ednc


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.1.1", 0))
        return int(s.getsockname()[1])


def _start(*args: str, env: dict[str, str] | None = None) -> subprocess.Popen[str]:
    return subprocess.Popen([EDNC, "sim", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "COLUMNS": "200", **(env or {})})


def _found(port_option: str, port: int, subnet: str) -> list[dict[str, object]]:
    others = [o for o in ("--modbus-port", "--opcua-port", "--ednc-port") if o != port_option]
    for _ in range(200):
        r = ednc("discover", "--subnet", subnet, port_option, str(port),
                 *[x for o in others for x in (o, "0")], "--json", "--timeout-ms", "300")
        assert r.returncode == 0, r.stderr
        found: list[dict[str, object]] = json.loads(r.stdout)
        if len(found) == 2 and all(f["link"] for f in found):  # both servers up
            return found
        time.sleep(0.3)
    return found


@pytest.mark.parametrize("link", ["modbus", "opcua"])
def test_sim_serves_windows_that_discover_finds(link: str) -> None:
    port = _free_port()
    block = {"modbus": 1, "opcua": 2}[link]  # each link its own names and addresses
    env = {"EDNC_OPCUA_PASSWORD": "sim-link-test-pw"}
    proc = _start("--link", link, "--machines", "2", "--secret", "abcdefghijklmnopqrst",
                  "--port", str(port), "--duration", "60", env=env)
    try:
        found = _found("--modbus-port" if link == "modbus" else "--opcua-port", port,
                       f"127.{block}.1.0/30")
    finally:
        proc.terminate()
        out, err = proc.communicate(timeout=30)
    assert [f["host"] for f in found] == [f"127.{block}.1.1", f"127.{block}.1.2"], (
        found, err[-2000:])
    assert all(f["kind"] == link for f in found)
    if link == "modbus":  # the identity names the machine, read through 03h
        assert [f["machine"] for f in found] == ["sim-pmc-001", "sim-pmc-002"]
    else:  # an OPC UA server shows no data without login
        assert all(f["link"]["endpoint"] == f"opc.tcp://{f['host']}:{port}"  # type: ignore[index]
                   for f in found)
    assert "controller serving its window on" in out


def test_an_opcua_fleet_without_its_password_is_refused() -> None:
    env = {k: v for k, v in os.environ.items() if k != "EDNC_OPCUA_PASSWORD"}
    r = subprocess.run([EDNC, "sim", "--link", "opcua", "--machines", "1", "--secret",
                        "abcdefghijklmnopqrst", "--duration", "1"], capture_output=True,
                       text=True, env=env, timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert "EDNC_OPCUA_PASSWORD" in r.stderr
