"""docker-compose.yml and the Dockerfile, checked without Docker (none runs here).

The file is parsed and every service, port, address and variable the center needs is
checked against the real code: the settings class validates the center's environment,
the real ``ednc`` command line accepts every option the containers pass, the fleet file
loads with both the simulator's and the center's readers, and each machine container's
fixed address is the one the center knows the machine by.
"""

from __future__ import annotations

import ipaddress
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

from machine_sim.fleet import load_fleet
from server.bootstrap import read_machines_file
from server.settings import Settings

REPO = Path(__file__).resolve().parents[1]
EDNC = str(Path(sys.executable).parent / "ednc")


@pytest.fixture(scope="module")
def compose() -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load((REPO / "docker-compose.yml").read_text())
    return data


def _mounted(service: dict[str, Any], inside: str) -> Path:
    """The repository path a container path comes from (read-only bind mounts)."""
    for volume in service.get("volumes", []):
        src, dst, *_ = volume.split(":")
        if inside == dst or inside.startswith(dst.rstrip("/") + "/"):
            return REPO / src.removeprefix("./") / inside[len(dst):].lstrip("/")
    raise AssertionError(f"{inside} is not mounted into the service")


def test_every_part_of_the_plant_is_there(compose: dict[str, Any]) -> None:
    services = compose["services"]
    assert {"mosquitto", "postgres", "center"} <= set(services)
    machines = [n for n, s in services.items() if "sim" in s.get("command", [])]
    assert len(machines) >= 6
    assert services["mosquitto"]["image"].startswith("eclipse-mosquitto")
    assert services["postgres"]["image"].startswith("postgres")
    conf = _mounted(services["mosquitto"], "/mosquitto/config/mosquitto.conf")
    assert re.search(r"^listener 1883$", conf.read_text(), re.M)
    # temperatures are not held back for the center's ACK (Nagle, server/mqtt.ack_at_once)
    assert re.search(r"^set_tcp_nodelay true$", conf.read_text(), re.M)


def test_the_center_environment_is_valid_settings(compose: dict[str, Any],
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    center = compose["services"]["center"]
    assert center["command"] == ["ednc", "serve"]  # the command the tests run natively
    env = dict(center["environment"])
    for key in ("EDNC_API_KEY", "EDNC_READ_KEY", "EDNC_SECRET_KEY"):
        # ${EDNC_...:?...}: required from the host
        assert str(env[key]).startswith("${" + key + ":?"), key
        env[key] = f"{key.lower()}-for-the-test"
    env["EDNC_MACHINES_FILE"] = str(_mounted(center, env["EDNC_MACHINES_FILE"]))
    for key in list(env):
        assert key.startswith("EDNC_"), key
        monkeypatch.setenv(key, str(env[key]))
    s = Settings()
    assert s.database_url.startswith("postgresql+psycopg://") and "@postgres:5432/" in \
        s.database_url
    assert s.mqtt_host == "mosquitto" and s.mqtt_port == 1883
    published = {p.split(":")[1] for p in center["ports"]}
    assert {str(s.http_port), str(s.machine_port)} <= published
    assert s.http_host == "0.0.0.0" and s.machine_host == "0.0.0.0"
    assert s.read_key is not None and s.secret_key is not None  # published API, PostgreSQL
    assert set(center["depends_on"]) >= {"postgres", "mosquitto"}
    pg = compose["services"]["postgres"]["environment"]
    assert f":{pg['POSTGRES_PASSWORD']}@" in s.database_url
    assert s.database_url.endswith("/" + pg["POSTGRES_DB"])


def test_each_machine_container_is_a_fleet_machine_at_its_own_address(
        compose: dict[str, Any]) -> None:
    services = compose["services"]
    center = services["center"]
    fleet_file = _mounted(center, center["environment"]["EDNC_MACHINES_FILE"])
    entries, _ = load_fleet(fleet_file)
    registered = {m.name: str(m.ip) for m in read_machines_file(fleet_file)}
    assert {e.machine.name for e in entries} == set(registered)
    subnet = ipaddress.ip_network(compose["networks"]["plant"]["ipam"]["config"][0]["subnet"])
    seen = set()
    for name, svc in services.items():
        cmd = svc.get("command", [])
        if "sim" not in cmd:
            continue
        only = cmd[cmd.index("--only") + 1]
        assert only in registered, (name, only)
        address = svc["networks"]["plant"]["ipv4_address"]
        assert ipaddress.ip_address(address) in subnet
        assert registered[only] == address  # the center knows it by this address
        assert _mounted(svc, cmd[cmd.index("--fleet") + 1]) == fleet_file
        entry = next(e for e in entries if e.machine.name == only)
        if entry.link_kind != "ednc":
            # the center connects to its controller's server, at the container's address
            assert "--center" not in cmd
            link = dict(entry.link or {})
            where = link.get("host") or link.get("endpoint", "")
            assert address in str(where), (only, link)
            ref = str(link.get("password_ref", ""))
            if ref.startswith("env:"):
                var = ref[4:]
                assert var in center["environment"] and var in svc["environment"], var
            seen.add(only)
            continue
        port = center["environment"]["EDNC_MACHINE_PORT"]
        assert cmd[cmd.index("--center") + 1] == f"center:{port}"
        assert cmd[cmd.index("--mqtt") + 1] == "mosquitto:1883"
        seen.add(only)
    assert seen == set(registered)  # every registered machine runs somewhere
    kinds = {e.link_kind for e in entries}
    assert kinds == {"ednc", "modbus", "opcua"}, kinds  # every link is in the plant


def test_the_containers_use_options_the_real_commands_have(compose: dict[str, Any]) -> None:
    helps = {sub: subprocess.run([EDNC, sub, "--help"], capture_output=True, text=True,
                                 check=True).stdout for sub in ("serve", "sim")}
    for svc in compose["services"].values():
        cmd = svc.get("command", [])
        if cmd[:1] != ["ednc"]:
            continue
        for option in (c for c in cmd[2:] if c.startswith("--")):
            assert option in helps[cmd[1]], (cmd[1], option)


def test_the_dockerfile_installs_every_package_and_serves() -> None:
    text = (REPO / "Dockerfile").read_text()
    assert re.search(r"^FROM python:3\.11", text, re.M)
    assert re.search(r"^RUN pip install .*\s\.$", text, re.M)
    assert 'CMD ["ednc", "serve"]' in text
    pyproject = (REPO / "pyproject.toml").read_text()
    packages = re.search(r"include = \[(.*?)\]", pyproject)
    assert packages is not None
    for pkg in re.findall(r'"(\w+)\*"', packages.group(1)):
        assert re.search(rf"^COPY {pkg} {pkg}$", text, re.M), pkg
